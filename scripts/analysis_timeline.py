#!/usr/bin/env python3
"""Tabulates the analysis timelines that a diagnostic build prints (TIMELINE lines; the build: the head with
scripts/device_timeline.patch, kept applying by tests/device_patch_test.sh (also the factorization's subtree phase
per thread, its top phase and each top front with its team's size as the level and its supernode as the vertices,
and, in its versions after 3da82e8, each top front's steps: front_assemble, front_entries, front_panels,
front_update and front_assemble_update; from 6991f51 to a20ea9b,
results/records/2026-11-28-top-branches/top_timeline.patch); from c1b899e on,
results/records/2026-11-28-given-tree/timeline_usage.patch (with the symbolic analysis's steps); from 30cb971 on,
results/records/2026-11-28-threads/timeline.patch, or tuning/timeline_usage.patch there, whose lines also carry the
thread's CPU seconds and minor page faults during each step; before, the timeline.patch of
2026-11-27-parallel-postorder, 2026-11-27-guided-splits or 2026-11-27-analysis-timeline), one run per block that
starts with a "# LABEL" line.
Per run: each step with its start (from the run's first step), its wall time and its thread (and, where the lines
carry them, its thread's user + system seconds and minor faults); then the analysis
split: the 2-ring pattern for the ordering, the 1-ring guide (where the build has one), the ordering, the
postordering analysis, the multifrontal symbolic analysis; and a bound on the ordering's longest chain of steps:
each dissection level's slowest split and slowest side extraction, then the slowest part's METIS_NodeND (the
slowest steps of two levels may lie on different branches, so the chain can be shorter; meaningful with more than
one thread).
usage: scripts/analysis_timeline.py FILE > table.md"""
import collections
import sys


def runs(path):
    label, steps = None, []
    for line in open(path):
        if line.startswith("# "):
            if steps:
                yield label, steps
            label, steps = line[2:].strip(), []
        elif line.startswith("TIMELINE "):
            what, level, n, start, end, tid = line.split()[1:7]
            usage = line.split()[7:10]  # user s, system s, minor faults: timeline_usage.patch's lines only
            cpu, faults = (float(usage[0]) + float(usage[1]), int(usage[2])) if len(usage) == 3 else (None, None)
            steps.append((what, int(level), int(n), float(start), float(end), tid, cpu, faults))
    if steps:
        yield label, steps


def table(label, steps):
    t0 = min(s[3] for s in steps)
    threads = {tid: k for k, tid in enumerate(dict.fromkeys(s[5] for s in steps))}
    print(f"### {label}\n")
    usage = any(s[6] is not None for s in steps)
    print("| step | level | vertices | start s | wall s | thread |" + (" CPU s | minor faults |" if usage else ""))
    print("|---|---|---|---|---|---|" + ("---|---|" if usage else ""))
    for what, level, n, start, end, tid, cpu, faults in sorted(steps, key=lambda s: s[3]):
        lvl = "" if level <= 0 else str(level)
        extra = (f" {cpu:.3f} | {faults} |" if cpu is not None else " | |") if usage else ""
        print(f"| {what} | {lvl} | {n or ''} | {start - t0:.3f} | {end - start:.3f} | {threads[tid]} |{extra}")
    wall = collections.defaultdict(float)
    split, induced = collections.defaultdict(float), collections.defaultdict(float)
    for what, level, n, start, end, *_ in steps:
        wall[what] += end - start
        if what in ("split", "induced"):
            longest = split if what == "split" else induced
            longest[level] = max(longest[level], end - start)
    splits = {k: split[k] + induced[k] for k in split}  # a level's slowest split, then its slowest side extraction
    parts = [s[4] - s[3] for s in steps if s[0] == "nodend"]
    chain = sum(splits.values()) + (max(parts) if parts else 0.0)
    phases = ("ordering_pattern", "ordering_guide", "ordering", "postorder_analysis", "symbolic")
    analysis = sum(wall[w] for w in phases)
    guide = f" + guide {wall['ordering_guide']:.3f}" if "ordering_guide" in wall else ""
    # Builds from e92e762 on time CHOLMOD's step of the symbolic analysis by its kind: from the ordering's tree or
    # from its own pass over the graph; before, as one step.
    cholmod = wall["cholmod_analysis"] + wall["symbolic_from_tree"] + wall["symbolic_cholmod_pass"]
    cholmod_step = "supernodal step from the given tree" if wall["symbolic_from_tree"] else "supernodal analysis"
    print()
    print(f"analysis {analysis:.3f} s = pattern {wall['ordering_pattern']:.3f}{guide} "
          f"+ ordering {wall['ordering']:.3f} "
          f"+ postorder analysis {wall['postorder_analysis']:.3f} + symbolic {wall['symbolic']:.3f} "
          f"(of it CHOLMOD's {cholmod_step} {cholmod:.3f}); "
          f"the ordering's longest chain {chain:.3f} s: splits by level "
          + ", ".join(f"{splits[k]:.3f}" for k in sorted(splits, reverse=True))
          + (f", then the slowest of {len(parts)} parts {max(parts):.3f}" if parts else "") + "\n")


def main(path):
    for label, steps in runs(path):
        table(label, steps)


if __name__ == "__main__":
    main(sys.argv[1])
