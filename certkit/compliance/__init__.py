"""The compliance engine: regulatory clauses, certkit's own equations, the measures of a
drop, the assessment (values, verdicts, findings) and the data-quality audit."""
