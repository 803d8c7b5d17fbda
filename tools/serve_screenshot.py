"""Screenshot of ``auvplan serve`` for the docs (docs/img/serve.png).

Usage: .venv/bin/python tools/serve_screenshot.py [--out docs/img/serve.png]

Serves the built-in showcase on 127.0.0.1 (a free port, in a thread), opens the page in Debian's
headless Chromium through Playwright (as the browser tests do), keeps the first mission as a
candidate, drags a waypoint onto the seamount's flank so that its legs break the altitude rule,
and saves the page.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
from playwright.sync_api import sync_playwright

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from auvplan.cli.serve import make_session  # noqa: E402
from auvplan.serve.app import make_app  # noqa: E402
from serve_helpers import running  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/img/serve.png")
    args = ap.parse_args()
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        raise SystemExit("chromium is not installed (tools/install-chromium.sh)")
    with tempfile.TemporaryDirectory() as root:
        session = make_session("showcase", [root])
        t = session.world.terrain
        i, j = np.unravel_index(np.argmax(t.z), t.z.shape)
        target = 0.5 * (np.array([t.x[j], t.y[i]]) + session.waypoints[2, :2])  # up the flank, into the seabed
        with running(make_app(session)) as url, sync_playwright() as p:
            b = p.chromium.launch(executable_path=browser, args=["--no-sandbox"])
            page = b.new_page(viewport={"width": 1500, "height": 900})
            page.goto(url + "/")
            page.wait_for_selector("body[data-ready='1']", timeout=60_000)
            page.click("#keep")
            page.wait_for_function("() => document.body.dataset.pending === '0'")
            src = session.waypoints[2, :2]
            a = page.evaluate("([x, y]) => window.auvplan.toPx(x, y)", [float(src[0]), float(src[1])])
            c = page.evaluate("([x, y]) => window.auvplan.toPx(x, y)", [float(target[0]), float(target[1])])
            page.mouse.move(*a)
            page.mouse.down()
            page.mouse.move(*c, steps=5)
            page.mouse.up()
            page.wait_for_selector("#violations li")
            page.wait_for_function("() => document.body.dataset.pending === '0'")
            page.click("#keep")
            page.wait_for_function("() => document.body.dataset.pending === '0'")
            page.wait_for_timeout(500)
            Path(args.out).parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=args.out)
            b.close()
    print(args.out)


if __name__ == "__main__":
    main()
