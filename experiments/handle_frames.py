#!/usr/bin/python3
"""The handle-frames driver (issue 16): handle-mode frames against full-mode frames: frame times of both modes, the
precompute, the responses' bytes against the memory read rate, and how far the two modes' results lie apart. A
driver: it writes CSV only; the report step (python3 -m dbtools.report --only handle_frames) writes the Markdown.
Not part of ./run reproduce (it runs the 26k and 104k armadillo for minutes): the run kept is a record,
results/records/2026-11-24-handle-frames/.

  experiments/handle_frames.py [--build DIR] [--results DIR] [--repeats R] [--frames F] [--quick] [--drags]
  (from the repository root, with Debian's /usr/bin/python3: numpy)

Each case is a deform cell (harness/deform_cell.h) with handle_frames=1, run in a fresh process of
exp_table_2_1 --cell: one init, the drag in full mode, then the same factored systems precompute their handle
responses and the drag runs again in handle mode (so the two modes are paired in one process, on one factor).
Rounds interleave the cases (round 1: every case, round 2: every case, ...), the report takes medians over the
rounds. Timing cases: the armadillo (26k vertices) and its Loop level 1 (104k) whole-mesh edits, lap / tf / lri,
soft constraints, and per tier a per-vertex drag (`targets`: the 30 vertices nearest the head lifted and bent, as
--drags makes them), lap / tf. Exactness cases: every BS08 edit (data/bs08/), lap / tf / lri, hard and soft, once.
Every case runs once more per round on the multifrontal_refined backend (3 frames): its refined solves converge to
the exact solution in both modes, so their difference (`refined:handle_vs_full`) is the handle-mode precompute's
own error, free of the default backend's rounding of these ill-conditioned systems (the default backend's
difference is recorded beside it; its full frame stays the thesis' one solve).
Writes RESULTS/handle_frames.csv (long: case, measure, value, unit, with provenance).
--quick: the 26k tier and one BS08 edit, one round (a smoke run).

--drags: instead, per-vertex drags (an edit's `targets` file) against full frames, to find the handle size up to
which handle-mode frames pay: for each tier, method (lap, tf; soft constraints) and handle size h (the h vertices
nearest the armadillo's head, lifted and bent: a smooth, non-affine drag; its feet, the lowest 5%, fixed), `deformbench deform` runs in
full mode and in handle mode (--handle-limit 1e6: no fallback), one process each, paired back to back; rounds
interleave the cases. Writes RESULTS/handle_drags.csv (frame medians, precompute, responses and the factor's bytes,
the two modes' difference, the load average).
"""
import argparse
import csv
import os
import subprocess
import sys

TIMED = [("armadillo_26k", "data/edits/armadillo_whole.edit"), ("armadillo_104k", "data/edits/armadillo_loop1_whole.edit")]
BS08 = ["plane", "cylinder", "bar", "cactus"]
METHODS = ["lap", "tf", "lri"]


def run_cell(build, spec):
    out = subprocess.run([os.path.join(build, "exp_table_2_1"), "--cell"] + spec, capture_output=True, text=True)
    line = next((l for l in out.stdout.splitlines() if l.startswith("DBCELL ")), None)
    if out.returncode != 0 or line is None:
        sys.exit(f"handle_frames: cell {' '.join(spec)} failed ({out.returncode}): {out.stderr.strip()[-500:]}")
    fields = dict(tok.split("=", 1) for tok in line.split()[1:] if "=" in tok)
    if fields.get("status") != "ok":
        sys.exit(f"handle_frames: cell {' '.join(spec)}: {fields.get('status')} {fields.get('message')}")
    return {k[2:]: (float(v), fields.get("u." + k[2:], "")) for k, v in fields.items() if k.startswith("m.")}


def write_csv(rows, path):
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    os.replace(path + ".tmp", path)
    print(f"[handle_frames] wrote {path}; its report: PYTHONPATH=python /usr/bin/python3 -m dbtools.report --results "
          f"{os.path.dirname(path) or '.'} --only handle_frames", file=sys.stderr)


