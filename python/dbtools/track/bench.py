"""The Google Benchmark suite (bench/phases.cpp -> bench_phases) through the one gate (`./run track bench`).

  python3 -m dbtools.track.bench [--baseline FILE] [--update-baseline] [--run FILE] [--repetitions N]
                                 [--min-time S] [--threads N] [--full] [gate options: --threshold PCT ...]
                                 [--allow-stale] [--allow-foreign] [--cell GLOB] [--measure M]
                                 [-- bench_phases flags]

Builds bench_phases (a Release build in $DEFORMBENCH_BUILD_DIR, default build/; the data step when its meshes are
missing), runs it with --threads (1) for the BLAS, OpenMP and the structured assembly (on a shared machine a
parallel region waits for descheduled threads), --repetitions (5) x --min-time (0.1 s) with random interleaving, and
keeps the raw record results/bench/run-<UTC>.json (--runs-dir). Its context carries the provenance
(core/provenance.h) and the suite's definition: `deformbench_suite` (the hash of every benchmark these options
register, listed by --benchmark_list_tests, whatever a --benchmark_filter ran), `deformbench_suite_version`
(bench/phases.cpp's) and `deformbench_build_type`. Then it gates the run against the baseline
(results/bench/baseline.json) with gate.py's rules on gbench.py's rows, writing results/bench/run-<UTC>.md.
Differences from the tracking suite's defaults: none in the rules; no round drift (--drift-cells 0), since gbench's
repetitions are not rounds over the suite.
A filtered run (-- --benchmark_filter=REGEX) compares the benchmarks that ran: the others are "not run".
--update-baseline records the run as the baseline instead; --run FILE gates an existing record.
Exit: 0 pass, 1 regression or usage, 2 could not build, run or read, 3 stale baseline, 4 foreign baseline.
"""
import argparse
import datetime
import os
import shutil
import subprocess
import sys
from pathlib import Path

from . import gate as g
from .driver import PACKAGES, Failure, cmake_build, log
from .gbench import suite_hash
from .history import InputError, load_history

TIERS = {"hand": "meshes/hand.off", "armadillo": "meshes/armadillo.off", "man": "meshes/man.off",
         "armadillo_loop1": "generated/armadillo_loop1.off"}


def parse_args(argv):
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    ap = g.UsageParser(prog="./run track bench", description=__doc__.split("\n")[0], allow_abbrev=False,
                       formatter_class=argparse.RawDescriptionHelpFormatter, epilog="\n".join(__doc__.split("\n")[2:]))
    ap.add_argument("--baseline", help="the baseline record (default results/bench/baseline.json)")
    ap.add_argument("--update-baseline", action="store_true", help="record this run as the baseline, no gate")
    ap.add_argument("--run", metavar="FILE", help="gate this bench_phases JSON instead of running the suite")
    ap.add_argument("--repetitions", type=int, default=5, help="repetitions per benchmark (5; the CPU-time rule "
                    "needs --min-repeats)")
    ap.add_argument("--min-time", type=float, default=0.1, help="seconds per repetition (0.1)")
    ap.add_argument("--threads", type=int, default=1, help="BLAS, OpenMP and assembly threads (1)")
    ap.add_argument("--full", action="store_true", help="all four tiers (bench_phases --full)")
    ap.add_argument("--markdown", help="the report (default: the run's .md)")
    ap.add_argument("--runs-dir", help="where runs are written (default results/bench)")
    ap.add_argument("--all", action="store_true", help="print every comparison, not only the notable ones")
    g.add_rule_options(ap)
    g.add_baseline_options(ap)
    g.add_filter_options(ap)
    ap.set_defaults(drift_cells=0)
    a = ap.parse_args(argv)
    if a.repetitions < 1 or a.min_time <= 0 or a.threads < 1:
        ap.error("--repetitions and --threads must be >= 1, --min-time > 0")
    if a.run and (extra or a.full):
        ap.error("--run gates an existing record: no bench_phases flags")
    return a, g.settings(ap, a, a.cell, a.measure), extra


