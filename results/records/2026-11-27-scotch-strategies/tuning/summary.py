#!/usr/bin/env python3
"""Tabulates study.csv: per pattern and orderer, the median time (min-max) and nnz(L) and flops against
METIS_NodeND's mean over the same seeds (mean and range over the draws). Usage: summary.py study.csv"""
import csv
import statistics
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
print("| pattern | orderer | draws | time s, median (min-max) | nnz(L) / METIS's mean (range) | flops / METIS's mean (range) |")
print("|---|---|---|---|---|---|")
for g in dict.fromkeys(r["pattern"] for r in rows):
    mine = [r for r in rows if r["pattern"] == g]
    base = [r for r in mine if r["orderer"] == "metis"]
    lnz0 = statistics.mean(float(r["nnz_l"]) for r in base)
    fl0 = statistics.mean(float(r["flops"]) for r in base)
    for k in dict.fromkeys(r["strategy"] for r in mine):
        rs = [r for r in mine if r["strategy"] == k]
        t = [float(r["time_s"]) for r in rs]
        a = [float(r["nnz_l"]) / lnz0 for r in rs]
        f = [float(r["flops"]) / fl0 for r in rs]
        name = "METIS_NodeND" if k == "NodeND" else f"SCOTCH {k}"
        print(f"| {g[1:]}k | {name} | {len(rs)} | {statistics.median(t):.3f} ({min(t):.3f}-{max(t):.3f}) "
              f"| {statistics.mean(a):.3f} ({min(a):.3f}-{max(a):.3f}) | {statistics.mean(f):.3f} ({min(f):.3f}-{max(f):.3f}) |")
