"""The gate's report: the comparisons that matter as a table on stdout, and all of them as Markdown."""
import math
import os

from .gate import cpu_drift
from .provenance import describe_machine


def fmt_value(x, measure):
    if math.isnan(x):
        return ""
    if measure.endswith("_s"):
        return f"{x:.4g}"
    return f"{x:.0f}" if abs(x) < 1e15 else f"{x:.6g}"


def fmt_row(c):
    ratio = "" if math.isnan(c.ratio) else f"{c.ratio:.3f}"
    p = "" if math.isnan(c.p) else f"{c.p:.3g}"
    return [c.cell, c.measure, c.cls, fmt_value(c.base, c.measure), fmt_value(c.now, c.measure), ratio, p,
            c.verdict, c.note]


HEADER = ["cell", "measure", "class", "baseline", "now", "ratio", "p", "verdict", "note"]


def describe(h):
    """A record's provenance in one line: commit, date, machine, suite, overrides, file."""
    m = h.meta
    parts = [m.get("date"), describe_machine(m) if m.get("machine_id") else "",
             f"suite {m['suite']}" if m.get("suite") else "",
             f"overrides: {m['overrides']}" if m.get("overrides") else ""]
    inner = ", ".join(p for p in parts if p)
    head = m.get("git_sha") or m.get("commit", "")[:12]
    return " ".join(x for x in (head, f"({inner})" if inner else "", h.path) if x)


def largest_time_ratios(cmps, cls="cpu", k=5, min_time_s=0.005):
    """The comparisons of a timed class with the largest change either way (those compared: same machine,
    enough runs, over min_time_s)."""
    t = [c for c in cmps if c.cls == cls and not math.isnan(c.ratio) and c.verdict != "new" and
         (not math.isnan(c.p) or cls == "time" and c.base >= min_time_s and c.note.startswith("raw"))]
    return sorted(t, key=lambda c: -abs(math.log(c.ratio)) if c.ratio > 0 else 0)[:k]


def not_gated_reason(c, s):
    """Why the comparison `c` (verdict "not gated") was not gated, in words."""
    if c.cls == "info":
        return "class info (the whole child's times: recorded, never compared)"
    if "other machine" in c.note:
        return "measured on another machine (times and memory of two machines are not comparable)"
    if "--gate-wall" in c.note:
        return "wall time (follows the load on a shared machine: reported; gated only with --gate-wall)"
    if c.note.startswith("under "):
        return (f"baseline median under {s.min_time_s * 1e3:g} ms (--min-time-s: such phases move by more than the "
                "threshold between runs of one commit)")
    if " runs < " in c.note:
        return (f"fewer than {s.min_repeats} rounds on a side (--min-repeats; --repeats, or --baseline-runs on a "
                "machine without history)")
    return c.note or "not gated"


def gated_lines(cmps, s):
    """What the gate compared and what it did not, with why: two lines, counts by class and by reason."""
    gated = [c for c in cmps if c.verdict not in ("not gated", "new", "not run")]
    by_cls, reasons = {}, {}
    for c in gated:
        by_cls[c.cls] = by_cls.get(c.cls, 0) + 1
    for c in cmps:
        if c.verdict == "not gated":
            why = not_gated_reason(c, s)
            reasons[why] = reasons.get(why, 0) + 1
    lines = [f"gated: {len(gated)} of {len(cmps)} comparisons (" +
             (", ".join(f"{k} {n}" for k, n in sorted(by_cls.items())) or "none") + ")"]
    if reasons:
        lines.append(f"not gated: {sum(reasons.values())}: " +
                     "; ".join(f"{n} {why}" for why, n in sorted(reasons.items(), key=lambda x: -x[1])))
    return lines


def resolution_lines(cmps, s):
    """The CPU-time phases gated whose resolution (the smallest slowdown the rule can fail there) is coarser than
    --target, each with why: what the gate cannot promise to catch, said rather than hidden."""
    gated = [c for c in cmps if c.cls == "cpu" and c.verdict in ("ok", "FAIL", "recorded only")]
    coarse = [c for c in gated if not c.gateable_at(s.target)]
    if not gated:
        return []
    return [f"CPU-time resolution: {len(gated) - len(coarse)} of {len(gated)} phases gated can fail a slowdown of "
            f"x{1 + s.target:g} (--target); coarser: {len(coarse)}" +
            "".join(f"; {c.cell} {c.measure} x{1 + c.resolution:.2f} ({c.bound_by})"
                    for c in sorted(coarse, key=lambda c: -c.resolution))]


