"""MUMPS's analysis-only estimates (rows of `scripts/mumps_ranks.sh estimate`) as machines of a given memory.

    python3 -m dbtools.reports.mumps_estimate results/records/2026-11-24-mumps-ranks/estimate.csv [--machine-mb 20000] [--levels 4,5]

Prints Markdown (from the rows of analyses only, `phases=analysis`): the estimates per mesh and number of ranks; how many machines they need, in core
(INFO(15) per rank, INFOG(16)/(17)) and out of core (INFO(17), INFOG(26)/(27)), packing each rank's estimate
into machines of --machine-mb MB (MUMPS's MB: 10^6 bytes) first fit decreasing; and an extrapolation of each
estimate one Loop level on (n x 4) from its growth between the two largest meshes measured on the same number
of ranks (value ~ n^e), checked against the exponent of the two levels below where there are three. A mesh
analyzed on 1 rank only gets its N-rank figures derived (not measured): its 1-rank estimates times the ratio of
the N-rank to the 1-rank estimates of the largest mesh analyzed on both.
"""
import argparse
import csv
import math
import sys

MEASURES = [("flops_estimated", "GFlop (RINFOG(1))", 1e-9), ("factor_entries_estimated", "factor entries, M (INFOG(3))", 1e-6),
            ("mb_in_core_max", "in core MB, largest rank (INFOG(16))", 1), ("mb_in_core_sum", "in core MB, all ranks (INFOG(17))", 1),
            ("mb_ooc_max", "out of core MB, largest rank (INFOG(26))", 1), ("mb_ooc_sum", "out of core MB, all ranks (INFOG(27))", 1)]


def machines(per_rank, capacity):
    """First fit decreasing of the ranks' MB into machines of `capacity`; None when one rank alone exceeds it."""
    if max(per_rank) > capacity:
        return None
    bins = []
    for x in sorted(per_rank, reverse=True):
        for i, b in enumerate(bins):
            if b + x <= capacity:
                bins[i] += x
                break
        else:
            bins.append(x)
    return len(bins)


def fmt_machines(per_rank, capacity):
    m = machines(per_rank, capacity)
    return f"{m}" if m is not None else f"none (a rank needs {max(per_rank):,.0f} MB)"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--machine-mb", type=float, default=20000, help="MB of each machine left to MUMPS")
    a = ap.parse_args()
    rows = [r for r in csv.DictReader(open(a.csv, newline="")) if r["phases"] == "analysis"]
    if not rows:
        sys.exit(f"{a.csv}: no rows")
    for r in rows:
        r["n"], r["ranks"] = int(r["n"]), int(r["ranks"])
        for k, _, _ in MEASURES:
            r[k] = float(r[k])
    rows.sort(key=lambda r: (r["n"], r["ranks"]))
    cap = a.machine_mb
    print("| mesh | vertices | ranks | ordering | analyze s (CPU s, rank 0) | GFlop | factor entries | in core MB max / sum "
          "| out of core MB max / sum | in core MB per rank (INFO(15)) | rank 0 peak RSS GB | machines in core / out of core |")
    print("|---|---:|---:|---|---:|---:|---:|---|---|---|---:|---|")
    for r in rows:
        ic = [float(x) for x in r["mb_in_core_rank"].split()]
        oc = [float(x) for x in r["mb_ooc_rank"].split()]
        print(f"| {r['model']} | {int(r['vertices']):,} | {r['ranks']} | {r['ordering_used']} | "
              f"{float(r['analyze_s']):.0f} ({float(r['analyze_cpu_s']):.0f}) | {r['flops_estimated'] * 1e-9:,.0f} | "
              f"{r['factor_entries_estimated'] * 1e-6:,.0f}M | {r['mb_in_core_max']:,.0f} / {r['mb_in_core_sum']:,.0f} | "
              f"{r['mb_ooc_max']:,.0f} / {r['mb_ooc_sum']:,.0f} | {' '.join(f'{x:.0f}' for x in ic)} | "
              f"{float(r['peak_rss_rank_bytes'].split()[0]) / 1e9:.2f} | {fmt_machines(ic, cap)} / {fmt_machines(oc, cap)} |")
    print(f"\nMachines: each rank's estimate packed into machines of {cap:,.0f} MB (first fit decreasing); "
          "'none' when one rank alone needs more.\n")
    derive(rows, cap)
    extrapolate(rows, cap)


