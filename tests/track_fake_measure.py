#!/usr/bin/python3
"""A stand-in for building and running exp_track, for the tests of dbtools.track (driver.py) (DEFORMBENCH_TRACK_MEASURE):
the "suite" of a commit is its file measure.txt (lines `MEASURE=VALUE`), written as a history of one cell.

  track_fake_measure.py machine-id                    prints the machine id (fake-machine)
  track_fake_measure.py cells ONLY                    prints the suite's cell names
  track_fake_measure.py measure SRC OUT COMMIT ONLY   writes the history of the tree at SRC to OUT

Time measures (names ending in _s) get five runs with a fixed +-3% spread, as CPU times (the class the gate
compares); the others are deterministic, once.
"""
import csv
import datetime
import os
import sys

CELL = "fake/cell"
SPREAD = [1.0, 1.03, 0.97, 1.01, 0.99]


def measure(src, out, commit):
    values = {}
    with open(f"{src}/measure.txt") as f:
        for line in f:
            if "=" in line:
                k, v = line.strip().split("=", 1)
                values[k] = float(v)
    sha = os.environ["DEFORMBENCH_GIT_SHA"]  # set by the driver: the short sha, "+dirty" for local changes
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%S.%fZ")
    rows = []
    for k, v in values.items():
        timed = k.endswith("_s")
        for i, f in enumerate(SPREAD if timed else [1.0]):
            rows.append({"commit": commit, "date": date, "machine_id": "fake-machine",
                         "cell": CELL, "kind": "fake", "tier": "fake", "measure": k,
                         "class": "cpu" if timed else "deterministic", "rate": "",
                         "value": repr(v * f), "unit": "", "repeat": str(i + 1), "blas_dgemm_before": "10",
                         "blas_dgemm_after": "10", "memory_read_before": "10", "memory_read_after": "10",
                         "load_avg_1m": "0", "spec": "kind=fake", "overrides": "", "message": "", "git_sha": sha})
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def main(argv):
    if argv[0] == "machine-id":
        print("fake-machine")
    elif argv[0] == "cells":
        print(CELL)
    elif argv[0] == "measure":
        measure(argv[1], argv[2], argv[3])
    else:
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
