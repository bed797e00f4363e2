#!/usr/bin/python3
"""Unit tests of the regression gate (python/dbtools/track) on synthetic records: a 30% slowdown of a CPU time is
flagged, a 5% one and pure noise pass, a 30% slowdown of a phase so short that it is under the absolute floor
(--min-delta-ms) is recorded only, a suite of 50 phases with this box's run-to-run spread and no change rarely
fails, a loaded machine (wall times x3, CPU times as they were) passes; with two runs a side, a slowdown within twice
the run-to-run spread passes, each comparison's resolution and what sets it, the report's list of the phases coarser
than --target; the power measurement (power.py, counting only what the gate can fail); wall times
are reported, and with --gate-wall a machine that is slower as a whole passes (normalization by the rates); the
deterministic, memory and status rules; a subset run compares what ran ("not run", never a failure); stale and
foreign baselines refused with their messages and exit codes (3, 4) unless allowed; bench_phases JSON records
(gbench.py) and the drivers' result CSVs (results.py) under the same rules; the report's count of what was gated and
why the rest was not; a record as github-action-benchmark's customSmallerIsBetter JSON (ci.py).
Run: PYTHONPATH=python tests/track_gate_test.py (ctest `track_gate`)."""
import math
import os
import random
import subprocess
import sys
import tempfile
import unittest

from dbtools.track import gate as g

CELL = "deform/armadillo/tf/structured/multifrontal"


def row(measure, cls, rate, value, repeat, dgemm=30.0, read=20.0, cell=CELL, machine="m1", **extra):
    r = {"commit": "c" * 40, "date": "2026-01-01T00:00:00Z", "machine_id": machine, "cell": cell,
         "measure": measure, "class": cls, "rate": rate, "value": "" if value is None else repr(value),
         "repeat": str(repeat), "blas_dgemm_before": repr(dgemm), "blas_dgemm_after": repr(dgemm),
         "memory_read_before": repr(read), "memory_read_after": repr(read), "git_sha": "cccccccccccc",
         "overrides": "", "message": ""}
    r.update(extra)
    return r


def timed(times, measure="factorize_s", rate="dgemm", dgemm=30.0, read=20.0, cls="time", **kw):
    """A history with one time measure, one row per repeat; dgemm / read may be per-repeat lists."""
    rows = []
    for i, t in enumerate(times):
        d = dgemm[i] if isinstance(dgemm, list) else dgemm
        m = read[i] if isinstance(read, list) else read
        rows.append(row(measure, cls, rate, t, i + 1, d, m, **kw))
    return g.History.from_rows(rows)


def cpu(times, **kw):
    return timed(times, measure="factorize_cpu_s", rate="", cls="cpu", **kw)


CPU = (CELL, "factorize_cpu_s")


def noisy(center, n, sigma, rng):
    return [center * (1 + rng.gauss(0, sigma)) for _ in range(n)]


def verdicts(base, now, **settings):
    return {(c.cell, c.measure): c for c in g.compare(base, now, g.Settings(**settings))}


def wall_verdicts(base, now, **settings):
    return verdicts(base, now, gate_wall=True, **settings)


def thirty_percent_slower(center, seed, sigma):
    """The CPU-time comparisons of 20 draws of 5 runs around `center` against 5 around 1.3 x `center`."""
    rng = random.Random(seed)
    return [verdicts(cpu(noisy(center, 5, sigma, rng)), cpu(noisy(1.3 * center, 5, sigma, rng)))[CPU]
            for _ in range(20)]


class CpuTimeRule(unittest.TestCase):
    def test_thirty_percent_slowdown_fails(self):
        for c in thirty_percent_slower(2.0, 11, 0.05):
            self.assertEqual(c.verdict, "FAIL", c)
            self.assertLess(c.p, 0.01)
            self.assertGreater(c.ratio, 1.15)

    def test_five_percent_slowdown_and_noise_pass(self):
        rng = random.Random(12)
        for center in [2.1] * 50 + [2.0] * 200:
            self.assertNotEqual(verdicts(cpu(noisy(2.0, 5, 0.05, rng)), cpu(noisy(center, 5, 0.05, rng)))[CPU]
                                .verdict, "FAIL")

    def test_thirty_percent_slowdown_of_a_tiny_phase_is_recorded_only(self):
        # A 6 ms phase 30% slower is 1.8 ms: past the threshold and significant, under the 3 ms floor.
        for c in thirty_percent_slower(0.006, 15, 0.03):
            self.assertEqual(c.verdict, "recorded only", c)
            self.assertLess(c.p, 0.01)
            self.assertGreater(c.ratio, 1.15)
            self.assertRegex(c.note, r"[0-9.]+ ms slower, under the 3 ms floor")
        # The floor is an option: at 1 ms the same slowdown fails.
        c = verdicts(cpu([0.006, 0.0061, 0.0059, 0.00605, 0.00595]), cpu([0.0078, 0.0079, 0.0077, 0.00785, 0.00775]),
                     min_delta_s=0.001)[CPU]
        self.assertEqual(c.verdict, "FAIL", c)

    def test_thirty_percent_slowdown_above_the_floor_fails(self):
        # A 20 ms phase (the solves of the armadillo solver cells) 30% slower is 6 ms: over the floor, it fails.
        for c in thirty_percent_slower(0.020, 16, 0.03):
            self.assertEqual(c.verdict, "FAIL", c)

    def test_a_suite_with_this_boxs_spread_rarely_fails(self):
        # 50 phases (about what a run of the suite gates), each run of each spread by 15% with a heavy right tail
        # (a few runs in a slow window), no change: the run-to-run spread of CPU time measured on this box at load
        # 1-3. At alpha 0.05 such suites raise about 0.6 false alarms per pair, at 0.01 a fifth of that.
        rng = random.Random(17)

        def phase_runs(center):
            return [center * (1 + abs(rng.gauss(0, 0.15))) * (1.4 if rng.random() < 0.1 else 1.0) for _ in range(5)]

        def suite():
            rows = []
            for k in range(50):
                for i, t in enumerate(phase_runs(0.02 * (k + 1))):
                    rows.append(row("init_cpu_s", "cpu", "", t, i + 1, cell=f"deform/c{k}"))
            return g.History.from_rows(rows)

        def false_alarms(alpha):
            return sum(sum(c.verdict == "FAIL" for c in g.compare(suite(), suite(), g.Settings(alpha=alpha)))
                       for _ in range(40))
        strict, loose = false_alarms(0.01), false_alarms(0.05)  # seeded: 5 and 25
        self.assertLessEqual(strict, 8, f"{strict} false alarms in 40 pairs of suites at alpha 0.01")
        self.assertGreaterEqual(loose, 3 * strict, f"{loose} at 0.05, {strict} at 0.01")

    def test_a_loaded_machine_passes_on_cpu_time(self):
        # Load triples the wall times; the CPU times of the same runs barely move: the CPU rule passes where the
        # wall rule (the rates probes did not see the load) would fail.
        rng = random.Random(13)
        base_cpu, now_cpu = noisy(1.0, 5, 0.03, rng), noisy(1.03, 5, 0.03, rng)
        self.assertEqual(verdicts(cpu(base_cpu), cpu(now_cpu))[CPU].verdict, "ok")
        wall = wall_verdicts(timed([t * 1.2 for t in base_cpu]), timed([t * 3.6 for t in now_cpu]))
        self.assertEqual(wall[(CELL, "factorize_s")].verdict, "FAIL")
        self.assertEqual(verdicts(timed([1.0] * 5), timed([3.0] * 5))[(CELL, "factorize_s")].verdict, "not gated")

    def test_a_suite_wide_drift_is_excused_one_cell_is_not(self):
        # Twelve cells whose CPU times all grew by 20% (contention with other processes, the same in every cell):
        # the rounds' drift excuses them; one cell 30% slower than a suite that did not move fails.
        rng = random.Random(14)

        def suite(factor, slow_cell=None):
            rows = []
            for k in range(12):
                f = factor * (1.3 if k == slow_cell else 1.0)
                for i, t in enumerate(noisy(0.5 * f, 5, 0.02, rng)):
                    rows.append(row("init_cpu_s", "cpu", "", t, i + 1, cell=f"deform/c{k}"))
            return g.History.from_rows(rows)

        base = suite(1.0)
        drifted = g.compare(base, suite(1.2), g.Settings())
        self.assertFalse([c for c in drifted if c.verdict == "FAIL"])
        self.assertTrue(all(c.ratio > 1.1 and abs(float(c.note.split()[1]) - 1) < 0.1 for c in drifted), drifted)
        self.assertEqual(g.compare(base, suite(1.2), g.Settings(drift_cells=0))[0].verdict, "FAIL")
        one = {c.cell: c.verdict for c in g.compare(base, suite(1.0, slow_cell=3), g.Settings())}
        self.assertEqual(one.pop("deform/c3"), "FAIL")
        self.assertEqual(set(one.values()), {"ok"})

    def test_too_few_runs_tiny_times_other_machine_not_gated(self):
        self.assertEqual(verdicts(cpu([1.0] * 4), cpu([2.0] * 4))[CPU].note, "4 runs < 5")
        self.assertEqual(verdicts(cpu([1e-4] * 5), cpu([2e-4] * 5))[CPU].verdict, "not gated")
        self.assertEqual(verdicts(cpu([1.0] * 5), cpu([2.0] * 5, machine="m2"))[CPU].note, "other machine")

    def test_info_never_gated(self):
        c = verdicts(timed([1.0] * 5, measure="cell_cpu_s", cls="info"), timed([9.0] * 5, measure="cell_cpu_s",
                                                                               cls="info"))
        self.assertEqual(c[(CELL, "cell_cpu_s")].verdict, "not gated")


