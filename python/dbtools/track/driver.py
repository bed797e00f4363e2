"""Regression tracking of init time and memory across commits (`./run track`, `python3 -m dbtools.track`).

  python3 -m dbtools.track [--runs N] [--baseline REV [--interleave] | --baseline-file CSV... | --baseline-runs N]
                           [--repeats N]
                           [--only GLOBS] [--override RULE]...
                           [gate options: --threshold PCT ...] [--allow-stale] [--allow-foreign]
                           [--save-reference] [--no-plots]
  python3 -m dbtools.track --bisect GOOD BAD --cell CELL --measure MEASURE [--runs N] [--repeats N] [--threshold PCT]

run (without --bisect): builds exp_track, runs the suite of data/experiments/track.toml (experiments/track.cpp)
--runs times (default 2), each run a new history file results/history/runs/<UTC>_<commit>_<machine>.csv, picks a
baseline and gates the runs, their rounds pooled (history.pooled), against it (gate.py: the cells that ran; a stale
or foreign baseline is refused, exit 3 / 4), writing results/track.md, the runs as github-action-benchmark JSON
(ci.py: runs/<name>.json beside each CSV, the runs pooled as results/history/latest.json), the trend figures
(dbtools.plots.history, into results/figures/) and the site (dbtools.site, results/site/). The build must be a
Release build. Why two runs a side by default: with one run a side the gate's CPU-time rule failed unchanged code
and missed planted slowdowns on a shared machine; the measurements are in results/records (docs/tracking.md).
  baseline: --baseline REV: the newest --runs histories of REV on this machine (those there are), else REV built
            in a git worktree (WORK/rev-<sha>) and measured --runs times now; default: the newest --runs histories
            of the newest ancestor commit (HEAD included) with a history on this machine id, clean and without
            overrides, in results/history/runs or results/history/reference (fewer when fewer exist: the report
            says so); else the newest committed reference of this machine, else of another machine (foreign:
            refused, exit 4, unless --allow-foreign, which gates its deterministic measures only); none at all: the
            runs are recorded, nothing gated. The baseline's histories are pooled as the runs are.
  --interleave (with --baseline REV): REV built in a worktree whatever its histories, and its runs alternated with
            this tree's, REV's first (B N B N ...: --runs of each): both sides then see the machine in the same
            states, minute by minute, which a baseline measured earlier does not (a VM's CPU speed moves between
            runs minutes apart; records 2026-11-26-gate-rule, 2026-11-26-gate-interleaved). Twice the time of a run.
--bisect: finds the first commit between GOOD and BAD where MEASURE of CELL regressed by the gate's rules: GOOD and
  BAD with --runs histories each (those there are, the others measured: that cell only, built in the worktree
  WORK/bisect), then `git bisect run` with this script's bisect-step (build, measure --runs times, gate against
  GOOD, pooled; a commit that does not build or cannot run the cell is skipped).
  WORK (default BUILD/track, git-ignored) holds only the worktrees of a command under way: each is removed when
  its commit is measured (--baseline) or the bisection ends.
Exit codes: 0 pass / found; 1 regression, usage, or (bisect) BAD not regressed; 2 could not build, measure or read;
3 stale baseline; 4 foreign baseline (provenance.py).
Environment: DEFORMBENCH_BUILD_DIR (default build/), JOBS (default 2), DEFORMBENCH_TRACK_MEASURE (tests: a command
`CMD machine-id` / `CMD measure SRC OUT COMMIT ONLY` used instead of building and running exp_track).
"""
import argparse
import csv
import datetime
import os
import shlex
import subprocess
import sys
from pathlib import Path

from . import ci
from . import gate as track_gate
from .history import InputError, load_runs

PY = "/usr/bin/python3"
# Runs of the suite a side of the gate by default (--runs; the default baseline: that many runs of its commit),
# their rounds pooled: one run a side does not make a gate that stays quiet on unchanged code on a shared machine
# (records 2026-11-26-gate-false-alarms, 2026-11-26-gate-default). power.py measures this configuration by default.
DEFAULT_RUNS = 2
PACKAGES = Path(__file__).resolve().parents[2]  # <repo>/python: the PYTHONPATH of the commands this one starts


