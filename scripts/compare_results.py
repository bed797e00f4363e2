#!/usr/bin/python3
"""Compares the CSVs two runs of the experiment drivers wrote (e.g. before and after a refactoring):
columns, measure names, row keys, and the numbers roughly.

  scripts/compare_results.py OLD_DIR NEW_DIR [--rename COLUMN:OLD=NEW ...] [--tolerance X]

For every CSV present in either directory: columns added / removed / reordered; rows (by the file's key columns)
only in one run; for long CSVs the measure names only in one run; and, over the rows in both, the numbers: exact
counts must agree (a relative difference over 1e-9 is listed), times and rates are summarized as the median and the
extremes of new/old. --rename maps a value of the old run to the new one's before comparing (e.g.
backend:eigen_llt=dense_llt). Exit 1 when a schema differs (columns, measures or row keys), else 0. Standard library
only: runs with any python3.
"""
import argparse
import csv
import math
import os
import statistics
import sys

# Key columns per file (the rest are values); files not listed are compared by columns only.
KEYS = {
    "table_2_1.csv": ["model", "system", "build", "backend", "factor_storage", "measure"],
    "scaling.csv": ["series", "level", "model", "system", "build", "backend", "measure"],
    "scaling_fits.csv": ["series", "system", "measure"],
    "table_2_1_thesis.csv": ["model", "stage", "measure"],
    "solvers.csv": ["model", "system", "backend", "ordering", "measure"],
    "frames.csv": ["case", "config"],
    "deform_cases.csv": ["case", "method"],
}
PROVENANCE = {"git_sha", "blas", "blas_core", "blas_coretype_env", "blas_threads", "build_threads",
              "hardware_threads", "cpu", "compiler", "timestamp"}
# Measures / columns that are counts of a deterministic computation: they must agree exactly.
EXACT_HINTS = ("vertices", "faces", "handle", "fixed", "free", "nnz", "_n", "n", "rhs_cols", "frames", "steps",
               "factor_bytes", "matrix_bytes", "held", "predicted_factor_nnz", "points")


def read(path, renames):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
        header = reader.fieldnames or []
    for r in rows:
        for col, old, new in renames:
            if r.get(col) == old:
                r[col] = new
    return header, rows


def is_exact(name):
    return name in ("n", "vertices", "faces") or any(name.startswith(h) or name.endswith(h) for h in EXACT_HINTS
                                                      if h not in ("n", "_n"))


def number(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return None


def compare_numbers(name, old_rows, new_rows, keys, out):
    """Values of the rows in both runs: (measure or column) -> list of (key, old, new)."""
    pairs = {}
    for k, o in old_rows.items():
        n = new_rows.get(k)
        if n is None:
            continue
        if "measure" in keys:
            items = [(o["measure"], o.get("value"), n.get("value"))]
        else:
            items = [(c, o[c], n.get(c)) for c in o if c not in keys and c not in PROVENANCE]
        for m, a, b in items:
            x, y = number(a), number(b)
            if x is None or y is None or math.isnan(x) or math.isnan(y):
                continue
            pairs.setdefault(m, []).append((k, x, y))
    for m, v in sorted(pairs.items()):
        if is_exact(m):
            bad = [(k, x, y) for k, x, y in v if abs(x - y) > 1e-9 * max(abs(x), abs(y), 1e-300)]
            if bad:
                out.append(f"  {name}: {m}: {len(bad)} of {len(v)} exact values differ, e.g. {bad[0]}")
            continue
        ratios = [y / x for _, x, y in v if x > 0 and y > 0]
        if ratios:
            out.append(f"  {name}: {m}: new/old median {statistics.median(ratios):.3g} "
                       f"(range {min(ratios):.3g}-{max(ratios):.3g}, {len(ratios)} values)")


def compare_file(name, old_dir, new_dir, renames, report):
    po, pn = os.path.join(old_dir, name), os.path.join(new_dir, name)
    if not os.path.exists(po) or not os.path.exists(pn):
        report["schema"].append(f"{name}: only in {'new' if os.path.exists(pn) else 'old'} run")
        return
    ho, ro = read(po, renames)
    hn, rn = read(pn, renames)
    if ho != hn:
        added = [c for c in hn if c not in ho]
        removed = [c for c in ho if c not in hn]
        report["schema"].append(f"{name}: columns added {added}, removed {removed}"
                                + ("" if added or removed else " (reordered)"))
    keys = [k for k in KEYS.get(name, []) if k in ho and k in hn]
    if not keys:
        return
    ko = {tuple(r[k] for k in keys): r for r in ro}
    kn = {tuple(r[k] for k in keys): r for r in rn}
    if "measure" in keys:
        mo, mn = {r["measure"] for r in ro}, {r["measure"] for r in rn}
        if mo != mn:
            report["schema"].append(f"{name}: measures only old {sorted(mo - mn)}, only new {sorted(mn - mo)}")
    only_old, only_new = sorted(set(ko) - set(kn)), sorted(set(kn) - set(ko))
    if only_old or only_new:
        report["schema"].append(f"{name}: {len(only_old)} row keys only old (e.g. {only_old[:3]}), "
                                f"{len(only_new)} only new (e.g. {only_new[:3]})")
    report["info"].append(f"{name}: {len(ro)} rows old, {len(rn)} new, {len(set(ko) & set(kn))} keys in both")
    compare_numbers(name, ko, kn, keys, report["numbers"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rename", action="append", default=[], help="COLUMN:OLD=NEW")
    a = ap.parse_args()
    renames = []
    for r in a.rename:
        col, _, rest = r.partition(":")
        old, _, new = rest.partition("=")
        renames.append((col, old, new))
    names = sorted({f for d in (a.old, a.new) for f in os.listdir(d) if f.endswith(".csv")})
    report = {"schema": [], "info": [], "numbers": []}
    for name in names:
        compare_file(name, a.old, a.new, renames, report)
    for section in ("info", "schema", "numbers"):
        print(f"== {section}")
        for line in report[section]:
            print(line)
    return 1 if report["schema"] else 0


if __name__ == "__main__":
    sys.exit(main())