def two_runs(medians, spread=(1.0, 1.01, 0.99, 1.005, 0.995), **kw):
    """A side of two runs (pooled as ./run track pools them), their rounds `spread` times each run's median."""
    from dbtools.track.history import pooled
    return pooled([cpu([m * f for f in spread], **kw) for m in medians])


class RunSpreadRule(unittest.TestCase):
    """With several runs a side, a CPU-time slowdown must also exceed --noise-k (2) x the run-to-run spread."""

    def test_run_spread(self):
        from dbtools.track.history import pooled_round
        self.assertEqual(g.run_spread({1: 2.0, 2: 2.0, 3: 9.0, pooled_round(1, 1): 2.5, pooled_round(1, 2): 2.5}), 0.25)
        self.assertEqual(g.run_spread({1: 2.0, 2: 3.0, 3: 9.0}), 0.0)  # one run: no spread measured

    def test_a_slowdown_within_twice_the_spread_passes_past_it_fails(self):
        # Runs of each side 25% apart (medians 2.0 and 2.5): the bar is 50%; x1.25 is significant and past the
        # threshold but within it; x1.6 fails; with --noise-k 0 (the threshold alone) x1.25 fails.
        base = two_runs([2.0, 2.5])
        c = verdicts(base, two_runs([2.5, 3.125]))[CPU]
        self.assertEqual(c.verdict, "ok", c)
        self.assertLess(c.p, 0.01)
        self.assertGreater(c.ratio, 1.15)
        self.assertIn("run spread 25.0%: within 2 x the run-to-run spread (25.0%), not failed", c.note)
        self.assertEqual((c.resolution, c.bound_by), (0.5, "run spread"))
        self.assertFalse(c.gateable_at(0.3))
        self.assertEqual(verdicts(base, two_runs([3.2, 4.0]))[CPU].verdict, "FAIL")
        self.assertEqual(verdicts(base, two_runs([2.5, 3.125]), noise_k=0)[CPU].verdict, "FAIL")

    def test_the_larger_sides_spread_counts(self):
        # A quiet baseline (runs 1% apart) against a run whose two runs are 25% apart: the run's spread sets the bar.
        c = verdicts(two_runs([2.0, 2.02]), two_runs([2.5, 3.125]))[CPU]
        self.assertEqual((c.verdict, c.bound_by, c.resolution), ("ok", "run spread", 0.5))

    def test_resolution_set_by_the_threshold_or_the_floor(self):
        c = verdicts(two_runs([2.0, 2.1]), two_runs([2.6, 2.73]))[CPU]  # spread 5%: the threshold's 15% holds
        self.assertEqual((c.verdict, c.bound_by, c.resolution), ("FAIL", "threshold", 0.15))
        c = verdicts(two_runs([0.006, 0.006]), two_runs([0.0078, 0.0078]))[CPU]  # 3 ms floor / 6 ms = 50%
        self.assertEqual((c.verdict, c.bound_by, c.resolution), ("recorded only", "floor", 0.5))
        self.assertTrue(c.gateable_at(0.6))

    def test_one_run_a_side_is_the_threshold_alone(self):
        base = [2.0, 2.5, 2.1, 2.4, 2.2]
        c = verdicts(cpu(base), cpu([1.3 * x for x in base]))[CPU]
        self.assertEqual((c.verdict, c.bound_by, c.resolution), ("FAIL", "threshold", 0.15))
        self.assertNotIn("run spread", c.note)

    def test_the_report_names_the_phases_coarser_than_the_target(self):
        from dbtools.track import report
        base = pooled_sides([("init_cpu_s", [2.0, 2.5]), ("solve_cpu_s", [2.0, 2.1])])
        now = pooled_sides([("init_cpu_s", [2.0, 2.5]), ("solve_cpu_s", [2.0, 2.1])])
        lines = report.resolution_lines(g.compare(base, now), g.Settings())
        self.assertEqual(lines, [f"CPU-time resolution: 1 of 2 phases gated can fail a slowdown of x1.3 (--target); "
                                 f"coarser: 1; {CELL} init_cpu_s x1.50 (run spread)"])
        self.assertIn("coarser: 0", report.resolution_lines(g.compare(base, now), g.Settings(target=0.6))[0])


def pooled_sides(measures):
    """Two runs pooled, each with the CPU-time measures `measures` ((name, [median of run 1, of run 2]))."""
    from dbtools.track.history import pooled
    spread = (1.0, 1.01, 0.99, 1.005, 0.995)
    return pooled([g.History.from_rows([row(m, "cpu", "", med[k] * f, i + 1) for m, med in measures
                                        for i, f in enumerate(spread)]) for k in (0, 1)])


