"""``report.md`` of the solver benchmark: its tables, text and figures."""
