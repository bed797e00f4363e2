"""A diagnostic of this record, NOT the project's rule: dbtools.track.power with the CPU-time rule deciding on the
drift-normalized medians alone. The default (python/dbtools/track/gate.py) also requires the raw median to be slower
by as much, so that normalization may excuse a slowdown, never make one; this shows what that requirement costs
when the machine's speed moves the whole suite between invocations. Everything else is the default rule (the
threshold, twice the run spread, the U test on the normalized rounds, the floor).
  PYTHONPATH=python /usr/bin/python3 results/records/2026-11-26-gate-rule/normalized_only.py RUN RUN ... [power options]
"""
import statistics
import sys

from dbtools.track import gate as g
from dbtools.track import power


def compare_cpu_normalized_only(c, base, now, key, s, same_machine, drift):
    b, n = g._runs(base, key), g._runs(now, key)
    c.base, c.now = statistics.median(b), statistics.median(n)
    nb, nn = drift.normalized(base, key, "base"), drift.normalized(now, key, "now")
    if c.base <= 0 or statistics.median(nb) <= 0:
        return
    c.ratio = statistics.median(nn) / statistics.median(nb)
    c.note = f"raw {c.now / c.base:.3f}"
    _, need = g._cpu_bar(c, base, now, key, s, drift)
    if g._time_verdict(c, nb, nn, c.base, s, same_machine) and c.ratio > 1 + need:
        g._floor_verdict(c, c.base * (c.ratio - 1), s)


default_configuration = power.configuration
power.configuration = lambda a, s, n: ("VARIANT (normalized_only.py, NOT ./run track's rule: CPU time decided on the "
                                       "drift-normalized medians alone); " + default_configuration(a, s, n))
g._compare_cpu = compare_cpu_normalized_only
sys.exit(power.main())
