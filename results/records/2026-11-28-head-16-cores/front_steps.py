#!/usr/bin/env python3
"""The top fronts' steps: summed wall time, share, flops and rate per thread of each step (assembly, matrix entries,
panel factorization, update matrix, the update's assembly), by team size, from the diagnostic build's timelines and
each top supernode's flops and shape in the 8- and 16-thread plans (top_flops.txt). Panel flops n^3/3 + (m - n) n^2,
update flops (m - n)(m - n + 1) n, for a front of m rows and n columns; a step's rate per thread is its flops over
its wall time times its team's size.

- front_steps/: the 2-core development machine, DEFORMBENCH_THREADS=16 (fronts on teams of one, two at once, the
  root on two), two runs per edit, one file per run;
- front_steps_16/steps.txt: the 16-core device, 16 and 8 threads, two runs each, one "# eK, T threads, run i" block
  per run.

    /usr/bin/python3 results/records/2026-11-28-head-16-cores/front_steps.py > results/records/2026-11-28-head-16-cores/front_steps.md
"""
import collections
import pathlib

here = pathlib.Path(__file__).parent
STEPS = ("front_assemble", "front_entries", "front_panels", "front_update", "front_assemble_update")
NAMES = {"e1": "104k", "e2": "416k"}
flops = {}
for line in (here / "top_flops.txt").read_text().splitlines():
    _, edit, T, s, own, _, rows, cols = line.split()
    flops[("e1" if edit.endswith("loop1_whole") else "e2", int(T), int(s))] = (int(rows), int(cols))


def step_flops(what, m, n):
    nr = m - n
    return {"front_panels": n**3 / 3 + nr * n * n, "front_update": nr * (nr + 1) * n}.get(what, 0.0)


def runs():
    """(machine, edit, threads, lines) per run."""
    for i, tier in ((1, "e1"), (2, "e1"), (1, "e2"), (2, "e2")):
        stem = NAMES[tier]
        yield "2 cores", tier, 16, (here / "front_steps" / f"steps_{stem}_{i}.txt").read_text().splitlines()
    block = None
    for line in (here / "front_steps_16" / "steps.txt").read_text().splitlines():
        if line.startswith("#"):
            if block:
                yield block
            tier, T = line.split()[1].rstrip(","), int(line.split()[2])
            block = ("16 cores", tier, T, [])
        else:
            block[3].append(line)
    if block:
        yield block


agg = collections.defaultdict(lambda: [0.0, 0.0, 0.0, 0])  # wall, flops, thread-seconds, runs
for machine, tier, T, lines in runs():
    seen = set()
    for line in lines:
        f = line.split()
        if f[1] not in STEPS:
            continue
        team, s, wall = int(f[2]), int(f[3]), float(f[5]) - float(f[4])
        m, n = flops[(tier, T, s)]
        key = (machine, tier, T, "1" if team == 1 else "2-7" if team < 8 else str(team), f[1])
        a = agg[key]
        a[0] += wall
        a[1] += step_flops(f[1], m, n)
        a[2] += wall * team
        seen.add(key)
    for key in seen:
        agg[key][3] += 1

print("Per run (the sums over the runs divided by their number). Team: the front's team size.\n")
print("| machine | edit | T | team | step | wall s | share of the team's steps | GFlop | GFlop/s a thread |")
print("|---|---|---|---|---|---|---|---|---|")
groups = sorted({k[:4] for k in agg}, key=lambda k: (k[0], k[1], -k[2], len(k[3]), k[3]))
for g in groups:
    total = sum(agg[g + (w,)][0] for w in STEPS if g + (w,) in agg)
    for w in STEPS:
        if g + (w,) not in agg:
            continue
        wall, fl, ts, n = agg[g + (w,)]
        rate = f"{fl / ts / 1e9:.0f}" if fl else "-"
        cells = [g[0], NAMES[g[1]], g[2], g[3], w, f"{wall / n:.3f}", f"{wall / total:.0%}", f"{fl / n / 1e9:.1f}", rate]
        print("| " + " | ".join(str(c) for c in cells) + " |")
