#!/usr/bin/env bash
# The multifrontal extend-add by runs of consecutive parent rows (commit in README.md) against the entry-by-entry
# loop: the 104k TF deformation (multifrontal, --frames 1) by two builds, alternating (the order flips per round),
# at 1 and 2 threads, each run right after a process that wrote and freed 2 GB (the warm state of
# ../2026-11-27-fresh-memory: the factor's first touch then costs what it costs on a machine that backs its memory,
# so the extend-add's own time is not drowned in the VM's page backing). Each run under `perf record` (4 kHz):
# the CPU samples in FrontFactorization::assemble_child itself. The meshes of a pair are compared byte for byte.
# Writes runs.csv (every deform row with its provenance), rates.csv (the preparing process's machine rates: dgemm,
# memory read, first touch), cmp.txt and table.md here.
# usage: results/records/2026-11-27-extend-add-runs/run.sh BASE NEW [ROUNDS]   (from the repository root, after
#        cmake --build build --target exp_machine_rates)
set -euo pipefail
base=$1 new=$2 rounds=${3:-4}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
rm -f "$here/runs.csv" "$here/rates.csv"
one() {  # label (base or new) threads round: one run of that build appended to runs.csv
  local bin=$base; [ "$1" = new ] && bin=$new
  export DEFORMBENCH_THREADS=$2 OPENBLAS_NUM_THREADS=$2
  build/exp_machine_rates --first-touch-mb 2048 --csv "$t/rates.csv" >/dev/null
  if [ -f "$here/rates.csv" ]; then tail -n +2 "$t/rates.csv" >> "$here/rates.csv"; else cp "$t/rates.csv" "$here/rates.csv"; fi
  perf record -q -F 4000 -o "$t/perf.data" "$bin" deform data/edits/armadillo_loop1_whole.edit --method tf \
    --constraints soft --frames 1 --out "$t/$1.ply" --csv "$t/o.csv" >/dev/null 2>"$t/perf.err"
  local samples
  samples=$(perf report -i "$t/perf.data" --no-children --sort sym -n --stdio 2>/dev/null |
    awk '/FrontFactorization::assemble_child/ { s += $2 } END { print s + 0 }')
  /usr/bin/python3 scripts/append_rows.py "$t/o.csv" "$here/runs.csv" binary="$1" round="$3" \
    extend_add_samples="$samples"
}
pairs=(base new new base)  # odd rounds base first, even rounds new first
for ((r = 1; r <= rounds; r++)); do
  for threads in 1 2; do
    k=$(((r + 1) % 2 * 2))
    one "${pairs[k]}" "$threads" "$r" && one "${pairs[k + 1]}" "$threads" "$r"
    same=DIFFER; cmp -s "$t/base.ply" "$t/new.ply" && same=identical
    echo "round $r, $threads threads: the meshes are $same"
  done
done | tee "$here/cmp.txt"
/usr/bin/python3 - "$here" > "$here/table.md" <<'PY'
import csv, statistics, sys
here = sys.argv[1]
rows = list(csv.DictReader(open(f"{here}/runs.csv")))
def med(xs, f="%.3f"): return (f + " (" + f + "-" + f + ")") % (statistics.median(xs), min(xs), max(xs))
cols = [("extend_add_samples", "extend-add CPU s (samples / 4000)", lambda r: float(r["extend_add_samples"]) / 4000),
        ("factorize_s", "factorize s", lambda r: float(r["factorize_s"])),
        ("init_s", "init s", lambda r: float(r["init_s"]))]
print("| threads | binary | " + " | ".join(c[1] for c in cols) + " | " +
      " | ".join(c[1].split(" (")[0] + " new / base, per round" for c in cols[:2]) + " |")
print("|---" * (2 + len(cols) + len(cols[:2])) + "|")
for threads in ("1", "2"):
    for b in ("base", "new"):
        rs = [r for r in rows if r["binary"] == b and r["blas_threads"] == threads]
        cells = [med([c[2](r) for r in rs]) for c in cols]
        ratios = ["", ""]
        if b == "new":
            for k, c in enumerate(cols[:2]):
                base = {r["round"]: c[2](r) for r in rows if r["binary"] == "base" and r["blas_threads"] == threads}
                ratios[k] = ", ".join("%.3f" % (c[2](r) / base[r["round"]]) for r in rs)
        print(f"| {threads} | {b} {rs[0]['git_sha']} | " + " | ".join(cells) + " | " + " | ".join(ratios) + " |")
r0 = rows[0]
print()
print(f"{r0['mesh']} ({r0['vertices']} vertices), {r0['method']}, {r0['backend']}; {r0['blas']} core {r0['blas_core']}, "
      f"{r0['cpu']}, {r0['compiler']}; {len(rows)} runs.")
PY
cat "$here/table.md"
