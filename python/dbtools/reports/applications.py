"""results/applications.md: coating transfer and transplanting (exp_applications, data/experiments/applications.toml)
from results/applications.csv, one row per case, and the renders figures/render_app_CASE.png (dbtools/plots/applications.py).
Reads the CSV and checks which renders exist; measures nothing (the seam-angle ratios below are quotients of the
CSV's own numbers).
"""
import math
import os

from .common import (cite_figure, fmt, isnan, number, provenance, read_rows, repeated_spread, spread_name,
                     write_atomically)

SIZES = [("source_patch_vertices", "source patch V"), ("patch_vertices", "target region V"),
         ("target_vertices", "target V"), ("result_vertices", "result V"), ("band_faces", "band faces"),
         ("welded", "welded"), ("band_by_diagonal", "band by diagonal"), ("rho", "rho")]
QUALITY = [("detail_error", "detail error"), ("seam_max_deg_before", "seam max before"),
           ("seam_max_deg_after", "seam max after"), ("seam_mean_deg_before", "seam mean before"),
           ("seam_mean_deg_after", "seam mean after"), ("nonmanifold", "non-manifold"),
           ("degenerate_faces", "degenerate faces"), ("open_seam_edges", "open seam edges"),
           ("max_displacement_rel", "max move")]
AMPLITUDE = [("sigma", "sigma"), ("height_max_ratio", "max height ratio"), ("height_rms_ratio", "RMS height ratio"),
             ("self_error", "self-coating error"), ("detail_error", "detail error")]
TIMES = [("parameterize_s", "parameterize"), ("smooth_s", "smooth"), ("map_s", "map"), ("build_s", "build"),
         ("analyze_s", "analyze"), ("factorize_s", "factorize"), ("solve_s", "solve"), ("total_s", "total"),
         ("n", "LSE n"), ("nnz_factor", "factor nnz")]


COUNTS = {"source_patch_vertices", "patch_vertices", "target_vertices", "result_vertices", "band_faces", "welded",
          "band_by_diagonal", "nonmanifold", "degenerate_faces", "open_seam_edges", "n", "nnz_factor"}


def spec(column):
    return "{:.0f}" if column in COUNTS else "{:.4g}"


def value_cell(r, k):
    """A column's value; a timing that is a median of several runs with its spread (least - largest, n)."""
    get = lambda name: number(r.get(name, ""))  # noqa: E731
    return fmt(get(k), spec(k)) + (repeated_spread(get, k, lambda x: f"{x:.4g}") if k.endswith("_s") else "")


def table(rows, columns):
    o = ["| case |" + "".join(f" {lab} |" for _, lab in columns), "|---|" + "---|" * len(columns)]
    for r in rows:
        o.append(f"| `{r['case']}` |" + "".join(f" {value_cell(r, k)} |" for k, _ in columns))
    return "\n".join(o)


def runs_note(rows):
    """How many runs the times are, from the CSV's NAME_reps columns."""
    reps = {number(r.get(spread_name(k, "reps"), "")) for r in rows for k, _ in TIMES if k.endswith("_s")}
    reps = sorted(int(x) for x in reps if not isnan(x))
    if not reps or reps == [1]:
        return "Times are one run each on the shared machine."
    return (f"Times are medians over up to {reps[-1]} runs each on the shared machine, least - largest and n beside "
            "them where there are several.")


def amplitude_note(rows):
    """The coat cases that differ only in amplitude: how the seam angle follows it."""
    by = {r["case"]: r for r in rows}
    # the full-amplitude case with the half-amplitude one's map and encoding (the defaults)
    half = by.get("coat_plane_flat_amp05")
    full = half and (by.get("coat_plane_flat") or by.get(f"coat_plane_flat.{half['map']}.{half['encoding']}"))
    if not full or not half:
        return ""
    a0, a1 = number(full["seam_max_deg_before"]), number(full["seam_max_deg_after"])
    b0, b1 = number(half["seam_max_deg_before"]), number(half["seam_max_deg_after"])
    heights = number(half["height_max_ratio"]) / number(full["height_max_ratio"])
    if any(isnan(x) for x in (a0, a1, b0, b1, heights)) or a1 - a0 <= 0:
        return ""
    seam = (b1 - b0) / (a1 - a0)
    # A dihedral angle is linear in the slopes that make it up to a relative term of order its square (radians):
    # the tolerance for "linear" is that term at the larger angle.
    tol, dev = math.radians(max(a1, b1)) ** 2, abs(seam / heights - 1)
    o = (f"The flat target's seam is {fmt(a0, '{:.3g}')} degrees before and {fmt(a1, '{:.3g}')} after the coating at "
         f"full amplitude (`{full['case']}`), {fmt(b0, '{:.3g}')} before and {fmt(b1, '{:.3g}')} after with the "
         f"amplitude halved (`{half['case']}`): the change scales by {seam:.5g}, the coating's largest height by "
         f"{heights:.5g} (`max height ratio`), {dev:.2g} apart (relative). ")
    if dev > tol:
        return o + (f"That is more than {tol:.2g}, the angle's own second-order term (its square in radians): the "
                    "angle does not follow the transferred detail linearly, so part of it is not the coating's own "
                    "slope.\n")
    return o + (f"That is within {tol:.2g}, the angle's own second-order term (its square in radians): the angle "
                "follows the transferred detail linearly, so it is the slope of the coating itself where it reaches "
                "the region's boundary (the whole BS08 plane is mapped onto the region), not a crease of the solve. "
                "The boundary vertices are fixed and the detail is transferred up to them; a coating that must meet "
                "the boundary flat would need the detail faded towards it, which the method (Sorkine et al. 2004) "
                "does not do.\n")


