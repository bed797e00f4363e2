#!/usr/bin/env bash
# The device runs' diagnostic patch (scripts/device_timeline.patch, built by `scripts/device_threads.sh prepare`
# with DIAG_PATCH) still applies to this tree: a change to a file it touches must bring the patch along, or the
# next session with a device machine finds it broken. Skipped (77) outside a git checkout.
#
#   tests/device_patch_test.sh SOURCE_DIR
set -uo pipefail
SRC=$1
git -C "$SRC" rev-parse --is-inside-work-tree > /dev/null 2>&1 || { echo "not a git checkout: skipped"; exit 77; }
out=$(git -C "$SRC" apply --check scripts/device_timeline.patch 2>&1) ||
  { echo "$out"; echo "FAIL: scripts/device_timeline.patch no longer applies. Refresh it: apply it to a worktree of the"
    echo "head (git apply --reject, then the rejected hunks by hand), git add -N solvers/base/timeline.h, git diff > it"
    exit 1; }
echo "scripts/device_timeline.patch applies"
