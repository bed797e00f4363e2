#!/usr/bin/env python3
"""The top fronts' steps on the 2-core development machine: summed wall time, share, flops and rate per thread of
each step (assembly, matrix entries, panel factorization, update matrix, the update's assembly), from the
diagnostic build's timelines in front_steps/ (DEFORMBENCH_THREADS=16 on 2 cores: fronts on teams of one, two at
once, the root on two) and each top supernode's flops and shape (top_flops.txt). Panel flops n^3/3 + (m - n) n^2,
update flops (m - n)(m - n + 1) n, for a front of m rows and n columns.

    /usr/bin/python3 results/records/2026-11-28-head-16-cores/front_steps.py > results/records/2026-11-28-head-16-cores/front_steps.md
"""
import collections
import pathlib

here = pathlib.Path(__file__).parent
fl = {}
for l in open(here / 'top_flops.txt'):
    _, e, T, s, own, w, rows, cols = l.split()
    fl[('e1' if e.endswith('loop1_whole') else 'e2', int(s))] = (float(own), int(rows), int(cols))
def step_flops(what, m, n):
    nr = m - n
    if what == 'front_panels': return n**3 / 3 + nr * n * n
    if what == 'front_update': return nr * (nr + 1) * n
    return 0
print('| edit | run | step | summed wall s | share of the fronts | GFlop | GFlop/s a thread |')
print('|---|---|---|---|---|---|---|')
for tier, stem in (('e1', '104k'), ('e2', '416k')):
    for i in (1, 2):
        agg = collections.defaultdict(lambda: [0.0, 0.0, 0.0])
        for l in open(here / 'front_steps' / f'steps_{stem}_{i}.txt'):
            p = l.split()
            if not p[1].startswith('front_'): continue
            team, s, w = int(p[2]), int(p[3]), float(p[5]) - float(p[4])
            own, m, n = fl[(tier, s)]
            a = agg[p[1]]; a[0] += w; a[1] += step_flops(p[1], m, n); a[2] += w * team
        tot = sum(a[0] for a in agg.values())
        for what in ('front_assemble', 'front_entries', 'front_panels', 'front_update', 'front_assemble_update'):
            w, f, tw = agg[what]
            rate = f'{f / tw / 1e9:.0f}' if f else '-'
            print(f"| {'104k' if tier == 'e1' else '416k'} | {i} | {what} | {w:.3f} | {w / tot:.0%} | {f / 1e9:.1f} | {rate} |")
