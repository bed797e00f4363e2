"""results/frames.md from the CSV exp_frames wrote (frames.csv, frames_settings.csv): does the LRI frame choice
change the result? The short answer, the algebra behind it, and the measured tables. Reads CSVs only."""
import math
import os
import statistics

from .common import (NAN, SPREAD_NOTE, count_flagged, fmt, isnan, number, provenance, read_rows, repeated_spread,
                     settings, spread_text, write_atomically)

# Regular cases: every solved frame kept some rank (sigma_min >= 1e-3). Where a frame collapses the rotation it is
# orthonormalized to is decided by round-off, so strategies can differ there even with polar.
COLLAPSED = 1e-3
# Below this smallest singular value a solved frame is called nearly collapsed (1 is a rotation).
NEAR_COLLAPSE = 0.1
# Vertex distances (rest-diagonal fractions) up to this are round-off of the solves, not a different result: the
# same bound decides whether strategies agree (polar and Gram-Schmidt) and whether a mesh returned to its rest shape.
ROUND_OFF = 1e-8
STRATEGY_NAMES = {"first": "first neighbour", "random": "random neighbour", "height_angle": "largest height angle",
                  "curvature": "curvature direction"}
IDEAL_COLUMNS = ["lap", "tf", "tf-normalized", "lri-first-gram_schmidt", "lri-random-gram_schmidt", "lri-height_angle-gram_schmidt",
                 "lri-curvature-gram_schmidt", "lri-first-polar"]


class Summary:
    """What the verdict needs of one case, from its rows."""

    def __init__(self, rows):
        r0 = rows[0]
        self.name, self.family, self.protocol = r0["case"], r0["family"], r0["protocol"]
        self.angle = number(r0["angle_deg"])
        self.ideal_rms, self.arap, self.detail, self.move, self.strat_gs_by = {}, {}, {}, {}, {}
        self.strat_polar = self.strat_gs = self.ortho_gap = 0.0
        self.polar_frames = {}  # strategies of the polar rows that carry diff_vs_first_max (an ordered set)
        self.sigma_min = 1.0  # over the LRI polar rows (Gram-Schmidt may have failed)
        self.errors = self.lri_gs_errors = 0
        self.has_ideal = any(not isnan(number(r["ideal_rms"])) for r in rows)
        for r in rows:
            self.add(r)

    def add(self, r):
        label, lri, polar = r["config"], r["method"] == "lri", r["orthonormalize"] == "polar"
        if r["status"] != "ok":
            self.errors += 1
            self.lri_gs_errors += lri and not polar
            return
        for d, col in ((self.ideal_rms, "ideal_rms"), (self.arap, "arap_energy"), (self.detail, "lri_detail_error"),
                       (self.move, "max_displacement")):
            if not isnan(number(r[col])):
                d[label] = number(r[col])
        if not lri:
            return
        first = number(r["diff_vs_first_max"])
        if not isnan(first):
            if polar:
                self.strat_polar = max(self.strat_polar, first)
                self.polar_frames[r["frames"]] = None
            else:
                self.strat_gs = max(self.strat_gs, first)
                self.strat_gs_by[r["frames"]] = first
        if not isnan(number(r["diff_vs_polar_max"])):
            self.ortho_gap = max(self.ortho_gap, number(r["diff_vs_polar_max"]))
        if polar and not isnan(number(r["frame_sigma_min"])):
            self.sigma_min = min(self.sigma_min, number(r["frame_sigma_min"]))

    def polar_compared(self):
        """Whether at least two polar strategies solved (first neighbour and another) to compare."""
        return len(self.polar_frames) >= 2

    def polar_same(self):
        """Whether every polar strategy gave the first-neighbour mesh up to round-off."""
        return self.polar_compared() and self.strat_polar <= ROUND_OFF


def f3(v):
    return f"{v:.3g}"


def cell(d, k):
    return f"{d[k]:.4f}" if k in d else "n/a"


def summaries(rows):
    by_case = {}
    for r in rows:
        by_case.setdefault(r["case"], []).append(r)
    return [Summary(rs) for rs in by_case.values()]


