"""A page per Markdown report of the report step (RESULTS/NAME.md), followed by its figures, and the index."""
import fnmatch
import os
import re

import markdown

from .layout import Page, esc

# report -> (page title, what it shows, its figures: globs under RESULTS/figures/, in order). A report that is not
# there has no page.
REPORTS = {
    "table_2_1": ("Table 2-1 vs the thesis", "the thesis' Table 2-1 (dense, naive and structured builds of LAP and "
                  "TF) reproduced beside the thesis' values, and the scaling of the structured build",
                  ["table_2_1_*.png", "scaling*.png"]),
    "solvers": ("Solver verdict", "every backend and ordering on the LAP and TF systems, the BLAS kernel sets, "
                "and the verdict", ["solvers_*.png"]),
    "frames": ("Frames study", "LRI's frame strategies against LAP and TF on bends, twists and edits",
               ["frames_*.png"]),
    "figures": ("Frames renders", "the thesis' figures: rest against every method's result, per case",
                ["render_*.png"]),
    "applications": ("Applications", "coating transfer and transplanting", ["render_app_*.png"]),
    "handle_frames": ("Handle frames", "frame times of the handle mode", []),
    "handle_drags": ("Handle drags", "drags in the handle mode", []),
}
# A study that writes its own folder (RESULTS/FOLDER/: its table and figures, not the report step's): folder ->
# (page title, what it shows, its table's file, its figures' globs in the folder). `./run threads` writes
# results/threads/ and then the site again.
FOLDERS = {
    "threads": ("Thread scaling", "the deformation's init, analysis and frames at each thread count on this "
                "machine (./run threads)", "table.md", ["threads.png"]),
}
# figures.md shows the frames study's renders; the applications' renders are the applications page's.
EXCLUDE = {"figures": ["render_app_*.png"]}
CITED = re.compile(r"`figures/([A-Za-z0-9_.\-]+\.png)`")
LINK = re.compile(r'(href|src)="([^"#:]+)(#[^"]*)?"')


def figure_names(results, name, globs, folder="figures"):
    try:
        files = sorted(os.listdir(os.path.join(results, folder)))
    except OSError:
        return []
    out = []
    for g in globs:
        out += [f for f in files if fnmatch.fnmatch(f, g) and f not in out and
                not any(fnmatch.fnmatch(f, x) for x in EXCLUDE.get(name, []))]
    return out


def relink(results, html_text):
    """Links of a report are relative to RESULTS: to another report's page when it has one, else ../PATH when the
    target exists, else plain text (a page never links to nothing)."""
    def sub(m):
        attr, target, frag = m.group(1), m.group(2), m.group(3) or ""
        stem, ext = os.path.splitext(os.path.basename(target))
        if ext == ".md" and os.path.dirname(target) == "" and stem in REPORTS and \
                os.path.exists(os.path.join(results, target)):
            return f'{attr}="{stem}.html{frag}"'
        if os.path.exists(os.path.join(results, target)):
            return f'{attr}="../{target}{frag}"'
        return f'data-missing-{attr}="{target}"'
    return LINK.sub(sub, html_text)


def cite_figures(results, text):
    """`figures/NAME.png` in a report's text: a link to the figure when it exists."""
    def sub(m):
        name = m.group(1)
        return f"[`figures/{name}`](figures/{name})" if os.path.exists(os.path.join(results, "figures", name)) \
            else m.group(0)
    return CITED.sub(sub, text)


def gallery(names, folder="figures"):
    if not names:
        return ""
    items = "".join(f'<figure><a href="../{folder}/{esc(n)}"><img src="../{folder}/{esc(n)}" alt="{esc(n)}" '
                    f'loading="lazy"></a><figcaption>{esc(n)}</figcaption></figure>\n' for n in names)
    return f'<h2 id="figures">Figures</h2>\n<div class="gallery">\n{items}</div>'


def pages(results):
    out = []
    for name, (title, what, globs) in REPORTS.items():
        path = os.path.join(results, f"{name}.md")
        if not os.path.exists(path):
            continue
        with open(path, encoding="utf-8") as f:
            text = f.read()
        body = markdown.markdown(cite_figures(results, text), extensions=["tables", "fenced_code"])
        body = relink(results, body) + gallery(figure_names(results, name, globs))
        out.append(Page(f"{name}.html", title, body, summary=what))
    for folder, (title, what, table, globs) in FOLDERS.items():
        path = os.path.join(results, folder, table)
        if not os.path.exists(path):
            continue
        with open(path, encoding="utf-8") as f:
            body = markdown.markdown(f"# {title}\n\n{f.read()}", extensions=["tables", "fenced_code"])
        figures = figure_names(results, folder, globs, folder)
        out.append(Page(f"{folder}.html", title, body + gallery(figures, folder), summary=what))
    return out


def index_body(results, pages):
    missing = [f"{n}.md" for n in REPORTS if not os.path.exists(os.path.join(results, f"{n}.md"))]
    items = "".join(f'<li><a href="{esc(p.name)}">{esc(p.title)}</a>' +
                    (f": {esc(p.summary)}" if p.summary else "") + "</li>\n"
                    for p in pages if p.nav)
    out = ["<h1>deformbench results</h1>",
           f"<p>Generated from <code>{esc(os.path.abspath(results))}</code> by the report step "
           "(<code>./run reproduce</code>; the history pages also by <code>./run track</code>). The reports "
           "never measure: each page shows a report of the drivers' CSVs and its figures.</p>",
           f"<ul class=\"index\">\n{items}</ul>"]
    if missing:
        out.append(f"<p>No page for the reports not under the results directory (their drivers did not run): "
                   f"{esc(', '.join(missing))}</p>")
    return "\n".join(out)
