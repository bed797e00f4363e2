"""results/figures.md: the thesis' figures (Zhou 2008: 2-3, 2-5, 3-4, 4-1, 4-4, 4-5) and the LSE report's bunny-ear
example mapped to the frames study's cases, each with its render (figures/render_CASE.png, dbtools/plots/render_meshes.py) and
the measures of frames.csv beside it. Reads frames.csv and checks which renders exist; measures nothing. The setups
(meshes, selections, transforms) are the cases of data/experiments/frames.toml and the edits under data/edits/.
"""
import math
import os
import re

from .common import (cite_figure, geomean, isnan, number, provenance, read_rows, repeated_spread, settings,
                     write_atomically)
from .frames import NEAR_COLLAPSE, ROUND_OFF

MEASURES = [("ideal_rms", "RMS to ideal"), ("edge_distortion", "edge-length distortion"),
            ("volume_change", "volume change"), ("max_displacement", "max displacement"),
            ("lri_detail_error", "LRI detail error"), ("init_s", "init s"), ("frame_s", "frame s (median)")]
TIMES = {"init_s", "frame_s"}  # shown with their spread over the repetitions where there are several
# The measures that say which method a result is nearest (nearest()): shape, not time or the handle's move.
SHAPE = ["ideal_rms", "edge_distortion", "volume_change", "lri_detail_error"]
# Relative differences within this band count as a tie (the band frames.md uses for frame strategies).
TIE = 0.01
LABELS = {"lap": "LAP", "tf": "TF", "tf-normalized": "TF normalized scale",
          "lri-first-gram_schmidt": "LRI first-neighbour frames, Gram-Schmidt",
          "lri-height_angle-gram_schmidt": "LRI height-angle frames (thesis eq. 4-4), Gram-Schmidt",
          "lri-curvature-gram_schmidt": "LRI principal-direction frames, Gram-Schmidt",
          "lri-first-polar": "LRI first-neighbour frames, polar",
          "lri-uncoordinated": "LRI uncoordinated (handle frames at rest), first-neighbour, Gram-Schmidt"}
# Short names for the generated sentences; a figure's "short" overrides them where its context names them better.
SHORT = {"lap": "LAP", "tf": "TF", "tf-normalized": "normalized TF", "lri-first-polar": "LRI polar",
         "lri-first-gram_schmidt": "LRI first-neighbour/GS", "lri-height_angle-gram_schmidt": "LRI height-angle/GS",
         "lri-curvature-gram_schmidt": "LRI principal-direction/GS", "lri-uncoordinated": "uncoordinated LRI"}
METHODS = ["lap", "tf", "tf-normalized", "lri-first-polar"]
FRAMES = ["lri-first-gram_schmidt", "lri-height_angle-gram_schmidt", "lri-curvature-gram_schmidt", "lri-first-polar"]