class WallTimeRule(unittest.TestCase):
    def test_thirty_percent_slowdown_fails(self):
        rng = random.Random(1)
        for _ in range(20):
            base = timed(noisy(2.0, 5, 0.05, rng))
            now = timed(noisy(2.6, 5, 0.05, rng))
            c = wall_verdicts(base, now)[(CELL, "factorize_s")]
            self.assertEqual(c.verdict, "FAIL", c)
            self.assertLess(c.p, 0.05)
            self.assertGreater(c.ratio, 1.15)

    def test_five_percent_slowdown_passes(self):
        rng = random.Random(2)
        for _ in range(50):
            base = timed(noisy(2.0, 5, 0.05, rng))
            now = timed(noisy(2.1, 5, 0.05, rng))
            self.assertNotEqual(wall_verdicts(base, now)[(CELL, "factorize_s")].verdict, "FAIL")

    def test_pure_noise_passes(self):
        # Noise as between runs on this box (5% per run): the threshold alone keeps every comparison ok.
        rng = random.Random(3)
        for _ in range(200):
            base, now = timed(noisy(2.0, 5, 0.05, rng)), timed(noisy(2.0, 5, 0.05, rng))
            self.assertNotEqual(wall_verdicts(base, now)[(CELL, "factorize_s")].verdict, "FAIL")

    def test_heavy_noise_fails_at_most_alpha(self):
        # Heavy noise (20% per run) often moves a median of five by 15%; the U test then bounds false alarms by
        # alpha: an exact 5-vs-5 one-sided test has P(p < 0.05) = 12/252 under no change.
        rng = random.Random(3)
        fails = sum(wall_verdicts(timed(noisy(2.0, 5, 0.2, rng)), timed(noisy(2.0, 5, 0.2, rng)))
                    [(CELL, "factorize_s")].verdict == "FAIL" for _ in range(400))
        self.assertLessEqual(fails, 0.05 * 400 + 3 * math.sqrt(400 * 0.05 * 0.95), f"{fails} of 400 failed")
        strict = sum(wall_verdicts(timed(noisy(2.0, 5, 0.2, rng)), timed(noisy(2.0, 5, 0.2, rng)), alpha=0.01)
                     [(CELL, "factorize_s")].verdict == "FAIL" for _ in range(400))
        self.assertLessEqual(strict, 0.01 * 400 + 3 * math.sqrt(400 * 0.01 * 0.99), f"{strict} of 400 at 0.01")

    def test_one_slow_outlier_passes(self):
        base = timed([2.0, 2.02, 1.98, 2.01, 1.99])
        now = timed([2.0, 2.02, 1.98, 2.01, 4.5])  # one run in a slow window: median unmoved, not significant
        self.assertEqual(wall_verdicts(base, now)[(CELL, "factorize_s")].verdict, "ok")

    def test_slower_machine_is_normalized_away(self):
        # The whole machine at half speed: every time doubles and the dgemm rate around it halves.
        rng = random.Random(4)
        base = timed(noisy(2.0, 5, 0.03, rng), dgemm=30.0)
        now = timed([2 * t for t in noisy(2.0, 5, 0.03, rng)], dgemm=15.0)
        c = wall_verdicts(base, now)[(CELL, "factorize_s")]
        self.assertEqual(c.verdict, "ok", c)
        self.assertAlmostEqual(c.ratio, 1.0, delta=0.1)
        self.assertAlmostEqual(float(c.note.split()[1]), 2.0, delta=0.2)  # "raw 1.98": the unnormalized ratio

    def test_per_run_rates_normalize_each_run(self):
        # Two of five runs in a slow window (time x1.5, rate / 1.5): normalized, the runs agree again.
        base = timed([2.0, 2.01, 1.99, 2.02, 1.98], dgemm=30.0)
        now = timed([3.0, 3.03, 2.0, 2.01, 1.99], dgemm=[20.0, 20.0, 30.0, 30.0, 30.0])
        self.assertAlmostEqual(wall_verdicts(base, now)[(CELL, "factorize_s")].ratio, 1.0, delta=0.02)

    def test_a_slowdown_made_by_the_normalization_alone_does_not_fail(self):
        # Same raw times; the probes around the new runs read a machine twice as fast (a burst of load that ended
        # before the short cell ran): normalized 2x slower, raw unchanged.
        base = timed([2.0, 2.01, 1.99, 2.02, 1.98], dgemm=15.0)
        now = timed([2.0, 2.01, 1.99, 2.02, 1.98], dgemm=30.0)
        c = wall_verdicts(base, now)[(CELL, "factorize_s")]
        self.assertAlmostEqual(c.ratio, 2.0, delta=0.05)
        self.assertEqual(c.verdict, "ok", c)
        self.assertIn("not failed", c.note)

    def test_read_rate_for_solves_and_builds(self):
        base = timed([0.1] * 5, measure="frame_s", rate="read", read=20.0)
        now = timed([0.2] * 5, measure="frame_s", rate="read", read=10.0, dgemm=60.0)
        self.assertAlmostEqual(wall_verdicts(base, now)[(CELL, "frame_s")].ratio, 1.0, delta=1e-9)

    def test_init_is_normalized_by_its_parts(self):
        def hist(build, factor, dgemm, read):
            rows = []
            for i in range(5):
                for m, rate, t in (("build_s", "read", build), ("analyze_s", "read", 0.0),
                                   ("factorize_s", "dgemm", factor), ("init_s", "mixed", build + factor)):
                    rows.append(row(m, "time", rate, t, i + 1, dgemm, read))
            return g.History.from_rows(rows)
        # The build at half the read rate took twice as long; the factorization ran at the same dgemm rate.
        base, now = hist(1.0, 2.0, 30.0, 20.0), hist(2.0, 2.0, 30.0, 10.0)
        self.assertAlmostEqual(wall_verdicts(base, now)[(CELL, "init_s")].ratio, 1.0, delta=1e-9)

    def test_too_few_runs_and_tiny_times_are_not_gated(self):
        v = wall_verdicts(timed([1.0] * 3), timed([2.0] * 3))[(CELL, "factorize_s")]
        self.assertEqual((v.verdict, v.note), ("not gated", "3 runs < 5"))
        v = wall_verdicts(timed([1e-4] * 5), timed([2e-4] * 5))[(CELL, "factorize_s")]
        self.assertEqual(v.verdict, "not gated")

    def test_other_machine_times_not_gated(self):
        v = wall_verdicts(timed([1.0] * 5), timed([2.0] * 5, machine="m2"))[(CELL, "factorize_s")]
        self.assertEqual((v.verdict, v.note), ("not gated", "other machine"))


def single(measure, cls, value, machine="m1"):
    return g.History.from_rows([row(measure, cls, "", value, 1, machine=machine)])


