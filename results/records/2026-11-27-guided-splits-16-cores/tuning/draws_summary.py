"""Summarizes draws.txt (draws.sh): per pattern and mode, over METIS's draws, the separator columns' flops, their
share, and the heaviest part against the mean of the parts, with the default seed's (-1) values beside."""
import statistics
import sys

rows = {}
for line in open(sys.argv[1]):
    t = line.split()
    key = (t[0], t[t.index("mode") + 1])
    value = lambda name: float(t[t.index(name) + 1])
    rows.setdefault(key, []).append((int(t[t.index("seed") + 1]), value("topfl"), value("topfl") / value("allfl"),
                                     value("partmax/mean"), value("fl")))
print("| pattern | mode | draws | separator flops: median (range) | default seed | separator share: median | "
      "heaviest part / mean: median (range) | default seed | flops: median |")
print("|---|---|---|---|---|---|---|---|---|")
for (pattern, mode), v in sorted(rows.items()):
    col = lambda k: [r[k] for r in v]
    default = next(r for r in v if r[0] == -1)
    print(f"| {pattern} | {mode} | {len(v)} | {statistics.median(col(1)):.3g} ({min(col(1)):.3g}-{max(col(1)):.3g}) "
          f"| {default[1]:.3g} | {statistics.median(col(2)):.3f} | {statistics.median(col(3)):.2f} "
          f"({min(col(3)):.2f}-{max(col(3)):.2f}) | {default[3]:.2f} | {statistics.median(col(4)):.3g} |")
