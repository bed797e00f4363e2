#!/usr/bin/python3
"""Handle-mode frames against full-mode frames (issue 16): frame medians of both modes, the precompute, the
responses' bytes against the memory read rate, and how far the two modes' results lie apart.

  scripts/handle_frames.py [--build DIR] [--results DIR] [--repeats R] [--frames F] [--quick]

Each case is a deform cell (harness/deform_cell.h) with handle_frames=1, run in a fresh process of
exp_table_2_1 --cell: one init, the drag in full mode, then the same factored systems precompute their handle
responses and the drag runs again in handle mode (so the two modes are paired in one process, on one factor).
Rounds interleave the cases (round 1: every case, round 2: every case, ...), the report takes medians over the
rounds. Timing cases: the armadillo (26k vertices) and its Loop level 1 (104k) whole-mesh edits, lap / tf / lri,
soft constraints. Exactness cases: every BS08 edit (data/bs08/), lap / tf / lri, hard and soft, once.
Writes RESULTS/handle_frames.csv (long: case, measure, value, unit, with provenance) and RESULTS/handle_frames.md.
--quick: the 26k tier and one BS08 edit, one round (a smoke run). --report-only: rewrite the .md from the .csv.
--note TEXT: a paragraph for the .md (e.g. the machine's load during the run).
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
    a = ap.parse_args()
    path = os.path.join(a.results, "handle_frames.csv")
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

    def record(case, tier, method, constraints, rnd, spec):
        m = run_cell(a.build, spec)
        print(f"[handle_frames] {case} {method} {constraints} round {rnd}: full {m['frame_s'][0] * 1e3:.3f} ms, "
              f"handle {m['frame_handle_s'][0] * 1e3:.3f} ms, precompute {m['precompute_s'][0]:.3f} s, "
              f"diff {m['handle_vs_full'][0]:.2e}", file=sys.stderr, flush=True)
        for k, (v, unit) in m.items():
            rows.append({"case": case, "tier": tier, "method": method, "constraints": constraints, "round": rnd,
                         "frames": spec[-2].split("=")[1], "measure": k, "value": repr(v), "unit": unit,
                         "command": "build/exp_table_2_1 --cell " + " ".join(spec), **prov})

    for rnd in range(1, rounds + 1):
        for tier, edit in timed:
            for method in METHODS:
                record(tier, tier, method, "soft", rnd,
                       ["kind=deform", f"edit={edit}", f"model={tier}", f"method={method}", "constraints=soft",
                        f"frames={a.frames}", "handle_frames=1"])
    for stem in bs08:
        for method in METHODS:
            for constraints in ("hard", "soft"):
                record("bs08_" + stem, "bs08", method, constraints, 1,
                       ["kind=deform", f"edit=data/bs08/{stem}", f"model=bs08_{stem}", f"method={method}",
                        f"constraints={constraints}", "frames=5", "handle_frames=1"])
    os.makedirs(a.results, exist_ok=True)
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    os.replace(path + ".tmp", path)
    report(rows, os.path.join(a.results, "handle_frames.md"), prov, a.note)


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
           "| case | method | full frame ms | handle frame ms | ratio | responses MB | read GB/s | pass ms | "
           "init s | precompute s | handle vs full | rounds |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    lri = ["\nLRI's handle frame in parts (medians, ms): the frame system from its responses; the orthonormalization; "
           "the position right-hand side (the rest of rhs); the position solve.\n",
           "| case | responses | orthonormalize | position rhs | position solve |", "|---|---|---|---|---|"]
    keys = sorted({(r["case"], r["method"], r["constraints"]) for r in rows},
                  key=lambda k: (not k[0].startswith("armadillo"), k[0], METHODS.index(k[1]), k[2]))
    for case, method, cons in keys:
        g = lambda m: med(case, method, cons, m)[0]  # noqa: E731
        n = med(case, method, cons, "frame_s")[1]
        out.append(f"| {case} ({cons}) | {method} | {g('frame_s') * 1e3:.3f} | {g('frame_handle_s') * 1e3:.3f} | "
                   f"{g('frame_s') / g('frame_handle_s'):.0f}x | {g('response_bytes') / 1e6:.1f} | "
                   f"{g('memory_read'):.1f} | {g('response_pass_s') * 1e3:.3f} | {g('init_s'):.2f} | "
                   f"{g('precompute_s'):.3f} | {max(float(r['value']) for r in rows if (r['case'], r['method'], r['constraints'], r['measure']) == (case, method, cons, 'handle_vs_full')):.1e} | {n} |")
        if method == "lri":
            lri.append(f"| {case} ({cons}) | {g('response_s') * 1e3:.3f} | {g('orthonormalize_s') * 1e3:.3f} | "
                       f"{(g('handle_rhs_s') - g('orthonormalize_s')) * 1e3:.3f} | {g('handle_solve_s') * 1e3:.3f} |")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(out + lri) + "\n")
    os.replace(path + ".tmp", path)


if __name__ == "__main__":
    main()
