"""Before/after renders of the frames experiment (exp_frames): one PNG per case, panels rest (coloured by role:
fixed grey, free red, handle yellow, as in thesis fig. 4-4), the analytic ideal where there is one, and the results
of LAP, TF (free and normalized scale) and LRI (every frame strategy with Gram-Schmidt, and first-neighbour frames
with polar orthonormalization; the other polar results coincide with it, see results/frames.md).

Reads results/meshes/frames/CASE__{rest,ideal,<config>}.ply (binary little-endian PLY as written by
db::write_mesh) and CASE__roles.sel; writes OUT/render_CASE.png. Flat shading by face normal, Agg backend.
Drawn as a 2D PolyCollection of an orthographic projection, faces sorted back to front (painter's algorithm):
mplot3d's Poly3DCollection does the same sort, but its axes are square, which leaves slender shapes (a bar
standing up) a few pixels wide; the 2D panels take the shape's own aspect ratio, shared by all panels of a case
(but a result far larger than the others, or a rest shape whose frame would leave the results' panels mostly
empty, is drawn in a frame of its own, its size in its title). Where the results differ by too little to tell apart
side by side, a grid of distance maps below the shapes colours each result by its per-vertex distance from LAP's, in
rest bounding-box diagonals, with a colour bar.

usage: python3 -m dbtools.plots.render_meshes [--results results] [--out RESULTS/figures] [--cases SUBSTRING]
       [--max-faces N]
"""
import glob
import os
import sys
import textwrap

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.cm import ScalarMappable  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402

from .cli import out_dir, parser  # noqa: E402

PANELS = [
    ("rest", "rest (fixed / free / handle)"),
    ("ideal", "analytic ideal"),
    ("lap", "LAP"),
    ("tf", "TF"),
    ("tf-normalized", "TF, normalized scale"),
    ("lri-first-gram_schmidt", "LRI first, Gram-Schmidt"),
    ("lri-random-gram_schmidt", "LRI random, Gram-Schmidt"),
    ("lri-height_angle-gram_schmidt", "LRI height angle, Gram-Schmidt"),
    ("lri-curvature-gram_schmidt", "LRI curvature, Gram-Schmidt"),
    ("lri-first-polar", "LRI first, polar"),
    ("lri-uncoordinated", "LRI uncoordinated (handle frames at rest)"),
]
COLORS = {"lap": (0.35, 0.55, 0.85), "tf": (0.35, 0.75, 0.55), "tf-normalized": (0.55, 0.8, 0.35),
          "lri-uncoordinated": (0.8, 0.4, 0.55), "ideal": (0.75, 0.75, 0.75)}
TITLES = dict(PANELS)
LRI_COLOR = (0.85, 0.6, 0.35)
ROLE_COLORS = np.array([[0.62, 0.66, 0.72], [0.86, 0.32, 0.30], [0.97, 0.85, 0.25]])  # fixed, free, handle


def read_ply(path):
    """Binary little-endian PLY with 'property double x/y/z' and 'property list uchar int vertex_indices'."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise ValueError(f"{path}: not a PLY file")
    header = data[:end].decode("ascii").splitlines()
    body = data[end + len(b"end_header\n"):]
    if "format binary_little_endian 1.0" not in header:
        raise ValueError(f"{path}: expected binary_little_endian")
    nv = nf = None
    props = []
    for line in header:
        t = line.split()
        if t[:2] == ["element", "vertex"]:
            nv = int(t[2])
        elif t[:2] == ["element", "face"]:
            nf = int(t[2])
        elif t and t[0] == "property":
            props.append(" ".join(t[1:]))
    expected = ["double x", "double y", "double z", "list uchar int vertex_indices"]
    if nv is None or nf is None or props != expected:
        raise ValueError(f"{path}: unexpected PLY layout {props}")
    V = np.frombuffer(body, dtype="<f8", count=3 * nv).reshape(nv, 3)
    rec = np.dtype([("n", "u1"), ("i", "<i4", (3,))])
    faces = np.frombuffer(body, dtype=rec, count=nf, offset=24 * nv)
    if nf and not np.all(faces["n"] == 3):
        raise ValueError(f"{path}: only triangles are supported")
    return V, faces["i"].astype(np.int64)


def read_roles(path, n):
    if not os.path.exists(path):
        return None
    vals = [int(l.split()[0]) for l in open(path) if l.strip() and not l.lstrip().startswith("#")]
    return np.array(vals) if len(vals) == n else None


def camera(elev, azim):
    """Orthographic camera as mplot3d's view_init(elev, azim) with +z up: right, up and towards-viewer axes."""
    e, a = np.radians(elev), np.radians(azim)
    d = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    r = np.array([-np.sin(a), np.cos(a), 0.0])
    return r, np.cross(d, r), d