def provenance(build):
    out = subprocess.run([os.path.join(build, "deformbench"), "provenance"], capture_output=True, text=True, check=True)
    return dict(l.split(": ", 1) for l in out.stdout.splitlines() if ": " in l)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--results", default="results")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--drags", action="store_true")
    ap.add_argument("--sizes", default="", help="--drags: handle sizes, e.g. 10,30,100 (default per tier/method)")
    a = ap.parse_args()
    if a.drags:
        drags(a)
        return
    timed = TIMED[:1] if a.quick else TIMED
    bs08 = BS08[-1:] if a.quick else BS08
    rounds = 1 if a.quick else a.repeats
    prov = provenance(a.build)
    rows = []

    def record(case, tier, method, constraints, rnd, spec, prefix=""):
        m = run_cell(a.build, spec)
        print(f"[handle_frames] {case} {method} {constraints} round {rnd}{' ' + prefix[:-1] if prefix else ''}: full "
              f"{m['frame_s'][0] * 1e3:.3f} ms, handle {m['frame_handle_s'][0] * 1e3:.3f} ms, precompute "
              f"{m['precompute_s'][0]:.3f} s (cpu {m['precompute_cpu_s'][0]:.3f} s), diff {m['handle_vs_full'][0]:.2e}",
              file=sys.stderr, flush=True)
        for k, (v, unit) in m.items():
            rows.append({"case": case, "tier": tier, "method": method, "constraints": constraints, "round": rnd,
                         "frames": spec[-2].split("=")[1], "measure": prefix + k, "value": repr(v), "unit": unit,
                         "command": "build/exp_table_2_1 --cell " + " ".join(spec), **prov})

    def both(case, tier, method, constraints, rnd, spec, frames):
        """The case on the default backend (timed), then on the refined one (exactness, 3 frames)."""
        record(case, tier, method, constraints, rnd, spec + [f"frames={frames}", "handle_frames=1"])
        record(case, tier, method, constraints, rnd,
               spec + ["backend=multifrontal_refined", "frames=3", "handle_frames=1"], prefix="refined:")

    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        drag_edits = {tier: drag_edit(tmp, mesh, TARGETS_H, a.frames)[0] for tier, mesh in DRAG_MESH.items()
                      if any(t == tier for t, _ in timed)}
        for rnd in range(1, rounds + 1):
            for tier, edit in timed:
                for method in METHODS:
                    both(tier, tier, method, "soft", rnd, ["kind=deform", f"edit={edit}", f"model={tier}",
                                                            f"method={method}", "constraints=soft"], a.frames)
                for method in ("lap", "tf"):  # lri refuses per-vertex targets
                    both(f"{tier} targets h={TARGETS_H}", tier, method, "soft", rnd,
                         ["kind=deform", f"edit={drag_edits[tier]}", f"model={tier}_targets", f"method={method}",
                          "constraints=soft"], a.frames)
    for stem in bs08:
        for method in METHODS:
            for constraints in ("hard", "soft"):
                both("bs08_" + stem, "bs08", method, constraints, 1,
                     ["kind=deform", f"edit=data/bs08/{stem}", f"model=bs08_{stem}", f"method={method}",
                      f"constraints={constraints}"], 5)
    os.makedirs(a.results, exist_ok=True)
    write_csv(rows, os.path.join(a.results, "handle_frames.csv"))


DRAG_SIZES = {("armadillo_26k", "lap"): [30, 100, 300, 1000], ("armadillo_26k", "tf"): [10, 30, 100, 300],
              ("armadillo_104k", "lap"): [100, 300, 1000], ("armadillo_104k", "tf"): [10, 30, 100]}
HEAD = (-20.2599, 97.1076, -28.8554)  # the timing edits' handle centre (data/edits/armadillo_whole.edit)
DRAG_MESH = {"armadillo_26k": "data/meshes/armadillo.off", "armadillo_104k": "data/generated/armadillo_loop1.off"}
TARGETS_H = 30  # the timing cases' per-vertex drag (handle_drags.md: where handle frames stop paying)


def read_off(path):
    import numpy as np
    with open(path) as f:
        assert f.readline().strip() == "OFF"
        nv = int(f.readline().split()[0])
        return np.loadtxt(f, max_rows=nv)


