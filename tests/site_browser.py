#!/usr/bin/python3
"""Opens every page of a generated site (dbtools.site) in headless Chromium through the DevTools protocol and fails on
what a reader would hit: a console error or an uncaught exception (Runtime.consoleAPICalled type error/assert,
Runtime.exceptionThrown, Log.entryAdded level error: a resource that failed to load), a broken link (every
relative href/src of every page must exist on disk), and, on viewer.html, a canvas that was not drawn (the
screenshot of the canvas must hold many colours and a good share of non-background pixels).

  site_browser.py SITE_DIR [--screenshot PNG] [--min-colours N] [--page-shots DIR]

Exit 0 all pages clean, 1 a check failed (each failure named on stdout), 2 Chromium could not be driven.
Needs Debian's chromium and python3-websocket; software WebGL (SwiftShader) in headless mode.
"""
import argparse
import base64
import glob
import html.parser
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

import websocket

CHROMIUM = ["chromium", "--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader", "--allow-file-access-from-files", "--window-size=1400,1100",
            "--remote-debugging-port=0", "about:blank"]
# Chromium's own performance notes about software GL (a screenshot reads the canvas back): not page errors.
BENIGN = re.compile(r"GL Driver Message \(OpenGL, Performance|GPU stall due to ReadPixels")


class Links(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.targets = []

    def handle_starttag(self, tag, attrs):
        for k, v in attrs:
            if k in ("href", "src") and v:
                self.targets.append(v)


def broken_links(site):
    """'page: target' for every relative href/src of every page that does not exist on disk."""
    out = []
    for page in sorted(glob.glob(os.path.join(site, "**", "*.html"), recursive=True)):
        p = Links()
        with open(page, encoding="utf-8") as f:
            p.feed(f.read())
        for t in p.targets:
            if re.match(r"^[a-z][a-z0-9+.-]*:", t, re.I) or t.startswith("#"):
                if not t.startswith("file:"):
                    continue
            path = t.split("#")[0].split("?")[0]
            if path and not os.path.exists(os.path.normpath(os.path.join(os.path.dirname(page), path))):
                out.append(f"{os.path.relpath(page, site)}: {t}")
    return out


class Browser:
    def __init__(self):
        self.profile = tempfile.mkdtemp(prefix="site_browser.")
        self.proc = subprocess.Popen(CHROMIUM + [f"--user-data-dir={self.profile}"], stdout=subprocess.DEVNULL,
                                     stderr=subprocess.PIPE, text=True)
        port = None
        deadline = time.time() + 60
        while time.time() < deadline and port is None:
            line = self.proc.stderr.readline()
            if not line and self.proc.poll() is not None:
                break
            m = re.search(r"DevTools listening on ws://[^:]+:(\d+)/", line)
            port = m.group(1) if m else None
        if port is None:
            raise RuntimeError("chromium did not start its DevTools endpoint")
        # stderr must keep draining, or chromium blocks on a full pipe
        self.drain = subprocess.Popen(["cat"], stdin=self.proc.stderr, stdout=subprocess.DEVNULL)
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10))
        page = next(t for t in targets if t["type"] == "page")
        self.ws = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=60, suppress_origin=True)
        self.next_id, self.events = 0, []
        for domain in ("Runtime", "Log", "Page"):
            self.call(f"{domain}.enable")

    def call(self, method, **params):
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == self.next_id:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self.events.append(msg)

    def wait_event(self, method, timeout):
        deadline = time.time() + timeout
        while time.time() < deadline:
            for e in self.events:
                if e.get("method") == method:
                    return True
            self.ws.settimeout(max(deadline - time.time(), 0.1))
            try:
                self.events.append(json.loads(self.ws.recv()))
            except websocket.WebSocketTimeoutException:
                break
        return False

    def evaluate(self, expr):
        return self.call("Runtime.evaluate", expression=expr, returnByValue=True).get("result", {}).get("value")

    def close(self):
        try:
            self.ws.close()
        finally:
            self.proc.terminate()
            self.proc.wait(timeout=20)
            self.drain.wait(timeout=20)
            shutil.rmtree(self.profile, ignore_errors=True)