class Failure(Exception):
    """Could not build, measure or read: exit 2."""


def log(msg):
    print(f"[track] {msg}", file=sys.stderr, flush=True)


def sh(cmd, cwd=None, check=True, capture=True, env=None):
    p = subprocess.run(cmd, cwd=cwd, text=True, env=env, stdout=subprocess.PIPE if capture else None,
                       stderr=subprocess.PIPE if capture else None)
    if check and p.returncode != 0:
        err = (p.stderr or "").strip().splitlines()[-5:] if capture else []
        raise Failure(f"{' '.join(map(str, cmd))}: exit {p.returncode}" + ("\n  " + "\n  ".join(err) if err else ""))
    return p


def git(repo, *args, check=True):
    return sh(["git", "-C", str(repo), *args], check=check).stdout.strip()


def rev(repo, name):
    p = sh(["git", "-C", str(repo), "rev-parse", "--verify", "--quiet", f"{name}^{{commit}}"], check=False)
    if p.returncode != 0:
        raise UsageError(f"{name}: not a commit of {repo}")
    return p.stdout.strip()


class UsageError(Exception):
    pass


def is_ancestor(repo, a, b):
    return sh(["git", "-C", str(repo), "merge-base", "--is-ancestor", a, b], check=False).returncode == 0


class Context:
    """Where things are: the repository measured, its build, the worktrees for other commits, the histories."""

    def __init__(self, a):
        self.repo = Path(a.repo).resolve() if a.repo else PACKAGES.parent
        self.build = Path(os.environ.get("DEFORMBENCH_BUILD_DIR") or self.repo / "build").resolve()
        self.work = Path(a.work_dir).resolve() if a.work_dir else self.build / "track"
        self.history = Path(a.history_dir).resolve() if a.history_dir else self.repo / "results" / "history"
        self.report = Path(a.report).resolve() if a.report else self.repo / "results" / "track.md"
        self.config = Path(a.config).resolve() if a.config else self.repo / "data" / "experiments" / "track.toml"
        self.data = self.repo / "data"
        self.jobs = os.environ.get("JOBS", "2")
        hook = os.environ.get("DEFORMBENCH_TRACK_MEASURE")
        self.hook = shlex.split(hook) if hook else None
        self.args, self.repeats, self.runs = a, a.repeats, a.runs
        self.only, self.overrides, self.build_current = a.only, a.override or [], not a.no_build


# ------------------------------------------------------------------------------------------------ measuring
def build(ctx, src, build_dir):
    """Configures (when new) and builds exp_track of the tree at `src` in `build_dir`."""
    if not ctx.hook:
        cmake_build(src, build_dir, "exp_track", ctx.jobs)


