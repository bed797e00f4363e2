"""Summarizes balance.txt (balance.sh): per pattern and ufactor of the deeper splits, over METIS's draws, the
vertex-level flops (mean, and against ufactor 200's mean), the heaviest part against the parts' mean, and the
slowest and summed METIS_NodeND seconds of the parts (one process, one thread)."""
import statistics
import sys

rows = {}
for line in open(sys.argv[1]):
    t = line.split()
    value = lambda name: float(t[t.index(name) + 1])
    rows.setdefault((t[0], int(value("uf2"))), []).append(
        (value("fl"), value("partmax/mean"), value("ndmax"), value("ndsum")))
print("| pattern | ufactor below the first split | draws | flops: mean | against 200 | heaviest part / mean: median "
      "(range) | slowest part s: median (range) | parts' sum s: median |")
print("|---|---|---|---|---|---|---|---|")
for (pattern, uf), v in sorted(rows.items(), key=lambda kv: (kv[0][0], -kv[0][1])):
    col = lambda k: [r[k] for r in v]
    base = statistics.mean(r[0] for r in rows[(pattern, 200)])
    print(f"| {pattern} | {uf} | {len(v)} | {statistics.mean(col(0)):.4g} | {statistics.mean(col(0)) / base:.3f} | "
          f"{statistics.median(col(1)):.2f} ({min(col(1)):.2f}-{max(col(1)):.2f}) | "
          f"{statistics.median(col(2)):.3f} ({min(col(2)):.3f}-{max(col(2)):.3f}) | {statistics.median(col(3)):.2f} |")