def alternatives_table(rows):
    """The coat cases with their disk map and detail encoding: how big the coating arrives, and the self-coatings'
    reconstruction error."""
    coats = [r for r in rows if r["app"] == "coat"]
    if not coats:
        return ""
    cols = [("map", "map"), ("encoding", "encoding")] + AMPLITUDE
    o = ["| case |" + "".join(f" {lab} |" for _, lab in cols), "|---|" + "---|" * len(cols)]
    for r in coats:
        cells = [r.get("map", ""), r.get("encoding", "")] + [fmt(number(r.get(k, "")), "{:.3g}") for k, _ in AMPLITUDE]
        o.append(f"| `{r['case']}` |" + "".join(f" {c} |" for c in cells))
    return "\n".join(o)


def write(results):
    """Writes RESULTS/applications.md, citing the renders under RESULTS/figures; False when there is no
    applications.csv."""
    rows = read_rows(os.path.join(results, "applications.csv"))
    if not rows:
        return False
    p = provenance(rows)
    o = ["# Coating transfer and transplanting\n",
         f"Generated by the report step (dbtools/reports/applications.py) from `applications.csv` (git "
         f"{p.get('git_sha')}, {p.get('blas')} {p.get('blas_core')}, {p.get('blas_threads')} BLAS threads); nothing "
         "here is measured again. `build/exp_applications` reruns the cases of data/experiments/applications.toml "
         "(`--meshes results/meshes/applications` for the renders). " + runs_note(rows) + "\n",
         "## Cases\n"]
    for r in rows:
        render = cite_figure(results, f"render_app_{r['case']}.png", "dbtools/plots/applications.py")
        o.append(f"- `{r['case']}`: {r['app']} {r['source']} ({r['source_region']}) onto {r['target']} "
                 f"({r['target_region']}); render {render}")
    o += ["", "## Sizes\n",
          "V: vertices. A transplant's result has the target's vertices outside the region plus the source patch's "
          "(its boundary welded onto the hole's loop when the two coincide: `welded` 1); `band faces` are the "
          "zippered strip's; `rho` the parameter radius the source was placed at.\n", table(rows, SIZES), "",
          "## The coating's size: disk maps and detail encodings\n",
          "Each coat case with each disk map (`uniform` Tutte, `mean-value` Floater, `cotangent` harmonic) and each "
          "detail encoding (`height`: the displacement from the smooth surface in its frames; `laplacian`: Laplacian "
          "coordinates). Height ratios: the coating's normal heights on the target, (result - target) . n, against the "
          "source's, (V - smooth) . n, times `sigma` (the boundary-length ratio): largest |height|, and root mean square "
          "weighted by vertex area; 1 is a coating that arrives at its size, the issue's band is 0.85 to 1.15. "
          "`self-coating error` (target `self`: the source's own smooth version): the largest distance of the result "
          "from the source over the patch's bounding-box diagonal, which must be rounding.\n",
          alternatives_table(rows), "",
          "## Detail and seam\n",
          "`detail error`: coat, the mapped coating against what the solved surface carries (relative, patch "
          "interior); transplant, the result's Laplacian coordinates against the placed source's where the blend is "
          "1. `seam max/mean` (degrees): dihedral angles across the region's boundary in the target before; after, "
          "across every edge of the band (transplant) or the same boundary (coat, welded transplant). "
          "`non-manifold`, `degenerate faces` and `open seam edges` (boundary edges the result has beyond the "
          "target's) are 0 for a sound join. `max move`: the largest move of the LSE solve from its start, in target "
          "bounding-box diagonals.\n", table(rows, QUALITY), "", amplitude_note(rows),
          "## Times (seconds) and system sizes\n", table(rows, TIMES), ""]
    write_atomically(os.path.join(results, "applications.md"), "\n".join(o))
    return True