# Each figure: the thesis' caption and what it shows, our cases and configurations, and where ours differs and why.
FIGURES = [
    {"title": "Thesis fig. 2-3: dragging a bunny's ear, LAP against TF",
     "thesis": "One ear of the bunny is only dragged (a translation); the thesis points out that a natural result "
               "turns the ear where it meets the head, which LAP cannot do (its Laplacian coordinates do not rotate) "
               "and TF does.",
     "cases": ["bunny_ear"], "configs": METHODS,
     "seen": "Seen from the side (+z; the bunny faces -x), the ear is dragged backwards in the image plane. LAP "
             "stretches the ear along the drag and keeps it narrow; TF turns it and widens it towards the tip (its "
             "fitted similarities scale up); TF with normalized scale turns it with less widening; LRI turns it and "
             "keeps it thin. The distance maps below the shapes (each result's distance from LAP's) put every "
             "difference in the ear, largest for TF at its tip.",
     "ours": "CGAL's `bunny00` (data/meshes, the Stanford bunny rescaled into [-0.5, 0.5], +y up); "
             "`data/edits/figures/bunny_ear.edit`: the {handle:bunny_ear} vertices nearest the tip of the ear that "
             "reaches highest moved 0.15 along +x, a sphere of radius 0.24 around the ear free, the rest fixed.",
     "differs": "The thesis does not give its bunny's resolution, selection or drag vector; ours are chosen to match "
                "the description (a pure translation of the ear tip). The render shows the whole bunny from +z, its "
                "side, where the drag lies in the image plane."},
    {"title": "The LSE report's example: the bunny's ear",
     "thesis": "The report (Laplacian Surface Editing, Sorkine et al. 2004, re-implemented in Python) deforms the "
               "ear of the Stanford bunny with the TF energy (fitted s, h, t per vertex), the handle and region "
               "picked by vertex index in Blender, and concludes that the ear deforms while keeping its detail.",
     "cases": ["bunny_ear"], "configs": ["tf", "tf-normalized", "lap"],
     "seen": "The TF panel of render_bunny_ear.png is the report's method: the ear follows the tip, its surface "
             "detail kept, widening towards the tip.",
     "ours": "The same case as fig. 2-3: TF (`--method tf`, translation fitted as in the report's 7-unknown T_i) on "
             "CGAL's bunny00.",
     "differs": "The report's vertex indices and mesh file are not given, so the selection is ours; its solve is a "
                "dense or SciPy least-squares solve, ours the factored normal equations (the same minimizer)."},
    {"title": "Thesis fig. 2-5: editing a large model (armadillo)",
     "thesis": "An armadillo of 48969 points deformed interactively, made practical by the initialization "
               "optimizations of chapter 2 (Table 2-1).",
     "cases": ["armadillo_arm"], "configs": METHODS,
     "seen": "Seen from behind (+z), the right arm (on the image's right) comes down in every method; at this scale "
             "the methods look alike (the table's edge-length distortion tells them apart), and the shell's detail "
             "outside the region is untouched. The distance maps below the shapes (each result's distance from "
             "LAP's) show where they differ: along the arm only, uncoordinated LRI most at the hand.",
     "ours": "CGAL's armadillo ({vertices:armadillo_arm} vertices): `data/edits/figures/armadillo_arm.edit` lowers "
             "the right hand by a {angle:armadillo_arm}-degree turn about the shoulder, the arm free, the body fixed.",
     "differs": "Our bundled armadillo has {vertices:armadillo_arm} vertices against the thesis' 48969 points (its "
                "Loop-subdivided 104k version is in Table 2-1's timings, results/table_2_1.md); the thesis does not "
                "say which edit it made. {times}"},
    {"title": "Thesis fig. 3-4: coordinated against uncoordinated frame and position control (LRI)",
     "thesis": "In LRI the handle's frames and positions are both constrained; when the frame rotation does not "
               "match the position change the result is poor, when they are coordinated it is natural.",
     "cases": ["dino_head90", "bs08_cactus"],
     "configs": ["lap", "lri-first-gram_schmidt", "lri-uncoordinated"],
     "seen": "Coordinated LRI turns the dino's head with a smooth neck and bends the cactus with its arms turned "
             "along; LAP, without frames, leaves the dino's neck thinner and the cactus' top swollen. Uncoordinated "
             "LRI moves the handle's positions as far as the others but keeps every frame at rest: the cactus' trunk "
             "shears into a straight slant with both arms still upright and a kink under the handle, and the "
             "dino's neck shears where the turned head meets it.",
     "ours": "`exp_frames` runs LRI twice on each case: coordinated (the method: the handle's frames turn by the "
             "rotation part of the transform that moves its positions, methods/lri.h) and uncoordinated "
             "(`deformbench deform ... --method lri --lri-frame-control uncoordinated`: the handle's frames stay at "
             "rest while its positions move), first-neighbour frames and Gram-Schmidt in both; LAP beside them.",
     "differs": "The thesis (section 3.4.2) gives no setup for its uncoordinated panel, only that the frame control "
                "and the position control disagree; ours is the plainest disagreement (frames not turned at all). "
                "With every frame constraint at rest the frame solve returns the rest frames exactly, so the "
                "position solve asks each edge for its rest vector: an edge-vector Laplacian edit without rotation; "
                "LAP's Laplacian coordinates do not rotate either (which of LAP and coordinated LRI its measures lie "
                "nearer: Measured, above).",
     "short": {"lri-first-gram_schmidt": "coordinated LRI"},
     "worst": ("lri_detail_error", ["lap", "lri-first-gram_schmidt", "lri-uncoordinated"]),
     "nearest": ("lri-uncoordinated", ["lap", "lri-first-gram_schmidt"], ["dino_head90", "bs08_cactus"])},
    {"title": "Thesis fig. 4-1: multi-turn rotation keeps the detail",
     "thesis": "LRI keeps the local detail through rotations of several full turns.",
     "cases": ["bar_twist720", "bar_twist1080"], "configs": METHODS,
     "seen": "Through 2 and 3 turns LRI keeps the bar's square section and edges, its twist winding less evenly "
             "than the ideal; plain TF swells into a bulb below the handle; normalized TF stays slender but pinches "
             "unevenly; LAP returns to the rest bar (its result is linear in the handle, and a chain of full turns "
             "sums to nothing).",
     "ours": "The procedural bar (1 x 1 x 8, {vertices:bar_twist720} vertices) twisted by 2 and 3 full turns as "
             "chains of {step}-degree edits, each re-using the previous result as its rest mesh (a single transform "
             "cannot tell k turns from none).",
     "differs": "The thesis' model carries surface detail; the bar's detail is its sharp edges and flat faces, which "
                "`LRI detail error` and the distance to the analytic twist measure. Chaining is ours: the thesis "
                "drives the rotation interactively, which is a chain of small edits too."},
    {"title": "Thesis fig. 4-4: 180-degree cylinder bend and multi-turn cuboid twist, principal-direction frames "
              "against plain LRI",
     "thesis": "Frames along the principal curvature directions make the 180-degree bend and the multi-turn twist "
               "of a cuboid more natural than the original LRI frames.",
     "cases": ["cyl60x32_bend180", "cgal_cyl_bend180", "bar_twist720", "bar_twist1080"], "configs": FRAMES,
     "seen": "At 180 degrees every LRI frame strategy folds the tube into an inverted V with a kink at mid-length "
             "(the panels are alike); TF and normalized TF round the arch, LAP flattens its top. The twists' LRI "
             "panels are alike for every strategy.",
     "ours": "Procedural cylinders (60 rings x 32 segments, radius 1, height 10; and CGAL's half tube) bent by 180 "
             "degrees with the analytic bend as ideal; the bar twisted by 2 and 3 turns. LRI with first-neighbour, "
             "height-angle and principal-direction (curvature) frames.",
     "differs": "results/frames.md derives and measures why the frame choice cannot matter with polar "
                "orthonormalization and matters only through Gram-Schmidt's first axis.",
     "why_not": "Why, as we read it: the frame solve is linear and "
                "least-squares, so its solved frames average rotations whatever basis each vertex starts from; the "
                "basis enters the result only through Gram-Schmidt's first axis (polar orthonormalization removes "
                "it), and at 180 degrees and more the averaging, not the basis, dominates. The thesis shows one "
                "picture per variant without a measure, so a visual gain there may come from its model's detail "
                "(principal directions are well defined on its scanned shapes, ill defined on our cylinder's flat "
                "axis and the bar's faces) rather than from the method.",
     "collapse": ["cyl60x32_bend180", "cgal_cyl_bend180"],
     "compare": ("lri-curvature-gram_schmidt", "lri-first-gram_schmidt", "ideal_rms")},
    {"title": "Thesis fig. 4-5: more edits",
     "thesis": "Further LRI edits on scanned models (the dinosaur's head turned among them).",
     "cases": ["dino_head90", "bs08_cactus", "bs08_bar", "bs08_cylinder", "bs08_plane", "armadillo_arm"],
     "configs": METHODS,
     "seen": "The BS08 cactus shows plain TF's blow-up (the trunk swells to several times its size; that panel has "
             "a frame of its own, its size against the others' in its title). The dino's results differ by too "
             "little to tell apart side by side; the distance maps below its shapes put the differences in the neck "
             "and the head.",
     "ours": "CGAL's dino with its head turned {angle:dino_head90} degrees (`data/edits/dino_head.edit`), the four "
             "Botsch-Sorkine 2008 edits (data/bs08) and the armadillo arm.",
     "differs": "The thesis' other models are not bundled; the BS08 edits are the standard benchmark set of that "
                "survey and stand in for them.",
     "nearest": ("tf-normalized", ["lap", "lri-first-polar"], ["bs08_cactus"])},
]