class OtherRules(unittest.TestCase):
    def test_deterministic(self):
        self.assertEqual(verdicts(single("nnz_factor", "deterministic", 1000),
                                  single("nnz_factor", "deterministic", 1000))[(CELL, "nnz_factor")].verdict, "ok")
        for now, want in ((1004, "changed"), (1006, "FAIL"), (990, "changed")):
            c = verdicts(single("nnz_factor", "deterministic", 1000), single("nnz_factor", "deterministic", now))
            self.assertEqual(c[(CELL, "nnz_factor")].verdict, want, now)

    def test_deterministic_compares_across_machines(self):
        c = verdicts(single("factor_bytes", "deterministic", 100), single("factor_bytes", "deterministic", 110, "m2"))
        self.assertEqual(c[(CELL, "factor_bytes")].verdict, "FAIL")

    def test_peak_rss(self):
        for now, want in ((104, "ok"), (106, "FAIL")):
            c = verdicts(single("peak_rss_bytes", "memory", 100), single("peak_rss_bytes", "memory", now))
            self.assertEqual(c[(CELL, "peak_rss_bytes")].verdict, want)
        c = verdicts(single("peak_rss_bytes", "memory", 100), single("peak_rss_bytes", "memory", 200, "m2"))
        self.assertEqual(c[(CELL, "peak_rss_bytes")].verdict, "not gated")

    def test_failed_cell_fails_new_and_missing_are_reported(self):
        base = g.History.from_rows([row("nnz", "deterministic", "", 5, 1), row("nnz", "deterministic", "", 5, 1,
                                                                                cell="solve/x")])
        now = g.History.from_rows([row("status", "status", "", None, 1, message="error: boom"),
                                   row("nnz", "deterministic", "", 5, 1, cell="solve/y")])
        c = verdicts(base, now)
        self.assertEqual(c[(CELL, "status")].verdict, "FAIL")
        self.assertIn("boom", c[(CELL, "status")].note)
        self.assertEqual(c[("solve/y", "nnz")].verdict, "new")
        self.assertEqual(c[("solve/x", "nnz")].verdict, "not run")

    def test_cell_and_measure_filters(self):
        base = g.History.from_rows([row("nnz", "deterministic", "", 5, 1), row("n", "deterministic", "", 5, 1)])
        now = g.History.from_rows([row("nnz", "deterministic", "", 9, 1), row("n", "deterministic", "", 9, 1)])
        self.assertEqual([c.measure for c in g.compare(base, now, g.Settings(measures=("n",)))], ["n"])
        self.assertEqual(g.compare(base, now, g.Settings(cells=("solve/*",))), [])


class CommandLine(unittest.TestCase):
    def write(self, d, name, rows):  # noqa: also called unbound (write_csv)
        import csv
        path = os.path.join(d, name)
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        return path

    def run_gate(self, *args):
        return subprocess.run([sys.executable, "-m", "dbtools.track.gate", *args], text=True, capture_output=True)

    def test_exit_codes_and_report(self):
        with tempfile.TemporaryDirectory() as d:
            base = self.write(d, "b.csv", [row("nnz_factor", "deterministic", "", 1000, 1)])
            same = self.write(d, "s.csv", [row("nnz_factor", "deterministic", "", 1000, 1)])
            worse = self.write(d, "w.csv", [row("nnz_factor", "deterministic", "", 2000, 1)])
            self.assertEqual(self.run_gate(base, same).returncode, 0)
            md = os.path.join(d, "track.md")
            p = self.run_gate(base, worse, "--markdown", md)
            self.assertEqual(p.returncode, 1)
            self.assertRegex(p.stdout, r"nnz_factor\s+deterministic\s+1000\s+2000\s+2\.000\s+FAIL")
            with open(md) as f:
                text = f.read()
            self.assertIn("| " + CELL + " | nnz_factor | deterministic | 1000 | 2000 | 2.000 |  | FAIL |", text)
            self.assertEqual(self.run_gate(base, os.path.join(d, "none.csv")).returncode, 2)
            self.assertEqual(self.run_gate(base, md).returncode, 2)  # not a history
            self.assertEqual(self.run_gate(base, same, "--alpha", "2").returncode, 1)
            self.assertEqual(self.run_gate(base, same, "--min-delta-ms", "-1").returncode, 1)

    def test_recorded_only_is_named_in_the_report(self):
        def runs(times):
            return [row("solve_cpu_s", "cpu", "", t, i + 1) for i, t in enumerate(times)]
        with tempfile.TemporaryDirectory() as d:
            base = self.write(d, "b.csv", runs([0.006, 0.0061, 0.0059, 0.00605, 0.00595]))
            slow = self.write(d, "t.csv", runs([0.0078, 0.0079, 0.0077, 0.00785, 0.00775]))
            md = os.path.join(d, "track.md")
            p = self.run_gate(base, slow, "--markdown", md)
            self.assertEqual(p.returncode, 0, p.stdout)
            self.assertRegex(p.stdout, r"solve_cpu_s\s+cpu\s+.*recorded only\s+normalized 1\.3.*under the 3 ms floor")
            self.assertRegex(p.stdout, r"recorded only \(past the threshold .*\): " + CELL + r" solve_cpu_s 1\.3")
            with open(md) as f:
                self.assertIn("## Recorded only", f.read())
            self.assertEqual(self.run_gate(base, slow, "--min-delta-ms", "1").returncode, 1)
            self.assertEqual(self.run_gate(base).returncode, 1)