def summary_lines(base, now, cmps, s, notes=()):
    drift = cpu_drift(base, now, s)
    fails = [c for c in cmps if c.verdict == "FAIL"]
    counts = {}
    for c in cmps:
        counts[c.verdict] = counts.get(c.verdict, 0) + 1
    lines = [f"baseline: {describe(base)}", f"now:      {describe(now)}",
             f"rules: deterministic +{s.det_threshold:.1%} | peak RSS +{s.rss_threshold:.0%} | CPU time "
             f"+{s.threshold:.0%} and more than {s.noise_k:g} x its run-to-run spread (several runs a side), U-test "
             f"p < {s.alpha:g} (>= {s.min_repeats} runs), at least "
             f"{s.min_delta_s * 1e3:g} ms slower (else recorded only) | wall time "
             + ("the same, normalized by the machine rates, raw too" if s.gate_wall else "reported (--gate-wall)"),
             *notes,
             "comparisons: " + ", ".join(f"{v} {n}" for v, n in sorted(counts.items())) +
             (" (not run: in the baseline, not in this run)" if "not run" in counts else ""),
             "CPU drift by round (median ratio of the round's CPU times to the baseline's medians), baseline / now: "
             + " / ".join(" ".join(f"{f:.3f}" for _, f in sorted(d.items())) or "none"
                          for d in (drift.base, drift.now))]
    lines += gated_lines(cmps, s)
    lines += resolution_lines(cmps, s)
    recorded = [c for c in cmps if c.verdict == "recorded only"]
    if recorded:
        lines.append(f"recorded only (past the threshold and significant, but under the {s.min_delta_s * 1e3:g} ms "
                     "floor: short phases of one commit move that much between runs): "
                     + ", ".join(f"{c.cell} {c.measure} {c.ratio:.3f} (+{(c.now - c.base) * 1e3:.1f} ms)"
                                 for c in recorded))
    for cls, what in (("cpu", "CPU time"), ("time", "normalized wall time")):
        big = largest_time_ratios(cmps, cls, min_time_s=s.min_time_s)
        if big:
            lines.append(f"largest {what} changes: " + ", ".join(f"{c.cell} {c.measure} {c.ratio:.3f}" for c in big))
    lines.append(f"verdict: {'FAIL (' + str(len(fails)) + ' regression(s))' if fails else 'pass'}")
    return lines


def print_report(base, now, cmps, s, show_all=False, notes=()):
    rows = [fmt_row(c) for c in cmps if show_all or c.verdict not in ("ok", "not gated", "not run")]
    if rows:
        widths = [max(len(str(r[i])) for r in rows + [HEADER]) for i in range(len(HEADER))]
        for r in [HEADER] + rows:
            print("  ".join(str(x).ljust(w) for x, w in zip(r, widths)).rstrip())
        print()
    for line in summary_lines(base, now, cmps, s, notes):
        print(line)


def markdown(base, now, cmps, s, notes=(), title="Tracking suite"):
    out = [f"# {title}: last comparison", "", "Written by `python3 -m dbtools.track.gate` (`./run track`).", ""]
    out += [f"- {line}" for line in summary_lines(base, now, cmps, s, notes)]
    table = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    for title, pick in (("Failures", lambda c: c.verdict == "FAIL"),
                        ("Recorded only (under the --min-delta-ms floor)", lambda c: c.verdict == "recorded only"),
                        ("Other changes", lambda c: c.verdict in ("changed", "new")),
                        ("All comparisons", lambda c: True)):
        rows = [c for c in cmps if pick(c)]
        out += ["", f"## {title}", ""]
        out += table + ["| " + " | ".join(fmt_row(c)) + " |" for c in rows] if rows else ["none"]
    return "\n".join(out) + "\n"


def write_atomically(path, text):
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