def fmt(x):
    return "n/a" if isnan(x) else f"{x:.4g}"


def case_rows(rows):
    out = {}
    for r in rows:
        out.setdefault(r["case"], {})[r["config"]] = r
    return out


def setup_line(case, by_config):
    r = next(iter(by_config.values()))
    return (f"`{case}`: mesh {r['mesh'] or r['source']}, {r['vertices']} vertices, {r['handle']} handle / "
            f"{r['fixed']} fixed / {r['free']} free, {float(r['angle_deg']):.0f} degrees, {r['protocol']}")


def value(by_config, config, measure):
    """A measure of one configuration of a case, NaN where it failed or is missing."""
    r = by_config.get(config)
    return number(r.get(measure, "")) if r is not None and r["status"] == "ok" else math.nan


def short(fig, config):
    return {**SHORT, **fig.get("short", {})}.get(config, LABELS.get(config, config))


def polar_label(by_config):
    """The LRI polar row's name: 'every frame strategy' only where the polar strategies' meshes agree to round-off
    (diff_vs_first_max); otherwise it is the first-neighbour result and the others' largest difference."""
    diffs = [number(r["diff_vs_first_max"]) for r in by_config.values()
             if r["status"] == "ok" and r["method"] == "lri" and r["orthonormalize"] == "polar"]
    diffs = [d for d in diffs if not isnan(d)]
    if len(diffs) < 2:
        return LABELS["lri-first-polar"]
    if max(diffs) <= ROUND_OFF:
        return "LRI, polar (every frame strategy: the same mesh up to round-off)"
    return f"LRI first-neighbour frames, polar (the frame strategies differ by up to {max(diffs):.3g})"