class PowerScript(unittest.TestCase):
    """python3 -m dbtools.track.power on four synthetic runs of one commit (12 phases of 0.5 s, 2% noise)."""
    write = CommandLine.write

    def four_runs(self, d, rng, extra=lambda i: []):
        """Four history files of 12 phases of 0.5 s with 2% noise, run i with the rows extra(i) besides."""
        return [self.write(d, f"r{i}.csv", [row("init_cpu_s", "cpu", "", t, r + 1, cell=f"deform/c{k}")
                                            for k in range(12) for r, t in enumerate(noisy(0.5, 5, 0.02, rng))] +
                           extra(i)) for i in range(4)]

    def test_false_alarms_and_planted_slowdowns(self):
        rng = random.Random(21)
        with tempfile.TemporaryDirectory() as d:
            paths = self.four_runs(d, rng)
            tool = ["-m", "dbtools.track.power"]
            p = subprocess.run([sys.executable, *tool, *paths, "--pool", "1", "--slowdown", "1.5"], text=True,
                               capture_output=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("NOT ./run track's default", p.stdout.splitlines()[0])
            self.assertIn("false alarms: 0 in 12 ordered pairs (1 run(s) a side", p.stdout)
            self.assertIn("planted x1.5 slowdowns caught where the gate can fail them (its resolution under x1.5): "
                          "50 ms and over 1.00 of 144, all 1.00 of 144\n", p.stdout)
            self.assertIn("phases caught in fewer than 80% of the pairs where gateable: 0 of 12\n", p.stdout)
            self.assertIn("phases not gateable at x1.5 in some pairs (its resolution there set by): 0\n", p.stdout)
            # The default: ./run track's sides, two consecutive runs (one invocation) against two, pooled.
            p = subprocess.run([sys.executable, *tool, *paths, "--slowdown", "1.01"], text=True, capture_output=True)
            self.assertRegex(p.stdout.splitlines()[0], r"^configuration: 2 run\(s\) a side \(consecutive runs, one "
                             r"invocation of ./run track each\), rounds pooled; 4 run\(s\) given; .*: ./run track's "
                             r"default")
            self.assertIn("runs 1+2 -> 3+4: 12 CPU comparisons", p.stdout)
            self.assertIn("false alarms: 0 in 2 ordered pairs (2 run(s) a side", p.stdout)
            # A 1% slowdown is finer than the 15% threshold: no phase is gateable at x1.01, and the output says so.
            self.assertIn("(its resolution under x1.01): all none of 0\n", p.stdout)
            self.assertIn("every gated comparison counted: 0.00 of 24; 24 of 24 not gateable at x1.01", p.stdout)
            self.assertIn("phases not gateable at x1.01 in some pairs (its resolution there set by): 12; deform/c0 "
                          "init_cpu_s in 2 of 2 (threshold);", p.stdout)
            # --interleaved: ./run track --interleave's sides, the alternate runs of each four, in both orders.
            p = subprocess.run([sys.executable, *tool, *paths, "--interleaved"], text=True, capture_output=True)
            self.assertIn("(alternate runs of one invocation, both orders (./run track --interleave))",
                          p.stdout.splitlines()[0])
            self.assertIn("runs 1+3 -> 2+4: 12 CPU comparisons", p.stdout)
            self.assertIn("runs 2+4 -> 1+3: 12 CPU comparisons", p.stdout)
            self.assertIn("false alarms: 0 in 2 ordered pairs", p.stdout)
            self.assertEqual(subprocess.run([sys.executable, *tool, *paths, "--interleaved", "--any-sets"],
                                            capture_output=True).returncode, 1)
            p = subprocess.run([sys.executable, *tool, *paths, "--any-sets"], text=True, capture_output=True)
            self.assertIn("false alarms: 0 in 6 ordered pairs (2 run(s) a side", p.stdout)
            self.assertIn("(any disjoint sets)", p.stdout.splitlines()[0])
            p = subprocess.run([sys.executable, *tool, *paths, paths[0], "--alpha", "0.05"], text=True,
                               capture_output=True)
            self.assertIn("NOT ./run track's default", p.stdout.splitlines()[0])
            self.assertIn(f"left out (not a whole side of 2): {paths[0]}", p.stdout)  # the fifth run
            self.assertEqual(subprocess.run([sys.executable, *tool, paths[0], "--pool", "1"]).returncode, 1)
            self.assertEqual(subprocess.run([sys.executable, *tool, *paths[:3], "--pool", "2"]).returncode, 1)

    def test_a_phase_whose_runs_spread_is_listed_not_counted(self):
        # Twelve phases with 2% noise and one whose runs alternate between medians 25% apart: with two runs a side
        # (the default) that phase's resolution is 2 x 25%, coarser than x1.3: listed, its misses not in the power.
        rng = random.Random(22)
        with tempfile.TemporaryDirectory() as d:
            paths = self.four_runs(d, rng, lambda i: [
                row("init_cpu_s", "cpu", "", (0.5, 0.625)[i % 2] * f, r + 1, cell="deform/wide")
                for r, f in enumerate((1.0, 1.01, 0.99, 1.005, 0.995))])
            p = subprocess.run([sys.executable, "-m", "dbtools.track.power", *paths], text=True, capture_output=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("false alarms: 0 in 2 ordered pairs", p.stdout)
            self.assertIn("(its resolution under x1.3): 50 ms and over 1.00 of 24, all 1.00 of 24\n", p.stdout)
            self.assertIn("every gated comparison counted: 0.92 of 26; 2 of 26 not gateable at x1.3", p.stdout)
            self.assertIn("phases caught in fewer than 80% of the pairs where gateable: 0 of 12\n", p.stdout)
            self.assertIn("not gateable at x1.3 in some pairs (its resolution there set by): 1; deform/wide init_cpu_s "
                          "in 2 of 2 (run spread)\n", p.stdout)


class Pooled(unittest.TestCase):
    """history.pooled: several runs of one commit as one record, as ./run track gates each side (--runs)."""

    def test_rounds_side_by_side(self):
        from dbtools.track.history import pooled, pooled_round
        a = g.History.from_rows([row("init_cpu_s", "cpu", "", t, k + 1) for k, t in enumerate([1.0, 2.0])])
        b = g.History.from_rows([row("init_cpu_s", "cpu", "", t, k + 1) for k, t in enumerate([3.0, 4.0])] +
                                [row("status", "status", "", None, 1, cell="solve/x", message="error: boom")])
        p = pooled([a, b])
        self.assertEqual(p.values[(CELL, "init_cpu_s")],
                         {1: 1.0, 2: 2.0, pooled_round(1, 1): 3.0, pooled_round(1, 2): 4.0})
        self.assertEqual(set(p.rates), {(CELL, 1), (CELL, 2), (CELL, pooled_round(1, 1)), (CELL, pooled_round(1, 2))})
        self.assertEqual((p.runs, p.failed), (2, {"solve/x": "error: boom"}))  # a cell failed in one run failed
        self.assertEqual(a.values[(CELL, "init_cpu_s")], {1: 1.0, 2: 2.0})  # the runs themselves unchanged
        self.assertEqual((a.runs, pooled([a]).runs), (1, 1))

    def test_history_views_join_a_commits_runs(self):
        """dbtools.plots.history.joined (the trend figures and the site): the runs of one commit in a row on one
        machine are one point, rounds renumbered as pooled numbers them; another commit or machine starts another."""
        from dbtools.plots.history import joined, run_count
        from dbtools.track.history import pooled, pooled_round

        def run(date, sha, machine="m1"):
            return [row("init_cpu_s", "cpu", "", 1.0, k, date=date, git_sha=sha, machine=machine) for k in (1, 2)]
        runs = [run("d1", "aaa"), run("d2", "aaa"), run("d3", "aaa", machine="m2"), run("d4", "aaa"),
                run("d5", "bbb"), run("d6", "aaa")]
        out = joined(runs)
        self.assertEqual([[r["date"] for r in rows] for rows in out],
                         [["d1", "d1", "d2", "d2", "d4", "d4"], ["d3", "d3"], ["d5", "d5"], ["d6", "d6"]])
        self.assertEqual([r["repeat"] for r in out[0]],
                         ["1", "2"] + [str(pooled_round(k, r)) for k in (1, 2) for r in (1, 2)])
        self.assertEqual([run_count(rows) for rows in out], [3, 1, 1, 1])
        self.assertEqual(g.History.from_rows(out[0]).values[(CELL, "init_cpu_s")].keys(),
                         pooled([g.History.from_rows(r) for r in (runs[0], runs[1], runs[3])]).values[
                             (CELL, "init_cpu_s")].keys())

    def test_runs_started_in_one_second_count_apart(self):
        """exp_track names a history file by its second (a second run in the same second gets '-2'): the trend view
        and the site count the files joined, not the distinct dates."""
        from dbtools.plots.history import read_runs, run_count
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "history", "runs"))
            rows = [row("init_cpu_s", "cpu", "", 1.0, k) for k in (1, 2)]  # one date, commit and machine
            for name in ("20260101T000000Z_c_m1.csv", "20260101T000000Z_c_m1-2.csv"):
                write_csv(os.path.join(d, "history", "runs"), name, rows)
            self.assertEqual([run_count(r) for r in read_runs(d)], [2])


def write_csv(d, name, rows):
    return CommandLine.write(None, d, name, rows)


def run_module(module, *args):
    return subprocess.run([sys.executable, "-m", module, *args], text=True, capture_output=True)


