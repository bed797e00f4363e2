"""Which BLAS kernel set runs of the solver study (results/solvers.csv and solvers_blas_*.csv) are distinct, for the
report (experiments/reports/solvers.py) and the plot (plots/solvers.py) alike. Standard library only."""
import glob
import os

from common import provenance, read_rows


def kernel_sets(results):
    """The BLAS kernel set runs to compare, by the core OpenBLAS reported in their rows (not by the
    OPENBLAS_CORETYPE asked for: two settings can load the same kernels): (distinct, duplicates), each a list of
    (core, path). distinct starts with solvers.csv's own run, then each solvers_blas_*.csv whose core no earlier run
    has; duplicates are the variant files whose core an earlier run already has (compared with it they would show
    noise as a kernel effect)."""
    distinct, duplicates = [], []
    for path in [os.path.join(results, "solvers.csv")] + sorted(glob.glob(os.path.join(results, "solvers_blas_*.csv"))):
        core = provenance(read_rows(path)).get("blas_core")
        if not core:
            continue
        (duplicates if any(core == c for c, _ in distinct) else distinct).append((core, path))
    return distinct, duplicates
