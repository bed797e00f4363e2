"""The tracking history as pages, in airspeed velocity's shape: a page per tracked measure, on it a chart per cell
over the runs in date order (labelled by commit), each run's rounds drawn as their spread (min-max whisker,
interquartile box) and its median joined run to run; machines apart (a section each: times of two machines do not
share an axis). Reads RESULTS/history/{runs,reference}/*.csv (dbtools.plots.history.read_runs: runs with --override
rules left out, the runs of one commit taken in a row joined into one, as `./run track --runs` takes them) through
the gate's record (dbtools.track.history). Charts are inline SVG: nothing to load."""
import re
import statistics
import sys
from collections import defaultdict

from ..plots.history import read_runs, run_count
from ..plots.styles import COLOURS
from ..track.history import History, InputError
from ..track.provenance import describe_machine
from .layout import Page, esc

TRACKED = ("deterministic", "memory", "cpu", "time")  # the gate's classes; "info" is recorded, never compared
W, H, PAD_L, PAD_R, PAD_T, PAD_B = 440, 170, 62, 10, 10, 38


def spread(values):
    """(min, q1, median, q3, max) of a run's rounds."""
    v = sorted(values)
    if len(v) == 1:
        return (v[0],) * 5
    q = statistics.quantiles(v, n=4, method="inclusive")
    return v[0], q[0], q[1], q[2], v[-1]


def collect(results):
    """{machine: {"meta": newest run's meta, "runs": [meta], "series": {(measure, cell): [(run index, spread)]},
    "class": {measure: class}}}"""
    machines = {}
    for rows in read_runs(results):
        try:
            h = History.from_rows(rows)
        except InputError as e:  # a history of another format: left out, said so
            print(f"[site] history left out: {e}", file=sys.stderr)
            continue
        m = machines.setdefault(h.meta["machine_id"], {"runs": [], "series": defaultdict(list), "class": {},
                                                       "files": 0})
        m["files"] += run_count(rows)
        m["meta"] = h.meta
        i = len(m["runs"])
        m["runs"].append(h.meta)
        for (cell, measure), reps in h.values.items():
            cls = h.classes[(cell, measure)][0]
            vals = [x for x in reps.values() if x == x]
            if cls in TRACKED and vals:
                m["series"][(measure, cell)].append((i, spread(vals)))
                m["class"][measure] = cls
    return machines


def unit_of(measure):
    if measure.endswith("_s"):
        return "s"
    return "bytes" if measure.endswith("bytes") else ""


def fmt(x):
    return f"{x:.4g}"


