#!/usr/bin/env bash
# python3 -m dbtools.track (./run track) on a scratch git repository whose "suite" is tests/track_fake_measure.py (its
# measure.txt as a history of one cell): the default, two runs a side (--runs 2: two runs made, pooled, against the
# newest two of the baseline commit, pooled; fewer when fewer exist, said so; the report naming both sides), the
# default baseline (the newest histories of an ancestor, never a dirty run; each run's github-action-benchmark JSON
# beside its CSV, the runs pooled as history/latest.json), --runs 1, --baseline REV measured
# in a worktree and then reused, the committed reference as a fresh clone's
# baseline (another machine's: refused as foreign, exit 4, unless --allow-foreign), a baseline holding a cell the
# suite no longer defines refused as stale (exit 3), and --bisect finding planted regressions of a deterministic
# and of a timed measure; --baseline-runs N on a machine without history (N runs pooled into the baseline, times
# gated at once, the report saying what was gated) and on one with history (nothing extra runs). Seconds, no build.
#   track_scripts_test.sh SOURCE_DIR
set -u
SRC=$(cd "$1" && pwd)
. "$(dirname "$0")/check_lib.sh"  # $T, expect, fail, ok, $fails
export DEFORMBENCH_TRACK_MEASURE="/usr/bin/python3 $SRC/tests/track_fake_measure.py"

R=$T/repo
git init -q "$R" && cd "$R" || exit 1
git config user.email test@example.com && git config user.name test
step() {  # step SUBJECT NNZ TIME: a commit whose suite measures these
  printf 'nnz_factor=%s\nfactorize_s=%s\n' "$2" "$3" >measure.txt
  git add measure.txt && git commit -qm "$1" --allow-empty && git tag "${1%% *}"
}
step c1 1000 1.0; step c2 1000 1.0; step "c3 slower factorization" 1000 1.5; step c4 1000 1.5
step "c5 more fill" 1300 1.5; step c6 1300 1.5; step c7 1300 1.5
sha() { git -C "$R" rev-parse "$1"; }
no_worktrees() {  # the worktrees of other commits are removed once measured
  [ "$(git -C "$R" worktree list | wc -l)" -eq 1 ] && [ -z "$(ls -A "$T/work" 2>/dev/null)" ] &&
    ok "$1: no worktree left" || fail "$1: worktrees left: $(git -C "$R" worktree list; ls -A "$T/work")"
}

export PYTHONPATH=$SRC/python
TRACK=(/usr/bin/python3 -m dbtools.track --repo "$R" --work-dir "$T/work" --history-dir "$T/history"
  --report "$T/track.md" --no-plots)

