#!/usr/bin/env python3
"""Tabulates parts.txt: per pattern, levels and orderer of the parts, nnz(L) and flops against METIS_NodeND's parts
under the same splits (same seed), and the parts' slowest and summed ordering seconds. Usage: parts_summary.py FILE"""
import collections
import statistics
import sys

runs = []
for line in open(sys.argv[1]):
    w = line.split()
    kv = dict(zip(w[2::2], w[3::2]))
    runs.append((w[0], w[1], int(kv["levels"]), int(kv["seed"]), float(kv["parts_max"]), float(kv["parts_sum"]),
                 float(kv["lnz"]), float(kv["flops"])))
base = {(g, L, s): (lnz, fl) for g, k, L, s, _, _, lnz, fl in runs if k == "nodend"}
rows = collections.defaultdict(list)
for g, k, L, s, tmax, tsum, lnz, fl in runs:
    b = base[(g, L, s)]
    rows[(g, L, k)].append((tmax, tsum, lnz / b[0], fl / b[1]))
print("| pattern | levels | parts ordered by | draws | slowest part s (median) | parts' sum s (median) "
      "| nnz(L) / NodeND parts' (range) | flops / NodeND parts' (range) |")
print("|---|---|---|---|---|---|---|---|")
for (g, L, k), r in rows.items():
    med = lambda i: statistics.median(x[i] for x in r)
    rng = lambda i: f"{min(x[i] for x in r):.3f}-{max(x[i] for x in r):.3f}"
    name = "METIS_NodeND" if k == "nodend" else f"SCOTCH {k}"
    print(f"| {g[1:]}k | {L} | {name} | {len(r)} | {med(0):.3f} | {med(1):.3f} | {rng(2)} | {rng(3)} |")
