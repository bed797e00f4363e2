#!/usr/bin/env bash
# scripts/check_layers.sh bites: on a scratch tree with one include of each forbidden kind (the solver library
# reaching into src/, the library reaching into the experiment harness, a lower layer of src/ reaching up) it
# names each offending line and exits 1; the same tree without them passes.
#
#   tests/layers_test.sh SOURCE_DIR
set -euo pipefail
SRC=$1
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir -p "$T"/solvers/base "$T"/src/deformbench/{core,mesh,methods} "$T"/experiments/harness
printf '#include "solvers/base/error.h"\n' >"$T/solvers/registry.cpp"
printf '#pragma once\n' >"$T/solvers/base/error.h"
printf '#include "solvers/registry.h"\n#include "core/cli.h"\n' >"$T/src/deformbench/mesh/mesh.cpp"
printf '#include "mesh/mesh.h"\n' >"$T/src/deformbench/methods/drag.cpp"
printf '#include "methods/drag.h"\n' >"$T/experiments/harness/cell.cpp"
git -C "$T" init -q
bash "$SRC/scripts/check_layers.sh" "$T" >"$T/clean.out" || { cat "$T/clean.out"; echo "FAIL: a clean tree fails"; exit 1; }

printf '#include "mesh/mesh.h"\n' >>"$T/solvers/registry.cpp"
printf '#include "harness/cell.h"\n' >>"$T/src/deformbench/methods/drag.cpp"
printf '#include "methods/drag.h"\n' >>"$T/src/deformbench/core/cli.cpp"
rc=0
bash "$SRC/scripts/check_layers.sh" "$T" >"$T/bad.out" || rc=$?
cat "$T/bad.out"
[[ $rc -eq 1 ]] || { echo "FAIL: exit $rc, expected 1"; exit 1; }
for want in 'solvers/registry.cpp:2 includes "mesh/mesh.h"' 'methods/drag.cpp:2 includes "harness/cell.h"' \
  'core/cli.cpp:1 includes "methods/drag.h"'; do
  grep -qF "$want" "$T/bad.out" || { echo "FAIL: not reported: $want"; exit 1; }
done
echo "layers_test: all passed"