def errors_of(events):
    out = []
    for e in events:
        m, p = e.get("method"), e.get("params", {})
        if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", []))
            out.append(f"console.{p['type']}: {text}")
        elif m == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            out.append(f"uncaught: {d.get('exception', {}).get('description') or d.get('text')}")
        elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            entry = p["entry"]
            out.append(f"log error: {entry.get('text')} {entry.get('url', '')}".strip())
    return [x for x in out if not BENIGN.search(x)]


def canvas_check(b, shot, min_colours):
    """Waits for the viewer's first drawn frame, screenshots the canvas; (failure or None, summary)."""
    deadline = time.time() + 60
    while time.time() < deadline and not (b.evaluate("window.DB_VIEWER_DRAWN || 0") or 0):
        time.sleep(0.25)
    if not b.evaluate("window.DB_VIEWER_DRAWN || 0"):
        return "viewer.html: the viewer drew no frame within 60 s", ""
    r = b.evaluate("(function(){var r=document.getElementById('canvas').getBoundingClientRect();"
                   "return [r.left+window.scrollX, r.top+window.scrollY, r.width, r.height];})()")
    if not r or r[2] < 50 or r[3] < 50:
        return f"viewer.html: the canvas is {r}", ""
    clip = {"x": r[0], "y": r[1], "width": r[2], "height": r[3], "scale": 1}
    png = base64.b64decode(b.call("Page.captureScreenshot", format="png", clip=clip,
                                  captureBeyondViewport=True)["data"])
    if shot:
        with open(shot, "wb") as f:
            f.write(png)
    import matplotlib.image
    import numpy as np
    img = (matplotlib.image.imread(io.BytesIO(png))[..., :3] * 255).round().astype(np.uint8)
    flat = img.reshape(-1, 3)
    colours = len(np.unique(flat, axis=0))
    drawn = float(np.mean(np.any(flat < 245, axis=1)))  # not the white background
    summary = f"canvas {int(r[2])}x{int(r[3])}: {colours} colours, {drawn:.1%} non-background"
    if colours < min_colours or drawn < 0.02:
        return f"viewer.html: blank canvas ({summary})", summary
    # Every choice of the colouring, then every case: what a reader clicks through (errors are collected after).
    n = b.evaluate("(function(){var r=document.getElementById('ref'), n=r.options.length;"
                   "for (var k=0;k<n;k++){r.value=r.options[k].value;r.dispatchEvent(new Event('change'));}"
                   "var c=document.getElementById('case');"
                   "for (var k=c.options.length-1;k>=0;k--){c.value=c.options[k].value;"
                   "c.dispatchEvent(new Event('change'));} return n + '/' + c.options.length;})()")
    time.sleep(2)
    return None, f"{summary}; colourings/cases clicked through: {n}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("site")
    ap.add_argument("--screenshot", help="write the viewer's canvas here (PNG)")
    ap.add_argument("--min-colours", type=int, default=50)
    ap.add_argument("--page-shots", help="write a screenshot of every page's first screen into this folder")
    a = ap.parse_args()
    site = os.path.abspath(a.site)
    pages = sorted(glob.glob(os.path.join(site, "*.html")))
    failures = [f"broken link: {x}" for x in broken_links(site)]
    try:
        b = Browser()
    except (RuntimeError, OSError, websocket.WebSocketException) as e:
        print(f"site_browser: error: {e}")
        return 2
    try:
        for page in pages:
            b.events = []
            b.call("Page.navigate", url="file://" + page)
            if not b.wait_event("Page.loadEventFired", 60):
                failures.append(f"{os.path.basename(page)}: no load event within 60 s")
                continue
            note = ""
            if os.path.basename(page) == "viewer.html" and b.evaluate("!!document.getElementById('canvas')"):
                fail, note = canvas_check(b, a.screenshot, a.min_colours)
                failures += [fail] if fail else []
            time.sleep(0.3)
            if a.page_shots:
                shot = b.call("Page.captureScreenshot", format="png")["data"]
                with open(os.path.join(a.page_shots, os.path.basename(page) + ".png"), "wb") as f:
                    f.write(base64.b64decode(shot))
            b.call("Runtime.evaluate", expression="0")  # collects the events that arrived meanwhile
            errs = errors_of(b.events)
            failures += [f"{os.path.basename(page)}: {e}" for e in errs]
            print(f"{'FAIL' if errs else 'ok  '} {os.path.basename(page)}" + (f" ({note})" if note else ""))
    finally:
        b.close()
    for f in failures:
        print(f"FAIL {f}")
    print(f"{len(pages)} page(s), {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
