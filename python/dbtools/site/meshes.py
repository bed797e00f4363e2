"""The 3D viewer's data and page: the frames study's meshes (exp_frames --meshes, RESULTS/meshes/frames/CASE__*.ply
and CASE__roles.sel) re-encoded compactly for the browser, one script per case, and viewer.html (static/viewer.js on
three.js r111 from Debian's libjs-three, copied into the site: no CDN, no download).

RESULTS/site/meshes/CASE.js calls DB_MESHES.add({...}) with base64 little-endian arrays: F (uint32 faces, shared by
every configuration: one mesh, moved), roles (uint8 per vertex: 0 fixed, 1 free = the region of interest, 2
handle) and per configuration V (float32 positions). meshes/index.js lists the cases; the viewer loads a case's
script when it is picked (file:// allows <script src>, not fetch)."""
import base64
import glob
import json
import os
import shutil
import sys

import numpy as np

from ..plots.render_meshes import read_ply, read_roles
from .layout import Page, esc

# Configurations shown, in panel order (exp_frames' labels): the rest mesh, the analytic ideal where a case has one,
# LAP, TF, TF with its scale removed, LRI with the library's default frames (first neighbour, Gram-Schmidt).
CONFIGS = [("rest", "rest"), ("ideal", "analytic ideal"), ("lap", "LAP"), ("tf", "TF"),
           ("tf-normalized", "TF, scale-free"), ("lri-first-gram_schmidt", "LRI")]
DEFAULT_CASE = "bs08_cactus"
THREE = "/usr/share/javascript/three"  # Debian's libjs-three
THREE_FILES = [("three.min.js", "three.min.js"), ("examples/js/controls/OrbitControls.js", "OrbitControls.js")]


def b64(array, dtype):
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


def encode_case(frames_dir, case):
    """The case's record for the viewer, or None when its rest mesh or roles cannot be read."""
    V0, F = read_ply(os.path.join(frames_dir, f"{case}__rest.ply"))
    roles = read_roles(os.path.join(frames_dir, f"{case}__roles.sel"), len(V0))
    if roles is None:
        return None
    configs = []
    for key, label in CONFIGS:
        path = os.path.join(frames_dir, f"{case}__{key}.ply")
        if not os.path.exists(path):
            continue
        V, Fk = read_ply(path)
        if V.shape != V0.shape or not np.array_equal(Fk, F):
            continue  # another mesh, not this one moved: not comparable vertex by vertex
        configs.append({"key": key, "label": label, "V": b64(V, "<f4")})
    return {"name": case, "vertices": len(V0), "faces": len(F), "F": b64(F, "<u4"), "roles": b64(roles, "u1"),
            "diag": float(np.linalg.norm(V0.max(axis=0) - V0.min(axis=0))), "configs": configs}


def write_data(results, site):
    """meshes/CASE.js per case and meshes/index.js; the cases' summaries."""
    frames_dir = os.path.join(results, "meshes", "frames")
    cases = sorted(os.path.basename(p)[:-len("__rest.ply")] for p in glob.glob(os.path.join(frames_dir, "*__rest.ply")))
    out_dir = os.path.join(site, "meshes")
    os.makedirs(out_dir, exist_ok=True)
    index = []
    for case in cases:
        try:
            rec = encode_case(frames_dir, case)
        except (OSError, ValueError) as e:  # an unreadable mesh costs its case only
            print(f"[site] viewer: case {case} left out: {e}", file=sys.stderr)
            continue
        if rec is None:
            continue
        with open(os.path.join(out_dir, f"{case}.js"), "w") as f:
            f.write(f"DB_MESHES.add({json.dumps(rec)});\n")
        index.append({"name": case, "vertices": rec["vertices"], "faces": rec["faces"],
                      "configs": [c["label"] for c in rec["configs"]], "file": f"meshes/{case}.js"})
    index.sort(key=lambda c: (c["name"] != DEFAULT_CASE, c["name"]))
    with open(os.path.join(out_dir, "index.js"), "w") as f:
        f.write(f"var DB_CASES = {json.dumps(index)};\n")
    return index


def copy_three(site):
    """three.js into site/three/; False when libjs-three is not installed."""
    if not all(os.path.exists(os.path.join(THREE, src)) for src, _ in THREE_FILES):
        return False
    os.makedirs(os.path.join(site, "three"), exist_ok=True)
    for src, dst in THREE_FILES:
        shutil.copy(os.path.join(THREE, src), os.path.join(site, "three", dst))
    return True


VIEWER = """<h1>Deformed meshes</h1>
<p>The frames study's results (<code>exp_frames --meshes</code>), one case at a time: the rest mesh coloured by
role (<span class="swatch" style="background:#9ea8b8"></span> fixed, <span class="swatch"
style="background:#db524d"></span> free: the region of interest, <span class="swatch"
style="background:#f7d940"></span> handle) beside each method's result coloured by its per-vertex distance from the
chosen reference, in rest bounding-box diagonals (one scale for all panels; a result blown far past the rest
size saturates), or every panel by role. Handle vertices are marked by <span class="swatch"
style="background:#e0218a"></span> points on every panel. Drag to turn, wheel to zoom, right-drag to pan; the
panels share the camera.</p>
<div class="controls"><label>case <select id="case"></select></label>
<label>distance from <select id="ref"></select></label> <span id="status"></span></div>
<div id="viewer"><canvas id="canvas"></canvas><div id="labels"></div></div>
<div class="colourbar"><span id="cb-lo"></span><div class="ramp"></div><span id="cb-hi"></span></div>"""


def pages(results, site):
    index = write_data(results, site)
    if not index:
        body = ("<h1>Deformed meshes</h1><p>No meshes of the frames study under <code>meshes/frames</code> "
                "(<code>./run reproduce</code> writes them).</p>")
        return [Page("viewer.html", "3D viewer", body)]
    if not copy_three(site):
        body = ("<h1>Deformed meshes</h1><p>three.js is not installed (Debian's <code>libjs-three</code>, "
                f"<code>{esc(THREE)}</code>): the viewer needs it. <code>./run reproduce</code> installs it.</p>")
        return [Page("viewer.html", "3D viewer", body)]
    scripts = ["three/three.min.js", "three/OrbitControls.js", "meshes/index.js", "viewer.js"]
    what = "the deformed meshes in 3D: rest against LAP, TF, scale-free TF and LRI, per-vertex distances"
    return [Page("viewer.html", "3D viewer", VIEWER, scripts, summary=what)]