def shade(V, F, base, light, ambient=0.25):
    T = V[F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None] + 1e-300
    lam = np.abs(n @ light)  # two-sided: open meshes show their inside too
    k = (ambient + (1 - ambient) * lam)[:, None]
    base = np.broadcast_to(np.asarray(base, dtype=float), (len(F), 3))
    return np.clip(base * k, 0, 1)


DPI = 90
# Distance maps are drawn when the methods' results differ, but no vertex of any lies farther from the reference's
# than this fraction of a panel's width: at page size, where a panel is a few centimetres wide, that is too little
# to see by comparing the shapes.
DISTANCE_MAP_BELOW = 0.1
# ... and when they differ by more than rounding: results closer than this, in rest bounding-box diagonals, are the
# same solution (no map of rounding noise).
SAME_BELOW = 1e-6
# A panel whose shape is this many times the median panel's size gets a frame of its own.
OWN_FRAME_ABOVE = 2.0
# The rest shape gets a frame of its own where sharing the results' frame would make that frame this many times
# larger in area (a straight bar beside its bends: every panel mostly empty).
REST_OWN_FRAME_ABOVE = 1.5
VIEWS = {"cgal_cyl": (20.0, 35.0), "dino": (20.0, -50.0), "bar_twist": (20.0, -60.0), "bs08_plane": (25.0, -70.0),
         "bunny": (90.0, -90.0), "armadillo": (90.0, -90.0)}  # (elev, azim) by prefix


def view_for(case, Vs):
    """Per-case view, else looks along the axis of smallest extent of all meshes together (bends happen across it)."""
    for prefix, v in VIEWS.items():
        if case.startswith(prefix):
            return v
    allV = np.vstack(Vs)
    ext = allV.max(0) - allV.min(0)
    ax = int(np.argmin(ext))
    azim = {0: 0.0, 1: -90.0, 2: -90.0}[ax]
    elev = 90.0 if ax == 2 else 15.0
    return elev, azim


def draw(ax, V, F, colors, cam):
    """Painter's algorithm on an orthographic projection: far faces first, flat colours, no edges."""
    r, u, d = cam
    P = np.stack([V @ r, V @ u], axis=1)
    order = np.argsort((V @ d)[F].mean(axis=1))
    pc = PolyCollection(P[F[order]], facecolors=colors[order], edgecolors="face", linewidths=0.1)
    ax.add_collection(pc)


def layout(n, aspect):
    """(rows, cols, panel width, panel height) in inches for n panels of height / width `aspect`: a tall shape (a bar
    standing up) all in one row, else three a row."""
    cols = n if aspect > 2.0 else min(3, n)
    pw = min(4.2, 18.0 / cols)
    ph = float(np.clip(pw * aspect, 1.2, 9.0))
    return int(np.ceil(n / cols)), cols, pw, ph


def title_lines(text, width_in, fontsize):
    """The title wrapped to the panel's width (an average glyph is about 0.55 em wide)."""
    return textwrap.fill(text, max(12, int(width_in * 72 / (0.55 * fontsize))))


def differences(meshes, keys, rest):
    """(reference key, key -> per-vertex distance from the reference's result in rest bounding-box diagonals) for
    the method panels; (None, {}) when fewer than two methods."""
    methods = [k for k in keys if k not in ("rest", "ideal")]
    if len(methods) < 2:
        return None, {}
    ref = methods[0]
    diag = np.linalg.norm(rest.max(0) - rest.min(0))
    return ref, {k: np.linalg.norm(meshes[k][0] - meshes[ref][0], axis=1) / diag for k in methods if k != ref}