def time_cell(r, m):
    """A timing with its spread (least - largest, n) where it is a median of several repetitions."""
    get = lambda k: number(r.get(k, ""))  # noqa: E731
    return fmt(get(m)) + repeated_spread(get, m, fmt)


def metrics_table(by_config, configs):
    o = ["| configuration |" + "".join(f" {lab} |" for _, lab in MEASURES), "|---|" + "---|" * len(MEASURES)]
    for c in configs:
        r = by_config.get(c)
        if r is None:
            continue
        label = polar_label(by_config) if c == "lri-first-polar" else LABELS.get(c, c)
        if r["status"] != "ok":
            o.append(f"| {label} | {r['status']} |" + " |" * (len(MEASURES) - 1))
            continue
        o.append(f"| {label} |" + "".join(f" {time_cell(r, m) if m in TIMES else fmt(number(r.get(m, '')))} |"
                                          for m, _ in MEASURES))
    return "\n".join(o)


def comparison(fig, cases):
    """`a` against `b` on the figure's cases: ('case x vs y (+z%)' line, the ratios x / y) for fig['compare']."""
    a, b, m = fig["compare"]
    parts, ratios = [], []
    for case in fig["cases"]:
        x, y = (number(cases.get(case, {}).get(c, {}).get(m, "")) for c in (a, b))
        if not isnan(x) and not isnan(y) and y > 0 and x > 0:
            parts.append(f"`{case}` {fmt(x)} vs {fmt(y)} ({100 * (x / y - 1):+.0f}%)")
            ratios.append(x / y)
    if not parts:
        return "", ratios
    g = geomean(ratios)
    better = sum(r < 1 for r in ratios)
    return (f"{LABELS.get(a, a)} against {LABELS.get(b, b)}, {dict(MEASURES)[m]}: " + "; ".join(parts) +
            f". Over these {len(ratios)} cases: geometric mean ratio {g:.3f} ({100 * (g - 1):+.1f}%), closer in "
            f"{better} of {len(ratios)}.\n"), ratios


