"""deformbench's Python tools: reports, figures and regression tracking (run with PYTHONPATH=<repo>/python)."""
