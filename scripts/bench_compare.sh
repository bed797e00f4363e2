#!/usr/bin/env bash
# Reruns the Google Benchmark suite (bench/phases.cpp -> bench_phases) and compares it with the committed
# baseline results/bench/baseline.json: prints Google Benchmark's compare.py report and FAILS (exit 1) when any
# benchmark's median CPU time (gbench's cpu_time) is slower than the baseline by more than the threshold, or when
# its `bytes` or `nnz_L` counter (deterministic: matrix / factor bytes, factor nonzeros) grew by more than 0.5%;
# every change of a counter is reported. CPU time, as in ./run track: the suite runs single-threaded, so time
# slicing by other processes on a shared machine does not lengthen it, where it stretches the wall time
# (real_time); the wall-time medians are reported beside it and gated only with --gate-wall.
#
#   scripts/bench_compare.sh [--threshold PCT] [--gate-wall] [--repetitions N] [--min-time S] [--threads N]
#                            [--full] [--baseline FILE] [--update-baseline] [--run FILE] [-- EXTRA bench_phases FLAGS]
#
#   --threshold PCT     allowed slowdown of the median over repetitions, percent (default 25)
#   --gate-wall         gate the wall time (real_time) by the same threshold too (a quiet machine; with --threads
#                       above 1 gbench's cpu_time counts the main thread only, so gate the wall time then)
#   --repetitions N     repetitions per benchmark (default 5); --min-time S: seconds per repetition (default 0.1)
#   --threads N         OMP_NUM_THREADS, OPENBLAS_NUM_THREADS and DEFORMBENCH_THREADS (assembly) for the run
#                       (default 1: on a shared machine a parallel region waits for descheduled threads; the
#                       baseline was recorded with 1)
#   --full              also the man and armadillo_loop1 tiers (not in the baseline: reported, never gated)
#   --update-baseline   record this run as the new baseline instead of comparing
#   --run FILE          compare this existing run (a bench_phases JSON) instead of running the suite
#   after --             passed to bench_phases, e.g. -- --benchmark_filter='factorize/.*'
#
# Works from a fresh clone: configures and builds bench_phases in $DEFORMBENCH_BUILD_DIR (default build/) and runs
# scripts/data.sh when the meshes are missing. Each run is kept as results/bench/run-<UTC time>.json (git-ignored);
# the comparison as results/bench/run-<UTC time>.compare.json. Exit codes: 0 no regression, 1 regression or a
# benchmark that errored / disappeared, 2 usage or setup error.
#
# Timings are machine-specific: the baseline was recorded on the machine named in its "context" (and in its
# deformbench_* keys: CPU, BLAS core, git sha). On another machine record your own first with --update-baseline.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${DEFORMBENCH_BUILD_DIR:-$ROOT/build}
JOBS=${JOBS:-2}
PY=/usr/bin/python3
COMPARE=/usr/share/benchmark/compare.py
BASELINE=$ROOT/results/bench/baseline.json
THRESHOLD=25
REPS=5
MIN_TIME=0.1
FULL=()
UPDATE=0
THREADS=1
GATE_WALL=0
EXTRA=()
RUN=

die() { echo "bench_compare: error: $*" >&2; exit 2; }
log() { echo "bench_compare: $*" >&2; }

while (($#)); do
  case "$1" in
    --threshold) THRESHOLD=${2:?--threshold needs a value}; shift 2 ;;
    --gate-wall) GATE_WALL=1; shift ;;
    --repetitions) REPS=${2:?}; shift 2 ;;
    --min-time) MIN_TIME=${2:?}; shift 2 ;;
    --full) FULL=(--full); shift ;;
    --threads) THREADS=${2:?}; shift 2 ;;
    --baseline) BASELINE=${2:?}; shift 2 ;;
    --update-baseline) UPDATE=1; shift ;;
    --run) RUN=${2:?--run needs a file}; shift 2 ;;
    -h|--help) sed -n '2,31p' "$0"; exit 0 ;;
    --) shift; EXTRA=("$@"); break ;;
    *) die "unknown argument '$1' (see --help)" ;;
  esac
done