def derive(rows, cap):
    big = [r for r in rows if r["ranks"] == 1 and not any(q["n"] == r["n"] and q["ranks"] > 1 for q in rows)]
    for b in big:
        refs = [r for r in rows if r["n"] < b["n"] and r["ranks"] == 1]
        if not refs:
            continue
        ref1 = max(refs, key=lambda r: r["n"])
        ref = [r for r in rows if r["n"] == ref1["n"] and r["ranks"] > 1]
        if not ref:
            continue
        print(f"{b['model']} on N ranks, derived from its 1-rank analysis and {ref1['model']}'s N-rank / 1-rank "
              "ratios (not measured):\n")
        print("| ranks | GFlop | in core MB max / sum | out of core MB max / sum | machines in core / out of core |")
        print("|---:|---:|---|---|---|")
        for r in ref:
            f = {k: r[k] / ref1[k] for k, _, _ in MEASURES}
            ic = [float(x) / ref1["mb_in_core_sum"] * b["mb_in_core_sum"] for x in r["mb_in_core_rank"].split()]
            oc = [float(x) / ref1["mb_ooc_sum"] * b["mb_ooc_sum"] for x in r["mb_ooc_rank"].split()]
            print(f"| {r['ranks']} | {b['flops_estimated'] * f['flops_estimated'] * 1e-9:,.0f} | "
                  f"{b['mb_in_core_max'] * f['mb_in_core_max']:,.0f} / {b['mb_in_core_sum'] * f['mb_in_core_sum']:,.0f} | "
                  f"{b['mb_ooc_max'] * f['mb_ooc_max']:,.0f} / {b['mb_ooc_sum'] * f['mb_ooc_sum']:,.0f} | "
                  f"{fmt_machines(ic, cap)} / {fmt_machines(oc, cap)} |")
        print()


def extrapolate(rows, cap):
    by_ranks = {}
    for r in rows:
        by_ranks.setdefault(r["ranks"], []).append(r)
    print("Extrapolation one Loop level on (4x the unknowns), each estimate ~ n^e with e from the two largest meshes "
          "on the same ranks (e below: from the two meshes before them). Not a measurement.\n")
    print("| ranks | estimate | measured, n: value | e | e below | extrapolated, n: value |")
    print("|---:|---|---|---:|---:|---:|")
    for np_, rs in sorted(by_ranks.items()):
        if len(rs) < 2:
            continue
        a, b = rs[-2], rs[-1]
        for k, name, scale in MEASURES:
            e = math.log(b[k] / a[k]) / math.log(b["n"] / a["n"])
            below = ""
            if len(rs) >= 3:
                z = rs[-3]
                below = f"{math.log(a[k] / z[k]) / math.log(a['n'] / z['n']):.2f}"
            vals = ", ".join(f"{r['n'] / 1e6:.2f}M: {r[k] * scale:,.0f}" for r in rs)
            print(f"| {np_} | {name} | {vals} | {e:.2f} | {below} | {4 * b['n'] / 1e6:.2f}M: {b[k] * 4 ** e * scale:,.0f} |")
        ic = b["mb_in_core_sum"] * 4 ** (math.log(b["mb_in_core_sum"] / a["mb_in_core_sum"]) / math.log(b["n"] / a["n"]))
        oc = b["mb_ooc_sum"] * 4 ** (math.log(b["mb_ooc_sum"] / a["mb_ooc_sum"]) / math.log(b["n"] / a["n"]))
        print(f"| {np_} | machines of {cap:,.0f} MB, at least (all ranks' sum / machine) | | | | "
              f"in core {math.ceil(ic / cap)}, out of core {math.ceil(oc / cap)} |")


if __name__ == "__main__":
    main()
