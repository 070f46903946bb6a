"""What a reviewer reads: the report's view, figures and rendering, results.json, the audit
tables, the baseline comparison and the provenance record."""