def det(cell, value, **kw):
    return row("nnz_factor", "deterministic", "", value, 1, cell=cell, **kw)


class SubsetRuns(unittest.TestCase):
    def test_entries_that_did_not_run_are_not_run_never_a_failure(self):
        base = g.History.from_rows([det("deform/a", 10), det("deform/b", 10), det("solve/c", 10)])
        now = g.History.from_rows([det("deform/a", 10)])
        c = verdicts(base, now)
        self.assertEqual({k: v.verdict for k, v in c.items()},
                         {("deform/a", "nnz_factor"): "ok", ("deform/b", "nnz_factor"): "not run",
                          ("solve/c", "nnz_factor"): "not run"})
        with tempfile.TemporaryDirectory() as d:
            p = run_module("dbtools.track.gate", write_csv(d, "b.csv", [det("deform/a", 10), det("deform/b", 10)]),
                           write_csv(d, "n.csv", [det("deform/a", 10)]))
            self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
            self.assertIn("comparisons: not run 1, ok 1 (not run: in the baseline, not in this run)", p.stdout)
            self.assertNotIn("deform/b", p.stdout.split("baseline:")[0])  # not listed as a notable comparison


def spec_rows(spec, cell=CELL, overrides="", measure="nnz_factor", cls="deterministic", **kw):
    return [row(measure, cls, "", 100, 1, cell=cell, spec=spec, overrides=overrides, **kw)]


class StaleBaselines(unittest.TestCase):
    SPEC = "kind=deform model=hand method=tf build=structured mesh=data/meshes/hand.off frames=5"

    def refused(self, base_rows, now_rows, suite_cells=None):
        base, now = g.History.from_rows(base_rows, "base.csv"), g.History.from_rows(now_rows, "now.csv")
        with self.assertRaises(g.Refused) as e:
            g.check(base, now, suite_cells)
        self.assertEqual((e.exception.kind, e.exception.exit_code), ("stale", 3))
        self.assertRegex(str(e.exception), r"^the baseline base.csv \(commit cccccccccccc, .*machine m1\) is stale: ")
        self.assertIn("--allow-stale", str(e.exception))
        return str(e.exception)

    def test_a_cell_defined_otherwise(self):
        msg = self.refused(spec_rows(self.SPEC), spec_rows(self.SPEC.replace("frames=5", "frames=9")))
        self.assertIn(f"{CELL}: frames=5 in the baseline, 9 now", msg)

    def test_keys_the_runs_overrides_set_are_the_change_under_test(self):
        base = g.History.from_rows(spec_rows(self.SPEC))
        now = g.History.from_rows(spec_rows(self.SPEC + " ordering=natural", overrides="kind=deform: ordering=natural"))
        self.assertEqual(g.check(base, now).notes, [])

    def test_a_changed_cell_list_measure_class_or_measure_set(self):
        msg = self.refused(spec_rows("") + spec_rows("", cell="solve/gone"), spec_rows(""), suite_cells=[CELL])
        self.assertIn("1 cell(s) the suite no longer defines: solve/gone", msg)
        msg = self.refused(spec_rows("", measure="init_s", cls="time"), spec_rows("", measure="init_s", cls="cpu"))
        self.assertIn(f"{CELL} init_s: class time in the baseline, cpu now", msg)
        msg = self.refused(spec_rows("") + spec_rows("", measure="flops"), spec_rows(""))
        self.assertIn(f"{CELL}: flops no longer measured", msg)

    def test_another_suite_definition(self):
        msg = self.refused(spec_rows("", suite="bench_phases v1, aaa (80 benchmarks)"),
                           spec_rows("", suite="bench_phases v2, aaa (80 benchmarks)"))
        self.assertIn("suite definition 'bench_phases v1, aaa (80 benchmarks)' in the baseline, "
                      "'bench_phases v2, aaa (80 benchmarks)' now", msg)

    def test_exit_3_unless_allowed(self):
        with tempfile.TemporaryDirectory() as d:
            base = write_csv(d, "b.csv", spec_rows(self.SPEC))
            now = write_csv(d, "n.csv", [dict(r, value="200") for r in spec_rows(self.SPEC.replace("5", "9"))])
            p = run_module("dbtools.track.gate", base, now)
            self.assertEqual(p.returncode, 3, p.stdout)
            self.assertRegex(p.stderr, r"track_gate: error: the baseline .*b\.csv .* is stale: .*frames=5 in the "
                                       r"baseline, 9 now")
            self.assertEqual(p.stdout, "")
            p = run_module("dbtools.track.gate", base, now, "--allow-stale")
            self.assertEqual(p.returncode, 1, p.stderr)  # compared: nnz_factor doubled
            self.assertIn("stale baseline compared anyway (--allow-stale)", p.stdout)


class ForeignBaselines(unittest.TestCase):
    def test_another_machine_is_refused_with_exit_4_unless_allowed(self):
        def rows(machine, cpu_model, factor):
            return [row("factorize_cpu_s", "cpu", "", t * factor, i + 1, machine=machine, machine_cpu=cpu_model)
                    for i, t in enumerate([1.0, 1.01, 0.99, 1.02, 0.98])] + \
                [row("nnz_factor", "deterministic", "", 1000 * factor, 1, machine=machine, machine_cpu=cpu_model)]
        with tempfile.TemporaryDirectory() as d:
            base = write_csv(d, "b.csv", rows("m1", "Intel Xeon", 1))
            now = write_csv(d, "n.csv", rows("m2", "AMD EPYC", 1.5))
            p = run_module("dbtools.track.gate", base, now)
            self.assertEqual(p.returncode, 4, p.stdout)
            self.assertRegex(p.stderr, r"the baseline .*b\.csv \(commit cccccccccccc, .*machine m1 "
                                       r"\(CPU Intel Xeon\)\) is foreign: CPU Intel Xeon in the baseline, AMD EPYC now: .*--allow-foreign")
            p = run_module("dbtools.track.gate", base, now, "--allow-foreign", "--all")
            self.assertEqual(p.returncode, 1, p.stderr)
            self.assertRegex(p.stdout, r"nnz_factor +deterministic +1000 +1500 +1\.500 +FAIL")
            self.assertRegex(p.stdout, r"factorize_cpu_s +cpu .*not gated +other machine")
            self.assertIn("foreign baseline (--allow-foreign): deterministic measures only", p.stdout)

    def test_another_build_type_is_foreign(self):
        base = g.History.from_rows([det(CELL, 1, build_type="Release")], "b.csv")
        now = g.History.from_rows([det(CELL, 1, build_type="Debug")], "n.csv")
        with self.assertRaisesRegex(g.Refused, "is foreign: build Release in the baseline, Debug now"):
            g.check(base, now)


