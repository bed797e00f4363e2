"""The thread-scaling record's table and figure from the files scripts/device_threads.sh's run wrote (issue 31,
item 4). Reads DEST/threads.csv (one deform row per run, prefixed with tier, round, threads and the ordering
asked), rates.csv and failed.csv; writes DEST/table.md and DEST/threads.png. Medians over the rounds a key has,
with their range; efficiency is t(1) / (T t(T)) of the medians, against the key's one-thread run (none: '-').
With --solves: the `solves`, `blas`, `factor` or `team` mode's files instead (deform rows of one binary or two,
deformbench_base and deformbench, in interleaved rounds; analysis_T.csv of exp_analysis): per mesh, method, T and
BLAS threads each round's frame, solve, factorization and top-phase times of each binary, the new / base solve
ratio per round; each round's init and analysis phase with the new / base init ratio; the analysis split.
Measures nothing.

    /usr/bin/python3 scripts/device_threads_report.py [--solves] results/records/DATE-threads
"""
import csv
import statistics
import sys
from collections import defaultdict
from pathlib import Path

TIERS = {}  # tier -> (its edit's name, its vertex count as "104k"), from the rows load() reads


def tier(t):
    """The tables' name of a tier: its edit and vertex count."""
    return f"{TIERS[t][0]} ({TIERS[t][1]})" if t in TIERS else f"tier {t}"


def short(t):
    """The legend's: the vertex count, or the edit where two tiers have the same count."""
    return TIERS[t][1] if [v for _, v in TIERS.values()].count(TIERS[t][1]) == 1 else TIERS[t][0]


def load(dest, binary="deformbench"):
    runs = defaultdict(list)
    for r in csv.DictReader(open(dest / "threads.csv")):
        v = int(r["vertices"])
        TIERS.setdefault(r["tier"], (r["edit"], f"{round(v / 1000)}k" if v >= 1000 else str(v)))
        if r.get("binary", "deformbench") != binary:
            continue
        runs[(r["tier"], r["method"], r["backend"], r["ordering"], int(r["threads"]))].append(r)
    return runs


def med(rows, col):
    return statistics.median(float(r[col]) for r in rows)


def spread(rows, col, scale=1.0, fmt="{:.2f}"):
    vals = sorted(float(r[col]) * scale for r in rows)
    text = fmt.format(statistics.median(vals))
    return text if len(vals) == 1 else f"{text} ({fmt.format(vals[0])}-{fmt.format(vals[-1])})"


