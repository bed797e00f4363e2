#!/usr/bin/env python3
"""The factorization's top fronts at 16 threads, grouped by their team's size: how many, their flops, their summed
wall time and the rate per thread; then how busy the
phase kept its 16 threads. Joins the diagnostic build's timeline (team/ and team2/timeline.txt: one
`top_front` line per front, its team's size as the level and its supernode as the vertices) with each top
supernode's own flops (top_flops.txt, from exp_tree_parallelism with top_flops.patch).

    /usr/bin/python3 results/records/2026-11-28-head-16-cores/top_rates.py > results/records/2026-11-28-head-16-cores/top_rates.md
"""
import collections
import pathlib

here = pathlib.Path(__file__).parent
tiers = {"armadillo_loop1_whole": "e1", "armadillo_loop2_whole": "e2"}
names = {"e1": "104k", "e2": "416k"}
flops = {}
for line in (here / "top_flops.txt").read_text().splitlines():
    _, edit, _, s, own, _, rows, cols = line.split()
    flops[(tiers[edit], int(s))] = (float(own), int(rows))

print("| call | edit | team size | fronts | rows (median) | GFlop | summed wall s | GFlop/s per thread |")
print("|---|---|---|---|---|---|---|---|")
for call in ("team", "team2"):
    tier, agg = None, collections.defaultdict(list)
    for line in (here / call / "timeline.txt").read_text().splitlines():
        if line.startswith("#"):
            tier = line.split()[1].rstrip(",")
            continue
        f = line.split()
        if f[1] != "top_front":
            continue
        team, s, start, end = int(f[2]), int(f[3]), float(f[4]), float(f[5])
        agg[(tier, team)].append((flops[(tier, s)], end - start))
    for (tier, team), fronts in sorted(agg.items()):
        gf = sum(own for (own, _), _ in fronts) / 1e9
        wall = sum(w for _, w in fronts)
        rows = sorted(r for (_, r), _ in fronts)[len(fronts) // 2]
        cells = [call, names[tier], team, len(fronts), rows, f"{gf:.1f}", f"{wall:.3f}", f"{gf / wall / team:.0f}"]
        print("| " + " | ".join(str(c) for c in cells) + " |")

print()
print("| call | edit | top phase s | fronts' thread-seconds (wall x team) | of the phase's 16 threads |")
print("|---|---|---|---|---|")
for call in ("team", "team2"):
    tier, phase, busy = None, {}, collections.Counter()
    for line in (here / call / "timeline.txt").read_text().splitlines():
        if line.startswith("#"):
            tier = line.split()[1].rstrip(",")
            continue
        f = line.split()
        if f[1] == "top_phase":
            phase[tier] = float(f[5]) - float(f[4])
        elif f[1] == "top_front":
            busy[tier] += int(f[2]) * (float(f[5]) - float(f[4]))
    for tier in sorted(phase):
        share = busy[tier] / (16 * phase[tier])
        print(f"| {call} | {names[tier]} | {phase[tier]:.3f} | {busy[tier]:.2f} | {share:.0%} |")