def gbench_doc(cpu_model="AMD EPYC", version="1", suite="abc (3 benchmarks)", scale=None, names=None, error=None):
    """A bench_phases JSON: 5 repetitions of each benchmark (+ their aggregates), counters, one context."""
    scale = scale or {}
    ctx = {"date": "2026-01-01T00:00:00+00:00", "deformbench_git_sha": "abcdef123456", "deformbench_cpu": cpu_model,
           "deformbench_blas_core": "Haswell", "deformbench_hardware_threads": "2", "deformbench_blas_threads": "1",
           "deformbench_build_threads": "1", "deformbench_timestamp": "2026-01-01T00:00:00Z",
           "deformbench_suite_version": version, "deformbench_suite": suite, "deformbench_build_type": "Release"}
    out = []
    for name, ms in (names or {"factorize/mesh:hand/system:lap/build:structured/backend:umfpack": 20.0,
                               "solve/mesh:hand/system:lap/build:structured/backend:umfpack": 2.0,
                               "build/mesh:hand/system:lap/build:structured": 8.0}).items():
        if name == error:
            out.append({"name": name, "run_name": name, "run_type": "iteration", "error_occurred": True,
                        "error_message": "solver failed"})
            continue
        f = scale.get(name, {})
        for i, k in enumerate([1.0, 1.01, 0.99, 1.02, 0.98]):
            out.append({"name": name, "run_name": name, "run_type": "iteration", "repetition_index": i,
                        "cpu_time": ms * k * f.get("cpu_time", 1) * 1e3, "real_time": ms * k * f.get("real_time", 1)
                        * 1e3, "time_unit": "us", "n": 1197.0, "nnz": 12508.0,
                        "nnz_L": round(122047 * f.get("nnz_L", 1)), "bytes": round(595176 * f.get("bytes", 1))})
        out.append({"name": name + "_median", "run_name": name, "run_type": "aggregate", "aggregate_name": "median",
                    "cpu_time": 1e9, "real_time": 1e9, "time_unit": "us"})
    return {"context": ctx, "benchmarks": out}


FACT = "factorize/mesh:hand/system:lap/build:structured/backend:umfpack"


class GoogleBenchmarkRecords(unittest.TestCase):
    def write(self, d, name, doc):
        import json
        path = os.path.join(d, name)
        with open(path, "w") as f:
            json.dump(doc, f)
        return path

    def gate(self, base, now, *args):
        with tempfile.TemporaryDirectory() as d:
            return run_module("dbtools.track.gate", self.write(d, "base.json", base), self.write(d, "now.json", now),
                              *args)

    def test_rows(self):
        with tempfile.TemporaryDirectory() as d:
            h = g.load_history(self.write(d, "r.json", gbench_doc(error="build/mesh:hand/system:lap/build:structured")))
        for got, want in zip(h.values[(FACT, "cpu_s")].values(), [1.0, 1.01, 0.99, 1.02, 0.98]):
            self.assertAlmostEqual(got, 0.02 * want, delta=1e-15)  # 20 ms * k, read in microseconds
        self.assertEqual(h.values[(FACT, "nnz_L")], {1: 122047.0})
        self.assertEqual(h.classes[(FACT, "bytes")][0], "deterministic")
        self.assertEqual(h.classes[(FACT, "wall_s")][0], "time")
        self.assertEqual(h.failed, {"build/mesh:hand/system:lap/build:structured": "solver failed"})
        self.assertEqual((h.meta["machine_cpu"], h.meta["build_type"], h.meta["suite"]),
                         ("AMD EPYC", "Release", "bench_phases v1, abc (3 benchmarks)"))

    def test_the_same_run_passes(self):
        p = self.gate(gbench_doc(), gbench_doc())
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertIn("verdict: pass", p.stdout)

    def test_counters_compared_exactly(self):
        p = self.gate(gbench_doc(), gbench_doc(scale={FACT: {"nnz_L": 1.01}}))
        self.assertEqual(p.returncode, 1, p.stdout)
        self.assertRegex(p.stdout, FACT + r" +nnz_L +deterministic +122047 +123267 +1\.010 +FAIL")
        p = self.gate(gbench_doc(), gbench_doc(scale={FACT: {"bytes": 0.99}}))
        self.assertEqual(p.returncode, 0, p.stdout)
        self.assertRegex(p.stdout, FACT + r" +bytes +deterministic +595176 +589224 +0\.990 +changed")

    def test_cpu_time_by_the_cpu_rule_wall_time_reported(self):
        p = self.gate(gbench_doc(), gbench_doc(scale={FACT: {"cpu_time": 1.5}}))
        self.assertEqual(p.returncode, 1, p.stdout)
        self.assertRegex(p.stdout, FACT + r" +cpu_s +cpu +0\.02 +0\.03 +1\.500 +0\.00[0-9]+ +FAIL")
        p = self.gate(gbench_doc(), gbench_doc(scale={FACT: {"real_time": 2}}))
        self.assertEqual(p.returncode, 0, p.stdout)
        self.assertEqual(self.gate(gbench_doc(), gbench_doc(scale={FACT: {"real_time": 2}}), "--gate-wall")
                         .returncode, 1)

    def test_a_filtered_run_compares_what_ran(self):
        p = self.gate(gbench_doc(), gbench_doc(names={FACT: 20.0}))
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertIn("not run 12", p.stdout)

    def test_an_errored_benchmark_fails(self):
        p = self.gate(gbench_doc(), gbench_doc(error=FACT))
        self.assertEqual(p.returncode, 1, p.stdout)
        self.assertRegex(p.stdout, FACT + r" +status +status .*FAIL +solver failed")

    def test_stale_and_foreign(self):
        p = self.gate(gbench_doc(version="0"), gbench_doc())
        self.assertEqual(p.returncode, 3, p.stderr)
        self.assertIn("is stale: suite definition 'bench_phases v0, abc (3 benchmarks)' in the baseline, "
                      "'bench_phases v1, abc (3 benchmarks)' now", p.stderr)
        old = gbench_doc()
        for k in ("deformbench_suite_version", "deformbench_suite", "deformbench_build_type"):
            del old["context"][k]
        p = self.gate(old, gbench_doc())
        self.assertEqual(p.returncode, 3, p.stderr)
        self.assertIn("suite definition 'not recorded' in the baseline", p.stderr)
        p = self.gate(gbench_doc(cpu_model="Intel Xeon"), gbench_doc())
        self.assertEqual(p.returncode, 4, p.stderr)
        self.assertIn("is foreign: CPU Intel Xeon in the baseline, AMD EPYC now", p.stderr)

    def test_unreadable_records(self):
        bad = gbench_doc()
        del bad["context"]["deformbench_cpu"]
        p = self.gate(gbench_doc(), bad)
        self.assertEqual(p.returncode, 2)
        self.assertIn("no provenance in its context (no deformbench_cpu): not a bench_phases run", p.stderr)
        bad = gbench_doc()
        bad["benchmarks"][0]["cpu_time"] = "fast"
        p = self.gate(gbench_doc(), bad)
        self.assertEqual(p.returncode, 2)
        self.assertRegex(p.stderr, r"cpu_time 'fast' 'us' is not a time")