def polar_difference(s):
    """'`case` (up to D...)': how far a case's polar strategies lie apart, and why where its frames collapse."""
    why = (f"; a solved frame collapses, smallest singular value {f3(s.sigma_min)}, so round-off picks the rotation"
           if s.sigma_min < COLLAPSED else "")
    return f"`{s.name}` (up to {f3(s.strat_polar)}{why})"


def polar_line(ss):
    """The polar verdict: the cases where every strategy gives the same mesh up to round-off, and the exceptions."""
    compared = [s for s in ss if s.polar_compared()]
    same, differ = [s for s in compared if s.polar_same()], [s for s in compared if not s.polar_same()]
    names = list(dict.fromkeys(f for s in compared for f in s.polar_frames))
    if not differ:
        verdict = "no"
    else:
        verdict = "only where a solved frame collapses" if all(s.sigma_min < COLLAPSED for s in differ) else "yes"
    line = (f"- **Polar orthonormalization: {verdict}.** The {len(names)} strategies "
            f"({', '.join(STRATEGY_NAMES.get(f, f) for f in names)}) give the same mesh up to round-off (largest "
            f"vertex difference to the first-neighbour result at most {f3(ROUND_OFF)}) in {len(same)} of "
            f"{len(compared)} cases, largest there {f3(max((s.strat_polar for s in same), default=NAN))}")
    if differ:
        line += "; they differ in " + ", ".join(polar_difference(s) for s in differ)
    agree_collapsed = [s for s in same if s.sigma_min < COLLAPSED]
    if agree_collapsed:
        line += (f". A solved frame collapses (smallest singular value below {f3(COLLAPSED)}) also in "
                 f"{', '.join('`' + s.name + '`' for s in agree_collapsed)}, where the strategies agree all the same")
    return line + "."


def polar_label(c):
    """The LRI polar column's name for one case: 'any strategy' only where the strategies agree."""
    if c.polar_same():
        return "LRI polar (any strategy)"
    if c.polar_compared():
        return f"LRI polar first-neighbour (the strategies differ by up to {f3(c.strat_polar)})"
    return "LRI polar first-neighbour"


def bend_line(c):
    line = (f"- **{c.angle:g}-degree bend of the 60x32 cylinder**, RMS distance to the ideal: LAP "
            f"{cell(c.ideal_rms, 'lap')}, TF {cell(c.ideal_rms, 'tf')}, LRI first/GS "
            f"{cell(c.ideal_rms, 'lri-first-gram_schmidt')}, LRI height-angle/GS "
            f"{cell(c.ideal_rms, 'lri-height_angle-gram_schmidt')}, LRI curvature/GS "
            f"{cell(c.ideal_rms, 'lri-curvature-gram_schmidt')}, {polar_label(c)} "
            f"{cell(c.ideal_rms, 'lri-first-polar')}; smallest singular value of a solved LRI frame {f3(c.sigma_min)}.")
    if c.sigma_min < NEAR_COLLAPSE:
        line += (f" Below {f3(NEAR_COLLAPSE)}, some solved frames nearly collapse (point 4 below gives the reason; "
                 f"render `figures/render_{c.name}.png`).")
    return line


def short_answer(ss):
    worst_gs = max(ss, key=lambda s: s.strat_gs)
    max_gap = max(s.ortho_gap for s in ss)
    better = worse = ties = 0  # thesis 4.3: height-angle frames against first-neighbour frames (Gram-Schmidt)
    for s in ss:
        f, h = s.ideal_rms.get("lri-first-gram_schmidt"), s.ideal_rms.get("lri-height_angle-gram_schmidt")
        if f is None or h is None:
            continue
        rel = (h - f) / max(f, 1e-300)
        better, worse, ties = better + (rel < -0.01), worse + (rel > 0.01), ties + (abs(rel) <= 0.01)
    o = ["## Short answer\n", polar_line(ss)]
    o.append(f"- **Gram-Schmidt (b1 first): {'yes' if worst_gs.strat_gs > ROUND_OFF else 'no'}.** The strategies "
             f"differ by up to {f3(worst_gs.strat_gs)} (`{worst_gs.name}`); Gram-Schmidt and polar differ by up to "
             f"{f3(max_gap)} for the same strategy. Against the analytic ideal the thesis' height-angle frames "
             f"(eq. 4-4) beat first-neighbour frames by more than 1% RMS in {better} case(s), lose in {worse} and tie "
             f"within 1% in {ties}.")
    o += [bend_line(c) for name in ("cyl60x32_bend90", "cyl60x32_bend180") for c in ss if c.name == name]
    return "\n".join(o) + "\n"