def drag_edit(tmp, mesh, h, frames):
    """An .edit dragging the h vertices nearest HEAD, each along its own path; returns its path and the rest mesh."""
    import numpy as np
    V = read_off(mesh)
    ids = np.sort(np.argsort(np.linalg.norm(V - np.array(HEAD), axis=1), kind="stable")[:h])
    diag = np.linalg.norm(V.max(0) - V.min(0))
    P = V[ids]
    # Lifted by 5% of the diagonal and bent quadratically across the handle (a fifth of its radius): smooth, not
    # affine, and mild enough that TF's fitted similarities stay near rotations.
    q = (P - P.mean(0)) / max(np.linalg.norm(P - P.mean(0), axis=1).max(), 1e-12)
    r = np.linalg.norm(P - P.mean(0), axis=1).max()
    d = 0.2 * r * np.stack([q[:, 1] ** 2, q[:, 2] * q[:, 0], q[:, 0] ** 2], 1)
    lift = np.array([0, 0.05 * diag, 0])
    with open(os.path.join(tmp, f"h{h}.idx"), "w") as f:
        f.write(" ".join(map(str, ids)) + "\n")
    # The feet (the lowest 5% of the height) stay put: with nothing fixed, TF's energy barely resists similarities
    # about a small handle, and a non-rigid drag of it turns the whole model.
    with open(os.path.join(tmp, "roi.idx"), "w") as f:
        f.write(" ".join(map(str, np.nonzero(V[:, 1] > V[:, 1].min() + 0.05 * np.ptp(V[:, 1]))[0])) + "\n")
    with open(os.path.join(tmp, f"h{h}.txt"), "w") as f:
        for k in range(1, frames + 1):
            np.savetxt(f, P + (k / frames) * (d + lift), fmt="%.17g")
    path = os.path.join(tmp, f"h{h}.edit")
    with open(path, "w") as f:
        f.write(f"mesh = {os.path.abspath(mesh)}\nroi = indices:roi.idx\nhandle = indices:h{h}.idx\ntargets = h{h}.txt\n")
    return path, V


def run_drag(build, edit, method, mode, tmp):
    out, csv_path = os.path.join(tmp, f"{mode}.off"), os.path.join(tmp, f"{mode}.csv")
    cmd = [os.path.join(build, "deformbench"), "deform", edit, "--method", method, "--constraints", "soft",
           "--frame-mode", mode, "--out", out, "--csv", csv_path] + (["--handle-limit", "1e6"] if mode == "handle" else [])
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"handle_frames --drags: {' '.join(cmd)} failed ({r.returncode}): {r.stderr.strip()[-500:]}")
    with open(csv_path, newline="") as f:
        row = next(csv.DictReader(f))
    return row, read_off(out), " ".join(cmd)


def drags(a):
    import tempfile
    import numpy as np
    prov = provenance(a.build)
    tiers = TIMED[:1] if a.quick else TIMED
    cases = [(t, m, h) for t, _ in tiers for m in ("lap", "tf")
             for h in ([int(x) for x in a.sizes.split(",")] if a.sizes else DRAG_SIZES[(t, m)])]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for rnd in range(1, (1 if a.quick else a.repeats) + 1):
            for tier, method, h in cases:
                edit, V = drag_edit(tmp, DRAG_MESH[tier], h, a.frames)
                full, Vf, cfull = run_drag(a.build, edit, method, "full", tmp)
                hand, Vh, chand = run_drag(a.build, edit, method, "handle", tmp)
                diff = float(np.max(np.linalg.norm(Vh - Vf, axis=1)) / np.linalg.norm(V.max(0) - V.min(0)))
                m = {"full_frame_s": float(full["frame_s"]), "handle_frame_s": float(hand["frame_s"]),
                     "full_init_s": float(full["init_s"]), "handle_init_s": float(hand["init_s"]),
                     "precompute_s": float(hand["precompute_s"]), "response_bytes": float(hand["response_bytes"]),
                     "factor_bytes": float(hand["factor_bytes"]), "handle_vs_full": diff,
                     "load_average": os.getloadavg()[0]}
                print(f"[handle_drags] {tier} {method} h={h} round {rnd}: full {m['full_frame_s'] * 1e3:.2f} ms, "
                      f"handle {m['handle_frame_s'] * 1e3:.2f} ms, precompute {m['precompute_s']:.2f} s, responses "
                      f"{m['response_bytes'] / m['factor_bytes']:.2f} x factor, diff {diff:.1e}", file=sys.stderr,
                      flush=True)
                for k, v in m.items():
                    rows.append({"case": tier, "method": method, "handle": h, "round": rnd, "frames": a.frames,
                                 "measure": k, "value": repr(v), "command": cfull + " ; " + chand, **prov})
    os.makedirs(a.results, exist_ok=True)
    write_csv(rows, os.path.join(a.results, "handle_drags.csv"))


if __name__ == "__main__":
    main()
