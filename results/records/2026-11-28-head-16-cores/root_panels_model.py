#!/usr/bin/env python3
"""Counts, for the root front of the 16-thread plans (m = n = 3480 rows at 104k, 5526 at 416k: top_flops.txt), how
long its panel step takes on a team when every BLAS call runs at one rate: per panel, the left-looking tiles
(the diagonal block's dsyrk and 128-row tiles of the rectangle's dgemm, each over every earlier panel of 256
columns), claimed in tile order by whichever thread is free, then the panel's dpotrf on one thread and its dtrsm
tiles. In units of one thread's flops; `even` spreads every tile's flops over the team. `split`: the rectangle's
tiles also cut into columns of 128, and the diagonal block into its three 128 x 128 parts.

    /usr/bin/python3 results/records/2026-11-28-head-16-cores/root_panels_model.py
"""
import heapq

K, TILE = 256, 128


def pieces(n, step):
    return [min(step, n - k) for k in range(0, n, step)]


def makespan(costs, threads):
    free = [0.0] * threads
    for c in costs:
        heapq.heappush(free, heapq.heappop(free) + c)
    return max(free)


def panels(m, n, threads, split):
    total = even = 0.0
    for q in range((n + K - 1) // K):
        w = min(K, n - q * K)
        h = m - q * K - w
        rows = pieces(h, TILE)
        cols = pieces(w, TILE) if split else [w]
        if q > 0:
            if split and len(cols) == 2:
                diag = [q * cols[0] ** 2 * K, q * 2 * cols[0] * cols[1] * K, q * cols[1] ** 2 * K]
            else:
                diag = [q * w * w * K]
            costs = diag + [q * 2 * r * c * K for r in rows for c in cols]
            total += makespan(costs, threads)
            even += sum(costs) / threads
        trsm = [r * w * w for r in rows]
        total += w**3 / 3 + (makespan(trsm, threads) if trsm else 0.0)
        even += w**3 / 3 + sum(trsm) / threads
    return total, even


print("| root front | threads | tiles as now / even | cut into columns too / even |")
print("|---|---|---|---|")
for name, m in (("104k (3480 rows)", 3480), ("416k (5526 rows)", 5526)):
    for threads in (16, 8):
        now, even = panels(m, m, threads, False)
        cut, _ = panels(m, m, threads, True)
        print(f"| {name} | {threads} | {now / even:.2f} | {cut / even:.2f} |")
