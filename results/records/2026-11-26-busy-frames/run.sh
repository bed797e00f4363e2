#!/usr/bin/env bash
# Frames on a busy machine: each cell's frame median at 1 thread (quiet), then at 2 threads with one busy loop
# beside it, for one or more builds, interleaved (build A, build B, build A, ...) so the box's drift hits both.
# usage: run.sh ROUNDS DEFORMBENCH [DEFORMBENCH ...] > frames.csv     (run from the repository root)
set -euo pipefail
rounds=$1; shift
cases=(data/bs08/cylinder data/bs08/bar data/bs08/cactus data/bs08/plane data/edits/armadillo_whole.edit)
t=$(mktemp -d); trap 'rm -rf "$t"; kill $busy 2>/dev/null || true' EXIT; busy=
median_frame() {  # the frame median (ms) of one run: BIN THREADS ARGS...
  local bin=$1 th=$2; shift 2
  DEFORMBENCH_THREADS=$th OPENBLAS_NUM_THREADS=$th "$bin" deform "$@" --out "$t/o.ply" --csv "$t/o.csv" >/dev/null
  /usr/bin/python3 -c 'import csv,sys; r=next(csv.DictReader(open(sys.argv[1]))); print("%.4f" % (1e3*float(r["frame_median_s"])))' "$t/o.csv"
}
echo "build,case,method,frame_mode,round,threads,busy_loop,frame_median_ms"
for ((r = 1; r <= rounds; r++)); do
  for c in "${cases[@]}"; do
    for method in lap tf; do
      for mode in full handle; do
        args=("$c" --method "$method" --constraints soft --frame-mode "$mode" --frames 50)
        for bin in "$@"; do
          q=$(median_frame "$bin" 1 "${args[@]}")
          sh -c 'while :; do :; done' & busy=$!
          b=$(median_frame "$bin" 2 "${args[@]}")
          kill $busy; wait $busy 2>/dev/null || true; busy=
          echo "$bin,$(basename "$c"),$method,$mode,$r,1,no,$q"
          echo "$bin,$(basename "$c"),$method,$mode,$r,2,yes,$b"
        done
      done
    done
  done
done
