"""The Markdown reports, one module per experiment named after its driver (RESULTS/NAME.csv -> RESULTS/NAME.md via
write(results)); figures.py maps the thesis' figures onto the frames study, mumps_estimate.py prints a report of
results/records/2026-11-24-mumps-ranks/ (run alone, not by the report step), common.py is what they share. Standard library only; the report
step (dbtools.report) runs them after the figures."""