def improvement(fig, ratios):
    """Whether the thesis' improvement shows in comparison()'s ratios: closer by more than TIE in every case; where
    not, the counts and fig['why_not']."""
    if not ratios:
        return ""
    a, b, m = fig["compare"]
    n = len(ratios)
    closer, farther = sum(r < 1 - TIE for r in ratios), sum(r > 1 + TIE for r in ratios)
    g = geomean(ratios)
    counts = (f"{short(fig, a)} is closer than {short(fig, b)} by more than "
              f"{100 * TIE:g}% ({dict(MEASURES)[m]}) in {closer} of {n} cases, farther in {farther}, within "
              f"{100 * TIE:g}% in {n - closer - farther}; geometric mean ratio {g:.3f}")
    if closer == n:
        return f" The thesis' improvement is reproduced: {counts}."
    return f" The thesis' improvement is not reproduced: {counts}. {fig.get('why_not', '')}"


def collapse_line(fig, cases):
    """The solved LRI frames' smallest singular value on fig['collapse'], and whether they nearly collapse."""
    parts, lows, same = [], [], True
    for case in fig.get("collapse", []):
        sig = [value(cases.get(case, {}), c, "frame_sigma_min") for c in fig["configs"]]
        sig = [x for x in sig if not isnan(x)]
        if not sig:
            continue
        same = same and fmt(min(sig)) == fmt(max(sig))
        parts.append(f"{fmt(min(sig))} on `{case}`" if fmt(min(sig)) == fmt(max(sig))
                     else f"{fmt(min(sig))} - {fmt(max(sig))} on `{case}`")
        lows += [case] if min(sig) < NEAR_COLLAPSE else []
    if not parts:
        return ""
    out = (" Smallest singular value of a solved LRI frame (1 for a rotation), "
           + ("the same for every frame strategy" if same else "least - largest over the frame strategies") + ": "
           + ", ".join(parts) + ".")
    if lows:
        out += (f" Below {NEAR_COLLAPSE:g} (" + ", ".join(f"`{c}`" for c in lows) + ") the linear frame solve nearly "
                "collapses, whatever the frame choice (results/frames.md, point 4).")
    return out


def worst_line(fig, cases):
    """Per case, which of fig['worst']'s configurations has the largest of its measure."""
    m, configs = fig["worst"]
    parts = []
    for case in fig["cases"]:
        vals = {c: value(cases.get(case, {}), c, m) for c in configs}
        vals = {c: v for c, v in vals.items() if not isnan(v)}
        if len(vals) < 2:
            continue
        w = max(vals, key=vals.get)
        parts.append(f"{short(fig, w)} on `{case}` ({fmt(vals[w])}; "
                     + ", ".join(f"{short(fig, c)} {fmt(v)}" for c, v in vals.items() if c != w) + ")")
    return f"Largest {dict(MEASURES)[m]} of the {len(configs)}: " + "; ".join(parts) + "." if parts else ""


def nearest_case(fig, by_config, subject, cands):
    """Which candidate's value each SHAPE measure of `subject` lies nearest: {candidate: ['measure v (...)']}."""
    groups = {c: [] for c in cands}
    for m in SHAPE:
        v, cv = value(by_config, subject, m), {c: value(by_config, c, m) for c in cands}
        if isnan(v) or any(isnan(x) for x in cv.values()):
            continue
        near = min(cands, key=lambda c: abs(cv[c] - v))
        groups[near].append(f"{dict(MEASURES)[m]} {fmt(v)} ("
                            + ", ".join(f"{short(fig, c)} {fmt(cv[c])}" for c in cands) + ")")
    return groups


def nearest_line(fig, cases):
    """Per case of fig['nearest']: which of the candidates the subject's shape measures lie nearest."""
    subject, cands, on = fig["nearest"]
    word, out = "nearer" if len(cands) == 2 else "nearest", []
    for case in on:
        groups = nearest_case(fig, cases.get(case, {}), subject, cands)
        n = sum(len(g) for g in groups.values())
        if n:
            out.append(f"On `{case}`, {short(fig, subject)}'s values lie " + "; ".join(
                f"{word} {short(fig, c)}'s by {len(g)} of {n} measures: {', '.join(g)}" for c, g in groups.items() if g)
                + ".")
    return " ".join(out)