def distance_panels(sub, meshes, ref, dist, view, grid):
    """Each method's result coloured by its distance from the reference's (lightly shaded, one scale for all) on a
    grid of its own, with a colour bar. grid: (rows, cols, panel width in inches)."""
    rows, cols, pw = grid
    axes = sub.subplots(rows, cols, squeeze=False)
    vmax = max(float(d.max()) for d in dist.values())
    norm, cmap = Normalize(0.0, vmax), plt.get_cmap("viridis")
    Fs = view["faces"]
    for ax in axes.flat:
        ax.set_axis_off()
    for ax, (key, d) in zip(axes.flat, dist.items()):
        V = meshes[key][0]
        base = cmap(norm(d[Fs].mean(axis=1)))[:, :3]
        draw(ax, V, Fs, shade(V, Fs, base, view["light"], ambient=0.7), view["cam"])
        frame(ax, view["lims"][key])
        ax.set_title(title_lines(f"{TITLES[key]} (max {d.max():.2g})", pw, 8), fontsize=8)
    cb = sub.colorbar(ScalarMappable(norm, cmap), ax=list(axes.flat), location="bottom", shrink=0.6, aspect=40)
    cb.set_label(f"distance from {TITLES[ref]}'s result, per vertex / rest bounding-box diagonal", fontsize=9)
    sub.suptitle(f"where and by how much the results differ: each one's distance from {TITLES[ref]}'s",
                 fontsize=10)


def frame(ax, lim):
    ax.set_xlim(lim[0][0], lim[1][0])
    ax.set_ylim(lim[0][1], lim[1][1])
    ax.set_aspect("equal")
    ax.set_axis_off()


def box(points, pad=0.03):
    """The padded 2D bounding box (lo, hi) of projected points."""
    lo, hi = points.min(0), points.max(0)
    p = pad * (hi - lo).max()
    return lo - p, hi + p


def case_view(case, meshes, faces):
    """The camera, light and 2D frame the panels of a case share, so shapes compare directly. A result far larger
    than the others (TF's scale blow-up) gets a frame of its own, `own` its size against the shared one's, so that
    the others stay readable."""
    elev, azim = view_for(case, [m[0] for m in meshes.values()])
    cam = camera(elev, azim)
    r, u, d = cam
    light = 0.3 * r + 0.6 * u + 0.75 * d
    P = {k: np.stack([m[0] @ r, m[0] @ u], axis=1) for k, m in meshes.items()}
    size = {k: float((p.max(0) - p.min(0)).max()) for k, p in P.items()}
    typical = float(np.median(list(size.values())))
    own = {k: s / typical for k, s in size.items() if s > OWN_FRAME_ABOVE * typical}
    lo, hi = box(np.vstack([p for k, p in P.items() if k not in own]))
    results = [p for k, p in P.items() if k not in own and k != "rest"]
    if "rest" in P and "rest" not in own and results:
        rlo, rhi = box(np.vstack(results))
        if np.prod(hi - lo) > REST_OWN_FRAME_ABOVE * np.prod(rhi - rlo):  # the rest shape would empty the frames
            own["rest"], lo, hi = size["rest"] / typical, rlo, rhi
    lims = {k: box(p) if k in own else (lo, hi) for k, p in P.items()}
    extent = hi - lo
    return {"elev": elev, "azim": azim, "cam": cam, "light": light / np.linalg.norm(light), "faces": faces,
            "lims": lims, "own": own, "size": extent, "aspect": extent[1] / max(extent[0], 1e-300)}


def shape_panels(sub, keys, meshes, roles, view, grid):
    rows, cols, pw, fontsize = grid
    axes = sub.subplots(rows, cols, squeeze=False)
    Fs = view["faces"]
    for ax in axes.flat:
        ax.set_axis_off()
    for ax, key in zip(axes.flat, keys):
        V = meshes[key][0]
        if key == "rest" and roles is not None:
            base = ROLE_COLORS[roles[Fs].max(axis=1)]  # a face touching the handle is handle, else free if it touches one
        else:
            base = COLORS.get(key, LRI_COLOR)
        draw(ax, V, Fs, shade(V, Fs, base, view["light"]), view["cam"])
        frame(ax, view["lims"][key])
        own = f" (own frame: {view['own'][key]:.1f}x the others' size)" if key in view["own"] else ""
        ax.set_title(title_lines(TITLES[key] + own, pw, fontsize), fontsize=fontsize)


