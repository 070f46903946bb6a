"""The campaign as a user wrote it: the spec schema, its YAML source with line numbers,
the loaded campaign and each run's logger data in SI."""