def ensure_data(repo, build, tiers):
    missing = [t for t in tiers if not (repo / "data" / TIERS[t]).exists()]
    if missing:
        log(f"meshes of {', '.join(missing)} missing: running scripts/data.sh")
        env = dict(os.environ, DEFORMBENCH_BUILD_DIR=str(build))
        if subprocess.run(["bash", str(repo / "scripts" / "data.sh")], env=env).returncode != 0:
            raise Failure("the data step failed")


def definition(binary, options):
    """The suite these options define: the names of every benchmark bench_phases registers with them."""
    p = subprocess.run([str(binary), *options, "--benchmark_list_tests=true"], text=True, capture_output=True)
    names = [line.strip() for line in p.stdout.splitlines() if line.strip()]
    if p.returncode != 0 or not names:
        raise Failure(f"{binary} --benchmark_list_tests: exit {p.returncode}: {p.stderr.strip()[-400:]}")
    return names


def run_suite(a, repo, build, extra):
    """Runs bench_phases into RUNS/run-<UTC>.json: (its path, the names of the suite's benchmarks)."""
    cmake_build(repo, build, "bench_phases", os.environ.get("JOBS", "2"))
    ensure_data(repo, build, list(TIERS) if a.full else ["hand", "armadillo"])
    binary = build / "bench_phases"
    options = ["--data", str(repo / "data"), *(["--full"] if a.full else []),
               *[x for x in extra if not x.startswith("--benchmark_")]]
    names = definition(binary, options)
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    out = Path(a.runs_dir or repo / "results" / "bench").resolve() / f"run-{stamp}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    threads = str(a.threads)
    env = dict(os.environ, DEFORMBENCH_SOURCE_DIR=str(repo), OMP_NUM_THREADS=threads, OPENBLAS_NUM_THREADS=threads,
               DEFORMBENCH_THREADS=threads)
    cmd = [str(binary), *options, f"--benchmark_repetitions={a.repetitions}", f"--benchmark_min_time={a.min_time}",
           "--benchmark_display_aggregates_only=true", "--benchmark_enable_random_interleaving=true",
           f"--benchmark_out={out}", "--benchmark_out_format=json",
           f"--benchmark_context=deformbench_suite={suite_hash(names)},deformbench_build_type=Release",
           *[x for x in extra if x.startswith("--benchmark_")]]
    log(f"OPENBLAS_CORETYPE={os.environ.get('OPENBLAS_CORETYPE', '<unset: auto-detected>')}; {threads} thread(s); "
        f"{a.repetitions} repetitions x {a.min_time} s")
    if subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL).returncode != 0 or not out.exists():
        raise Failure(f"bench_phases did not run: {' '.join(cmd)}")
    log(f"wrote {out}")
    return out, names


def main(argv=None):
    a, s, extra = parse_args(sys.argv[1:] if argv is None else argv)
    repo = PACKAGES.parent
    build = Path(os.environ.get("DEFORMBENCH_BUILD_DIR") or repo / "build").resolve()
    baseline = Path(a.baseline) if a.baseline else repo / "results" / "bench" / "baseline.json"
    try:
        run, names = (Path(a.run), None) if a.run else run_suite(a, repo, build, extra)
        if a.update_baseline:
            load_history(run)  # a readable record, or no baseline
            shutil.copyfile(run, baseline)
            log(f"baseline updated: {baseline} (commit it)")
            return 0
        if not baseline.exists():
            raise Failure(f"no baseline at {baseline} (record one with --update-baseline)")
        base, now = load_history(baseline), load_history(run)
    except (Failure, InputError) as e:
        print(f"track bench: error: {e}", file=sys.stderr)
        return 2
    md = a.markdown if a.markdown or a.run else str(run.with_suffix(".md"))
    return g.gate(base, now, s, names, a.allow_stale, a.allow_foreign, md, show_all=a.all,
                  title="Google Benchmark suite")


if __name__ == "__main__":
    sys.exit(main())
