#!/usr/bin/env bash
# Checks the layer order (docs/ and CMakeLists.txt): a source file may include project headers of its own layer or
# of a lower one, never of a higher one. The solver library (solvers/, its bottom layer solvers/base/) sits below
# everything under src/, so no file of solvers/ includes from src/; the experiment harness (experiments/harness/)
# sits above the library, so no library file includes it. Run by ctest (test "layers"); prints each offending #include and exits 1.
#
#   scripts/check_layers.sh [REPO_ROOT]
set -euo pipefail
ROOT=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}
cd "$ROOT"

# Lowest first. solvers/base/, solvers/ordering/, solvers/ and src/deformbench/<layer>/ hold the library layers.
LAYERS=(solvers/base solvers/ordering solvers core mesh edit operators systems methods applications harness)
rank_of() {  # layer name -> rank, or empty
  local i
  for i in "${!LAYERS[@]}"; do [[ ${LAYERS[$i]} == "$1" ]] && { echo "$i"; return; }; done
  return 0  # none: a header outside the layers (e.g. tests/test_util.h), not a failure under set -e
}
# A file's own layer rank: library folders by name; solvers/tests sit with the solvers (they must link the solver
# library alone); apps, experiments, bench and tests are above every layer.
file_rank() {
  case "$1" in
    src/deformbench/*) rank_of "$(cut -d/ -f3 <<<"$1")" ;;
    solvers/base/*) rank_of solvers/base ;;
    solvers/ordering/*) rank_of solvers/ordering ;;
    experiments/harness/*) rank_of harness ;;
    solvers/*) rank_of solvers ;;
    *) echo ${#LAYERS[@]} ;;
  esac
}
include_rank() {  # "mesh/mesh.h" -> rank of mesh; empty for a header outside the layers
  case "$1" in
    solvers/base/*) rank_of solvers/base ;;
    solvers/ordering/*) rank_of solvers/ordering ;;
    *) rank_of "${1%%/*}" ;;
  esac
}

bad=0
checked=0
while IFS= read -r f; do
  own=$(file_rank "$f")
  [[ -n $own ]] || { echo "layers: $f is in no known layer (add its folder to LAYERS)"; bad=1; continue; }
  while IFS=: read -r line inc; do
    r=$(include_rank "$inc")
    [[ -n $r ]] || continue
    checked=$((checked + 1))
    if ((r > own)); then
      echo "layers: $f:$line includes \"$inc\" (layer ${LAYERS[$r]} is above this file's)"
      bad=1
    fi
  done < <(grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$f" | sed -E 's/^([0-9]+):[^"]*"([^"]+)".*/\1:\2/')
done < <(git ls-files -co --exclude-standard -- 'src/*.h' 'src/*.cpp' 'solvers/*.h' 'solvers/*.cpp' \
  'apps/*.cpp' 'apps/*.h' 'experiments/*.cpp' 'experiments/*.h' 'bench/*.cpp' 'tests/*.cpp' 'tests/*.h')
((checked > 0)) || { echo "layers: no #include lines found under $ROOT"; exit 1; }
((bad == 0)) && echo "layers: $checked project includes checked, none reaches up (order: ${LAYERS[*]})"
exit $bad
