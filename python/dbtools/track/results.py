"""Two runs of the experiment drivers compared by the gate's rules (e.g. before and after a refactoring, or a
sharded run against the whole): their result CSVs read as records.

  python3 -m dbtools.track.results OLD_DIR NEW_DIR [--rename COLUMN:OLD=NEW ...] [--all]

The schema first: for every CSV in either directory, columns added, removed or reordered; for the files of KEYS
(their key columns), row keys and (long tables) measure names only in one run. Then the numbers of the rows in both:
each row key is a cell (`FILE:key/values`), each value a measure (long tables: the `measure` column's name; wide
ones: each value column); exact counts (is_exact: vertices, n, nnz, factor and matrix bytes, frames, ...) are class
deterministic, compared exactly (gate.py: any change reported, an increase over 0.5% fails); every other number is
class info, its new/old ratio summarized per measure (median and range), never gated: times of two runs move with
the machine. Provenance columns (git sha, BLAS, CPU, timestamp) are left out. --rename maps a value of the old run
to the new one's before comparing (e.g. backend:eigen_llt=dense_llt).
Exit: 0 the same schema and no deterministic increase, 1 otherwise (or usage), 2 unreadable directory or file.
"""
import argparse
import csv
import os
import statistics
import sys

from . import gate as g
from . import report
from .history import History, InputError

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
# Measures / columns that count what a deterministic computation made: compared exactly. Rates, ratios, times and
# measured memory (RSS) are not: "handle" counts vertices, "fps_handle" is a rate.
EXACT = {"n", "nnz", "nnz_factor", "vertices", "faces", "handle", "fixed", "free", "frames", "steps", "rhs_cols",
         "points", "factor_flops"}


def is_exact(name):
    if name in EXACT or name.endswith("_reps") or name.startswith("held_bytes:"):
        return True
    if "rss" in name:
        return False
    return name.endswith("_bytes") or name.startswith("predicted_") and not name.endswith("_s")


def read(path, renames):
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            rows, header = list(reader), reader.fieldnames or []
    except (OSError, csv.Error, UnicodeDecodeError) as e:
        raise InputError(f"{path}: {e}")
    for r in rows:
        for col, old, new in renames:
            if r.get(col) == old:
                r[col] = new
    return header, rows


def record_rows(name, rows, keys):
    """The gate's rows of one file's `rows`: a cell per row key, a measure per number."""
    out, seen = [], {}
    for r in rows:
        cell = f"{name}:" + "/".join(r[k] for k in keys if k != "measure")
        items = [(r["measure"], r.get("value"))] if "measure" in keys else \
            [(c, v) for c, v in r.items() if c not in keys and c not in PROVENANCE]
        for measure, value in items:
            try:
                float(value)
            except (TypeError, ValueError):
                continue  # a label or a status: the schema check covers it
            repeat = seen[(cell, measure)] = seen.get((cell, measure), 0) + 1
            out.append({"commit": "", "date": "", "machine_id": "", "cell": cell, "measure": measure,
                        "class": "deterministic" if is_exact(measure) else "info", "rate": "", "value": value,
                        "repeat": str(repeat), "blas_dgemm_before": "", "blas_dgemm_after": "",
                        "memory_read_before": "", "memory_read_after": ""})
    return out


def schema(name, old, new, keys):
    """The schema differences of one file (both runs have it)."""
    (ho, ro), (hn, rn) = old, new
    out = []
    if ho != hn:
        added, removed = [c for c in hn if c not in ho], [c for c in ho if c not in hn]
        out.append(f"{name}: columns added {added}, removed {removed}" + ("" if added or removed else " (reordered)"))
    if not keys:
        return out
    ko, kn = ({tuple(r[k] for k in keys) for r in rows} for rows in (ro, rn))
    if "measure" in keys:
        mo, mn = {r["measure"] for r in ro}, {r["measure"] for r in rn}
        if mo != mn:
            out.append(f"{name}: measures only old {sorted(mo - mn)}, only new {sorted(mn - mo)}")
    only_old, only_new = sorted(ko - kn), sorted(kn - ko)
    if only_old or only_new:
        out.append(f"{name}: {len(only_old)} row keys only old (e.g. {only_old[:3]}), {len(only_new)} only new "
                   f"(e.g. {only_new[:3]})")
    return out


def ratios(cmps):
    """Per info measure: the new/old ratios over the cells both runs have, summarized."""
    by = {}
    for c in cmps:
        if c.cls == "info" and c.base > 0 and c.now > 0:
            by.setdefault(c.measure, []).append(c.now / c.base)
    return [f"{m}: new/old median {statistics.median(v):.3g} (range {min(v):.3g}-{max(v):.3g}, {len(v)} values)"
            for m, v in sorted(by.items())]


def compare_dirs(old_dir, new_dir, renames):
    """(schema differences, the records of both runs)."""
    try:
        names = sorted({f for d in (old_dir, new_dir) for f in os.listdir(d) if f.endswith(".csv")})
    except OSError as e:
        raise InputError(f"{e.filename}: {e.strerror}")
    problems, rows = [], ([], [])
    for name in names:
        po, pn = os.path.join(old_dir, name), os.path.join(new_dir, name)
        if not (os.path.exists(po) and os.path.exists(pn)):
            problems.append(f"{name}: only in the {'new' if os.path.exists(pn) else 'old'} run")
            continue
        old, new = read(po, renames), read(pn, renames)
        keys = [k for k in KEYS.get(name, []) if k in old[0] and k in new[0]]
        problems += schema(name, old, new, keys)
        if keys:
            rows[0].extend(record_rows(name, old[1], keys))
            rows[1].extend(record_rows(name, new[1], keys))
    if not rows[0] or not rows[1]:
        raise InputError(f"no numbers of a known result file ({', '.join(KEYS)}) in both runs")
    return problems, History.from_rows(rows[0], old_dir), History.from_rows(rows[1], new_dir)


def main(argv=None):
    ap = g.UsageParser(prog="python3 -m dbtools.track.results", description=__doc__.split("\n")[0],
                       allow_abbrev=False, formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="\n".join(__doc__.split("\n")[2:]))
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rename", action="append", default=[], help="COLUMN:OLD=NEW")
    ap.add_argument("--all", action="store_true", help="print every comparison")
    a = ap.parse_args(sys.argv[1:] if argv is None else argv)
    renames = []
    for r in a.rename:
        col, _, rest = r.partition(":")
        old, eq, new = rest.partition("=")
        if not (col and old and eq):
            ap.error(f"--rename {r}: not COLUMN:OLD=NEW")
        renames.append((col, old, new))
    try:
        problems, base, now = compare_dirs(a.old, a.new, renames)
    except InputError as e:
        print(f"results: error: {e}", file=sys.stderr)
        return 2
    # Rows of one run only are schema differences, listed above: the gate compares the rows of both.
    cmps = [c for c in g.compare(base, now, g.Settings(), same_machine=True) if c.verdict not in ("new", "not run")]
    report.print_report(base, now, cmps, g.Settings(), a.all, [*ratios(cmps), *(f"schema: {p}" for p in problems)])
    if problems:
        print(f"results: the schema differs ({len(problems)} difference(s))")
    return 1 if problems or any(c.verdict == "FAIL" for c in cmps) else 0


if __name__ == "__main__":
    sys.exit(main())
