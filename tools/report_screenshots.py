"""Screenshots of a mission report for the docs (docs/img/report-*.png; part of `make docs`).

Usage: .venv/bin/python tools/report_screenshots.py [SCENARIO] [--out docs/img]

Runs the scenario (the demo's by default) into a temporary folder, opens its report.html in
Debian's headless Chromium through Playwright (as the browser test does) and saves the 3D view,
the plan view and the profiles.
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
from pathlib import Path

from playwright.sync_api import sync_playwright

from auvplan.app.run import DEMO_SCENARIO
from auvplan.cli import main


def shoot(report: Path, out: Path) -> list[Path]:
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        raise SystemExit("chromium is not installed (tools/install-chromium.sh)")
    written = []
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=browser,
                              args=["--no-sandbox", "--use-gl=swiftshader", "--enable-unsafe-swiftshader"])
        page = b.new_page(viewport={"width": 1300, "height": 900})
        page.goto(report.as_uri())
        page.wait_for_selector("#view3d canvas", state="attached", timeout=60_000)
        page.wait_for_timeout(3000)
        for div in ("view3d", "planview", "profiles"):
            path = out / f"report-{div}.png"
            page.locator(f"#{div}").screenshot(path=str(path))
            written.append(path)
        b.close()
    return written


def run(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenario", nargs="?", default=DEMO_SCENARIO)
    ap.add_argument("--out", type=Path, default=Path("docs/img"))
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "run"
        main(["run", args.scenario, "--out", str(folder)])
        for path in shoot(folder / "report.html", args.out):
            print(path)


if __name__ == "__main__":
    run()
