#!/usr/bin/env bash
# Where the factorization's subtree phase goes on a many-core machine: each subtree group's wall span, its thread's
# user and system CPU seconds and page faults (getrusage RUSAGE_THREAD), its flops, printed by a build with
# group_times.patch (deformbench_groups; DBT=1). Run on the lent device (carry .device, after prepare below):
#   here:  cmake --build build --target deformbench (with the patch applied), then
#          DEVICE_BUNDLE=PATH/device-bundle.sh scripts/device_threads.sh prepare
#          cp build/deformbench .device/bin/deformbench_groups; cp THIS .device/subtree.sh
#   there: DEADLINE=150 bash .device/subtree.sh   -> $OUT/runs.txt (one block per run), machine.txt
# The features_*.txt beside it: the same build here, DBF=1 DEFORMBENCH_THREADS=16 (the plan, and so the groups,
# depend only on the tree and the thread count), printing each group's supernodes and entries.
set -euo pipefail
D=$PWD/.device; O=${OUT:?}
for l in libblas.so.3 liblapack.so.3; do ldconfig -p | grep -q "$l " || cp "$D/fallback/$l" "$D/lib/"; done
export LD_LIBRARY_PATH=$D/lib
deadline=$((SECONDS + ${DEADLINE:-150}))
W=$(mktemp -d); cd "$W"
{ nproc; lscpu | grep -E "Model name|^CPU\(s\)"; for f in enabled defrag; do echo "thp $f: $(cat /sys/kernel/mm/transparent_hugepage/$f)"; done
  cat /proc/loadavg; } > "$O/machine.txt" 2>&1 || true
gunzip -c "$D/armadillo_loop1.off.gz" > l1.off
"$D/bin/meshtool" subdivide l1.off l2.off 1 > /dev/null 2>&1 || echo "subdivide failed" >> "$O/machine.txt"
for k in 1 2; do
  printf 'mesh = l%s.off\nroi = all\nhandle = nearest:-20.2599,97.1076,-28.8554,100\ntransform = translate:0,10,0\n' $k > e$k.edit
done
for T in 1 16; do DEFORMBENCH_THREADS=$T OPENBLAS_NUM_THREADS=$T "$D/bin/exp_machine_rates" --csv r$T.csv >> "$O/machine.txt" 2>&1 || true; done
one() {  # tier method threads round estimated_seconds
  [ $((SECONDS + $5)) -le $deadline ] || return 0
  { echo "== tier $1 method $2 threads $3 round $4"
    DBT=1 DEFORMBENCH_THREADS=$3 OPENBLAS_NUM_THREADS=$3 timeout 100 "$D/bin/deformbench_groups" deform e$1.edit --method $2 \
      --constraints soft --frames 1 --solver multifrontal --out o.ply --csv o.csv 2>&1 | grep -E "^(group|subtrees|tree|alloc|permute|prepare) " || true
    cut -d, -f20,21,23-27 o.csv; } >> "$O/runs.txt"
}
for r in 1 2 3; do for T in 16 8 4; do one 1 tf $T $r 6; done; one 1 lap 16 $r 4; done
for r in 1 2; do one 2 tf 16 $r 25; done
one 1 tf 1 1 12
cat "$O/machine.txt"
