"""The static report site, results/site/index.html: the reports and their figures as pages, the tracking history
over commits, and a 3D viewer of the deformed meshes, all opening from disk (file://, no server).

  python3 -m dbtools.site [--results results]       (PYTHONPATH=<repo>/python; Debian's python3)

Written last by the report step (dbtools.report) and again by `./run track`. Like the reports it never measures: it
reads what the drivers and the report step left under the results directory (the Markdown reports RESULTS/NAME.md,
RESULTS/figures/*.png, the thread-scaling folder RESULTS/threads/ of `./run threads`, the tracking histories
RESULTS/history/{runs,reference}/*.csv and the frames study's meshes RESULTS/meshes/frames/*.ply) and writes
RESULTS/site/ whole (replaced, never patched):
  index.html, NAME.html        a page per report (reports.py), its figures linked from ../figures/; threads.html
  history.html, history_M.html the history of each tracked measure over commits, machines apart (history.py)
  viewer.html, meshes/*.js     the deformed meshes, rest against LAP / TF / scale-free TF / LRI (meshes.py)
  three/                       three.js r111 and its OrbitControls, copied from Debian's libjs-three
file:// pages cannot fetch(): every datum is a .js file loaded by <script src>, meshes as base64 binary
(float32 positions, uint32 faces, uint8 vertex roles).
"""
import os
import shutil
import sys

from . import history, meshes, reports
from .layout import STATIC, Page, write_pages


def log(text):
    print(f"[site] {text}", file=sys.stderr)


def write(results):
    """Writes RESULTS/site/ from what is under RESULTS; the number of pages written."""
    site = os.path.join(results, "site")
    tmp = site + f".tmp.{os.getpid()}"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    for name in ("style.css", "viewer.js"):
        shutil.copy(os.path.join(STATIC, name), tmp)
    pages = reports.pages(results) + history.pages(results) + meshes.pages(results, tmp)
    pages.insert(0, Page("index.html", "deformbench results", reports.index_body(results, pages)))
    write_pages(tmp, pages)
    # Replaced whole, so a page of an earlier run never survives next to this run's.
    shutil.rmtree(site, ignore_errors=True)
    os.replace(tmp, site)
    log(f"{len(pages)} pages: {os.path.join(site, 'index.html')}")
    return len(pages)
