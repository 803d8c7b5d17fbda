"""``auvplan serve``: the edit → checked round trip for 100- and 1 000-waypoint missions (issue 41).

Over HTTP (uvicorn on 127.0.0.1 in a thread): POST /api/edit moving one waypoint, as the page does
(with the revision it holds: the server re-checks only the changed legs, ``mission check``'s figures,
and answers with the splice from that revision; the page applies it only on that revision and sends one
request at a time); with ``--browser`` also in headless Chromium, from the mouse release to
the chart and the check panel redrawn.  Prints the median and the 90th percentile of each, and with
``--figure`` writes them, with the load, to ``docs/figures/serve-redraw.md`` (quoted in docs/serve.md).

The mission is an n-waypoint zigzag over the showcase seamount: every turn is tighter than the
vehicle's turn radius, so the check lists n - 1 violations, the page's worst case.

    python benchmarks/serve.py [--browser] [--repeats 20] [--figure]
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from auvplan.cli.serve import make_session  # noqa: E402
from auvplan.serve.app import make_app  # noqa: E402
from serve_helpers import running  # noqa: E402


def _mission(session, n: int) -> None:
    """An n-waypoint zigzag over the showcase seamount at a safe depth."""
    m = session.mission
    w = np.linspace(m.start, m.goal, n)
    w[1:-1, 0] += np.where(np.arange(1, n - 1) % 2 == 0, 40.0, -40.0)
    w[1:-1, 2] = -2300.0
    session._apply(w, "bench", f"{n} waypoints")


def _http(url: str, session, n: int, repeats: int) -> list[float]:
    rng = np.random.default_rng(0)
    times = []
    with httpx.Client(base_url=url, timeout=60) as c:
        rev = c.get("/api/state").json()["rev"]
        for _ in range(repeats):
            k = int(rng.integers(1, n - 1))
            x, y = session.waypoints[k, :2] + rng.normal(0.0, 30.0, 2)
            t0 = time.perf_counter()
            r = c.post("/api/edit", json={"op": "move", "index": k, "x": float(x), "y": float(y), "rev": rev})
            st = r.json()
            times.append(time.perf_counter() - t0)
            assert r.status_code == 200 and "delta" in st, st
            rev = st["rev"]
    return times


def _browser(url: str, session, n: int, repeats: int) -> list[float]:
    from playwright.sync_api import sync_playwright

    times = []
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=shutil.which("chromium"), args=["--no-sandbox"])
        page = b.new_page(viewport={"width": 1400, "height": 900})
        page.goto(url + "/")
        page.wait_for_selector("body[data-ready='1']", timeout=60_000)
        for r in range(repeats):
            k = 1 + (r * 7) % (n - 2)
            src = session.waypoints[k, :2]
            a = page.evaluate("([x, y]) => window.auvplan.toPx(x, y)", [float(src[0]), float(src[1])])
            page.mouse.move(*a)
            page.mouse.down()
            page.mouse.move(a[0] + 3, a[1] + 3)
            before = page.evaluate("() => document.body.dataset.drawn")
            t0 = time.perf_counter()
            page.mouse.up()
            page.wait_for_function(f"() => document.body.dataset.drawn !== '{before}' && "
                                   "document.body.dataset.pending === '0'")
            times.append(time.perf_counter() - t0)
        b.close()
    return times


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--browser", action="store_true", help="also time the round trip in headless Chromium")
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--figure", action="store_true", help="write docs/figures/serve-redraw.md")
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    table = ["| waypoints | round trip | median | p90 |", "|---:|---|---:|---:|"]
    with tempfile.TemporaryDirectory() as root:
        session = make_session("showcase", [root])
        with running(make_app(session)) as url:
            for n in (100, 1000):
                _mission(session, n)
                rows = [("HTTP edit → checked state", _http(url, session, n, args.repeats))]
                if args.browser:
                    rows.append(("browser release → redrawn", _browser(url, session, n, args.repeats)))
                for what, t in rows:
                    ms = 1e3 * np.asarray(t)
                    print(f"{n:5d} waypoints  {what:28s} median {np.median(ms):7.1f} ms  "
                          f"p90 {np.percentile(ms, 90):7.1f} ms  (n={len(ms)})")
                    table.append(f"| {n:,} | {what} | {np.median(ms):.0f} ms | {np.percentile(ms, 90):.0f} ms |"
                                 .replace(",", " "))
    load = f"{load0:.1f}–{os.getloadavg()[0]:.1f}"
    print(f"load average {load} on {os.cpu_count()} cores")
    if args.figure:
        out = Path(__file__).resolve().parents[1] / "docs" / "figures" / "serve-redraw.md"
        out.write_text("\n".join(table) + f"\n\n`python benchmarks/serve.py --browser --repeats {args.repeats} "
                       f"--figure`: showcase, an n-waypoint zigzag (n − 1 turn violations), one waypoint moved "
                       f"per edit (seed 0); load average {load} on {os.cpu_count()} cores.\n", encoding="utf-8")
        print(f"wrote {out}")


if __name__ == "__main__":
    main()
