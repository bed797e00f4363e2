"""Each 16-thread group's make-up (bins_*_T16.txt: its subtrees, its flops and its largest subtree's, over the
mean group's) beside its CPU seconds (user + system) over the run's mean group in each round of runs.txt.
Measures nothing.   /usr/bin/python3 groups.py > groups.md  (in this folder)"""
import re
from pathlib import Path

here = Path(__file__).parent


def numbers(line):
    return {k: float(v) for k, v in re.findall(r"(\w+) ([\d.]+)", line)}


print("| vertices | group | subtrees | flops / mean | largest subtree / mean group | CPU s / mean group, per round |")
print("|---|---|---|---|---|---|")
for tier, name in (("1", "104k"), ("2", "416k")):
    bins = {int(l.split()[1]): numbers(l) for l in (here / f"bins_{name}_T16.txt").open()}
    times = {}
    for block in (here / "runs.txt").read_text().split("== ")[1:]:
        rows = block.strip().split("\n")
        head = dict(re.findall(r"(\w+) (\w+)", rows[0]))
        if head["tier"] != tier or head["method"] != "tf" or head["threads"] != "16":
            continue
        cpu = {int(r.split()[1]): numbers(r)["user"] + numbers(r)["sys"] for r in rows if r.startswith("group ")}
        mean = sum(cpu.values()) / len(cpu)
        for i, t in cpu.items():
            times.setdefault(i, []).append(t / mean)
    for i, b in sorted(bins.items()):
        print(f"| {name} | {i} | {b['subtrees']:.0f} | {b['flops']:.2f} | {b['largest']:.2f} | "
              f"{', '.join(f'{t:.2f}' for t in times[i])} |")
