"""Renders of the applications experiment (exp_applications: coating transfer, transplanting): one PNG per case,
panels source (its patch orange), target (its patch orange), result, and the result's patch close up beside the
target's (the same camera), so the transferred detail and the seam can be checked by eye. A coating's result is
coloured by its normal height, (result - target) . n over the target's vertex normals, in target-patch diagonals,
on one diverging scale shared by every coat case rendered together (its ends: the median of the cases' largest
heights; a colour bar beside), so the coating's amplitude shows: the same coating at half the amplitude is half as
saturated, one too tall saturates. Transplants keep the patch colours.

Reads results/meshes/applications/CASE__{source,target,result}.ply and CASE__{source_patch,patch,result_patch}.txt
(the vertex ids of the source and target patches, and of the result's transferred or grafted part: a transplant's
result is a joined mesh with its own faces, the graft and the zippered band blue); writes OUT/render_app_CASE.png. Drawing as render_meshes.py (flat shading, orthographic, painter's
algorithm), whose helpers it imports.

usage: python3 -m dbtools.plots.applications [--results results] [--out RESULTS/figures] [--cases SUBSTRING]
"""
import glob
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .cli import out_dir, parser  # noqa: E402
from matplotlib.cm import ScalarMappable  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402

from .render_meshes import camera, draw, read_ply, shade  # noqa: E402

BASE = np.array([0.62, 0.66, 0.72])
PATCH = np.array([0.95, 0.62, 0.25])
RESULT = np.array([0.35, 0.55, 0.85])


def view_for(V, patch):
    """Looks at the patch from its mean normal direction, tilted a little so relief shows."""
    P = V[patch]
    c = P.mean(0)
    _, _, vt = np.linalg.svd(P - c, full_matrices=False)
    n = vt[2]  # its sign is the SVD's, which rounding decides
    out = np.dot(n, c - V.mean(0))
    if abs(out) > 1e-6 * np.linalg.norm(V.max(0) - V.min(0)):
        n = n if out > 0 else -n  # face outwards from the mesh's centre
    else:  # a patch at the mesh's centre (a plane, a disc on it): look from the side its largest component points to
        n = n if n[np.argmax(np.abs(n))] > 0 else -n
    elev = np.degrees(np.arcsin(np.clip(n[2], -1, 1)))
    azim = np.degrees(np.arctan2(n[1], n[0]))
    return elev - 25.0 if elev > 60 else elev + 20.0, azim + 20.0


def vertex_normals(V, F):
    """Unit area-weighted vertex normals."""
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n = np.zeros_like(V)
    for c in range(3):
        np.add.at(n, F[:, c], fn)
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def coat_heights(d, case):
    """Per target vertex: the coating's normal height over the target patch's bounding-box diagonal; None when
    the case is no coating (a transplant's result has vertices of its own)."""
    Vt, Ft = read_ply(os.path.join(d, f"{case}__target.ply"))
    Vr, Fr = read_ply(os.path.join(d, f"{case}__result.ply"))
    if Vr.shape != Vt.shape or Fr.shape != Ft.shape or not np.array_equal(Fr, Ft):
        return None
    patch = np.loadtxt(os.path.join(d, f"{case}__patch.txt"), dtype=np.int64, ndmin=1)
    diag = np.linalg.norm(Vt[patch].max(0) - Vt[patch].min(0))
    return ((Vr - Vt) * vertex_normals(Vt, Ft)).sum(1) / diag


def height_colors(h, F, scale):
    """Face colours from the mean normal height of their corners on a diverging map, +-scale at its ends."""
    return plt.get_cmap("RdBu_r")(Normalize(-scale, scale)(h[F].mean(1)))[:, :3]


def panel(ax, V, F, colors, cam, lim, title):
    draw(ax, V, F, colors, cam)
    ax.set_xlim(lim[0][0], lim[1][0])
    ax.set_ylim(lim[0][1], lim[1][1])
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)


def limits(V, cam, pad=0.05):
    r, u, _ = cam
    P = np.stack([V @ r, V @ u], axis=1)
    lo, hi = P.min(0), P.max(0)
    p = pad * (hi - lo).max()
    return lo - p, hi + p


