#!/usr/bin/env bash
# Same input, same thread count, same bytes: the deformed mesh of repeated runs at 2 threads, with a busy loop
# beside them (thread timing varies most when a core is taken), must be identical byte for byte.
#  - BS08 cactus: lap, tf and lri, full and handle frame modes, the multifrontal backends (double, mixed,
#    refined, out of core), every parallel region forced onto threads (DEFORMBENCH_PARALLEL_MIN_SECONDS=0) so the
#    small system takes the paths large ones take;
#  - the 26k armadillo edit: tf and lap, full and handle, with the default thread choices; tf with the ringnd
#    vertex ordering.
# usage: determinism_test.sh BUILD_DIR SOURCE_DIR
set -u
B=$1 S=$2
. "$S/tests/check_lib.sh"
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=2
sh -c 'while :; do :; done' &
busy=$!
trap 'kill $busy 2>/dev/null; rm -rf "$T"' EXIT

# same_bytes NAME RUNS ARGS...: RUNS runs of `deformbench deform ARGS`, their meshes compared.
same_bytes() {
  local name=$1 runs=$2 i
  shift 2
  for ((i = 1; i <= runs; i++)); do
    if ! "$B/deformbench" deform "$@" --out "$T/$name.$i.ply" >"$T/log" 2>&1; then
      fail "$name: run $i failed: $(tail -3 "$T/log")"
      return
    fi
  done
  local k
  k=$(md5sum "$T/$name".*.ply | awk '{print $1}' | sort -u | wc -l)
  if [ "$k" -eq 1 ]; then ok "$name: $runs runs, identical bytes"; else fail "$name: $runs runs gave $k different meshes"; fi
  rm -f "$T/$name".*.ply
}

cactus=$S/data/bs08/cactus
for method in lap tf lri; do
  for mode in full handle; do
    for solver in multifrontal multifrontal_mixed multifrontal_refined ooc; do
      # The float factor of cactus' TF system cannot refine the handle responses (a stall, exit 3, by design).
      [ "$method-$mode-$solver" = tf-handle-multifrontal_mixed ] && continue
      args=(--method "$method" --constraints soft --frame-mode "$mode" --frames 4)
      case $solver in
        ooc) mkdir -p "$T/factor"; args+=(--solver multifrontal --factor-dir "$T/factor") ;;
        *) args+=(--solver "$solver") ;;
      esac
      DEFORMBENCH_PARALLEL_MIN_SECONDS=0 same_bytes "cactus-$method-$mode-$solver" 3 "$cactus" "${args[@]}"
    done
  done
done

armadillo=$S/data/edits/armadillo_whole.edit
if [ -f "$S/data/meshes/armadillo.off" ]; then
  for method in tf lap; do
    for mode in full handle; do
      same_bytes "armadillo-$method-$mode" 3 "$armadillo" --method "$method" --constraints soft --frame-mode "$mode" --frames 5
    done
  done
  # The ring dissection orders the two sides of each split in two processes at once.
  same_bytes "armadillo-tf-ringnd" 3 "$armadillo" --method tf --constraints soft --ordering ringnd --frames 3
else
  fail "data/meshes/armadillo.off is missing (scripts/data.sh extracts it)"
fi

echo "determinism: $fails failure(s)"
[ "$fails" -eq 0 ]
