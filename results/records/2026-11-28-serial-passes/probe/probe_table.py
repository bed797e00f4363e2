#!/usr/bin/env python3
"""Tabulates the PROBE lines of probe_device.sh's runs (call1.txt, call2.txt beside this script): each step of the
TF init's serial passes, in ms, per edit and thread count, one value per run. The prints are cumulative within a
group (the setup's since the adjacency started, the structured build's since it started, the backend's analysis
and factorization prologue since each started); the steps are their differences. Usage: probe_table.py > probe.md"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
# (step, print, the print it follows within its group or None)
STEPS = [
    ("vertex adjacency", "adjacency", None),
    ("components anchored", "anchored", "adjacency"),
    ("Laplacian weights and coordinates", "operator", None),
    ("stencil counts (memory check)", "check_build", None),
    ("2-ring pattern", "pattern", None),
    ("K's layout (expand_upper)", "expand", "pattern"),
    ("K's values (threads' column ranges)", "fill", "expand"),
    ("C and the soft weights", "C", "fill"),
    ("backend: symbolic analysis", "mf_analyze_blocks", None),
    ("backend: plans", "mf_plans", "mf_analyze_blocks"),
    ("backend: pattern hash (analyze)", "mf_remember", "mf_plans"),
    ("factorize: pattern hash and finite check", "mf_prepare", None),
    ("factorize: the diagonal", "mf_diag", "mf_prepare"),
    ("factorize: factor mapped, memory check", "mf_mapped", "mf_diag"),
    ("factorize: lower triangle's row counts", "mf_counts", None),
]


def runs(path):
    """{(edit, T): [ {print: seconds} per run ]}"""
    out, cur = {}, None
    for line in open(path):
        m = re.match(r"# (e\d) T=(\d+) run (\d+)", line)
        if m:
            cur = {}
            out.setdefault((m.group(1), int(m.group(2))), []).append(cur)
            continue
        if line.startswith("PROBE ") and cur is not None:
            words = line.split()[1:]
            for k in range(0, len(words) - 1, 2):
                cur.setdefault(words[k], float(words[k + 1]))  # first print of a name (subtrees_start repeats)
    return out


def step_ms(run, name, after):
    if name not in run or (after and after not in run):
        return None
    return 1e3 * (run[name] - (run[after] if after else 0.0))


def main():
    edits = {"e1": "104k", "e2": "416k"}
    for call, what in (("call1", "call 1: the head 014ba5e with the prints"),
                       ("call2", "call 2: the head 7aea034 with the prints")):
        data = runs(os.path.join(HERE, call + ".txt"))
        keys = sorted(data, key=lambda k: (k[0], -k[1]))
        print(f"### {what}\n")
        print("| step | " + " | ".join(f"{edits[e]} TF, T = {t}" for e, t in keys) + " |")
        print("|---|" + "---|" * len(keys))
        for label, name, after in STEPS:
            cells = []
            for k in keys:
                vals = [step_ms(r, name, after) for r in data[k]]
                cells.append(", ".join("-" if v is None else f"{v:.1f}" for v in vals))
            print(f"| {label} | " + " | ".join(cells) + " |")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