ALGEBRA = """## The algebra

Write the rest frame of vertex i as F_i = [b1 b2 N] (orthonormal), the connection R_ij = F_i^T F_j (eqs. 3-16, \
3-17) and the discrete forms d_ij = F_i^T (x_j - x_i) (eqs. 3-12, 3-13). Per world component c the frame system \
minimizes sum_(i,j) |u_j - R_ij^T u_i|^2 over u_i = row c of the unknown frame F'_i.

1. **The rest frames drop out of the frame solve.** Substitute F'_i = W_i F_i, i.e. u_i = F_i^T w_i with w_i = row c \
of W_i: u_j - R_ij^T u_i = F_j^T (w_j - w_i), whose norm is |w_j - w_i|. The frame energy is the graph Laplacian energy \
of W, and the constraints read W = R_h on the handle and W = I on fixed vertices. So F'_i = W_i F_i with W the \
harmonic blend of the constraint rotations - for one handle, W_i = I + h_i (R_h - I) with h the discrete harmonic \
function (0 fixed, 1 handle) - whatever b1 (or even N) was chosen. Another b1 is F_i Z_i with Z_i a rotation about \
N_i; the solved frame becomes W_i F_i Z_i and the forms Z_i^T d_ij (`tests/lri_test.cpp`: \
PolarResultDoesNotDependOnTheFrameStrategy, FrameSolveIsAHarmonicBlendOfRotations).
2. **Orthonormalization decides.** The position targets are orth(W_i F_i Z_i) Z_i^T d_ij. The polar factor commutes \
with orthogonal factors on the right, orth(W F Z) = orth(W) F Z, so the targets are orth(W_i) (x_j - x_i) for every \
strategy: LRI with polar orthonormalization is a harmonic rotation blend followed by a Poisson reconstruction, \
independent of the frames. Gram-Schmidt keeps the direction of the first column, W_i b1_i, which differs between \
strategies whenever W_i is not a scaled rotation (it is not: a linear blend of rotations shrinks and shears).
3. **Where differences come from:** (a) the orthonormalization order (Gram-Schmidt), measured below; (b) weights \
that depend on the frame axes (none here: every edge weighs 1; any weight symmetric in i, j and computed from the \
geometry keeps point 1); (c) constraints that are not frames of one rotation per vertex (soft constraint weights do \
not matter, they transform like the energy); (d) round-off, which is harmless unless W_i is singular.
4. **W is singular at 180 degrees.** For a half turn about axis a, W = aa^T + (1 - 2h)(I - aa^T): the singular values \
are 1 and |1 - 2h| (twice), zero on the level set h = 1/2. polar(W) jumps from I to R_h across it, so the \
reconstruction kinks there instead of bending; Gram-Schmidt breaks down on a vertex exactly on the level set (b1 \
vanishes: SolverError, case `cyl31x16_bend180_symmetric`) and near it snaps b1 to the axis. No choice of b1 repairs \
this: the linear frame solve cannot represent rotations of 180 degrees or more, and chained edits (the twists) are \
the linear way around it.
"""