class WhatIsGated(unittest.TestCase):
    """The report says what the gate compared and, for the rest, why not (report.gated_lines)."""

    def test_counts_by_class_and_reasons(self):
        from dbtools.track import report
        base = g.History.from_rows(
            [row("nnz", "deterministic", "", 5, 1), row("child_wall_s", "info", "", 1.0, 1)] +
            [row("frame_cpu_s", "cpu", "", 0.002, k) for k in range(1, 6)] +
            [row("init_cpu_s", "cpu", "", 0.5, k) for k in range(1, 6)] +
            [row("init_s", "time", "mixed", 0.5, k) for k in range(1, 6)])
        s = g.Settings()
        lines = report.gated_lines(g.compare(base, base, s), s)
        self.assertEqual(lines[0], "gated: 2 of 5 comparisons (cpu 1, deterministic 1)")
        self.assertRegex(lines[1], r"^not gated: 3: ")
        for why in ("1 baseline median under 5 ms (--min-time-s", "1 wall time (follows the load",
                    "1 class info (the whole child's times"):
            self.assertIn(why, lines[1])
        other = g.compare(base, g.History.from_rows([row("init_cpu_s", "cpu", "", 0.5, k, machine="m2")
                                                     for k in range(1, 6)]), s)
        self.assertIn("1 measured on another machine", report.gated_lines(other, s)[1])
        few = g.compare(base, g.History.from_rows([row("init_cpu_s", "cpu", "", 0.5, 1)]), s)
        self.assertIn("1 fewer than 5 rounds on a side", report.gated_lines(few, s)[1])


class BenchmarkJson(unittest.TestCase):
    """ci.py: a record as github-action-benchmark's customSmallerIsBetter input."""

    def test_shape(self):
        import json
        from dbtools.track import ci
        rows = ([row("factorize_cpu_s", "cpu", "", t, k + 1) for k, t in enumerate([0.5, 0.6, 0.4])] +
                [row("nnz_factor", "deterministic", "", 1000, 1), row("peak_rss_bytes", "memory", "", 2048, 1),
                 row("child_wall_s", "info", "", 1.0, 1), row("status", "status", "", None, 1, cell="solve/x",
                                                              message="error: boom"),
                 row("nnz", "deterministic", "", 5, 1, cell="solve/x")])
        with tempfile.TemporaryDirectory() as d:
            path = write_csv(d, "run.csv", rows)
            out = ci.write([path], os.path.join(d, "latest.json"))
            self.assertEqual(out, [os.path.join(d, "run.json")])
            with open(out[0]) as f:
                doc = json.load(f)
            with open(os.path.join(d, "latest.json")) as f:
                self.assertEqual(json.load(f), doc)
            self.assertRaises(ValueError, ci.write, out)  # never over a JSON record
            # Two runs of one invocation (--runs 2): a JSON beside each, latest.json of their rounds pooled.
            second = write_csv(d, "run2.csv", [row("factorize_cpu_s", "cpu", "", t, k + 1)
                                               for k, t in enumerate([0.7, 0.8, 0.9])])
            out = ci.write([path, second], os.path.join(d, "latest.json"))
            self.assertEqual(out, [os.path.join(d, "run.json"), os.path.join(d, "run2.json")])
            with open(os.path.join(d, "latest.json")) as f:
                both = {e["name"]: e for e in json.load(f)}
            with open(out[1]) as f:
                self.assertEqual([e["value"] for e in json.load(f)], [0.8])
        pooled_entry = both[f"{CELL} factorize_cpu_s"]
        self.assertAlmostEqual(pooled_entry["value"], (0.6 + 0.7) / 2, places=15)  # the median of the 6 rounds
        self.assertEqual(pooled_entry["range"], "± 0.25")
        self.assertIn("6 round(s) of 2 runs, min 0.4, max 0.9", pooled_entry["extra"])
        self.assertIsInstance(doc, list)
        by = {e["name"]: e for e in doc}
        # info and the failed cell's measures are left out; every entry has the fields the action reads
        self.assertEqual(sorted(by), [f"{CELL} factorize_cpu_s", f"{CELL} nnz_factor", f"{CELL} peak_rss_bytes"])
        for e in doc:
            self.assertLessEqual(set(e), {"name", "unit", "value", "range", "extra"})
            self.assertIsInstance(e["name"], str)
            self.assertIsInstance(e["unit"], str)
            self.assertIsInstance(e["value"], (int, float))
            self.assertIsInstance(e["extra"], str)
        t = by[f"{CELL} factorize_cpu_s"]
        self.assertEqual((t["unit"], t["value"], t["range"]), ("s", 0.5, "± 0.1"))
        self.assertIn("class cpu; 3 round(s), min 0.4, max 0.6; commit cccccccccccc; machine m1", t["extra"])
        self.assertEqual((by[f"{CELL} nnz_factor"]["unit"], by[f"{CELL} nnz_factor"]["value"]), ("count", 1000))
        self.assertNotIn("range", by[f"{CELL} nnz_factor"])
        self.assertEqual(by[f"{CELL} peak_rss_bytes"]["unit"], "bytes")


class DriverResults(unittest.TestCase):
    """dbtools.track.results: two runs of the drivers' CSVs, schema first, numbers by the gate's rules."""
    HEADER = "model,system,build,backend,factor_storage,measure,value,unit,git_sha,cpu\n"

    def run_on(self, old_rows, new_rows, header_new=None):
        with tempfile.TemporaryDirectory() as d:
            for sub, rows, header in (("old", old_rows, self.HEADER), ("new", new_rows, header_new or self.HEADER)):
                os.mkdir(os.path.join(d, sub))
                with open(os.path.join(d, sub, "table_2_1.csv"), "w") as f:
                    f.write(header + "".join(rows))
            return run_module("dbtools.track.results", os.path.join(d, "old"), os.path.join(d, "new"))

    def rows(self, nnz, init, sha="a"):
        return [f"hand,lap,structured,multifrontal,memory,nnz_factor,{nnz},count,{sha},X\n",
                f"hand,lap,structured,multifrontal,memory,init_s,{init},s,{sha},X\n",
                f"hand,lap,structured,multifrontal,memory,fps_handle,{1 / init},1/s,{sha},X\n"]

    def test_same_schema_and_counts_pass_times_and_rates_summarized(self):
        p = self.run_on(self.rows(1000, 0.75), self.rows(1000, 0.5, sha="b"))
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertIn("init_s: new/old median 0.667 (range 0.667-0.667, 1 values)", p.stdout)
        self.assertIn("fps_handle: new/old median 1.5", p.stdout)  # a rate, not a count of handles

    def test_a_count_grown_fails_a_schema_change_fails(self):
        p = self.run_on(self.rows(1000, 0.5), self.rows(1100, 0.5))
        self.assertEqual(p.returncode, 1, p.stdout)
        self.assertRegex(p.stdout, r"table_2_1\.csv:hand/lap/structured/multifrontal/memory +nnz_factor +deterministic "
                                   r"+1000 +1100 +1\.100 +FAIL")
        p = self.run_on(self.rows(1000, 0.5), [r.rsplit(",", 1)[0] + "\n" for r in self.rows(1000, 0.5)],
                        self.HEADER.replace(",cpu", ""))
        self.assertEqual(p.returncode, 1, p.stdout)
        self.assertIn("schema: table_2_1.csv: columns added [], removed ['cpu']", p.stdout)
        p = self.run_on(self.rows(1000, 0.5), self.rows(1000, 0.5)[:1])
        self.assertEqual(p.returncode, 1, p.stdout)
        self.assertIn("table_2_1.csv: measures only old ['fps_handle', 'init_s'], only new []", p.stdout)


if __name__ == "__main__":
    unittest.main()