ncsv() { ls "$1"/*.csv 2>/dev/null | wc -l; }
expect "first run: recorded, nothing to compare" 0 "recorded 2 run\(s\), .*nothing to compare" -- "${TRACK[@]}"
[ "$(ncsv "$T/history/runs")" -eq 2 ] && ok "the default makes two runs" || fail "runs: $(ls "$T/history/runs")"
expect "second run: the first two are its baseline" 0 \
  "baseline: the newest histories of an ancestor commit on this machine: 2 run\(s\) of $(sha c7 | cut -c1-12)" -- \
  "${TRACK[@]}"
[ "$(ncsv "$T/history/runs")" -eq 4 ] && ok "two more runs" || fail "runs: $(ls "$T/history/runs")"
first2=$(ls "$T"/history/runs/*.csv | head -2 | tr '\n' ' ')
for f in $first2; do grep -q "$(basename "$f")" "$T/output" || fail "the baseline does not name $f: $(cat "$T/output")"; done
grep -q "^runs a side: 2 run(s) now, 2 run(s) in the baseline, each side's rounds pooled" "$T/output" &&
  grep -q "^now: .* and 1 more, pooled" "$T/output" && grep -q "^baseline: .* and 1 more, pooled" "$T/output" &&
  ok "two runs pooled a side, said so" || fail "sides: $(cat "$T/output")"
[ -f "$T/track.md" ] && grep -q "verdict: pass" "$T/track.md" &&
  grep -q "^- runs a side: 2 run(s) now, 2 run(s) in the baseline" "$T/track.md" && ok "report written" ||
  fail "no report: $(cat "$T/track.md")"
# The run as github-action-benchmark's customSmallerIsBetter input, beside its CSV and at a fixed path for CI.
/usr/bin/python3 - "$T/history" >"$T/json.out" 2>&1 <<'PY' && ok "JSON beside each run and latest.json" ||
  fail "JSON: $(cat "$T/json.out")"
import glob, json, os, sys
h = sys.argv[1]
csvs = sorted(glob.glob(f"{h}/runs/*.csv"))
assert csvs and all(os.path.exists(c[:-4] + ".json") for c in csvs), os.listdir(f"{h}/runs")
doc = json.load(open(f"{h}/latest.json"))
last = json.load(open(csvs[-1][:-4] + ".json"))  # one run: 5 rounds; latest.json: the invocation's 2 runs pooled
assert [e["value"] for e in doc] == [e["value"] for e in last] and "5 round(s), min" in last[0]["extra"], last
assert "10 round(s) of 2 runs" in doc[0]["extra"], doc
by = {e["name"]: e for e in doc}
assert sorted(by) == ["fake/cell factorize_s", "fake/cell nnz_factor"], by
assert by["fake/cell factorize_s"]["unit"] == "s" and by["fake/cell factorize_s"]["value"] == 1.5, by
assert by["fake/cell factorize_s"]["range"] == "± 0.045", by
assert by["fake/cell nnz_factor"]["value"] == 1300 and "range" not in by["fake/cell nnz_factor"], by
assert all(isinstance(e["extra"], str) and "commit" in e["extra"] for e in doc)
PY

printf 'nnz_factor=5000\nfactorize_s=1.5\n' >measure.txt  # uncommitted: a dirty run
expect "dirty run gated" 1 "nnz_factor +deterministic +1300 +5000" -- "${TRACK[@]}"
git checkout -q measure.txt
expect "a dirty run is never a baseline" 0 "verdict: pass" -- "${TRACK[@]}"

expect "--baseline REV without history: measured in a worktree" 1 \
  "$(sha c1 | cut -c1-12) built in a worktree and measured now" -- "${TRACK[@]}" --baseline c1
grep -Eq "fake/cell +nnz_factor +deterministic +1000 +1300 +1.300 .*FAIL" "$T/output" &&
  grep -Eq "fake/cell +factorize_s +cpu +1 +1.5 +1.500 +[0-9.e-]+ +FAIL" "$T/output" &&
  ok "--baseline c1 names both regressions" || fail "--baseline c1 report: $(cat "$T/output")"
no_worktrees "--baseline c1"
expect "--baseline REV with history: reused" 1 \
  "the newest histories of $(sha c1 | cut -c1-12) on this machine: 2 run\(s\) of $(sha c1 | cut -c1-12)" -- "${TRACK[@]}" \
  --baseline c1
# --interleave: c1 built in a worktree whatever its histories, its runs alternated with this tree's (their history
# files may share a second with this tree's: the checks after it pick HEAD's files by name).
n0=$(ncsv "$T/history/runs")
expect "--baseline REV --interleave" 1 \
  "$(sha c1 | cut -c1-12) built in a worktree, its runs interleaved with this tree's \(2 of each\)" -- "${TRACK[@]}" \
  --baseline c1 --interleave
grep -Eq "fake/cell +nnz_factor +deterministic +1000 +1300 +1.300 .*FAIL" "$T/output" &&
  [ "$(ncsv "$T/history/runs")" -eq $((n0 + 4)) ] && ok "--interleave: two runs of each, gated" ||
  fail "--interleave: $(ls "$T/history/runs"; cat "$T/output")"
grep -o "measuring [0-9a-f]*" "$T/output" | awk '{print $2}' | cut -c1-7 | tr '\n' ' ' >"$T/order"
c1s=$(sha c1 | cut -c1-7); hs=$(sha HEAD | cut -c1-7)
[ "$(cat "$T/order")" = "$c1s $hs $c1s $hs " ] && ok "--interleave: the baseline's runs first, alternated" ||
  fail "--interleave order: $(cat "$T/order")"
no_worktrees "--interleave"
expect "--interleave without --baseline" 1 "--interleave needs --baseline REV" -- "${TRACK[@]}" --interleave
expect "--baseline-file" 0 "the history file\(s\) given \(1\)" -- "${TRACK[@]}" \
  --baseline-file "$(ls "$T"/history/runs/*_"$(sha HEAD | cut -c1-12)"_*.csv | tail -1)"
grep -q "^runs a side: 2 run(s) now, 1 run(s) in the baseline" "$T/output" && ok "--baseline-file: one run" ||
  fail "--baseline-file: $(cat "$T/output")"
expect "--baseline-file twice: pooled" 0 "the history file\(s\) given \(2\)" -- "${TRACK[@]}" --runs 1 \
  $(ls "$T"/history/runs/*_"$(sha HEAD | cut -c1-12)"_*.csv | tail -2 | sed 's/^/--baseline-file /')
grep -q "^runs a side: 1 run(s) now, 2 run(s) in the baseline" "$T/output" && ok "--runs 1, two baseline files" ||
  fail "--runs 1: $(cat "$T/output")"
expect "--runs 0" 1 "--runs must be >= 1" -- "${TRACK[@]}" --runs 0

expect "bisect a deterministic measure" 0 "first bad commit for fake/cell nnz_factor: $(sha c5) c5 more fill" -- "${TRACK[@]}" \
  --bisect c1 c7 --cell fake/cell --measure nnz_factor
expect "bisect a timed measure" 0 "first bad commit for fake/cell factorize_s: $(sha c3) c3 slower factorization" -- "${TRACK[@]}" \
  --bisect c2 HEAD --cell fake/cell --measure factorize_s
expect "bisect: BAD not regressed" 1 "does not regress" -- "${TRACK[@]}" --bisect c5 c7 --cell fake/cell --measure nnz_factor
no_worktrees "bisect"
git -C "$R" bisect log >/dev/null 2>&1 && fail "bisect left running" || ok "bisect state reset"
expect "bisect: GOOD after BAD" 1 "not an ancestor" -- "${TRACK[@]}" --bisect c7 c1 --cell fake/cell --measure nnz_factor
expect "bisect without --cell" 1 "needs --cell and --measure" -- "${TRACK[@]}" --bisect c1 c7
expect "unknown revision" 1 "nosuch: not a commit" -- "${TRACK[@]}" --baseline nosuch
expect "unknown option" 1 "unrecognized arguments" -- "${TRACK[@]}" --baselin c1

# --baseline-runs on a machine without history: N runs of this commit pooled into the baseline, times gated at once.
expect "--baseline-runs 2 without history" 0 "a local baseline of 2 run\(s\) of this commit" -- "${TRACK[@]}" \
  --history-dir "$T/history4" --baseline-runs 2
grep -q "^gated: 2 of 2 comparisons (cpu 1, deterministic 1)" "$T/output" && ok "--baseline-runs: the CPU time gated" ||
  fail "--baseline-runs: $(cat "$T/output")"
grep -q "^- gated: 2 of 2 comparisons" "$T/track.md" &&
  grep -q "^- baseline: a local baseline of 2 run" "$T/track.md" &&
  ok "the report says what was gated and against what" || fail "track.md: $(cat "$T/track.md")"
[ "$(ncsv "$T/history4/runs")" -eq 4 ] &&
  grep -q "^baseline: .*history4/runs/.* and 1 more, pooled" "$T/output" &&
  ok "two runs gated as one baseline, then the two runs" || fail "history4: $(ls -R "$T/history4"; cat "$T/output")"
expect "--baseline-runs with history: not needed" 0 "--baseline-runs not needed" -- "${TRACK[@]}" --history-dir "$T/history4" \
  --baseline-runs 2
[ "$(ncsv "$T/history4/runs")" -eq 6 ] && ok "--baseline-runs with history: the two runs only" ||
  fail "history4: $(ls "$T/history4/runs")"
expect "--baseline-runs 0" 1 "--baseline-runs N: N >= 1" -- "${TRACK[@]}" --baseline-runs 0
# Without --no-plots a run refreshes the trend figures and the site (RESULTS/site/, dbtools.site) of the repository.
/usr/bin/python3 -m dbtools.track --repo "$R" --work-dir "$T/work" --history-dir "$T/history4" --report "$T/track.md" \
  >"$T/out" 2>&1 && [ -s "$R/results/site/index.html" ] && grep -q "\[site\] .* pages" "$T/out" &&
  ok "a run refreshes the site" || fail "no site after a run: $(tail -c 600 "$T/out")"

# A fresh clone: no runs of its own, only the committed reference (of a commit it does not have).
mkdir -p "$T/history2/reference"
sed "s/^$(sha c7)/$(printf 'f%.0s' {1..40})/" "$(ls "$T"/history/runs/*"$(sha c7 | cut -c1-12)"*.csv | head -1)" \
  >"$T/history2/reference/ref.csv"
TRACK+=(--history-dir "$T/history2")
expect "fresh clone: the committed reference" 0 "this machine's committed reference" -- "${TRACK[@]}"
# The reference is one run: the baseline has fewer runs than --runs asks, and the report says so.
grep -q "only 1 of the 2 asked (--runs) exist: 1 run(s) of ffffffffffff" "$T/output" &&
  grep -q "^- runs a side: 2 run(s) now, 1 run(s) in the baseline" "$T/track.md" &&
  grep -q "only 1 of the 2 asked" "$T/track.md" && ok "fewer baseline runs than --runs: said so" ||
  fail "fewer baseline runs: $(cat "$T/output" "$T/track.md")"

# A fresh clone on another machine: the only reference is foreign.
mkdir -p "$T/history3/reference"
sed "s/,fake-machine,/,other-machine,/" "$T/history2/reference/ref.csv" >"$T/history3/reference/ref.csv"
TRACK+=(--history-dir "$T/history3")
expect "another machine's reference: foreign" 4 \
  "the baseline .*ref.csv \(commit $(sha c7 | cut -c1-12), .*machine other-machine\) is foreign: machine id \
other-machine in the baseline, fake-machine now" -- "${TRACK[@]}"
grep -q "baseline refused (foreign, exit 4)" "$T/track.md" && ok "the report says it was refused" ||
  fail "track.md: $(head -3 "$T/track.md")"
expect "--allow-foreign: its deterministic measures" 0 \
  "foreign baseline \(--allow-foreign\): deterministic measures only" -- "${TRACK[@]}" --allow-foreign \
  --baseline-file "$T/history3/reference/ref.csv"  # the refused run above is this machine's newest history now
grep -q "^not gated: 1: 1 measured on another machine" "$T/output" &&
  ok "--allow-foreign: times not gated, saying why" || fail "--allow-foreign: $(cat "$T/output")"

# A baseline holding a cell the suite no longer defines: stale.
REF=$T/history2/reference/ref.csv
{ cat "$REF"; tail -n +2 "$REF" | sed "s|,fake/cell,|,fake/gone,|"; } >"$T/stale.csv"
expect "a cell the suite no longer defines: stale" 3 \
  "is stale: 1 cell\(s\) the suite no longer defines: fake/gone: record a baseline of the current suite" -- "${TRACK[@]}" \
  --baseline-file "$T/stale.csv"
expect "--allow-stale" 0 "stale baseline compared anyway \(--allow-stale\)" -- "${TRACK[@]}" --baseline-file "$T/stale.csv" \
  --allow-stale

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
