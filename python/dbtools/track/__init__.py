"""Regression tracking: one gate (gate.py) over the records of two suites, their history, and bisection.

Records (history.py): a run of the tracking suite (experiments/track.cpp -> exp_track: whole cells in child
processes; init and frame CPU time, peak RSS, exact counts) is a history CSV; a run of the Google Benchmark suite
(bench/phases.cpp -> bench_phases: the build, analyze, factorize, solve, precompute and frame phases in-process)
is its JSON, read as the same rows by gbench.py. Both are gated by gate.py's rules, the only comparator:

  python3 -m dbtools.track            driver.py: run the tracking suite, pick a baseline, gate, --bisect (./run track)
  python3 -m dbtools.track.bench      bench.py: run bench_phases, gate it against results/bench/baseline.json
                                      (./run track bench)
  python3 -m dbtools.track.gate       gate.py: two records (history CSV or bench_phases JSON)
  python3 -m dbtools.track.results    results.py: two runs of the experiment drivers' result CSVs
  python3 -m dbtools.track.power      power.py: the gate's false alarms and power on runs of one commit
  python3 -m dbtools.track.ci         ci.py: a record as github-action-benchmark JSON (customSmallerIsBetter)

Why gbench feeds the gate instead of leaving it: its phases are the library calls a regression shows in first
(one backend's factorization, one build), timed in-process without a child's start-up, and its counters are the
exact sizes (nnz, nnz(L), bytes) a change of ordering or storage moves; the tracking suite times whole cells. Two
gates with their own thresholds disagreed on the same phases; one set of rules, one report, one notion of
provenance serve both. A gbench repetition is one round of a benchmark's CPU time (gbench's cpu_time, a mean
over its iterations), its counters deterministic measures; its repetitions are not rounds over the suite, so
bench.py does not normalize by round drift.

Every comparison first checks the baseline's provenance (provenance.py): stale (another suite definition:
suite hash or version, cell list, a cell's spec, a measure's class or presence) exits 3, foreign (another
machine, BLAS core, thread count or build type) exits 4, each message naming the baseline and why; --allow-stale
and --allow-foreign override. A subset run (--only, --benchmark_filter) compares what ran: the baseline's other
entries are "not run". Exit codes of every command: 0 pass, 1 regression or usage, 2 could not build, run or
read, 3 stale baseline, 4 foreign baseline.
"""