def cmake_build(src, build_dir, target, jobs):
    """Configures `build_dir` as a Release build of `src` when it is new (else refuses another build type) and
    builds `target` there."""
    if (build_dir / "CMakeCache.txt").exists():
        check_release(build_dir)
    else:
        log(f"configuring {build_dir}")
        ccache = sh(["which", "ccache"], check=False).returncode == 0
        launcher = ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"] if ccache else []
        sh(["cmake", "-S", str(src), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release", *launcher])
    log(f"building {target} in {build_dir}")
    p = sh(["cmake", "--build", str(build_dir), "-j", jobs, "--target", target], check=False)
    if p.returncode != 0:
        tail = "\n".join((p.stdout + p.stderr).strip().splitlines()[-15:])
        raise Failure(f"build of {target} in {build_dir} failed:\n{tail}")


def check_release(build_dir):
    """Records are of Release builds only (the gate compares like with like): refuses another build type."""
    with open(build_dir / "CMakeCache.txt") as f:
        types = [line.strip().split("=", 1)[1] for line in f if line.startswith("CMAKE_BUILD_TYPE:")]
    if types != ["Release"]:
        raise Failure(f"{build_dir} is a {types[0] if types and types[0] else 'default'} build: the tracking suite "
                      "measures Release builds (cmake -DCMAKE_BUILD_TYPE=Release)")


def machine_id(ctx):
    cmd = ctx.hook + ["machine-id"] if ctx.hook else [str(ctx.build / "exp_track"), "--machine-id"]
    return sh(cmd).stdout.split()[0]


def short_sha(src):
    sha = git(src, "rev-parse", "--short=12", "HEAD")
    return sha + "+dirty" if git(src, "status", "--porcelain", "--untracked-files=no") else sha


def measure(ctx, src, build_dir, out, commit, only, overrides):
    """Runs the suite of the tree at `src` (built in `build_dir`) into the history `out`. The suite is always the
    current tree's config and data, so a baseline measures the same cells."""
    out.parent.mkdir(parents=True, exist_ok=True)
    if ctx.hook:
        cmd = ctx.hook + ["measure", str(src), str(out), commit, only or ""]
    else:
        cmd = [str(build_dir / "exp_track"), "--config", str(ctx.config), "--data", str(ctx.data), "--commit", commit,
               "--out", str(out), "--mesh-cache", str(ctx.repo / "results" / "cells" / "meshes")]
        cmd += ["--only", only] if only else []
        cmd += ["--repeats", str(ctx.repeats)] if ctx.repeats else []
        for o in overrides:
            cmd += ["--override", o]
    # Single-threaded as exp_track makes itself: also for a baseline commit whose driver predates that.
    env = dict(os.environ, DEFORMBENCH_SOURCE_DIR=str(src), DEFORMBENCH_GIT_SHA=short_sha(src),
               OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", DEFORMBENCH_THREADS="1")
    log(f"measuring {commit[:12]} ({src}) -> {out}")
    p = subprocess.run(cmd, cwd=str(ctx.repo), env=env, stdout=subprocess.DEVNULL)
    # A cell failed (the history says which): 5, the drivers' kCellsFailedExit (harness/driver.h); 3 from commits
    # before it.
    if p.returncode not in (0, 3, 5) or not out.exists():
        raise Failure(f"the suite of {commit[:12]} did not run (exit {p.returncode})")
    return out


def worktree(ctx, name, sha):
    """A detached worktree of `sha` under WORK/name (created, or moved to `sha`)."""
    wt = ctx.work / name
    if (wt / ".git").exists():
        git(wt, "checkout", "--quiet", "--detach", sha)
    else:
        ctx.work.mkdir(parents=True, exist_ok=True)
        git(ctx.repo, "worktree", "prune")
        git(ctx.repo, "worktree", "add", "--quiet", "--detach", str(wt), sha)
    return wt


def drop_worktree(ctx, wt):
    """Removes a worktree made by worktree() (its build folder with it): a commit's history, once recorded, is what
    later runs reuse."""
    if wt.exists():
        git(ctx.repo, "worktree", "remove", "--force", str(wt), check=False)
    git(ctx.repo, "worktree", "prune", check=False)


def run_path(ctx, commit_label, machine):
    """RESULTS/history/runs/<UTC>_<commit>_<machine>.csv, a name no run has taken."""
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    base = f"{stamp}_{commit_label.replace('+', '_')}_{machine}"
    path, k = ctx.history / "runs" / f"{base}.csv", 1
    while path.exists():
        k += 1
        path = ctx.history / "runs" / f"{base}-{k}.csv"
    return path


def measure_runs(ctx, src, build_dir, commit, label, machine, only, overrides, n):
    """`n` runs of the suite of the tree at `src`, back to back, each a history file of its own: their paths."""
    return [measure(ctx, src, build_dir, run_path(ctx, label, machine), commit, only, overrides) for _ in range(n)]


def measure_commit(ctx, sha, machine, only, n, tree="rev"):
    """Builds `sha` in a worktree and measures it `n` times (no overrides) into results/history/runs: the paths.
    The worktree WORK/rev-* is removed afterwards; WORK/bisect stays until the bisection ends."""
    wt = worktree(ctx, tree if tree == "bisect" else f"rev-{sha[:12]}", sha)
    try:
        build(ctx, wt, wt / "build")
        return measure_runs(ctx, wt, wt / "build", sha, sha[:12], machine, only, [], n)
    finally:
        if tree != "bisect":
            drop_worktree(ctx, wt)


def interleaved(ctx, sha, head, label, machine):
    """--interleave: `sha` built in a worktree, then its runs and this tree's alternated, `sha`'s first, --runs of
    each: (the baseline's paths, the run's paths). The worktree is removed afterwards."""
    wt = worktree(ctx, f"rev-{sha[:12]}", sha)
    try:
        build(ctx, wt, wt / "build")
        base, now = [], []
        for _ in range(ctx.runs):
            base.append(measure(ctx, wt, wt / "build", run_path(ctx, sha[:12], machine), sha, ctx.only, []))
            now.append(measure(ctx, ctx.repo, ctx.build, run_path(ctx, label, machine), head, ctx.only,
                               ctx.overrides))
        return base, now
    finally:
        drop_worktree(ctx, wt)


# ------------------------------------------------------------------------------------------------ histories
def read_meta(path):
    """The first row of a history file (its metadata), or None when it is no history."""
    try:
        with open(path, newline="") as f:
            row = next(csv.DictReader(f), None)
    except (OSError, csv.Error, UnicodeDecodeError):
        return None
    if not row or not all(k in row for k in ("commit", "date", "machine_id", "cell")):
        return None
    return dict(row, path=Path(path), reference=Path(path).parent.name == "reference",
                dirty=row.get("git_sha", "").endswith("+dirty") or row["commit"].endswith("+dirty"))


def histories(ctx):
    files = sorted((ctx.history / "runs").glob("*.csv")) + sorted((ctx.history / "reference").glob("*.csv"))
    return [m for m in map(read_meta, files) if m]


def newest(metas, n=1):
    """The newest `n` of `metas` (histories' first rows), oldest first."""
    return sorted(metas, key=lambda m: (m["date"], m["path"].name))[-n:]


def cells_of(path):
    with open(path, newline="") as f:
        return {r["cell"] for r in csv.DictReader(f)}


def suite_cells(ctx, only):
    """The names of the cells the suite defines (those --only picks, when given), from the driver's --dry-run."""
    if ctx.hook:
        out = sh(ctx.hook + ["cells", only or ""]).stdout
    else:
        cmd = [str(ctx.build / "exp_track"), "--config", str(ctx.config), "--data", str(ctx.data), "--dry-run"]
        out = sh(cmd + (["--only", only] if only else [])).stdout
    return {line.split()[0] for line in out.splitlines() if line.strip()}


def candidates(ctx, machine=None, commit=None, cells=()):
    """Clean histories without overrides that hold every cell of `cells` (of `machine` and `commit` when given)."""
    out = []
    for m in histories(ctx):
        if m["dirty"] or m.get("overrides") or (machine and m["machine_id"] != machine) or \
                (commit and m["commit"] != commit):
            continue
        if set(cells) <= cells_of(m["path"]):
            out.append(m)
    return out


def runs_of(metas, n):
    """The paths of the newest `n` histories of the commit and machine of the newest of `metas`, and a phrase
    saying how many that is ("2 runs of 1a2b3c4d5e6f", with "only" when fewer than `n` exist)."""
    top = newest(metas)[0]
    runs = newest([m for m in metas if m["commit"] == top["commit"] and m["machine_id"] == top["machine_id"]], n)
    few = f"only {len(runs)} of the {n} asked (--runs) exist: " if len(runs) < n else ""
    return [m["path"] for m in runs], f"{few}{len(runs)} run(s) of {top['commit'][:12]}"


def choose_baseline(ctx, machine, head, now):
    """(history paths, why) for the default baseline of the runs `now` (paths), or (None, why)."""
    mine = {Path(p).resolve() for p in now}
    clean = [m for m in candidates(ctx, cells=cells_of(now[0])) if m["path"].resolve() not in mine]
    same = [m for m in clean if m["machine_id"] == machine]
    anc = [m for m in same if is_ancestor(ctx.repo, m["commit"], head)]
    for pick, why in ((anc, "the newest histories of an ancestor commit on this machine"),
                      ([m for m in same if m["reference"]], "this machine's committed reference (not an ancestor)"),
                      ([m for m in clean if m["reference"]],
                       "a committed reference of another machine (foreign: --allow-foreign gates its deterministic "
                       "measures)")):
        if pick:
            paths, how = runs_of(pick, ctx.runs)
            return paths, f"{why}: {how}"
    return None, "no history of an ancestor commit on this machine and no committed reference"


def baseline_of_rev(ctx, sha, machine):
    """The newest --runs histories of `sha` on this machine (those there are), else `sha` built and measured now."""
    mine = candidates(ctx, machine, sha, suite_cells(ctx, ctx.only))
    if mine:
        paths, how = runs_of(mine, ctx.runs)
        return paths, f"the newest histories of {sha[:12]} on this machine: {how}"
    log(f"{sha[:12]} has no history on this machine: building it in a worktree")
    return (measure_commit(ctx, sha, machine, ctx.only, ctx.runs),
            f"{sha[:12]} built in a worktree and measured now: {ctx.runs} run(s)")


# ------------------------------------------------------------------------------------------------ gating
def sides_line(base, now):
    """What the two sides of the gate are, in words: how many runs each, pooled."""
    return (f"runs a side: {now.runs} run(s) now, {base.runs} run(s) in the baseline, each side's rounds pooled "
            f"(--runs, default {DEFAULT_RUNS})")


def gate(ctx, base_path, now_path, cells=(), measures=(), markdown=None, quiet=False, suite=None, notes=()):
    """gate.py's exit code for NOW against BASE (each a history path or a list of them, pooled: 0 pass, 1
    regression, 3 stale, 4 foreign baseline); `suite`: the cells the current suite defines; `notes`: lines for
    the report."""
    try:
        base, now = load_runs(base_path), load_runs(now_path)
    except InputError as e:
        raise Failure(str(e))
    a = ctx.args
    s = track_gate.settings(None, a, cells, measures)
    return track_gate.gate(base, now, s, suite, a.allow_stale, a.allow_foreign, markdown, quiet,
                           notes=[sides_line(base, now), *notes])


def plots(ctx):
    """The trend figures (dbtools.plots.history) into results/figures/; their failure leaves the verdict alone."""
    results = ctx.repo / "results"
    p = subprocess.run([PY, "-m", "dbtools.plots.history", "--results", str(results), "--out", str(results / "figures")],
                       env=dict(os.environ, PYTHONPATH=str(PACKAGES), PYTHONDONTWRITEBYTECODE="1"))
    if p.returncode != 0:
        log("dbtools.plots.history failed (the gate's verdict stands)")


def site(ctx):
    """The static site (dbtools.site, results/site/) with the new history; its failure leaves the verdict alone."""
    (ctx.repo / "results").mkdir(exist_ok=True)
    p = subprocess.run([PY, "-m", "dbtools.site", "--results", str(ctx.repo / "results")],
                       env=dict(os.environ, PYTHONPATH=str(PACKAGES), PYTHONDONTWRITEBYTECODE="1"))
    if p.returncode != 0:
        log("dbtools.site failed (the gate's verdict stands)")


def local_baseline(ctx, machine, head, label, n):
    """(baseline, why) from --baseline-runs: this machine's history of an ancestor when it has one (None: the
    default choice finds it), else `n` runs of the current tree measured now (their paths: gated as one record,
    history.pooled)."""
    mine = [m for m in candidates(ctx, machine, cells=suite_cells(ctx, ctx.only))
            if is_ancestor(ctx.repo, m["commit"], head)]
    if mine:
        return None, "this machine has a history of an ancestor commit: --baseline-runs not needed"
    log(f"no history of an ancestor commit on machine {machine}: a local baseline of {n} run(s) of this commit first")
    runs = measure_runs(ctx, ctx.repo, ctx.build, head, label, machine, ctx.only, ctx.overrides, n)
    return runs, (f"a local baseline of {n} run(s) of this commit on this machine, measured now, their rounds "
                  f"pooled ({', '.join(p.name for p in runs)}): this comparison is of unchanged code, a check of "
                  "the gate's noise here")


def save_reference(ctx, path, machine):
    """Makes `path` this machine's committed reference history (replacing the older one of this machine)."""
    ref = ctx.history / "reference"
    ref.mkdir(parents=True, exist_ok=True)
    for m in histories(ctx):
        if m["reference"] and m["machine_id"] == machine:
            m["path"].unlink()
    dest = ref / Path(path).name
    dest.write_bytes(Path(path).read_bytes())
    log(f"reference history of machine {machine}: {dest} (commit it)")


def cmd_run(ctx, a):
    if ctx.build_current:
        build(ctx, ctx.repo, ctx.build)
    elif not ctx.hook:
        check_release(ctx.build)
    machine, head = machine_id(ctx), rev(ctx.repo, "HEAD")
    base, why, now = None, "", None
    label = short_sha(ctx.repo)
    if a.interleave:
        sha = rev(ctx.repo, a.baseline)
        base, now = interleaved(ctx, sha, head, label, machine)
        why = f"{sha[:12]} built in a worktree, its runs interleaved with this tree's ({ctx.runs} of each)"
    elif a.baseline:
        base, why = baseline_of_rev(ctx, rev(ctx.repo, a.baseline), machine)
    elif a.baseline_file:
        base, why = [Path(p) for p in a.baseline_file], f"the history file(s) given ({len(a.baseline_file)})"
    if base is None and a.baseline_runs:
        base, why = local_baseline(ctx, machine, head, label, a.baseline_runs)
        if base is None:
            log(why)
    if now is None:
        now = measure_runs(ctx, ctx.repo, ctx.build, head, label, machine, ctx.only, ctx.overrides, ctx.runs)
    try:
        log(f"github-action-benchmark JSON: {', '.join(ci.write(now, ctx.history / 'latest.json'))} and "
            f"{ctx.history / 'latest.json'} ({len(now)} run(s) pooled)")
    except InputError as e:
        raise Failure(f"the run's history cannot be read: {e}")
    if base is None:
        base, why = choose_baseline(ctx, machine, head, now)
    code = 0
    if base is None:
        nxt = "uncommitted changes: never a baseline" if label.endswith("+dirty") or ctx.overrides else \
            "the baseline of the next run"
        log(f"recorded {len(now)} run(s), {', '.join(map(str, now))} ({nxt}); {why}: nothing to compare")
    else:
        log(f"baseline: {why}: {', '.join(map(str, base))}")
        code = gate(ctx, base, now, cells=ctx.only.split(",") if ctx.only else (), markdown=ctx.report,
                    suite=suite_cells(ctx, None), notes=[f"baseline: {why}"])
        if code in (0, 1):
            log(f"report: {ctx.report}")
    if a.save_reference:
        save_reference(ctx, now[-1], machine)
    if not a.no_plots:
        plots(ctx)
        site(ctx)
    return code


# ------------------------------------------------------------------------------------------------ bisect
def measured(ctx, sha, machine, cell):
    """--runs histories of `sha` on this machine holding `cell`: the newest there are, the others measured now in
    the bisect tree."""
    mine = [m["path"] for m in newest(candidates(ctx, machine, sha, [cell]), ctx.runs)]
    if len(mine) < ctx.runs:
        mine += measure_commit(ctx, sha, machine, cell, ctx.runs - len(mine), tree="bisect")
    return mine


def cmd_bisect(ctx, a):
    good, bad = rev(ctx.repo, a.bisect[0]), rev(ctx.repo, a.bisect[1])
    if not is_ancestor(ctx.repo, good, bad) or good == bad:
        raise UsageError(f"{a.bisect[0]} is not an ancestor of {a.bisect[1]}")
    if ctx.build_current:
        build(ctx, ctx.repo, ctx.build)
    machine = machine_id(ctx)
    try:
        return bisect(ctx, a, good, bad, machine)
    finally:
        drop_worktree(ctx, ctx.work / "bisect")


def bisect(ctx, a, good, bad, machine):
    good_h = measured(ctx, good, machine, a.cell)
    bad_h = measured(ctx, bad, machine, a.cell)
    code = gate(ctx, good_h, bad_h, [a.cell], [a.measure])
    if code not in (0, 1):
        return code
    if code == 0:
        print(f"{a.bisect[1]} does not regress {a.cell} {a.measure} against {a.bisect[0]}: nothing to bisect")
        return 1
    wt = worktree(ctx, "bisect", bad)
    step = [PY, "-m", "dbtools.track", "--repo", str(ctx.repo), "--work-dir", str(ctx.work),
            "--history-dir", str(ctx.history), "--config", str(ctx.config),
            "--bisect-step", *map(str, good_h), "--cell", a.cell, "--measure", a.measure, "--runs", str(ctx.runs),
            *track_gate.rule_args(a)]
    step += ["--repeats", str(ctx.repeats)] if ctx.repeats else []
    step += [f for f, on in (("--allow-stale", a.allow_stale), ("--allow-foreign", a.allow_foreign)) if on]
    git(wt, "bisect", "reset", check=False)
    try:
        git(wt, "bisect", "start", bad, good)
        p = sh(["git", "-C", str(wt), "bisect", "run", *step], check=False,
               env=dict(os.environ, PYTHONPATH=str(PACKAGES)))
        print(p.stdout)
        found = [line for line in p.stdout.splitlines() if line.endswith("is the first bad commit")]
        log_text = git(wt, "bisect", "log", check=False)
    finally:
        git(wt, "bisect", "reset", check=False)
    if not found:
        raise Failure(f"git bisect run found no first bad commit:\n{p.stdout}\n{p.stderr}")
    sha = found[0].split()[0]
    print(f"first bad commit for {a.cell} {a.measure}: {sha} {git(ctx.repo, 'log', '-1', '--format=%s', sha)}")
    print(log_text)
    return 0


def cmd_bisect_step(ctx, a):
    """One step of `git bisect run` in the bisect worktree: 0 good, 1 bad, 125 cannot tell (skip)."""
    wt = ctx.work / "bisect"
    sha = rev(wt, "HEAD")
    try:
        machine = machine_id(ctx)
        build(ctx, wt, wt / "build")
        now = measure_runs(ctx, wt, wt / "build", sha, sha[:12], machine, a.cell, [], ctx.runs)
        h = load_runs(now)
        if a.cell in h.failed:
            log(f"{sha[:12]}: the cell failed ({h.failed[a.cell]}): skipped")
            return 125
        code = gate(ctx, a.bisect_step, now, [a.cell], [a.measure])
        if code not in (0, 1):
            log(f"{sha[:12]}: its history cannot be gated against GOOD's (exit {code}): skipped")
        return code if code in (0, 1) else 125
    except (Failure, InputError) as e:
        log(f"{sha[:12]}: {e}: skipped")
        return 125


# ------------------------------------------------------------------------------------------------ main
def parse_args(argv):
    ap = track_gate.UsageParser(prog="./run track", description=__doc__.split("\n")[0], allow_abbrev=False,
                formatter_class=argparse.RawDescriptionHelpFormatter, epilog="\n".join(__doc__.split("\n")[2:]))
    ap.add_argument("--baseline", metavar="REV", help="compare with this commit (measured now when it has no history)")
    ap.add_argument("--interleave", action="store_true", help="with --baseline: build REV now and alternate its runs "
                    "with this tree's (both sides in the same machine state)")
    ap.add_argument("--runs", type=int, default=DEFAULT_RUNS, metavar="N", help="runs of the suite a side of the "
                    f"gate, rounds pooled: N runs now, the newest N of the baseline commit ({DEFAULT_RUNS})")
    ap.add_argument("--baseline-file", metavar="CSV", action="append", help="compare with this history file "
                    "(repeated: those runs pooled)")
    ap.add_argument("--baseline-runs", type=int, metavar="N", help="on a machine with no history of an ancestor "
                    "commit: first N runs of this commit as the baseline (pooled), so times are gated at once")
    ap.add_argument("--bisect", nargs=2, metavar=("GOOD", "BAD"), help="find the first commit where --measure of "
                    "--cell regressed")
    ap.add_argument("--cell", help="bisect: the cell (its name in the history, e.g. deform/armadillo/tf/structured/"
                    "multifrontal)")
    ap.add_argument("--measure", help="bisect: the measure (e.g. nnz_factor, init_cpu_s, peak_rss_bytes)")
    ap.add_argument("--repeats", type=int, help="rounds over the suite (default the config's, 10; timed measures "
                    "need >= 5 to be gated)")
    ap.add_argument("--only", help="only cells matching these globs (comma-separated)")
    ap.add_argument("--override", action="append", help="a rule 'key=value ...: key=value ...' changing the cells "
                    "it matches (e.g. 'kind=deform method=tf: ordering=natural'); such a run is never a baseline")
    track_gate.add_rule_options(ap)
    track_gate.add_baseline_options(ap)
    ap.add_argument("--config", help="the suite (default data/experiments/track.toml)")
    ap.add_argument("--save-reference", action="store_true", help="make this run the machine's committed reference")
    ap.add_argument("--no-plots", action="store_true", help="skip the trend figures (dbtools.plots.history) and the "
                    "site (dbtools.site)")
    ap.add_argument("--no-build", action="store_true", help="use the existing build of this tree")
    ap.add_argument("--history-dir", help="histories: runs/ and reference/ (default results/history)")
    ap.add_argument("--report", help="the Markdown report of the comparison (default results/track.md)")
    ap.add_argument("--repo", help=argparse.SUPPRESS)       # tests: the repository measured
    ap.add_argument("--work-dir", help="worktrees for other commits (default BUILD/track)")
    ap.add_argument("--bisect-step", nargs="+", help=argparse.SUPPRESS)  # internal: a step of git bisect run (GOOD's)
    a = ap.parse_args(argv)
    if (a.bisect or a.bisect_step) and not (a.cell and a.measure):
        ap.error("--bisect needs --cell and --measure")
    if sum(map(bool, (a.bisect, a.baseline, a.baseline_file))) > 1:
        ap.error("--bisect, --baseline and --baseline-file do not go together")
    if a.interleave and not a.baseline:
        ap.error("--interleave needs --baseline REV")
    if a.repeats is not None and a.repeats < 1:
        ap.error("--repeats must be >= 1")
    if a.runs < 1:
        ap.error("--runs must be >= 1")
    if a.baseline_runs is not None and (a.baseline_runs < 1 or a.bisect or a.baseline or a.baseline_file):
        ap.error("--baseline-runs N: N >= 1, and not with --bisect, --baseline or --baseline-file")
    track_gate.settings(ap, a)  # usage errors in the gate's options now, not after the run
    return a


def main(argv=None):
    a = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        ctx = Context(a)
        if a.bisect_step:
            return cmd_bisect_step(ctx, a)
        return cmd_bisect(ctx, a) if a.bisect else cmd_run(ctx, a)
    except UsageError as e:
        print(f"track: error: {e}", file=sys.stderr)
        return 1
    except Failure as e:
        print(f"track: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
