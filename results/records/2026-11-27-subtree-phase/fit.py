"""How well a group's flops, and its flops plus its fronts' entries, predict the CPU seconds (user + system) its
thread spent in the subtree phase on 16 cores: least squares over the 104k and 416k TF groups of runs.txt, the
groups' counts from features_*_T16.txt; per run, the largest group over the mean, measured and predicted.
Measures nothing.   /usr/bin/python3 fit.py  (in this folder; numpy)"""
import re
from pathlib import Path

import numpy as np

here = Path(__file__).parent


def numbers(line):
    return {k: float(v) for k, v in re.findall(r"(\w+) ([\d.]+)", line)}


features = {tier: {int(l.split()[1]): numbers(l) for l in (here / f"features_{name}_T16.txt").open()}
            for tier, name in (("1", "104k"), ("2", "416k"))}
runs = []
for block in (here / "runs.txt").read_text().split("== ")[1:]:
    rows = block.strip().split("\n")
    head = dict(re.findall(r"(\w+) (\w+)", rows[0]))
    if head["method"] != "tf" or head["threads"] != "16":
        continue
    groups = {int(r.split()[1]): numbers(r) for r in rows if r.startswith("group ")}
    f = features[head["tier"]]
    assert all(abs(f[i]["gflop"] - g["gflop"]) < 2e-3 for i, g in groups.items()), "not the same plan"
    runs.append((head, [(f[i]["gflop"], f[i]["front"] * 1e-9, g["user"] + g["sys"]) for i, g in groups.items()]))
X = np.array([[a, b] for _, rows in runs for a, b, _ in rows])
y = np.array([t for _, rows in runs for _, _, t in rows])
models = {"flops": [0], "flops + front entries": [0, 1]}
coef = {}
print("| model | s per GFlop | s per 1e9 front entries | median, largest relative error |\n|---|---|---|---|")
for name, cols in models.items():
    c = np.linalg.lstsq(X[:, cols], y, rcond=None)[0]
    coef[name] = (cols, c)
    err = np.abs(X[:, cols] @ c - y) / y
    print(f"| {name} | {c[0]:.4f} | {c[1] if len(c) > 1 else 0:.2f} | {np.median(err):.3f}, {err.max():.3f} |")
print("\n| vertices | round | largest / mean group: measured | flops | flops + front entries |\n|---|---|---|---|---|")
for head, rows in runs:
    a = np.array(rows)
    pred = a[:, :2] @ coef["flops + front entries"][1]
    print(f"| {'104k' if head['tier'] == '1' else '416k'} | {head['round']} | {a[:, 2].max() / a[:, 2].mean():.2f} | "
          f"{a[:, 0].max() / a[:, 0].mean():.2f} | {pred.max() / pred.mean():.2f} |")
print("\n| vertices | model | median, largest relative error (fitted on this mesh's groups only) |\n|---|---|---|")
for tier, name in (("1", "104k"), ("2", "416k")):
    a = np.array([r for head, rows in runs if head["tier"] == tier for r in rows])
    for model, cols in models.items():
        c = np.linalg.lstsq(a[:, cols], a[:, 2], rcond=None)[0]
        err = np.abs(a[:, cols] @ c - a[:, 2]) / a[:, 2]
        print(f"| {name} | {model} | {np.median(err):.3f}, {err.max():.3f} |")
