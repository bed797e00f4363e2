"""Renders of the applications experiment (exp_applications: coating transfer, transplanting): one PNG per case,
panels source (its patch orange), target (its patch orange), result, and the result's patch close up beside the
target's (the same camera), so the transferred detail and the seam can be checked by eye.

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
from .render_meshes import camera, draw, read_ply, shade  # noqa: E402

BASE = np.array([0.62, 0.66, 0.72])
PATCH = np.array([0.95, 0.62, 0.25])
RESULT = np.array([0.35, 0.55, 0.85])


def view_for(V, patch):
    """Looks at the patch from its mean normal direction, tilted a little so relief shows."""
    P = V[patch]
    c = P.mean(0)
    _, _, vt = np.linalg.svd(P - c, full_matrices=False)
    n = vt[2]
    if np.dot(n, c - V.mean(0)) < 0:  # face outwards from the mesh's centre
        n = -n
    elev = np.degrees(np.arcsin(np.clip(n[2], -1, 1)))
    azim = np.degrees(np.arctan2(n[1], n[0]))
    return elev - 25.0 if elev > 60 else elev + 20.0, azim + 20.0


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


def render_case(case, d, out_dir):
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
    panel(axes[2], Vr, Fr, shade(Vr, Fr, rc, light), cam, limits(Vr, cam), "result")
    # Close-up: the patch and a margin around it, before and after in one frame.
    c0 = Vt[patch].mean(0)
    radius = 1.4 * np.linalg.norm(Vt[patch] - c0, axis=1).max()
    near = np.linalg.norm(Vr - c0, axis=1) <= radius
    fz = near[Fr].all(axis=1)
    lim = limits(np.vstack([Vr[near], Vt[np.linalg.norm(Vt - c0, axis=1) <= radius]]), cam)
    panel(axes[3], Vr, Fr[fz], shade(Vr, Fr[fz], rc[fz], light), cam, lim, "result, close up (patch blue)")
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
    for p in found:
        case = os.path.basename(p)[: -len("__result.ply")]
        if cases in case:
            print(f"applications: wrote {render_case(case, d, out)}", file=sys.stderr)
    return 0


def main(argv=None):
    ap = parser(__doc__)
    ap.add_argument("--meshes", default=None, help="default: RESULTS/meshes/applications")
    ap.add_argument("--cases", default="", help="render only cases whose name contains this")
    a = ap.parse_args(argv)
    return plot(a.results, out_dir(a), a.meshes, a.cases)


if __name__ == "__main__":
    sys.exit(main())
