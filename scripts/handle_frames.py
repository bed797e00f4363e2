#!/usr/bin/python3
"""Handle-mode frames against full-mode frames (issue 16): frame medians of both modes, the precompute, the
responses' bytes against the memory read rate, and how far the two modes' results lie apart.

  scripts/handle_frames.py [--build DIR] [--results DIR] [--repeats R] [--frames F] [--quick]

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
Writes RESULTS/handle_frames.csv (long: case, measure, value, unit, with provenance) and RESULTS/handle_frames.md.
--quick: the 26k tier and one BS08 edit, one round (a smoke run). --report-only: rewrite the .md from the .csv.
--note TEXT: a paragraph for the .md (e.g. the machine's load during the run).

--drags: instead, per-vertex drags (an edit's `targets` file) against full frames, to find the handle size up to
which handle-mode frames pay: for each tier, method (lap, tf; soft constraints) and handle size h (the h vertices
nearest the armadillo's head, lifted and bent: a smooth, non-affine drag; its feet, the lowest 5%, fixed), `deformbench deform` runs in
full mode and in handle mode (--handle-limit 1e6: no fallback), one process each, paired back to back; rounds
interleave the cases. Writes RESULTS/handle_drags.csv and RESULTS/handle_drags.md (frame medians, precompute,
responses against the factor's bytes, the frames after which the precompute has paid, the two modes' difference).
"""
import argparse
import csv
import os
import statistics
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
    ap.add_argument("--report-only", action="store_true")
    ap.add_argument("--note", default="")
    ap.add_argument("--drags", action="store_true")
    ap.add_argument("--sizes", default="", help="--drags: handle sizes, e.g. 10,30,100 (default per tier/method)")
    a = ap.parse_args()
    if a.drags and not a.report_only:
        drags(a)
        return
    path = os.path.join(a.results, "handle_frames.csv")
    if a.report_only and a.drags:
        with open(os.path.join(a.results, "handle_drags.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        drags_report(rows, os.path.join(a.results, "handle_drags.md"), rows[0], a.note)
        return
    if a.report_only:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        report(rows, os.path.join(a.results, "handle_frames.md"), rows[0], a.note)
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
    write_csv(rows, path)
    report(rows, os.path.join(a.results, "handle_frames.md"), prov, a.note)


DRAG_SIZES = {("armadillo_26k", "lap"): [30, 100, 300, 1000], ("armadillo_26k", "tf"): [10, 30, 100, 300],
              ("armadillo_104k", "lap"): [100, 300, 1000], ("armadillo_104k", "tf"): [10, 30, 100]}
HEAD = (-20.2599, 97.1076, -28.8554)  # the timing edits' handle centre (data/edits/armadillo_whole.edit)
DRAG_MESH = {"armadillo_26k": "data/meshes/armadillo.off", "armadillo_104k": "data/generated/armadillo_loop1.off"}
TARGETS_H = 30  # the timing cases' per-vertex drag: responses a third of the factor's bytes (handle_drags.md)


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
    path = os.path.join(a.results, "handle_drags.csv")
    write_csv(rows, path)
    drags_report(rows, os.path.join(a.results, "handle_drags.md"), prov, a.note)


def drags_report(rows, path, prov, note):
    keys = sorted({(r["case"], r["method"], int(r["handle"])) for r in rows},
                  key=lambda k: (k[0] != "armadillo_26k", k[1], k[2]))
    med = lambda k, m: statistics.median(float(r["value"]) for r in rows  # noqa: E731
                                         if (r["case"], r["method"], int(r["handle"]), r["measure"]) == (*k, m))
    out = ["# Per-vertex drags: handle-mode frames against full frames (issue 16, item 3)\n",
           f"git {prov.get('git_sha')}, {prov.get('cpu')}, {prov.get('blas')} ({prov.get('blas_core')}), "
           f"{prov.get('build_threads')} worker threads, {prov.get('timestamp')}. Each case: the h vertices nearest the "
           "armadillo's head lifted by 5% of the diagonal and bent across the handle (a smooth, non-affine drag), the feet "
           "(lowest 5% of the height) fixed, soft constraints (every vertex an unknown), `deformbench deform` "
           "in full mode and in handle mode (`--handle-limit 1e6`), paired back to back, rounds interleaving the cases; "
           "medians over the rounds. `bytes ratio` = the responses one handle frame streams over the factor's bytes; "
           "`pays after` = the frames after which init + precompute + frames in handle mode cost less than init + "
           "frames in full mode (precompute / (full - handle)). Produced by `scripts/handle_frames.py --drags "
           f"--repeats {max(int(r['round']) for r in rows)} --frames {rows[0]['frames']}`; the exact commands are in "
           "handle_drags.csv.\n", note + "\n" if note else "",
           "| case | method | h | full frame ms | handle frame ms | full / handle | responses MB | factor MB | "
           "bytes ratio | precompute s | pays after (frames) | handle vs full | load | rounds |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for k in keys:
        g = lambda m: med(k, m)  # noqa: E731
        gain = g("full_frame_s") - g("handle_frame_s")
        pays = f"{g('precompute_s') / gain:.0f}" if gain > 0 else "never"
        n = len([r for r in rows if (r["case"], r["method"], int(r["handle"]), r["measure"]) == (*k, "precompute_s")])
        out.append(f"| {k[0]} | {k[1]} | {k[2]} | {g('full_frame_s') * 1e3:.2f} | {g('handle_frame_s') * 1e3:.2f} | "
                   f"{g('full_frame_s') / g('handle_frame_s'):.2f} | {g('response_bytes') / 1e6:.1f} | "
                   f"{g('factor_bytes') / 1e6:.1f} | {g('response_bytes') / g('factor_bytes'):.2f} | "
                   f"{g('precompute_s'):.2f} | {pays} | "
                   f"{max(float(r['value']) for r in rows if (r['case'], r['method'], int(r['handle']), r['measure']) == (*k, 'handle_vs_full')):.1e} | "
                   f"{g('load_average'):.1f} | {n} |")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(out) + "\n")
    os.replace(path + ".tmp", path)


def report(rows, path, prov, note):
    def med(case, method, constraints, measure):
        v = [float(r["value"]) for r in rows if (r["case"], r["method"], r["constraints"], r["measure"]) ==
             (case, method, constraints, measure)]
        return statistics.median(v) if v else float("nan"), len(v)

    out = ["# Handle-mode frames (issue 16)\n",
           f"git {prov.get('git_sha')}, {prov.get('cpu')}, {prov.get('blas')} ({prov.get('blas_core')}), "
           f"{prov.get('build_threads')} worker threads, {prov.get('timestamp')}. Medians over the rounds (fresh "
           "processes, cases interleaved); each cell runs the drag in full mode, then in handle mode on the same "
           "factor. `pass` = the responses' bytes at the memory read rate measured right after the handle drag "
           "(the least a handle frame could take). Produced by `scripts/handle_frames.py "
           f"--repeats {max(int(r['round']) for r in rows)}`; each row's exact cell command is in handle_frames.csv.\n",
           note + "\n" if note else "",
           "`precompute cpu s`: its CPU time (all threads), which a loaded machine's time-slicing does not "
           "lengthen. `handle vs full`: the largest distance between the two modes' last frames / bounding-box "
           "diagonal, the worst round, on the default backend (its full frame one solve, the thesis' measure) and on "
           "multifrontal_refined (both modes refined to the exact solution: the precompute's own error).\n",
           "| case | method | full frame ms | handle frame ms | ratio | responses MB | read GB/s | pass ms | "
           "init s | precompute s | precompute cpu s | handle vs full | refined: handle vs full | rounds |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    lri = ["\nLRI's handle frame in parts (medians, ms): the frame system from its responses; the orthonormalization; "
           "the position right-hand side (the rest of rhs); the position solve.\n",
           "| case | responses | orthonormalize | position rhs | position solve |", "|---|---|---|---|---|"]
    keys = sorted({(r["case"], r["method"], r["constraints"]) for r in rows},
                  key=lambda k: (not k[0].startswith("armadillo"), k[0], METHODS.index(k[1]), k[2]))
    def worst(case, method, cons, measure):
        v = [float(r["value"]) for r in rows if (r["case"], r["method"], r["constraints"], r["measure"]) ==
             (case, method, cons, measure)]
        return f"{max(v):.1e}" if v else "-"

    for case, method, cons in keys:
        g = lambda m: med(case, method, cons, m)[0]  # noqa: E731
        n = med(case, method, cons, "frame_s")[1]
        out.append(f"| {case} ({cons}) | {method} | {g('frame_s') * 1e3:.3f} | {g('frame_handle_s') * 1e3:.3f} | "
                   f"{g('frame_s') / g('frame_handle_s'):.0f}x | {g('response_bytes') / 1e6:.1f} | "
                   f"{g('memory_read'):.1f} | {g('response_pass_s') * 1e3:.3f} | {g('init_s'):.2f} | "
                   f"{g('precompute_s'):.3f} | {g('precompute_cpu_s'):.3f} | {worst(case, method, cons, 'handle_vs_full')} | "
                   f"{worst(case, method, cons, 'refined:handle_vs_full')} | {n} |")
        if method == "lri":
            lri.append(f"| {case} ({cons}) | {g('response_s') * 1e3:.3f} | {g('orthonormalize_s') * 1e3:.3f} | "
                       f"{(g('handle_rhs_s') - g('orthonormalize_s')) * 1e3:.3f} | {g('handle_solve_s') * 1e3:.3f} |")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(out + lri) + "\n")
    os.replace(path + ".tmp", path)


if __name__ == "__main__":
    main()
