"""Summarizes gnd.txt (gnd.sh): per pattern and ordering (METIS_NodeND of the whole graph, or guided dissection to
parts of LEAF vertices, ordered by AMD or by METIS_NodeND), over METIS's draws, the ordering's wall seconds and the
vertex-level nnz(L) and flops, each mean against METIS_NodeND's mean over the same draws."""
import statistics
import sys

rows = {}
for line in open(sys.argv[1]):
    t = line.split()
    value = lambda name: float(t[t.index(name) + 1])
    leaf, mode = int(value("leaf")), t[t.index("mode") + 1]
    name = "METIS_NodeND" if leaf == 0 else f"guided to {leaf}, " + ("METIS_NodeND" if mode.endswith("nd") else "AMD")
    rows.setdefault((t[0], leaf, name), []).append((value("order_s"), value("lnz"), value("fl")))
print("| pattern | ordering | draws | ordering s: mean (range) | against METIS_NodeND | nnz(L) against | flops against |")
print("|---|---|---|---|---|---|---|")
for (pattern, leaf, name), v in sorted(rows.items()):
    base = rows[(pattern, 0, "METIS_NodeND")]
    mean = lambda rs, k: statistics.mean(r[k] for r in rs)
    print(f"| {pattern} | {name} | {len(v)} | {mean(v, 0):.3f} ({min(r[0] for r in v):.3f}-{max(r[0] for r in v):.3f}) | "
          f"{mean(v, 0) / mean(base, 0):.2f} | {mean(v, 1) / mean(base, 1):.4f} | {mean(v, 2) / mean(base, 2):.4f} |")