def strategy_table(ss):
    o = ["## Measured: strategy against strategy\n\n`diff_vs_first_max`: largest vertex distance between a strategy's "
         "result and the first-neighbour result with the same orthonormalization. `diff_vs_polar_max`: Gram-Schmidt "
         "against polar, same strategy (maximum over strategies). `frame_sigma_min`: smallest singular value of any "
         "solved frame (1 for a rotation).\n\n| case | protocol | frame sigma min | polar: max over strategies | GS: "
         "random | GS: height_angle | GS: curvature | GS vs polar | LRI failures |\n|---|---|---|---|---|---|---|---|---|"]
    for s in ss:
        gs = lambda k: f3(s.strat_gs_by[k]) if k in s.strat_gs_by else "n/a"  # noqa: E731
        o.append(f"| {s.name} | {s.protocol} | {f3(s.sigma_min)} | {f3(s.strat_polar)} | {gs('random')} | "
                 f"{gs('height_angle')} | {gs('curvature')} | {f3(s.ortho_gap)} | {s.lri_gs_errors} |")
    return "\n".join(o) + "\n"


def ideal_tables(ss, step):
    o = ["## Measured: distance to the analytic ideal\n\n`ideal_rms`: RMS vertex distance to the analytic deformation. "
         f"Twists are chains of edits of at most {step} degrees, each re-using the previous result as rest mesh; "
         "`bar_twist360_single` is one 360-degree transform, which every linear method receives as the identity.\n",
         "| case |" + "".join(f" {c} |" for c in IDEAL_COLUMNS) + "\n|---|" + "---|" * len(IDEAL_COLUMNS)]
    o += [f"| {s.name} |" + "".join(f" {cell(s.ideal_rms, c)} |" for c in IDEAL_COLUMNS) for s in ss if s.has_ideal]
    keys = ("lap", "tf", "lri-first-gram_schmidt", "lri-height_angle-gram_schmidt", "lri-first-polar")
    o.append("\nLocal rigidity (`arap_energy`, relative) and LRI detail error (`lri_detail_error`), every case:\n\n"
             "| case | ARAP lap | ARAP tf | ARAP lri-first-gs | ARAP lri-height-gs | ARAP lri-polar | detail lap | "
             "detail tf | detail lri-first-gs | detail lri-height-gs | detail lri-polar |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|")
    o += [f"| {s.name} | " + " | ".join(cell(m, k) for m in (s.arap, s.detail) for k in keys) + " |" for s in ss]
    return "\n".join(o) + "\n"


def twist_line(t1, t1s):
    """Whether the chained full twist returned LAP to its rest mesh (largest vertex move within round-off), against
    the single 360-degree transform."""
    move, single = t1.move.get("lap", NAN), max(t1s.move.values(), default=NAN)
    if isnan(move):
        head = "- A chained full twist: LAP's largest vertex move is not in the CSV."
    elif move <= ROUND_OFF:
        head = (f"- A chained full twist leaves LAP where it started (largest vertex move {f3(move)}, round-off): "
                "LAP's result is linear in the handle positions, and the steps' handle displacements sum to zero "
                "over a full turn.")
    else:
        head = f"- A chained full twist moves LAP's vertices by up to {f3(move)} from the rest mesh."
    rest = "every method returns the rest mesh there, " if single <= ROUND_OFF else ""
    return (head + f" `ideal_rms` of LAP, chained: {cell(t1.ideal_rms, 'lap')}; of the single 360-degree transform: "
            f"{cell(t1s.ideal_rms, 'lap')} ({rest}largest vertex move of any method {f3(single)}). TF and LRI are "
            "rebuilt on every step's result, so the chain is not linear for them: LRI first/GS "
            f"{cell(t1.ideal_rms, 'lri-first-gram_schmidt')}, LRI polar {cell(t1.ideal_rms, 'lri-first-polar')}, TF "
            f"{cell(t1.ideal_rms, 'tf')}.")


def observations(ss):
    o = ["## Other measured observations\n"]
    t1 = next((s for s in ss if s.name == "bar_twist360"), None)
    t1s = next((s for s in ss if s.name == "bar_twist360_single"), None)
    if t1 and t1s:
        o.append(twist_line(t1, t1s))
    errors = sum(s.errors for s in ss)
    if errors:
        o.append(f"- {errors} configuration(s) failed; their rows carry the error in `status`.")
    o.append("- Renders: `figures/render_<case>.png` (dbtools/plots/render_meshes.py), figures: "
             "`figures/frames_*.png` (dbtools/plots/frames.py).")
    return "\n".join(o) + "\n"


