"""runs.txt (device.sh's output) as table.md: per run, the subtree phase's wall time, when its groups finished
(first, last), their threads' CPU seconds (user, system; mean and largest), the groups' flops balance, and the
run's factorization and top phase. Measures nothing.   /usr/bin/python3 summary.py  (in this folder)"""
import re
from pathlib import Path

here = Path(__file__).parent
lines = ["| vertices | method | T | round | subtree phase s | groups done s: first, last | user s: mean, max |"
         " system s: mean, max | group flops: max / mean | factorize s | top phase s |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
for block in (here / "runs.txt").read_text().split("== ")[1:]:
    rows = block.strip().split("\n")
    head = dict(re.findall(r"(\w+) (\w+)", rows[0]))
    groups = [{k: float(v) for k, v in re.findall(r"(\w+) ([\d.]+)", r)} for r in rows if r.startswith("group ")]
    phase = next(float(r.split()[1]) for r in rows if r.startswith("subtrees "))
    csv = dict(zip(rows[-2].split(","), rows[-1].split(",")))
    col = lambda k: [g[k] for g in groups]
    mean = lambda v: sum(v) / len(v)
    lines.append(f"| {'104k' if head['tier'] == '1' else '416k'} | {head['method']} | {head['threads']} | "
                 f"{head['round']} | {phase:.3f} | {min(col('end')):.3f}, {max(col('end')):.3f} | "
                 f"{mean(col('user')):.3f}, {max(col('user')):.3f} | {mean(col('sys')):.3f}, {max(col('sys')):.3f} | "
                 f"{max(col('gflop')) / mean(col('gflop')):.2f} | {float(csv['factorize_s']):.3f} | "
                 f"{float(csv['factorize_top_s']):.3f} |")
(here / "table.md").write_text("\n".join(lines) + "\n")
print("\n".join(lines))
