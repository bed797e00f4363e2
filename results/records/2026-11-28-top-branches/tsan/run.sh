#!/usr/bin/env bash
# ThreadSanitizer check of the multifrontal backend's top phase (not part of the build): drv.cpp factors and
# solves a 3x3-block grid system at DEFORMBENCH_THREADS = 2, 8 and 16 (DEFORMBENCH_PARALLEL_MIN_SECONDS=0, so the
# plans run on threads however small) with the solvers library built with -fsanitize=thread. kernels.cpp is
# compiled without it: its target_clones resolvers run before the sanitizer's runtime starts and crash under it.
# Writes drv.log here (TSan's reports, if any, and one line per thread count).
# usage: results/records/2026-11-28-top-branches/tsan/run.sh BUILD_DIR   (from the repository root; BUILD_DIR is
#        made here, a few minutes on 2 cores)
set -euo pipefail
b=${1:?BUILD_DIR} here=$(cd "$(dirname "$0")" && pwd) root=$PWD
cmake -S "$root" -B "$b" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDEFORMBENCH_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS=-fsanitize=thread -DCMAKE_C_FLAGS=-fsanitize=thread \
  -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread -DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=thread > /dev/null
cmake --build "$b" -j "$(nproc)" --target solvers_multifrontal_test > /dev/null
cd "$b/solvers"
var() { grep "^$1" CMakeFiles/$2.dir/flags.make | cut -d= -f2-; }
c++ $(var CXX_INCLUDES deformbench_solvers) $(var CXX_FLAGS deformbench_solvers | sed 's/-fsanitize=thread//g') \
  -c "$root/solvers/multifrontal/kernels.cpp" -o kernels.cpp.o
cp libdeformbench_solvers.a libsolvers_tsan.a && ar r libsolvers_tsan.a kernels.cpp.o
c++ $(var CXX_INCLUDES solvers_multifrontal_test) $(var CXX_FLAGS solvers_multifrontal_test) -c "$here/drv.cpp" -o drv.o
bash -c "$(sed 's|CMakeFiles/solvers_multifrontal_test.dir/tests/multifrontal_test.cpp.o|drv.o|; s|-o solvers_multifrontal_test|-o drv|; s|[^ ]*libgtest_main.a||; s| libdeformbench_solvers.a| libsolvers_tsan.a|' CMakeFiles/solvers_multifrontal_test.dir/link.txt)"
DEFORMBENCH_PARALLEL_MIN_SECONDS=0 OPENBLAS_NUM_THREADS=1 TSAN_OPTIONS=halt_on_error=0 ./drv > "$here/drv.log" 2>&1
echo "TSan reports: $(grep -c 'WARNING: ThreadSanitizer' "$here/drv.log" || true)"