# Issue 17: TF without its scale blow-up, against plain TF, LAP and LRI (first-neighbour frames, polar).
TF_SCALE_CONFIGS = [("lap", "LAP"), ("tf", "TF"), ("tf-normalized", "TF normalized"), ("lri-first-polar", "LRI polar")]
TF_SCALE_MEASURES = [("ideal_rms", "RMS to ideal"), ("volume_change", "volume change"),
                     ("edge_distortion", "edge-length distortion"), ("max_displacement", "max displacement")]


def tf_scale_values(rows):
    """{case: {config: {measure: value}}} of the configurations TF_SCALE_CONFIGS, in the CSV's case order."""
    out = {}
    wanted = dict(TF_SCALE_CONFIGS)
    for r in rows:
        if r["config"] in wanted and r["status"] == "ok":
            out.setdefault(r["case"], {})[r["config"]] = {m: number(r.get(m, "")) for m in
                                                          [m for m, _ in TF_SCALE_MEASURES] + ["init_s", "frame_s"]}
    return out


def cost_ratio(vals, measure):
    """'M (range LO - HI over N cases)': the median over the cases of normalized TF's time over plain TF's, finite
    ratios only (a missing or zero time gives none)."""
    rs = [c["tf-normalized"][measure] / c["tf"][measure] for c in vals.values()
          if "tf" in c and "tf-normalized" in c and c["tf"][measure] > 0]
    rs = [r for r in rs if math.isfinite(r)]
    if not rs:
        return "n/a"
    return f"{f3(statistics.median(rs))} (range {f3(min(rs))} - {f3(max(rs))} over {len(rs)} cases)"


def volume_note(vals, cases):
    """Over the cases where normalized TF changes the volume more than plain TF: where it shrinks, whether LRI
    polar shrinks there too, and whether plain TF pays with a larger edge-length distortion."""
    if not cases:
        return ""
    at = lambda c, k, m: vals[c].get(k, {}).get(m, NAN)  # noqa: E731
    shrink = [c for c in cases if at(c, "tf-normalized", "volume_change") < 0]
    both = [c for c in shrink if at(c, "lri-first-polar", "volume_change") < 0]
    edge = [c for c in cases if at(c, "tf", "edge_distortion") > at(c, "tf-normalized", "edge_distortion")]
    return (f" (there normalized TF loses volume in {len(shrink)} of {len(cases)}, LRI polar too in {len(both)} of "
            f"those; plain TF's smaller volume change comes with a larger edge-length distortion than normalized TF's "
            f"in {len(edge)} of {len(cases)}, see the table)")


def polar_note(ss):
    """How the report's one LRI polar configuration stands for the other strategies."""
    differ = [s for s in ss if s.polar_compared() and not s.polar_same()]
    if not differ:
        return "every frame strategy gives the same mesh up to round-off"
    return ("the other frame strategies give the same mesh up to round-off except in "
            + ", ".join(f"`{s.name}`, where they differ by up to {f3(s.strat_polar)}" for s in differ))


