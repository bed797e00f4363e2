"""The record the gate compares: one run of a suite, its provenance and its values by (cell, measure) and round.

A record is read from a history CSV of the tracking suite (experiments/track.cpp: one row per cell, measure and
round) or from a Google Benchmark JSON of bench_phases (converted row by row by gbench.py): both become the same
rows, so one set of rules (gate.py) compares them.
"""
import copy
import csv
import math
from dataclasses import dataclass, field

REQUIRED = ("commit", "date", "machine_id", "cell", "measure", "class", "rate", "value", "repeat",
            "blas_dgemm_before", "blas_dgemm_after", "memory_read_before", "memory_read_after")
# Provenance columns, read from the first row: every row of a record carries the same.
PROVENANCE = ("commit", "date", "machine_id", "git_sha", "overrides", "machine_cpu", "machine_cores",
              "machine_ram_gib", "machine_blas_core", "machine_threads", "build_type", "suite")


class InputError(Exception):
    """An unreadable record: exit 2."""


def number(text):
    try:
        return float(text) if text not in ("", None) else math.nan
    except ValueError:
        return math.nan


@dataclass
class History:
    """One run of a suite: its metadata and its rows, keyed for the gate."""
    path: str
    meta: dict
    values: dict = field(default_factory=dict)   # (cell, measure) -> {repeat: value}
    classes: dict = field(default_factory=dict)  # (cell, measure) -> (class, rate)
    rates: dict = field(default_factory=dict)    # (cell, repeat) -> {"dgemm": GFlop/s, "read": GB/s}
    failed: dict = field(default_factory=dict)   # cell -> message
    specs: dict = field(default_factory=dict)    # cell -> its definition ("key=value ..."; "" when not recorded)
    runs: int = 1                                # history files joined into this record (pooled)

    @staticmethod
    def from_rows(rows, path="<rows>"):
        if not rows:
            raise InputError(f"{path}: no rows")
        missing = [c for c in REQUIRED if c not in rows[0]]
        if missing:
            raise InputError(f"{path}: not a tracking record (no column {', '.join(missing)})")
        h = History(path, {k: rows[0].get(k) or "" for k in PROVENANCE})
        for r in rows:
            h._add(r)
        return h

    def _add(self, r):
        cell, measure = r["cell"], r["measure"]
        self.specs.setdefault(cell, r.get("spec") or "")
        if r["class"] == "status":
            self.failed[cell] = r.get("message") or "failed"
            return
        try:
            repeat = int(r["repeat"])
        except ValueError:
            raise InputError(f"{self.path}: {cell} {measure}: repeat '{r['repeat']}' is not a number")
        self.values.setdefault((cell, measure), {})[repeat] = number(r["value"])
        self.classes[(cell, measure)] = (r["class"], r["rate"])
        dgemm = (number(r["blas_dgemm_before"]) + number(r["blas_dgemm_after"])) / 2
        read = (number(r["memory_read_before"]) + number(r["memory_read_after"])) / 2
        self.rates[(cell, repeat)] = {"dgemm": dgemm, "read": read}

    @property
    def cells(self):
        return {c for c, _ in self.values} | set(self.failed)

    @property
    def dirty(self):
        return self.meta.get("git_sha", "").endswith("+dirty")


def pooled_round(k, r):
    """Round r of the k-th (from 0) of several runs pooled into one record: rounds of different runs stay apart,
    each with its own drift (gate.round_drift)."""
    return 1000 * k + r


def run_of(r):
    """The run (from 0) of a pooled record that round r came from (pooled_round's inverse)."""
    return r // 1000


def pooled(hs):
    """One record of the runs `hs` (of one commit, one machine), their rounds side by side (pooled_round): what
    `./run track` gates on each side when it has several runs (--runs, --baseline-runs), and power.py measures."""
    out = copy.deepcopy(hs[0])
    for k, h in enumerate(hs[1:], 1):
        for key, runs in h.values.items():
            out.values.setdefault(key, {}).update({pooled_round(k, r): v for r, v in runs.items()})
        out.rates.update({(c, pooled_round(k, r)): v for (c, r), v in h.rates.items()})
        out.failed.update(h.failed)
        out.runs += h.runs
    if len(hs) > 1:
        out.path = f"{hs[0].path} and {len(hs) - 1} more, pooled"
    return out


def load_runs(paths):
    """The record of one history file, or of a list of them (runs of one commit) pooled."""
    if not isinstance(paths, (list, tuple)):
        return load_history(paths)
    return pooled([load_history(p) for p in paths])


def load_history(path):
    """The record at `path`: a Google Benchmark JSON (*.json) or a tracking history CSV."""
    path = str(path)
    try:
        if path.endswith(".json"):
            from . import gbench
            return History.from_rows(gbench.rows(path), path)
        with open(path, newline="") as f:
            return History.from_rows(list(csv.DictReader(f)), path)
    except OSError as e:
        raise InputError(f"{path}: {e.strerror}")
    except (csv.Error, UnicodeDecodeError) as e:
        raise InputError(f"{path}: not a CSV file ({e})")