run_suite() {
  # Build (configure when the build folder is new).
  if [[ ! -f $BUILD/CMakeCache.txt ]]; then
    log "configuring $BUILD"
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null || die "cmake configure failed"
  fi
  log "building bench_phases in $BUILD"
  cmake --build "$BUILD" -j "$JOBS" --target bench_phases >/dev/null || die "build of bench_phases failed"

  # Data (hand and armadillo; --full needs man and armadillo_loop1, also made by the default data step).
  local need=("$ROOT/data/meshes/hand.off" "$ROOT/data/meshes/armadillo.off")
  ((${#FULL[@]})) && need+=("$ROOT/data/meshes/man.off" "$ROOT/data/generated/armadillo_loop1.off")
  local f
  for f in "${need[@]}"; do
    if [[ ! -f $f ]]; then
      log "$f missing: running scripts/data.sh"
      DEFORMBENCH_BUILD_DIR=$BUILD bash "$ROOT/scripts/data.sh" || die "data step failed"
      break
    fi
  done

  mkdir -p "$ROOT/results/bench"
  STAMP=$(date -u +%Y%m%dT%H%M%SZ)
  RUN=$ROOT/results/bench/run-$STAMP.json
  export DEFORMBENCH_SOURCE_DIR=$ROOT OMP_NUM_THREADS=$THREADS OPENBLAS_NUM_THREADS=$THREADS DEFORMBENCH_THREADS=$THREADS
  log "OPENBLAS_CORETYPE=${OPENBLAS_CORETYPE:-<unset: auto-detected>}; $THREADS thread(s); $REPS repetitions x ${MIN_TIME}s"
  "$BUILD/bench_phases" --data "$ROOT/data" "${FULL[@]}" \
    --benchmark_repetitions="$REPS" --benchmark_min_time="$MIN_TIME" \
    --benchmark_display_aggregates_only=true --benchmark_enable_random_interleaving=true \
    --benchmark_out="$RUN" --benchmark_out_format=json "${EXTRA[@]}" || die "bench_phases failed"
  log "wrote $RUN"
}

[[ -x $PY ]] || die "$PY not found"
[[ -f $COMPARE ]] || die "$COMPARE not found: install libbenchmark-tools (./run test installs it)"

if [[ -n $RUN ]]; then
  [[ -f $RUN ]] || die "--run $RUN: no such file"
else
  run_suite
fi

if ((UPDATE)); then
  cp "$RUN" "$BASELINE"
  log "baseline updated: $BASELINE"
  exit 0
fi
[[ -f $BASELINE ]] || die "no baseline at $BASELINE (record one with --update-baseline)"

# The report: compare.py's table (with a Mann-Whitney U test when scipy is available).
UTEST=()
if ! "$PY" -c 'import scipy, numpy' 2>/dev/null; then
  log "scipy/numpy missing for $PY (install python3-scipy): comparing without the U test"
  UTEST=(--no-utest)
fi
COLOR=()
[[ -t 1 ]] || COLOR=(--no-color)
"$PY" "$COMPARE" "${COLOR[@]}" "${UTEST[@]}" -a --dump_to_json "${RUN%.json}.compare.json" \
  benchmarks "$BASELINE" "$RUN" || log "compare.py failed (the gate below still runs)"

# The gate: median CPU time (and with --gate-wall real time) per benchmark against the baseline's.
FILTERED=0
for a in "${EXTRA[@]}"; do if [[ $a == --benchmark_filter* ]]; then FILTERED=1; fi; done
"$PY" - "$BASELINE" "$RUN" "$THRESHOLD" "$FILTERED" "$GATE_WALL" <<'EOF'
import json, statistics, sys

UNIT = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}

COUNTERS = ("bytes", "nnz_L")  # deterministic: compared exactly, an increase over 0.5% fails
COUNTER_LIMIT = 1.005

def counters(runs):
    """name -> {counter: value} from the repetitions (aggregates hold statistics of them: only the median serves,
    when the file has no repetitions)."""
    out = {}
    for b in runs:
        name = b.get("run_name", b["name"])
        if b.get("error_occurred") or (b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median"):
            continue
        if b.get("run_type") == "aggregate" and name in out:
            continue
        out.setdefault(name, {}).update({k: b[k] for k in COUNTERS if k in b})
    return out

def medians(path, clock):
    """name -> the median of `clock` (cpu_time | real_time) in seconds; name -> error message; the counters."""
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    med, reps, errors = {}, {}, {}
    for b in runs:
        name = b.get("run_name", b["name"])
        if b.get("error_occurred"):
            errors[name] = b.get("error_message", "error")
            continue
        t = b[clock] * UNIT[b.get("time_unit", "ns")]
        if b.get("run_type") == "aggregate":
            if b.get("aggregate_name") == "median":
                med[name] = t
        else:
            reps.setdefault(name, []).append(t)
    for name, ts in reps.items():
        med.setdefault(name, statistics.median(ts))
    return med, errors, counters(runs)

limit = 1.0 + float(sys.argv[3]) / 100.0
allow_missing = sys.argv[4] == "1"
gated = ("cpu_time", "real_time") if sys.argv[5] == "1" else ("cpu_time",)
bad = []


def time_gate(clock, gate):
    """Prints new / baseline of each benchmark's median `clock`; appends the regressions to `bad` when `gate`."""
    base, _, _ = medians(sys.argv[1], clock)
    new, new_err, _ = medians(sys.argv[2], clock)
    what = {"cpu_time": "CPU time", "real_time": "real (wall) time"}[clock]
    print(f"\ngate: median {what}, new / baseline, " + (f"fails above {limit:.2f}" if gate else
                                                         "reported only (--gate-wall gates it)"))
    for name in sorted(set(base) | set(new) | set(new_err)):
        if name in new_err:
            print(f"  ERROR      {name}: {new_err[name]}")
            bad.append(name)
        elif name not in new:
            if allow_missing:
                continue  # filtered out on purpose
            print(f"  MISSING    {name} (in the baseline, not in this run)")
            bad.append(name)
        elif name not in base:
            print(f"  NEW        {name}: {new[name]:.4g} s (no baseline)")
        else:
            r = new[name] / base[name]
            slower = r > limit
            tag = ("SLOWER" if gate else "slower") if slower else ("faster" if r < 1 / limit else "ok")
            if slower and gate:
                bad.append(f"{name} {clock}")
            print(f"  {tag:10s} {name}: {base[name]:.4g} s -> {new[name]:.4g} s ({(r - 1) * 100:+.1f}%)")
    return base, new


for clock in ("real_time", "cpu_time"):  # CPU time last: its medians are the whole suite's line below
    base, new = time_gate(clock, clock in gated)
bad = list(dict.fromkeys(bad))  # an error or a missing benchmark is listed by each clock's table once
_, _, base_cnt = medians(sys.argv[1], "cpu_time")
_, _, new_cnt = medians(sys.argv[2], "cpu_time")
print(f"\ngate: counters {', '.join(COUNTERS)} compared exactly, fail above {COUNTER_LIMIT:.3f} x the baseline")
changed = 0
for name in sorted(set(base_cnt) & set(new_cnt)):
    for k in COUNTERS:
        if k not in base_cnt[name] or k not in new_cnt[name] or base_cnt[name][k] == new_cnt[name][k]:
            continue
        b, n = base_cnt[name][k], new_cnt[name][k]
        grew = n > b * COUNTER_LIMIT
        changed += 1
        if grew:
            bad.append(f"{name} {k}")
        print(f"  {'GREW' if grew else 'changed':10s} {name} {k}: {b:.0f} -> {n:.0f}" +
              (f" ({(n / b - 1) * 100:+.2f}%)" if b else ""))
if not changed:
    print("  all equal")
ratios = [new[n] / base[n] for n in new if n in base and base[n] > 0]
if ratios:
    import math
    g = math.exp(sum(math.log(r) for r in ratios) / len(ratios))
    print(f"\nwhole suite: geometric mean of the CPU times new / baseline = {g:.2f} over {len(ratios)} benchmarks "
          "(a shift shared by every benchmark usually means machine load, not code)")
if bad:
    print(f"\nbench_compare: FAIL: {len(bad)} regression(s): a median {' or '.join(gated)} more than "
          f"{(limit - 1) * 100:.0f}% slower, "
          "a counter grown, or a benchmark errored / disappeared")
    sys.exit(1)
print(f"\nbench_compare: OK: no benchmark's {' or '.join(gated)} slower than the baseline by more than "
      f"{(limit - 1) * 100:.0f}%, "
      "no counter grown")
EOF