def times_note(rows, p):
    """What the tables' times are, from the CSV's repetition counts (init_reps, frame_reps)."""
    ok = [r for r in rows if r["status"] == "ok"]

    def reps(col):
        v = sorted({int(number(r.get(col, ""))) for r in ok if not isnan(number(r.get(col, "")))})
        return v, ("n/a" if not v else f"{v[0]}" if len(v) == 1 else f"{v[0]} to {v[-1]}")

    (ir, its), (fr, fts) = reps("init_reps"), reps("frame_reps")
    init = ("one run per cell" if ir == [1] else
            f"the median over `init_reps` = {its} runs per cell, least - largest and n beside it")
    frame = ("one solve" if fr == [1] else
             f"the median over `frame_reps` = {fts} timed repetitions of the edit's frame, least - largest and n "
             "beside it")
    return (f"Times: `init s` is {init}; `frame s` {frame}; a chained twist sums its "
            f"steps; one child process per cell on a shared machine with {p.get('hardware_threads', '?')} hardware "
            "threads.")


def fill(text, cases, ctx):
    """The setup numbers a figure's text names, from the CSV: {vertices:CASE}, {handle:CASE}, {angle:CASE}, and
    ctx's {step} and {times}."""
    def sub(mt):
        r = next(iter(cases.get(mt.group(2), {}).values()), None)
        if r is None:
            return "n/a"
        return f"{number(r['angle_deg']):g}" if mt.group(1) == "angle" else r[mt.group(1)]
    text = re.sub(r"\{(vertices|handle|angle):(\w+)\}", sub, text)
    return text.replace("{step}", ctx["step"]).replace("{times}", ctx["times"])


def section(fig, cases, results, ctx):
    o = [f"## {fig['title']}\n", f"**Thesis / report:** {fig['thesis']}\n",
         f"**Ours:** {fill(fig['ours'], cases, ctx)}\n"]
    line, ratios = comparison(fig, cases) if "compare" in fig else ("", [])
    o += [line] if line else []
    for case in fig["cases"]:
        if case not in cases:
            o.append(f"- `{case}`: not in frames.csv (run exp_frames with data/experiments/frames.toml).\n")
            continue
        render = cite_figure(results, f"render_{case}.png", "dbtools/plots/render_meshes.py")
        o.append(f"- {setup_line(case, cases[case])}; render {render}\n")
        o.append(metrics_table(cases[case], fig["configs"]) + "\n")
    o.append(f"**What the renders show** (looked at for this report's first version; rerun renders may differ in "
             f"detail): {fig['seen']}\n")
    measured = " ".join(t for t in (worst_line(fig, cases) if "worst" in fig else "",
                                    nearest_line(fig, cases) if "nearest" in fig else "") if t)
    o += [f"**Measured** (the tables above): {measured}\n"] if measured else []
    differs = fill(fig["differs"], cases, ctx) + collapse_line(fig, cases) + improvement(fig, ratios)
    o.append(f"**Where ours differs, and why:** {differs.rstrip()}\n")
    return "\n".join(o)


def write(results):
    """Writes RESULTS/figures.md; False when there is no frames.csv."""
    rows = read_rows(os.path.join(results, "frames.csv"))
    if not rows:
        return False
    cases = case_rows(rows)
    p = provenance(rows)
    st = settings(os.path.join(results, "frames_settings.csv"))
    ctx = {"step": f"{number(st.get('twist_step_deg', '')):g}", "times": times_note(rows, p)}
    head = ("# The thesis' figures and ours\n\nGenerated by the report step (dbtools/reports/figures.py) from "
            f"`frames.csv` (git {p.get('git_sha')}) and the renders of dbtools/plots/render_meshes.py; nothing here is "
            "measured again. Distances are in rest bounding-box diagonals; `volume change` is relative (closed meshes "
            f"only); `max displacement` is the largest vertex move. {ctx['times']} "
            "Render panels: rest (fixed grey, free red, handle yellow, as in thesis fig. 4-4), the analytic ideal "
            "where there is one, LAP, TF, TF with normalized scale and the LRI variants; where the results differ by "
            "too little to tell apart side by side, a grid of distance maps below them colours each result by its "
            "distance from LAP's (rest bounding-box diagonals, one colour bar). Each figure's "
            "setup is a case of data/experiments/frames.toml; `build/exp_frames --only CASE` reruns one.\n")
    write_atomically(os.path.join(results, "figures.md"), "\n".join([head] + [section(f, cases, results, ctx)
                                                                              for f in FIGURES]))
    return True
