"""Which BLAS kernel set runs of the solver study (results/solvers.csv and solvers_blas_*.csv) are distinct, for the
report (dbtools/reports/solvers.py) and the plot (dbtools/plots/solvers.py) alike. A run's kernel set is the core OpenBLAS
reported in its rows (blas_core), or the set data/experiments/blas_kernel_sets.txt maps that core to. Standard
library only."""
import glob
import os

from .common import provenance, read_rows

# python/dbtools/reports/ -> the repository's data/experiments/
ALIASES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "data", "experiments",
                       "blas_kernel_sets.txt")


def kernel_set_of(core, aliases=ALIASES):
    """The kernel set a core loads: its alias's, else the core itself."""
    with open(aliases) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 2 and not line.startswith("#") and parts[0] == core:
                return parts[1]
    return core


def kernel_sets(results):
    """The runs to compare, by kernel set (not by the OPENBLAS_CORETYPE asked for: two settings can load the same
    kernels): (distinct, duplicates), each a list of (core, kernel set, path). distinct starts with solvers.csv's own
    run, then each solvers_blas_*.csv whose kernel set no earlier run has; duplicates are the variant files whose
    set an earlier run already has (compared with it they would show noise as a kernel effect)."""
    distinct, duplicates = [], []
    for path in [os.path.join(results, "solvers.csv")] + sorted(glob.glob(os.path.join(results, "solvers_blas_*.csv"))):
        core = provenance(read_rows(path)).get("blas_core")
        if not core:
            continue
        kset = kernel_set_of(core)
        (duplicates if any(kset == s for _, s, _ in distinct) else distinct).append((core, kset, path))
    return distinct, duplicates