def render_case(case, files, out_dir, max_faces):
    meshes = {key: read_ply(files[key]) for key, _ in PANELS if files.get(key)}
    if "rest" not in meshes:
        return None
    V0, F = meshes["rest"]
    sel = np.arange(len(F))
    if len(F) > max_faces:  # drawing cost grows with the face count: thin out very large meshes
        sel = np.sort(np.random.default_rng(0).choice(len(F), max_faces, replace=False))
    view = case_view(case, meshes, F[sel])
    keys = [k for k, _ in PANELS if k in meshes]
    rows, cols, pw, ph = layout(len(keys), view["aspect"])
    # Where the results differ by too little to see, distance maps below the shapes show where and by how much.
    ref, dist = differences(meshes, keys, V0)
    inches = min(pw / view["size"][0], ph / view["size"][1])  # per model unit
    widest = max((float(x.max()) for x in dist.values()), default=0.0)
    maps = widest > SAME_BELOW and widest * np.linalg.norm(V0.max(0) - V0.min(0)) * inches < DISTANCE_MAP_BELOW * pw
    fontsize = 8 if cols > 3 else 10
    lines = max(title_lines(TITLES[k], pw, fontsize).count("\n") + 1 for k in keys) + bool(view["own"])
    top_h = (ph + 0.2 * lines * fontsize / 8) * rows + 0.5
    mcols = cols if cols > 3 else 4  # the maps smaller than the shapes, four a row
    mrows, mpw = int(np.ceil(len(dist) / mcols)), pw * cols / mcols
    bottom_h = ((float(np.clip(mpw * view["aspect"], 1.0, 9.0)) + 0.45) * mrows + 1.3) if maps else 0.0
    fig = plt.figure(figsize=(pw * cols, top_h + bottom_h), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[top_h, bottom_h]) if maps else (fig, None)
    shape_panels(top, keys, meshes, read_roles(files.get("roles", ""), len(V0)), view, (rows, cols, pw, fontsize))
    if maps:
        distance_panels(bottom, meshes, ref, dist, view, (mrows, mcols, mpw))
    thin = f", {len(sel)} of {len(F)} faces drawn" if len(sel) < len(F) else ""
    fig.suptitle(title_lines(f"{case}: {len(V0)} vertices{thin} (view elev {view['elev']:g}, azim {view['azim']:g})",
                             pw * cols, 11), fontsize=11)
    path = os.path.join(out_dir, f"render_{case}.png")
    fig.savefig(path, dpi=DPI, bbox_inches="tight", pad_inches=0.15)  # nothing cropped
    plt.close(fig)
    return path


def plot(results, out, meshes=None, cases="", max_faces=200000):
    """Renders every case under MESHES (default RESULTS/meshes/frames) whose name contains `cases`."""
    mesh_dir = meshes or os.path.join(results, "meshes", "frames")
    rests = sorted(glob.glob(os.path.join(mesh_dir, "*__rest.ply")))
    if not rests:
        print(f"render_meshes: no meshes under {mesh_dir} (run exp_frames first); nothing to render", file=sys.stderr)
        return 0
    os.makedirs(out, exist_ok=True)
    for rest in rests:
        case = os.path.basename(rest)[: -len("__rest.ply")]
        if cases not in case:
            continue
        files = {}
        for key, _ in PANELS:
            p = os.path.join(mesh_dir, f"{case}__{key}.ply")
            if os.path.exists(p):
                files[key] = p
        files["roles"] = os.path.join(mesh_dir, f"{case}__roles.sel")
        path = render_case(case, files, out, max_faces)
        if path:
            print(f"render_meshes: wrote {path}", file=sys.stderr)
    return 0


def main(argv=None):
    ap = parser(__doc__)
    ap.add_argument("--meshes", default=None, help="default: RESULTS/meshes/frames")
    ap.add_argument("--cases", default="", help="render only cases whose name contains this")
    ap.add_argument("--max-faces", type=int, default=200000)
    a = ap.parse_args(argv)
    return plot(a.results, out_dir(a), a.meshes, a.cases, a.max_faces)


if __name__ == "__main__":
    sys.exit(main())