def render_case(case, d, out_dir, scale=None):
    Vs, Fs = read_ply(os.path.join(d, f"{case}__source.ply"))
    Vt, Ft = read_ply(os.path.join(d, f"{case}__target.ply"))
    Vr, Fr = read_ply(os.path.join(d, f"{case}__result.ply"))
    patch = np.loadtxt(os.path.join(d, f"{case}__patch.txt"), dtype=np.int64, ndmin=1)
    in_patch = np.zeros(len(Vt), bool)
    in_patch[patch] = True
    face_in = in_patch[Ft].all(axis=1)
    cam = camera(*view_for(Vt, patch))
    r, u, dvec = cam
    light = 0.3 * r + 0.6 * u + 0.75 * dvec
    light /= np.linalg.norm(light)
    fig, axes = plt.subplots(1, 4, figsize=(17, 4.6))
    spatch = np.loadtxt(os.path.join(d, f"{case}__source_patch.txt"), dtype=np.int64, ndmin=1)
    s_in = np.zeros(len(Vs), bool)
    s_in[spatch] = True
    scam = camera(*view_for(Vs, spatch))
    sl = 0.3 * scam[0] + 0.6 * scam[1] + 0.75 * scam[2]
    scol = np.where(s_in[Fs].all(axis=1)[:, None], PATCH, BASE)
    panel(axes[0], Vs, Fs, shade(Vs, Fs, scol, sl / np.linalg.norm(sl)), scam, limits(Vs, scam), "source (patch orange)")
    colors = np.where(face_in[:, None], PATCH, BASE)
    panel(axes[1], Vt, Ft, shade(Vt, Ft, colors, light), cam, limits(Vt, cam), "target (patch orange)")
    rpatch = np.loadtxt(os.path.join(d, f"{case}__result_patch.txt"), dtype=np.int64, ndmin=1)
    r_in = np.zeros(len(Vr), bool)
    r_in[rpatch] = True
    rc = np.where(r_in[Fr].all(axis=1)[:, None], RESULT, BASE)
    h = coat_heights(d, case) if scale else None
    what = "patch blue"
    if h is not None:
        rc = np.where(r_in[Fr].all(axis=1)[:, None], height_colors(h, Fr, scale), BASE)
        what = "normal height"
    panel(axes[2], Vr, Fr, shade(Vr, Fr, rc, light), cam, limits(Vr, cam), f"result ({what})")
    # Close-up: the patch and a margin around it, before and after in one frame.
    c0 = Vt[patch].mean(0)
    radius = 1.4 * np.linalg.norm(Vt[patch] - c0, axis=1).max()
    near = np.linalg.norm(Vr - c0, axis=1) <= radius
    fz = near[Fr].all(axis=1)
    lim = limits(np.vstack([Vr[near], Vt[np.linalg.norm(Vt - c0, axis=1) <= radius]]), cam)
    panel(axes[3], Vr, Fr[fz], shade(Vr, Fr[fz], rc[fz], light), cam, lim, f"result, close up ({what})")
    if h is not None:
        bar = fig.colorbar(ScalarMappable(Normalize(-scale, scale), "RdBu_r"), ax=axes[3], fraction=0.04, pad=0.02)
        bar.set_label("normal height / patch diagonal", fontsize=8)
    fig.suptitle(f"{case}: source {len(Vs)} vertices, target {len(Vt)}, patch {len(patch)}, result {len(Vr)}",
                 fontsize=11)
    fig.tight_layout()
    path = os.path.join(out_dir, f"render_app_{case}.png")
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def plot(results, out, meshes=None, cases=""):
    """Renders every case under MESHES (default RESULTS/meshes/applications) whose name contains `cases`."""
    d = meshes or os.path.join(results, "meshes", "applications")
    found = sorted(glob.glob(os.path.join(d, "*__result.ply")))
    if not found:
        print(f"applications: no meshes under {d} (run exp_applications first); nothing to render", file=sys.stderr)
        return 0
    os.makedirs(out, exist_ok=True)
    chosen = [c for c in (os.path.basename(p)[: -len("__result.ply")] for p in found) if cases in c]
    heights = [h for h in (coat_heights(d, c) for c in chosen) if h is not None]
    # One colour scale for every coating: the median of their largest heights, so a coating too tall saturates.
    scale = float(np.median([np.abs(h).max() for h in heights])) if heights else None
    for case in chosen:
        print(f"applications: wrote {render_case(case, d, out, scale)}", file=sys.stderr)
    return 0


def main(argv=None):
    ap = parser(__doc__)
    ap.add_argument("--meshes", default=None, help="default: RESULTS/meshes/applications")
    ap.add_argument("--cases", default="", help="render only cases whose name contains this")
    a = ap.parse_args(argv)
    return plot(a.results, out_dir(a), a.meshes, a.cases)


if __name__ == "__main__":
    sys.exit(main())
