#!/usr/bin/env python3
"""Flops of each kind of dense call of the multifrontal factorization, from the supernodes' sizes (the file a build
with supernodes.patch writes: one "rows columns" line per supernode). The calls are front.cpp's: factor panels of
256 columns (FactorBlock::kWidth) and update panels of 128 columns (UpdateBlock::kWidth).
usage: DB_DUMP_SUPERNODES=S.txt DIAG deform ...; flops_by_call.py S.txt"""
import sys

W, WU = 256, 128  # FactorBlock::kWidth, UpdateBlock::kWidth
flops = dict.fromkeys(["earlier panels (dsyrk, dgemm)", "dpotrf", "dtrsm", "update matrix dsyrk",
                       "update matrix dgemm"], 0.0)
for line in open(sys.argv[1]):
    m, k = map(int, line.split())
    nr = m - k
    for q0 in range(0, k, W):  # factor_panels: panel q0 of width w, h rows below its diagonal block
        w = min(W, k - q0)
        h = m - q0 - w
        flops["dpotrf"] += w ** 3 / 3
        flops["dtrsm"] += h * w * w
        flops["earlier panels (dsyrk, dgemm)"] += q0 * (w * w + 2 * h * w)
    for u0 in range(0, nr, WU):  # form_update: update panel u0 of width wu, rows below its diagonal block
        wu = min(WU, nr - u0)
        flops["update matrix dsyrk"] += wu * wu * k
        flops["update matrix dgemm"] += 2 * (nr - u0 - wu) * wu * k
for name, f in flops.items():
    print(f"{name}: {f / 1e9:.2f} GFlop")
print(f"total: {sum(flops.values()) / 1e9:.2f} GFlop")
