#!/usr/bin/env bash
# The installed package as a consumer sees it: `cmake --install` this build into a scratch prefix, then configure,
# build and run tests/consumer/ (find_package(deformbench), deformbench::deform) against that prefix alone.
#
#   tests/install_consumer_test.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
SRC=$1
BUILD=$2
SCRATCH=$(mktemp -d)
trap 'rm -rf "$SCRATCH"' EXIT

cmake --install "$BUILD" --prefix "$SCRATCH/prefix" >"$SCRATCH/install.log"
for f in lib/libdeformbench_solvers.a lib/libdeformbench_deform.a include/deformbench/solvers/linear_solver.h \
  include/deformbench/methods/deformer.h lib/cmake/deformbench/deformbenchConfig.cmake; do
  [[ -f $SCRATCH/prefix/$f ]] || { echo "install: $f missing"; ls -R "$SCRATCH/prefix" | head -40; exit 1; }
done
# Nothing of the harness, the tools or the tests is installed.
if grep -E 'harness|/tests/|gtest' "$SCRATCH/install.log"; then echo "install: the lines above are not library files"; exit 1; fi

cmake -S "$SRC/tests/consumer" -B "$SCRATCH/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$SCRATCH/prefix" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$SCRATCH/configure.log" || { cat "$SCRATCH/configure.log"; exit 1; }
cmake --build "$SCRATCH/build" -j 2 >"$SCRATCH/build.log" 2>&1 || { tail -40 "$SCRATCH/build.log"; exit 1; }
# The consumer must have been compiled against the installed headers, not this source tree's.
if grep -rq -- "-I$SRC" "$SCRATCH/build/CMakeFiles/consumer.dir/flags.make"; then
  echo "consumer: compiled with include paths into the source tree"; exit 1
fi
"$SCRATCH/build/consumer" "$SCRATCH/deformed.off"
[[ -s $SCRATCH/deformed.off ]] || { echo "consumer: wrote no mesh"; exit 1; }
echo "install_consumer: installed, found, built and deformed"
