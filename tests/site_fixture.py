#!/usr/bin/python3
"""A tiny results directory for tests/site_test.sh: what the site generator (dbtools.site) reads, made in seconds
without the experiments: four Markdown reports citing figures and each other, their figures (small PNGs), and the
frames study's meshes of one case (a cylinder standing on z: rest, and four "results" bent by different amounts,
one blown up as TF's free scale can be), in the layout exp_frames writes (binary little-endian PLY, double x y z,
uchar-int faces; CASE__roles.sel 0 fixed / 1 free / 2 handle). The tracking histories are the test's
(tests/track_fake_measure.py).

  site_fixture.py RESULTS_DIR
"""
import os
import struct
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REPORTS = {
    "table_2_1": ("# Table 2-1 (fixture)\n\nA fixture report.\n\n| model | thesis | ours |\n|---|---|---|\n"
                  "| hand | 1.0 | 2.0 |\n\nFigure: `figures/table_2_1_init.png`; see [the frames study](frames.md).\n",
                  ["table_2_1_init.png"]),
    "solvers": ("# Solver verdict (fixture)\n\nFigure: `figures/solvers_orderings.png`.\n", ["solvers_orderings.png"]),
    "frames": ("# Frames study (fixture)\n\nFigure: `figures/frames_ideal.png`, renders "
               "`figures/render_tiny_cactus.png`.\n", ["frames_ideal.png", "render_tiny_cactus.png"]),
    "applications": ("# Applications (fixture)\n\n- coat: `figures/render_app_coat.png`\n", ["render_app_coat.png"]),
}


def figure(path, k):
    fig, ax = plt.subplots(figsize=(3, 2), dpi=60)
    ax.plot([0, 1, 2, 3], [k, k + 1, k + 3, k + 2], marker="o")
    ax.set_title(os.path.basename(path), fontsize=8)
    fig.savefig(path)
    plt.close(fig)


def cylinder(rings=24, segments=16, height=6.0):
    z = np.linspace(0, height, rings)
    a = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    V = np.array([[np.cos(t), np.sin(t), h] for h in z for t in a])
    F = []
    for r in range(rings - 1):
        for s in range(segments):
            i, j = r * segments + s, r * segments + (s + 1) % segments
            F += [[i, j, i + segments], [j, j + segments, i + segments]]
    return V, np.array(F)


def bend(V, degrees, scale=1.0):
    """Bends the part above z = 2 about the x axis, the top by `degrees`; `scale` grows it (TF's free scale)."""
    out = V.copy()
    t = np.clip((V[:, 2] - 2) / (V[:, 2].max() - 2), 0, 1) * np.radians(degrees)
    out[:, 1] = V[:, 1] * np.cos(t) - (V[:, 2] - 2) * np.sin(t) * scale
    out[:, 2] = 2 + V[:, 1] * np.sin(t) + (V[:, 2] - 2) * np.cos(t) * scale
    return out


def write_ply(path, V, F):
    with open(path, "wb") as f:
        f.write(f"ply\nformat binary_little_endian 1.0\nelement vertex {len(V)}\nproperty double x\n"
                f"property double y\nproperty double z\nelement face {len(F)}\n"
                "property list uchar int vertex_indices\nend_header\n".encode("ascii"))
        f.write(np.asarray(V, "<f8").tobytes())
        for tri in F:
            f.write(struct.pack("<B3i", 3, *tri))


def main(results):
    os.makedirs(os.path.join(results, "figures"), exist_ok=True)
    for k, (name, (text, figs)) in enumerate(REPORTS.items()):
        with open(os.path.join(results, f"{name}.md"), "w") as f:
            f.write(text)
        for fig in figs:
            figure(os.path.join(results, "figures", fig), k)
    threads = os.path.join(results, "threads")  # ./run threads' folder
    os.makedirs(threads, exist_ok=True)
    with open(os.path.join(threads, "table.md"), "w") as f:
        f.write("Runs: fixture.\n\n| edit (vertices) | T | init s |\n|---|---|---|\n| bar (6k) | 1 | 0.5 |\n")
    figure(os.path.join(threads, "threads.png"), 7)
    meshes = os.path.join(results, "meshes", "frames")
    os.makedirs(meshes, exist_ok=True)
    V, F = cylinder()
    for key, V_k in (("rest", V), ("lap", bend(V, 40)), ("tf", bend(V, 60, 1.6)), ("tf-normalized", bend(V, 60)),
                     ("lri-first-gram_schmidt", bend(V, 55))):
        write_ply(os.path.join(meshes, f"tiny_cactus__{key}.ply"), V_k, F)
    roles = np.where(V[:, 2] < 1, 0, np.where(V[:, 2] > 5, 2, 1))
    with open(os.path.join(meshes, "tiny_cactus__roles.sel"), "w") as f:
        f.write("# tiny_cactus: per vertex status 0 fixed, 1 free, 2 handle\n" + "".join(f"{r}\n" for r in roles))


if __name__ == "__main__":
    main(sys.argv[1])