def tf_scale_verdict(vals, large, polar):
    """Counts, over the cases that have both, of where TF normalized is better than TF and than LRI; `large`: the
    cases of large rotations (180 degrees and more, or chained twists); `polar`: polar_note."""
    def better(x, y):  # below, by more than round-off (ties such as the identity edit count for neither)
        return x < y - 1e-9 * max(abs(x), abs(y)) - 1e-12

    def count(a, b, measure, key=lambda x: x, only=None):
        n = wins = 0
        for name, case in vals.items():
            if a in case and b in case and (only is None or name in only):
                x, y = case[a].get(measure, NAN), case[b].get(measure, NAN)
                if not isnan(x) and not isnan(y):
                    n, wins = n + 1, wins + better(key(x), key(y))
        return wins, n

    def losses(a, b, measure, key=lambda x: x):
        return [name for name, c in vals.items() if a in c and b in c and better(key(c[b][measure]), key(c[a][measure]))]

    def at(case, config, measure):
        return vals.get(case, {}).get(config, {}).get(measure, NAN)

    def worst(config, measure):
        cands = [(c[config][measure], name) for name, c in vals.items() if config in c and not isnan(c[config][measure])]
        return max(cands, default=(NAN, "n/a"))

    e = count("tf-normalized", "tf", "edge_distortion")
    v = count("tf-normalized", "tf", "volume_change", abs)
    i = count("tf-normalized", "tf", "ideal_rms")
    il = count("tf-normalized", "lap", "ideal_rms")
    ir = count("tf-normalized", "lri-first-polar", "ideal_rms")
    el = count("tf-normalized", "lri-first-polar", "edge_distortion")
    wt, wn = worst("tf", "max_displacement"), worst("tf-normalized", "max_displacement")
    wv = worst("tf", "volume_change")
    il_tf = count("tf-normalized", "tf", "ideal_rms", only=large)
    il_lri = count("tf-normalized", "lri-first-polar", "ideal_rms", only=large)
    vol_losses = losses("tf-normalized", "tf", "volume_change", abs)
    o = ["## TF without the scale blow-up (`--tf-scale normalized`)\n",
         "The second pass keeps the rotation of every similarity TF fitted and drops its scale: each rest Laplacian "
         "coordinate turned by that rotation, then the LAP solve under the same constraints (methods/"
         "laplacian_deformer.h). Measured on every case of this study against plain TF, LAP and LRI (first-neighbour "
         f"frames, polar; {polar}). Distances are in rest bounding-box diagonals; `volume change` is relative and "
         "only for closed meshes; `max displacement` is the largest vertex move (the handle's own move is the floor).\n",
         f"- **Against plain TF:** lower edge-length distortion in {e[0]} of {e[1]} cases, a smaller volume change in "
         f"{v[0]} of {v[1]} closed cases, closer to the analytic ideal in {i[0]} of {i[1]} cases with one. Plain TF's "
         f"largest vertex move is {f3(wt[0])} diagonals (`{wt[1]}`), where normalized TF moves vertices by at most "
         f"{f3(at(wt[1], 'tf-normalized', 'max_displacement'))} and LAP {f3(at(wt[1], 'lap', 'max_displacement'))}; "
         f"its largest volume change is {f3(wv[0])} (`{wv[1]}`), normalized TF's there "
         f"{f3(at(wv[1], 'tf-normalized', 'volume_change'))}. Normalized TF's largest move over all cases is "
         f"{f3(wn[0])} (`{wn[1]}`, LAP's there {f3(at(wn[1], 'lap', 'max_displacement'))}).",
         "- **Where it is worse than plain TF:** farther from the ideal in "
         + (", ".join(f"`{c}`" for c in losses("tf-normalized", "tf", "ideal_rms")) or "no case")
         + "; a larger volume change in "
         + (", ".join(f"`{c}`" for c in vol_losses) or "no case") + volume_note(vals, vol_losses) + ".",
         "- **Cost:** a second, scalar factor and a second solve per frame: median over the cases of normalized TF's "
         f"init time over plain TF's {cost_ratio(vals, 'init_s')}, of its frame time {cost_ratio(vals, 'frame_s')}. "
         "Each cell's time is the median over its repetitions (see Timings), one child per cell on a shared machine.",
         f"- **Against LAP and LRI:** closer to the ideal than LAP in {il[0]} of {il[1]} cases and than LRI polar in "
         f"{ir[0]} of {ir[1]}; lower edge-length distortion than LRI polar in {el[0]} of {el[1]} cases.",
         f"- **Large rotations** ({len(large)} cases of 180 degrees or more, or chained twists): closer to the ideal "
         f"than plain TF in {il_tf[0]} of {il_tf[1]} and than LRI polar in {il_lri[0]} of {il_lri[1]}. Its rotations "
         "are those of TF's first pass, whose linearized similarities s I + [h]x fit a rotation well only up to "
         "moderate angles: the second pass removes the scale, not a wrong rotation.\n"]
    return "\n".join(o)


