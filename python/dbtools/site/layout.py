"""The pages' common frame: head, navigation between the top-level pages, the style sheet."""
import html
import os
from dataclasses import dataclass, field

STATIC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "static")


@dataclass
class Page:
    """One HTML page of the site: RESULTS/site/NAME, its title, its body (HTML) and the scripts it loads (paths
    relative to the site); `nav`: listed in every page's navigation bar."""
    name: str
    title: str
    body: str
    scripts: list = field(default_factory=list)
    nav: bool = True
    summary: str = ""


def esc(text):
    return html.escape(str(text), quote=True)


def render(page, nav_pages):
    links = " ".join(f'<a href="{esc(p.name)}"' + (' class="here"' if p.name == page.name else "") +
                     f">{esc(p.title)}</a>" for p in nav_pages)
    scripts = "".join(f'<script src="{esc(s)}"></script>\n' for s in page.scripts)
    return (f'<!doctype html>\n<html lang="en"><head><meta charset="utf-8">\n<title>{esc(page.title)} - deformbench'
            f'</title>\n<link rel="stylesheet" href="style.css">\n</head><body>\n<nav>{links}</nav>\n<main>\n'
            f"{page.body}\n</main>\n{scripts}</body></html>\n")


def write_pages(site, pages):
    """Writes every page, each with the navigation bar of the nav pages."""
    nav_pages = [p for p in pages if p.nav]
    for p in pages:
        with open(os.path.join(site, p.name), "w") as f:
            f.write(render(p, nav_pages))