def chart(cell, measure, points, runs, colour):
    """One cell's SVG: x = the machine's runs in date order, y = the measure, whisker min-max, box IQR, median line."""
    lo = min(p[1][0] for p in points)
    hi = max(p[1][4] for p in points)
    if hi == lo:
        lo, hi = lo - (abs(lo) * 0.05 or 1), hi + (abs(hi) * 0.05 or 1)
    pad = (hi - lo) * 0.08
    lo, hi = lo - pad, hi + pad
    n = max(len(runs), 2)
    x = lambda i: PAD_L + (W - PAD_L - PAD_R) * (i + 0.5) / n  # noqa: E731
    y = lambda v: PAD_T + (H - PAD_T - PAD_B) * (hi - v) / (hi - lo)  # noqa: E731
    out = [f'<svg class="chart" viewBox="0 0 {W} {H}" width="{W}" height="{H}" role="img">',
           f'<rect x="{PAD_L}" y="{PAD_T}" width="{W - PAD_L - PAD_R}" height="{H - PAD_T - PAD_B}" class="frame"/>']
    for k in range(5):
        v = lo + (hi - lo) * k / 4
        out.append(f'<text x="{PAD_L - 4}" y="{y(v) + 4:.1f}" class="tick" text-anchor="end">{fmt(v)}</text>')
    step = max(1, len(runs) // 8)
    for i, meta in enumerate(runs):
        if i % step == 0:
            label = esc((meta.get("git_sha") or meta.get("commit", ""))[:8])
            out.append(f'<text x="{x(i):.1f}" y="{H - PAD_B + 14}" class="tick" text-anchor="middle">{label}</text>')
    for lo_k, hi_k, opacity in ((0, 4, 0.12), (1, 3, 0.22)):  # the bands: min-max, then the interquartile range
        if len(points) > 1:
            edge = [f"{x(i):.1f},{y(s[hi_k]):.1f}" for i, s in points] + \
                   [f"{x(i):.1f},{y(s[lo_k]):.1f}" for i, s in reversed(points)]
            out.append(f'<polygon points="{" ".join(edge)}" fill="{colour}" fill-opacity="{opacity}" stroke="none"/>')
    line = " ".join(f"{x(i):.1f},{y(s[2]):.1f}" for i, s in points)
    out.append(f'<polyline points="{line}" fill="none" stroke="{colour}" stroke-width="1.5"/>')
    bw = min(14, (W - PAD_L - PAD_R) / n * 0.5)
    for i, (mn, q1, med, q3, mx) in points:
        meta = runs[i]
        tip = esc(f"{meta.get('git_sha') or meta.get('commit', '')[:12]} {meta.get('date')}: median {fmt(med)}, "
                  f"IQR {fmt(q1)}-{fmt(q3)}, min-max {fmt(mn)}-{fmt(mx)}")
        out += [f'<g><title>{tip}</title>',
                f'<line x1="{x(i):.1f}" x2="{x(i):.1f}" y1="{y(mn):.1f}" y2="{y(mx):.1f}" stroke="{colour}"/>',
                f'<rect x="{x(i) - bw / 2:.1f}" y="{y(q3):.1f}" width="{bw:.1f}" height="{max(y(q1) - y(q3), 1):.1f}"'
                f' fill="{colour}" fill-opacity="0.35" stroke="{colour}"/>',
                f'<circle cx="{x(i):.1f}" cy="{y(med):.1f}" r="3" fill="{colour}"/></g>']
    out.append(f'<text x="{PAD_L}" y="{H - 6}" class="axis">runs in date order (commit); {esc(measure)}'
               f'{" (" + unit_of(measure) + ")" if unit_of(measure) else ""}</text></svg>')
    return f'<div class="cell"><h4>{esc(cell)}</h4>{"".join(out)}</div>'


def page_name(measure):
    return "history_" + re.sub(r"[^A-Za-z0-9_]", "_", measure) + ".html"


def measure_page(measure, machines):
    body = [f"<h1>History: {esc(measure)}</h1>",
            "<p>Each chart: one cell over the runs of <code>./run track</code> on one machine, in date order, "
            "labelled by commit (the runs of one commit taken in a row, as one <code>./run track</code> takes "
            "them, joined). Per run, its rounds: whisker min-max, box interquartile range, dot and line the "
            "median. Hover a run for its figures. Machines are kept apart: their times are not comparable.</p>"]
    for k, (mid, m) in enumerate(sorted(machines.items())):
        cells = sorted(c for (ms, c) in m["series"] if ms == measure)
        if not cells:
            continue
        body.append(f"<h2>{esc(describe_machine(m['meta']))}</h2><p>{m['files']} run(s) as {len(m['runs'])} "
                    "point(s); class "
                    f"{esc(m['class'][measure])}</p><div class=\"charts\">")
        colour = COLOURS[k % len(COLOURS)]
        body += [chart(c, measure, m["series"][(measure, c)], m["runs"], colour) for c in cells]
        body.append("</div>")
    return Page(page_name(measure), f"History: {measure}", "\n".join(body), nav=False)


def pages(results):
    machines = collect(results)
    measures = sorted({ms for m in machines.values() for (ms, _) in m["series"]})
    if not measures:
        body = ("<h1>Tracking history</h1><p>No tracking history under <code>history/runs</code> or "
                "<code>history/reference</code>: <code>./run track</code> records one.</p>")
        return [Page("history.html", "History", body)]
    rows = "".join(f'<li><a href="{page_name(ms)}">{esc(ms)}</a> ({esc(cls_of(machines, ms))})</li>'
                   for ms in measures)
    runs = "".join(f"<tr><td>{esc(describe_machine(m['meta']))}</td><td>{m['files']} ({len(m['runs'])} point(s))"
                   "</td><td>"
                   f"{esc(m['runs'][0].get('date'))}</td><td>{esc(m['runs'][-1].get('date'))}</td></tr>"
                   for _, m in sorted(machines.items()))
    body = ("<h1>Tracking history</h1><p>The runs of the tracking suite (<code>./run track</code>, "
            "docs/tracking.md), a page per tracked measure (the gate's classes: deterministic, memory, CPU time, "
            "wall time).</p><table><tr><th>machine</th><th>runs</th><th>first</th><th>last</th></tr>"
            f"{runs}</table><ul>{rows}</ul>")
    what = "each tracked measure of the tracking suite over commits, with its spread, machines apart"
    return [Page("history.html", "History", body, summary=what)] + [measure_page(ms, machines) for ms in measures]


def cls_of(machines, measure):
    return next(m["class"][measure] for m in machines.values() if measure in m["class"])