def table(runs):
    out = ["| edit (vertices) | method | solver | ordering | T | rounds | init s, median (range) | build + analyze + factorize s |"
           " GFlop/s | top phase s (share of flops, GFlop/s) | subtree phase GFlop/s | frame ms, median (range) |"
           " init efficiency | nnz(L) |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(runs, key=lambda k: (k[0], k[1], k[2], k[3], k[4])):
        rows = runs[key]
        t, method, backend, ordering, T = key
        one = runs.get((t, method, backend, ordering, 1))
        eff = f"{med(one, 'init_s') / (T * med(rows, 'init_s')):.2f}" if one else "-"
        flops, fact = med(rows, "factor_flops"), med(rows, "factorize_s")
        top, sub = "-", "-"
        if backend.startswith("multifrontal") and flops > 0 and float(rows[0]["factor_top_flops"]) > 0:
            top_s, top_f = med(rows, "factorize_top_s"), med(rows, "factor_top_flops")
            top = f"{top_s:.2f} ({top_f / flops:.2f}" + (f", {top_f / top_s / 1e9:.0f})" if top_s > 0 else ")")
            sub = f"{(flops - top_f) / (fact - top_s) / 1e9:.0f}"
        out.append(f"| {tier(t)} | {method} | {backend} | {ordering} | {T} | {len(rows)} | {spread(rows, 'init_s')} | "
                   f"{med(rows, 'build_s'):.2f} + {med(rows, 'analyze_s'):.2f} + {fact:.2f} | {flops / fact / 1e9:.0f} | "
                   f"{top} | {sub} | {spread(rows, 'frame_s', 1e3, '{:.1f}')} | {eff} | {rows[0]['nnz_factor']} |")
    return out


def rates_table(dest):
    out = ["| phase | T | dgemm GFlop/s | memory read GB/s |", "|---|---|---|---|"]
    for r in csv.DictReader(open(dest / "rates.csv")):
        out.append(f"| {r['phase']} | {r['threads']} | {float(r['blas_dgemm_flops']) / 1e9:.0f} | "
                   f"{float(r['memory_read_bytes_per_s']) / 1e9:.0f} |")
    return out


def provenance(runs):
    r = next(iter(runs.values()))[0]
    return (f"git {r['git_sha']}, {r['blas']} (core {r['blas_core']}), cpu {r['cpu']}, {r['hardware_threads']} hardware "
            f"threads, {r['compiler']}")


def plot_series(ax, runs, s, col, scale, style):
    """One series of a panel: `col` (times `scale`) per T, its median barred from the least to the largest round;
    col None: the init efficiency from the medians (drawn only where the series has T = 1)."""
    Ts = sorted(k[4] for k in runs if k[:4] == s)
    c, m = style
    label = f"{short(s[0])} {s[1]} {s[2]} {s[3]}"
    if col is None:
        if 1 in Ts:
            t1 = med(runs[(*s, 1)], "init_s")
            ax.plot(Ts, [t1 / (T * med(runs[(*s, T)], "init_s")) for T in Ts], color=c, marker=m, label=label)
        return
    values = [[scale * float(r[col]) for r in runs[(*s, T)]] for T in Ts]
    ys = [scale * med(runs[(*s, T)], col) for T in Ts]
    spread = [[y - min(v) for y, v in zip(ys, values)], [max(v) - y for y, v in zip(ys, values)]]
    ax.errorbar(Ts, ys, yerr=spread, color=c, marker=m, capsize=3, label=label)


def figure(runs, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    series = sorted({k[:4] for k in runs})
    counts = sorted({k[4] for k in runs})
    colours = plt.get_cmap("tab10").colors
    markers = "osD^vP*Xh<>p"
    style = {s: (colours[i % 10], markers[i % len(markers)]) for i, s in enumerate(series)}
    panels = [("init s (build + analyze + factorize)", "init_s", 1, True),
              ("analysis s (ordering + symbolic)", "analyze_s", 1, True),
              ("full frame ms (median of 5 a run)", "frame_s", 1e3, True),
              ("init efficiency t(1) / (T t(T)), medians", None, 1, False)]
    fig, axes = plt.subplots(2, 2, figsize=(13, 11))
    for ax, (title, col, scale, logy) in zip(axes.flat, panels):
        for s in series:
            plot_series(ax, runs, s, col, scale, style[s])
        ax.set_xscale("log", base=2)
        ax.set_xticks(counts, [str(T) for T in counts])
        ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
        if logy:
            ax.set_yscale("log")
            plain = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
            ax.yaxis.set_major_formatter(plain)
            ax.yaxis.set_minor_formatter(matplotlib.ticker.FuncFormatter(
                lambda v, _: f"{v:g}" if f"{v:.0e}"[0] in "2346" else ""))
        ax.set_xlabel("threads T (DEFORMBENCH_THREADS = OPENBLAS_NUM_THREADS)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=9)
    edits = ", ".join(f"{short(t)}: {TIERS[t][0]}" if short(t) != TIERS[t][0] else TIERS[t][0] for t in sorted(TIERS))
    fig.suptitle(f"{edits}; --constraints soft, one process per run;\n"
                 "times: the median over a point's rounds, barred from the least to the largest")
    fig.tight_layout(rect=(0, 0.015 + 0.022 * -(-len(series) // 4), 1, 1))  # room for the legend's rows
    fig.savefig(path, dpi=110)


def main(dest):
    runs = load(dest)
    failed = list(csv.DictReader(open(dest / "failed.csv")))
    rounds = {k: len(v) for k, v in runs.items()}
    lines = [f"Runs: {provenance(runs)}.", "", *table(runs), "", "Machine rates at each T (exp_machine_rates; before "
             "and after the runs):", "", *rates_table(dest)]
    if failed:
        lines += ["", "Runs that failed or timed out: " + "; ".join(
            f"{tier(r['tier'])} {r['method']} {r['solver']} {r['ordering']} T={r['threads']} rc {r['rc']}" for r in failed)]
    lines += ["", f"Rounds per key: {min(rounds.values())} to {max(rounds.values())} (runs not started before the "
              "deadline are absent)."]
    (dest / "table.md").write_text("\n".join(lines) + "\n")
    figure(runs, dest / "threads.png")
    print("\n".join(lines))


def by_blas(dest, binary):
    runs = defaultdict(list)
    for r in csv.DictReader(open(dest / "threads.csv")):
        if r.get("binary", "deformbench") == binary:
            runs[(r["tier"], r["method"], int(r["threads"]), int(r["blas_threads"]))].append(r)
    return runs


def per_round(rows, col, scale=1e3, fmt="{:.1f}"):
    return ", ".join(fmt.format(float(r[col]) * scale) for r in sorted(rows, key=lambda r: r["round"]))


def init_rows(base, new):
    """Each round's init, its analysis phase and the whole command of both binaries, with the new / base init ratio
    per round."""
    lines = ["", "| edit (vertices) | method | T | BLAS threads | init s | base init s | new / base init | analyze s |"
             " base analyze s | command s | base command s |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(new, key=lambda k: (k[0], k[1], -k[2], -k[3])):
        b, n = base.get(key, []), new[key]
        by_round = {r["round"]: float(r["init_s"]) for r in b}
        ratios = ", ".join(f"{float(r['init_s']) / by_round[r['round']]:.2f}"
                           for r in sorted(n, key=lambda r: r["round"]) if r["round"] in by_round) or "-"
        seconds = lambda rows, col: per_round(rows, col, 1.0, "{:.2f}") or "-"
        # command_s: the whole deform command (device runs before it was recorded have none)
        command = lambda rows: seconds([r for r in rows if r.get("command_s")], "command_s")
        cells = [seconds(n, "init_s"), seconds(b, "init_s"), ratios, seconds(n, "analyze_s"), seconds(b, "analyze_s"),
                 command(n), command(b)]
        lines.append(f"| {tier(key[0])} | {key[1]} | {key[2]} | {key[3]} | {' | '.join(cells)} |")
    return lines


def solves(dest):
    base, new = by_blas(dest, "deformbench_base"), by_blas(dest, "deformbench")
    lines = [f"Runs: {provenance(load(dest))}. Per round, in round order; base: deformbench_base.", "",
             "| edit (vertices) | method | T | BLAS threads | rounds | frame ms | solve ms | base frame ms | base solve ms |"
             " new / base solve | factorize s | base factorize s | top phase s | base top phase s |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(new, key=lambda k: (k[0], k[1], -k[2], -k[3])):
        b, n = base.get(key, []), new[key]
        by_round = {r["round"]: float(r["solve_s"]) for r in b}
        ratios = ", ".join(f"{float(r['solve_s']) / by_round[r['round']]:.2f}"
                           for r in sorted(n, key=lambda r: r["round"]) if r["round"] in by_round) or "-"
        seconds = [per_round(rows, col, 1.0, "{:.2f}") or "-" for col in ("factorize_s", "factorize_top_s")
                   for rows in (n, b)]
        lines.append(f"| {tier(key[0])} | {key[1]} | {key[2]} | {key[3]} | {len(n)} | {per_round(n, 'frame_s')} | "
                     f"{per_round(n, 'solve_s')} | {per_round(b, 'frame_s') or '-'} | {per_round(b, 'solve_s') or '-'} | "
                     f"{ratios} | {' | '.join(seconds)} |")
    lines += init_rows(base, new)
    files = sorted(dest.glob("analysis_*.csv"), key=lambda p: int(p.stem.split("_")[1]))
    if files:
        lines += ["", "Medians of the rounds. Symbolic s: the multifrontal analysis as the deformation runs it "
                  "(from the ordering's elimination tree where it hands one); without it: the same analysis from "
                  "CHOLMOD's own pass over the graph, timed in the same rounds (exp_analysis builds since e92e762).",
                  "",
                  "| T | vertices | ordering | rounds | order s | symbolic s | symbolic s without the tree | "
                  "analysis s | nnz(L) |",
                  "|---|---|---|---|---|---|---|---|---|"]
    for path in files:
        groups = defaultdict(list)
        for r in csv.DictReader(open(path)):
            groups[(r["vertices"], r["ordering"])].append(r)
        for (v, o), rows in sorted(groups.items(), key=lambda kv: (int(kv[0][0]), kv[0][1])):
            own = f"{med(rows, 'mf_own_tree_s'):.3f}" if "mf_own_tree_s" in rows[0] else "-"
            lines.append(f"| {path.stem.split('_')[1]} | {v} | {o} | {len(rows)} | {med(rows, 'order_s'):.3f} | "
                         f"{med(rows, 'mf_analyze_s'):.3f} | {own} | {med(rows, 'analysis_s'):.3f} | "
                         f"{rows[0]['nnz_L']} |")
    (dest / "table.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    folder = Path(sys.argv[2] if sys.argv[1] == "--solves" else sys.argv[1])
    if not (folder / "threads.csv").is_file():  # no run finished before the deadline, or the wrong folder
        sys.exit(f"device_threads_report.py: no {folder / 'threads.csv'}: no run's rows to tabulate")
    if sys.argv[1] == "--solves":
        solves(folder)
    else:
        main(folder)
