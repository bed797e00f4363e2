"""Summarizes first_split's lines (study.txt) per graph and dissection level, as a Markdown table: the rank
correlation of the first separator's size (and of its sides' imbalance) with the ordering's flops; where METIS's
default seed ranks; what "best of k" would give, the first split computed under the seeds -1, 1, ..., k-1 (one per
idle thread) and the smallest separator kept (ties to the earlier seed), as its flops over the default seed's;
the least and the median flops of the 16 draws over the default's.
usage: /usr/bin/python3 summary.py study.txt"""
import collections
import sys


def ranks(xs):
    order = sorted(range(len(xs)), key=lambda i: xs[i])
    r = [0.0] * len(xs)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and xs[order[j + 1]] == xs[order[i]]:
            j += 1
        for k in range(i, j + 1):
            r[order[k]] = (i + j) / 2
        i = j + 1
    return r


def spearman(a, b):
    ra, rb = ranks(a), ranks(b)
    ma, mb = sum(ra) / len(ra), sum(rb) / len(rb)
    num = sum((x - ma) * (y - mb) for x, y in zip(ra, rb))
    den = (sum((x - ma) ** 2 for x in ra) * sum((y - mb) ** 2 for y in rb)) ** 0.5
    return num / den if den else float("nan")


def read(paths):
    rows = collections.defaultdict(list)
    for path in paths:
        for line in open(path):
            t = line.split()
            if len(t) != 18:
                continue
            sides = (int(t[10]), int(t[11]))
            t = t[:9] + t[12:]
            d = dict(zip(t[1::2], t[2::2]))
            key = (t[0], int(d["n"]), int(d["L"]))
            rows[key].append((int(d["seed"]), int(d["sep"]), float(d["fl"]), abs(sides[0] - sides[1])))
    return rows


def main():
    rows = read(sys.argv[1:])
    print("| graph | n | levels | draws | rank corr. (separator, flops) | rank corr. (imbalance, flops) "
          "| default seed's flops rank | best of 2 | best of 4 | best of 8 | best of 16 | least / default "
          "| median / default |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for (g, n, L), r in sorted(rows.items(), key=lambda kv: (kv[0][2], kv[0][1])):
        r.sort(key=lambda x: (x[0] != -1, x[0]))  # the default seed (-1) first, then 1, 2, ...
        sep, fl, imb = [x[1] for x in r], [x[2] for x in r], [x[3] for x in r]
        d = fl[0]
        rank = 1 + sum(f < d for f in fl)
        best = [min(r[:k], key=lambda x: x[1])[2] / d for k in (2, 4, 8, 16)]
        med = sorted(fl)[len(fl) // 2]
        print(f"| {g} | {n} | {L} | {len(r)} | {spearman(sep, fl):.2f} | {spearman(imb, fl):.2f} | {rank} of {len(r)} | "
              + " | ".join(f"{b:.3f}" for b in best) + f" | {min(fl) / d:.3f} | {med / d:.3f} |")


if __name__ == "__main__":
    main()
