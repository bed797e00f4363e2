# The seeds study's summary (tuning/study.sh): per graph and dissection levels, over the seeds 1..N, the splits'
# median seconds and the ratios of the 1-ring (guided) splits' nnz(L) and flops to the 2-ring splits' (of their
# means and of their medians), each mode's flops range; then the draw of METIS's default seed (-1, the one the
# project's runs get) in each mode, with its rank among that mode's seeded draws (1: the fewest flops).
# usage: summary.py STUDY_TXT > study.md
import collections
import statistics as st
import sys

draws = collections.defaultdict(dict)  # (graph, levels, mode) -> seed -> (split s, lnz, flops)
for line in open(sys.argv[1]):
    t = line.split()
    if len(t) >= 13 and t[1] == "L":
        draws[(t[0], int(t[2]), t[6])][int(t[4])] = (float(t[8]), float(t[10]), float(t[12]))


def seeded(key):
    return [v for s, v in sorted(draws.get(key, {}).items()) if s >= 1]


def default(key):
    """The default seed's flops and its rank among the seeded draws, or a dash."""
    d = draws.get(key, {}).get(-1)
    if d is None:
        return "-"
    rank = 1 + sum(1 for v in seeded(key) if v[2] < d[2])
    return f"{d[2]:.4g} ({rank} of {len(seeded(key)) + 1})"


print("| graph | levels | seeds | 2-ring split s (median) | 1-ring split s (median) | nnz ratio of means | flops ratio of"
      " means | nnz ratio of medians | flops ratio of medians | 2-ring flops range | 1-ring flops range | default seed:"
      " 2-ring flops (rank) | default seed: 1-ring flops (rank) |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for g, L in sorted({k[:2] for k in draws}):
    a, b = seeded((g, L, "ring2")), seeded((g, L, "ring1"))
    n = min(len(a), len(b))
    if n == 0:
        continue
    a, b = a[:n], b[:n]

    def ratio(i, f):
        return f([r[i] for r in b]) / f([r[i] for r in a])

    def med(x, i):
        return st.median([r[i] for r in x])

    def span(x):
        return f"{min(r[2] for r in x):.4g}-{max(r[2] for r in x):.4g}"

    print(f"| {g} | {L} | {n} | {med(a, 0):.3f} | {med(b, 0):.3f} | {ratio(1, st.mean):.4f} | {ratio(2, st.mean):.4f} | "
          f"{ratio(1, st.median):.4f} | {ratio(2, st.median):.4f} | {span(a)} | {span(b)} | "
          f"{default((g, L, 'ring2'))} | {default((g, L, 'ring1'))} |")
