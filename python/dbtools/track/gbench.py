"""bench_phases' Google Benchmark JSON as tracking records, so that the one gate (gate.py) compares it.

Each benchmark is a cell (its name, the join key: `factorize/mesh:hand/system:lap/build:structured/backend:umfpack`),
each repetition a round:
  cpu_s    gbench's cpu_time of the repetition (a mean over its iterations), class `cpu`: the CPU-time rule
  wall_s   gbench's real_time, class `time` without machine rates: reported, gated only with --gate-wall
  n, nnz, nnz_L, bytes   the counters, class `deterministic` (from the first repetition; every repetition of a
           benchmark computes the same): compared exactly
A benchmark that errored is a failed cell. Aggregates (mean, median, ...) are left out: the rules take the
repetitions. The provenance comes from the run's context (core/provenance.h's `deformbench_*` keys): the machine
id is the hash of its CPU, cores, BLAS core and thread counts (not exp_track's id, which also hashes the RAM);
`suite` joins the binary's `deformbench_suite_version` with `deformbench_suite` (the hash of every benchmark the
options register, whatever a filter ran), which the runner (bench.py) passes in.
"""
import json
import math

from .history import InputError

UNIT = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
COUNTERS = ("n", "nnz", "nnz_L", "bytes")
CONTEXT = ("deformbench_git_sha", "deformbench_cpu", "deformbench_blas_core", "deformbench_hardware_threads",
           "deformbench_blas_threads", "deformbench_build_threads")


def fnv(text):
    """FNV-1a, 48 bits as 12 hex digits (the shape of exp_track's machine id)."""
    h = 1469598103934665603
    for c in text.encode():
        h = ((h ^ c) * 1099511628211) % 2 ** 64
    return f"{h >> 16:012x}"


def suite_hash(names):
    """The definition of a suite of benchmarks as one short string: the hash of its sorted names and their count."""
    names = sorted(set(names))
    return f"{fnv(chr(10).join(names))} ({len(names)} benchmarks)"


def _context(doc, path):
    ctx = doc.get("context") if isinstance(doc, dict) else None
    if not isinstance(ctx, dict) or not isinstance(doc.get("benchmarks"), list):
        raise InputError(f"{path}: not a Google Benchmark JSON (no context or benchmarks)")
    missing = [k for k in CONTEXT if k not in ctx]
    if missing:
        raise InputError(f"{path}: no provenance in its context (no {', '.join(missing)}): not a bench_phases run")
    return ctx


def meta(ctx):
    """The provenance columns of every row."""
    parts = {"machine_cpu": ctx["deformbench_cpu"], "machine_cores": ctx["deformbench_hardware_threads"],
             "machine_blas_core": ctx["deformbench_blas_core"],
             "machine_threads": f"{ctx['deformbench_blas_threads']}/{ctx['deformbench_build_threads']}"}
    version, names = ctx.get("deformbench_suite_version", ""), ctx.get("deformbench_suite", "")
    suite = f"bench_phases v{version or '?'}, {names or 'benchmark list not recorded'}" if version or names else ""
    return {"commit": ctx["deformbench_git_sha"], "git_sha": ctx["deformbench_git_sha"],
            "date": ctx.get("deformbench_timestamp", ctx.get("date", "")),
            "machine_id": fnv("".join(f"{k}={v};" for k, v in parts.items())), **parts,
            "build_type": ctx.get("deformbench_build_type", ""), "suite": suite, "overrides": ""}


def _seconds(b, clock, path):
    t, unit = b.get(clock), b.get("time_unit", "ns")
    if not isinstance(t, (int, float)) or not math.isfinite(t) or t < 0 or unit not in UNIT:
        raise InputError(f"{path}: {b.get('name')}: {clock} {t!r} {unit!r} is not a time")
    return t * UNIT[unit]


def _row(m, cell, measure, cls, value, repeat, message=""):
    return {**m, "cell": cell, "measure": measure, "class": cls, "rate": "", "value": "" if value is None else
            repr(float(value)), "repeat": str(repeat), "blas_dgemm_before": "", "blas_dgemm_after": "",
            "memory_read_before": "", "memory_read_after": "", "spec": "", "message": message}


def rows_of(doc, path="<json>"):
    """The tracking rows of a parsed bench_phases JSON."""
    m = meta(_context(doc, path))
    out, seen = [], {}
    for b in doc["benchmarks"]:
        if not isinstance(b, dict) or "name" not in b:
            raise InputError(f"{path}: a benchmark entry without a name")
        cell = b.get("run_name", b["name"])
        if b.get("error_occurred"):
            out.append(_row(m, cell, "status", "status", None, 1, b.get("error_message") or "error"))
            continue
        if b.get("run_type") == "aggregate":
            continue
        repeat = seen[cell] = seen.get(cell, 0) + 1
        out.append(_row(m, cell, "cpu_s", "cpu", _seconds(b, "cpu_time", path), repeat))
        out.append(_row(m, cell, "wall_s", "time", _seconds(b, "real_time", path), repeat))
        if repeat == 1:
            out += [_row(m, cell, k, "deterministic", b[k], 1) for k in COUNTERS if isinstance(b.get(k), (int, float))]
    if not out:
        raise InputError(f"{path}: no benchmark ran")
    return out


def rows(path):
    try:
        with open(path) as f:
            doc = json.load(f)
    except json.JSONDecodeError as e:
        raise InputError(f"{path}: not JSON ({e})")
    return rows_of(doc, path)
