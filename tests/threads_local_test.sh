#!/usr/bin/env bash
# ./run threads' grid on this machine (`scripts/device_threads.sh local`, the device run's grid), on two small
# edits at T = 1, 2 and two rounds:
# - every run of the grid is a threads.csv row with its provenance, the table names each key, the figure is drawn;
# - a run that fails is a failed.csv row, the command exits 5 and the other runs are kept;
# - no run succeeding, or SIGTERM mid-run (exit 143), leaves the earlier results byte for byte, no scratch folder
#   and no child running.
# It asserts what was run and kept, never a time.
#   threads_local_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1
BIN=$2
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, $fails
cd "$SRC" || exit 1
export TMPDIR=$T/tmp  # the run's scratch folders: none may be left
mkdir -p "$TMPDIR"
EDITS="$SRC/data/edits/bar_bend.edit
$SRC/data/bs08/cylinder"
grid() { THREADS=${THREADS:-1 2} ROUNDS=${ROUNDS:-2} BUILD=$BIN bash scripts/device_threads.sh local "$@"; }
no_scratch() {
  [ -z "$(ls -A "$TMPDIR")" ] || fail "$1: scratch left in TMPDIR: $(ls "$TMPDIR")"
  [ -z "$(find "$T/results" -maxdepth 1 -name '.threads.*')" ] || fail "$1: a staging folder left in results/"
}

# 1. The whole grid. Per edit (tier): round 1 multifrontal and CHOLMOD x TF and LAP x T = 1, 2; TF under ringnd at
#    T = 2, 1; round 2 as round 1. 18 rows a tier.
EDITS=$EDITS grid "$T/results/threads" > "$T/out" 2>&1
rc=$?
D=$T/results/threads
if [ $rc -ne 0 ]; then fail "grid: exit $rc: $(tail -5 "$T/out")"; else ok "grid: exit 0"; fi
/usr/bin/python3 - "$D" <<'EOF' && ok "grid: every run is a row with its provenance" || fail "grid: rows"
import collections, csv, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/threads.csv")))
keys = collections.Counter((r["tier"], r["method"], r["backend"], r["ordering"], r["threads"]) for r in rows)
want = {}
for tier in "12":
    for m in ("tf", "lap"):
        for s in ("multifrontal", "cholmod_supernodal"):
            for t in "12":
                want[(tier, m, s, "default", t)] = 2
    for t in "12":
        want[(tier, "tf", "multifrontal", "ringnd", t)] = 1
assert dict(keys) == want, (dict(keys), want)
for r in rows:
    assert r["blas_threads"] == r["threads"] and r["git_sha"] and r["blas_core"] and r["hardware_threads"], r
    assert float(r["init_s"]) > 0 and float(r["frame_s"]) > 0, r
assert {r["edit"] for r in rows if r["tier"] == "1"} == {"bar_bend"}, "tier 1 is the first edit"
assert {r["edit"] for r in rows if r["tier"] == "2"} == {"cylinder"}, "tier 2 is the second edit"
rates = list(csv.DictReader(open(sys.argv[1] + "/rates.csv")))
assert sorted((r["phase"], r["threads"]) for r in rates) == [("after", "1"), ("after", "2"), ("before", "1"), ("before", "2")], rates
assert open(sys.argv[1] + "/failed.csv").read().splitlines()[1:] == []
EOF
n=$(grep -c '^| bar_bend (6k) \|^| cylinder (5k) ' "$D/table.md")
[ "$n" = 20 ] && ok "grid: the table has a line per key" || fail "grid: table lines: $n, expected 20"
[ "$(head -c 4 "$D/threads.png" | tail -c 3)" = PNG ] && ok "grid: figure drawn" || fail "grid: no threads.png"
no_scratch grid
cp -r "$D" "$T/before"

# 2. A run that fails (an edit whose mesh is missing): its rows in failed.csv, the others kept, exit 5. One thread,
#    one round: 5 runs a tier.
sed 's|^mesh = .*|mesh = no_such_mesh.off|' data/edits/bar_bend.edit > "$T/broken.edit"
EDITS="$SRC/data/edits/bar_bend.edit
$T/broken.edit" THREADS=1 ROUNDS=1 grid "$T/results/partial" > "$T/out" 2>&1
rc=$?
[ $rc -eq 5 ] && ok "failed runs: exit 5" || fail "failed runs: exit $rc, expected 5"
failed=$(($(wc -l < "$T/results/partial/failed.csv") - 1)); kept=$(($(wc -l < "$T/results/partial/threads.csv") - 1))
[ "$failed" = 5 ] && [ "$kept" = 5 ] && grep -q 'tier 2 tf multifrontal default T=1 rc' "$T/results/partial/table.md" && ok "failed runs: 5 failed rows named in the table, 5 kept" ||
  fail "failed runs: $failed failed, $kept kept"
no_scratch "failed runs"

# 3. No run succeeding: exit 5, the earlier results as they were.
EDITS=$T/broken.edit THREADS=1 ROUNDS=1 grid "$D" > "$T/out" 2>&1
rc=$?
[ $rc -eq 5 ] && grep -q "no run succeeded" "$T/out" && ok "no run succeeding: exit 5, said" ||
  fail "no run succeeding: exit $rc: $(tail -3 "$T/out")"
diff -r "$T/before" "$D" > /dev/null && ok "no run succeeding: results unchanged" || fail "no run succeeding: results changed"
no_scratch "no run succeeding"

# 4. SIGTERM once a run is seen running: exit 143, the earlier results as they were, no child left.
(EDITS="$SRC/data/edits/armadillo_whole.edit" THREADS="1 2" BUILD=$BIN exec bash scripts/device_threads.sh local "$D") \
  > "$T/out" 2>&1 &
pid=$!  # the script itself
end=$((SECONDS + 120))
until pgrep -f "deform $SRC/data/edits/armadillo_whole.edit" > /dev/null || ((SECONDS > end)); do sleep 0.05; done
kill -TERM $pid
wait $pid
rc=$?
[ $rc -eq 143 ] && ok "SIGTERM: exit 143" || fail "SIGTERM: exit $rc, expected 143: $(tail -3 "$T/out")"
sleep 0.5
pgrep -f "deform $SRC/data/edits/armadillo_whole.edit" > /dev/null && fail "SIGTERM: a run left running" || ok "SIGTERM: no child left"
diff -r "$T/before" "$D" > /dev/null && ok "SIGTERM: results unchanged" || fail "SIGTERM: results changed"
no_scratch SIGTERM

[ $fails -eq 0 ] && echo "PASS" || { echo "$fails failure(s)"; exit 1; }