def tf_scale_table(vals):
    o = ["| case | method |" + "".join(f" {lab} |" for _, lab in TF_SCALE_MEASURES),
         "|---|---|" + "---|" * len(TF_SCALE_MEASURES)]
    for name, case in vals.items():
        for c, label in TF_SCALE_CONFIGS:
            if c in case:
                o.append(f"| {name} | {label} |" + "".join(
                    " n/a |" if isnan(case[c][m]) else f" {case[c][m]:.4f} |" for m, _ in TF_SCALE_MEASURES))
    return "\n".join(o) + "\n"


def timings(rows, st):
    """Every cell's init and frame time, the frame's with its spread over the repetitions, flagged where they
    disagree."""
    getters = [(r, lambda m, r=r: number(r.get(m, ""))) for r in rows if r["status"] == "ok"]
    ms = lambda x: f"{x * 1e3:.3g}"  # noqa: E731
    init_reps = max((g("init_reps") for _, g in getters if not isnan(g("init_reps"))), default=1)
    init_runs = ("once per cell" if init_reps <= 1 else
                 f"up to {init_reps:.0f} times per cell, the median with its spread")
    o = ["## Timings\n",
         f"Init: build + analyze + factorize, {init_runs}; frame: the edit's frame solved "
         f"{st.get('frame_repeats', 'once or more')} times with the same transform (`--frame-repeats`), the median with "
         "its spread (least - largest, n = repetitions). A chained twist sums its steps (init, and each repetition of "
         "the frame). One child process per cell on a shared machine: compare orders of magnitude.\n",
         "| case | configuration | init ms | frame ms |", "|---|---|---:|---:|"]
    for r, get in getters:
        o.append(f"| {r['case']} | {r['config']} | {fmt(get('init_s') * 1e3, '{:.3g}')}"
                 f"{repeated_spread(get, 'init_s', ms)} | "
                 f"{fmt(get('frame_s') * 1e3, '{:.3g}')} {spread_text(get, 'frame_s', ms)} |")
    o.append(f"\n{SPREAD_NOTE} Flagged here: {count_flagged([g for _, g in getters], ['frame_s'])} frame(s), "
             f"{count_flagged([g for _, g in getters], ['init_s'])} init(s).\n")
    return "\n".join(o)


def write(results):
    """Writes RESULTS/frames.md; False when there is no frames.csv."""
    rows = read_rows(os.path.join(results, "frames.csv"))
    if not rows:
        return False
    st, p = settings(os.path.join(results, "frames_settings.csv")), provenance(rows)
    ss = summaries(rows)
    core = p.get("blas_coretype_env")
    head = ("# Does the LRI frame choice change the result?\n\nGenerated by the report step (dbtools/reports/"
            f"frames.py) from `{st.get('csv', 'frames.csv')}` (exp_frames: {len(rows)} rows, {len(ss)} cases, "
            f"{st.get('seconds', '?')} s); git {p.get('git_sha')} | {p.get('blas')} core {p.get('blas_core')} "
            f"({'auto-detected' if core in ('', 'auto') else 'OPENBLAS_CORETYPE=' + core}) | {p.get('blas_threads')} "
            f"BLAS threads, {p.get('build_threads')} build threads, {p.get('hardware_threads')} hw threads. Every "
            "number below is a column of that CSV: distances are relative to the rest bounding-box diagonal.\n")
    step = f3(number(st.get("twist_step_deg", "30")))
    tfs = tf_scale_values(rows)
    parts = [head, short_answer(ss), ALGEBRA, strategy_table(ss), ideal_tables(ss, step)]
    if any("tf-normalized" in c for c in tfs.values()):
        large = {s.name for s in ss if s.angle >= 180 - 1e-9 or s.protocol == "chained"}
        parts += [tf_scale_verdict(tfs, large, polar_note(ss)), tf_scale_table(tfs)]
    parts += [observations(ss), timings(rows, st)]
    write_atomically(os.path.join(results, "frames.md"), "\n".join(parts))
    return True
