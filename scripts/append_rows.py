#!/usr/bin/env python3
"""Appends the rows of a CSV file to another, each with leading columns NAME=VALUE; the header goes in only when
the target is new or empty. For the run scripts of dated records (results/records/*/run.sh), which tag each row a
driver wrote (its provenance kept whole) with the binary, round or state that produced it.

usage: scripts/append_rows.py SOURCE TARGET NAME=VALUE ...
"""
import csv
import os
import sys


def main(argv):
    if len(argv) < 3 or any("=" not in a for a in argv[2:]):
        sys.exit(__doc__.strip().splitlines()[-1])
    source, target, tags = argv[0], argv[1], [a.split("=", 1) for a in argv[2:]]
    with open(source, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"append_rows: {source} has no rows")
    new = not os.path.exists(target) or os.path.getsize(target) == 0
    with open(target, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=[k for k, _ in tags] + list(rows[0].keys()))
        if new:
            w.writeheader()
        for r in rows:
            w.writerow({**dict(tags), **r})


if __name__ == "__main__":
    main(sys.argv[1:])
