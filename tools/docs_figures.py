"""The documented figures: measured into docs/figures/, copied into the docs, checked (issue 40).

A figure is a file ``docs/figures/NAME.md`` written by a measurement (this tool's ``measure``, or a
benchmark's summary turned into text by ``from-bench``).  The docs quote it between markers::

    <!-- figure: NAME -->...<!-- /figure -->

(inline within a sentence, or around a table on lines of their own).  ``sync`` copies every figure file
into its blocks; ``--check`` (and ``tests/golden/test_doc_figures.py``) fails when a block differs from its
file, names a file that does not exist, or a figure file is quoted nowhere: a number in the docs cannot
drift from the measurement it came from.  ``make docs`` measures, takes the screenshots, regenerates the
scenario reference and the architecture picture, and syncs.

Usage::

    .venv/bin/python tools/docs_figures.py measure                 # demo, mission table, quick figures (~4 min)
    .venv/bin/python tools/docs_figures.py measure sim-hour        # one quick figure (tools/figures_fast.py)
    .venv/bin/python tools/docs_figures.py from-bench results/docs/gauntlet --name gauntlet-predictive
    .venv/bin/python tools/docs_figures.py bench doc001-tracking   # one heavy figure (tools/figures_bench.py)
    .venv/bin/python tools/docs_figures.py sync                    # copy the figures into the docs
    .venv/bin/python tools/docs_figures.py check                   # exit 1 on a stale or orphan figure
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

__all__ = ["ROOT", "FIGURES", "BLOCK", "doc_files", "blocks", "problems", "sync", "main"]

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ROOT / "docs" / "figures"
BLOCK = re.compile(r"<!-- figure: ([\w.-]+) -->(.*?)<!-- /figure -->", re.S)
"""A quoted figure: its name and the text between the markers."""

AUVPLAN = Path(sys.executable).parent / "auvplan"
MISSION_RUNS = (("showcase", "`demo` (`showcase`, "), ("dynamic-terrain", "`run dynamic-terrain` ("),
                ("salish-shelf", "`run salish-shelf` ("), ("marcus-wake", "`run marcus-wake` ("))
LINE_FORMATS = ("csv", "geojson", "gpx", "kml", "plan", "yaml")


def doc_files(root: Path = ROOT) -> list[Path]:
    """The Markdown files that may quote figures: README.md and docs/*.md (not the figures themselves)."""
    return [root / "README.md", *sorted((root / "docs").glob("*.md"))]


def blocks(text: str) -> list[tuple[str, str]]:
    """``(name, quoted text)`` of every figure block of a document."""
    return [(m.group(1), m.group(2)) for m in BLOCK.finditer(text)]


def _same(quoted: str, figure: str) -> bool:
    return quoted.strip() == figure.strip()


def problems(root: Path = ROOT) -> list[str]:
    """Every stale block, missing figure file and figure file quoted nowhere (empty when all is current)."""
    figures = root / "docs" / "figures"
    out, used = [], set()
    for doc in doc_files(root):
        if not doc.exists():
            continue
        for name, quoted in blocks(doc.read_text()):
            used.add(name)
            src = figures / f"{name}.md"
            if not src.exists():
                out.append(f"{doc.relative_to(root)}: figure {name!r} has no file {src.relative_to(root)}")
            elif not _same(quoted, src.read_text()):
                out.append(f"{doc.relative_to(root)}: figure {name!r} differs from {src.relative_to(root)}")
    for src in sorted(figures.glob("*.md")):
        if src.stem not in used:
            out.append(f"{src.relative_to(root)} is quoted nowhere")
    return out


def sync(root: Path = ROOT) -> list[Path]:
    """Copy each figure file into its blocks; returns the documents changed."""
    figures = root / "docs" / "figures"
    changed = []
    for doc in doc_files(root):
        if not doc.exists():
            continue
        text = doc.read_text()

        def fill(m: re.Match[str]) -> str:
            src = figures / f"{m.group(1)}.md"
            if not src.exists():
                return m.group(0)
            body = src.read_text().strip()
            quoted = f"\n{body}\n" if "\n" in m.group(2) or "\n" in body else body
            return f"<!-- figure: {m.group(1)} -->{quoted}<!-- /figure -->"

        new = BLOCK.sub(fill, text)
        if new != text:
            doc.write_text(new)
            changed.append(doc)
    return changed


def _write(name: str, text: str) -> None:
    FIGURES.mkdir(parents=True, exist_ok=True)
    (FIGURES / f"{name}.md").write_text(text.strip() + "\n")
    print(f"docs/figures/{name}.md: {text.strip()[:100]}")


def _size(path: Path) -> str:
    n = path.stat().st_size
    return f"{n / 1e6:.2f} MB" if n >= 100_000 else f"{max(1, round(n / 1e3))} kB"


def _check(folder: Path, scenario: str, names: list[str]) -> list[dict[str, object]]:
    r = subprocess.run([str(AUVPLAN), "mission", "check", *(str(folder / n) for n in names), "--scenario", scenario,
                        "--json"], capture_output=True, text=True, check=False)
    if r.returncode != 0:
        raise SystemExit(f"mission check on {folder}: exit {r.returncode}\n{r.stdout}{r.stderr}")
    data = json.loads(r.stdout)
    return data if isinstance(data, list) else data.get("files", [data])


def _run(scenario: str, out: Path) -> tuple[float, float, float]:
    """Run a scenario into ``out``: wall s, CPU s, peak RSS MiB of the child."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.perf_counter()
    cmd = [str(AUVPLAN), "demo", "--out", str(out)] if scenario == "showcase" else \
        [str(AUVPLAN), "run", scenario, "--out", str(out)]
    subprocess.run(cmd, check=True, capture_output=True)
    wall = time.perf_counter() - wall
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    return wall, cpu, after.ru_maxrss / 1024


def _waypoints(folder: Path) -> int:
    with (folder / "mission.csv").open() as f:
        return sum(1 for _ in csv.DictReader(f))


def measure() -> None:
    """Run the demo and the mission table's scenarios and write their figures."""
    load = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scenario, label in MISSION_RUNS:
            folder = Path(tmp) / scenario
            wall, cpu, rss = _run(scenario, folder)
            sim = json.loads((folder / "sim_metrics.json").read_text())
            scen = folder / "scenario.toml"
            min_alt = re.search(r"^min_altitude_m\s*=\s*([\d.]+)", scen.read_text(), re.M)
            moos = _check(folder, str(scen), ["mission.moos"])[0]
            lines = _check(folder, str(scen), [f"mission.{f}" for f in LINE_FORMATS])
            line_alt = min(float(c["min_altitude_m"]) for c in lines)  # type: ignore[arg-type]
            small = sorted((folder / f"mission.{f}").stat().st_size for f in ("moos", "plan", "yaml", "csv"))
            rows.append(f"| {label}{sim['distance_m'] / 1000:.1f} km flown, `min_altitude_m` "
                        f"{float(min_alt.group(1)) if min_alt else 0:g}) | {_waypoints(folder)} waypoints | "
                        f"{moos['min_altitude_m']:.1f} / {moos['executor_min_altitude_m']:.1f} / {line_alt:.1f} m | "
                        f"{_size(folder / 'track.csv')} | {_size(folder / 'mission.geojson')} | "
                        f"{_size(folder / 'mission.kml')} | {_size(folder / 'mission.gpx')} | "
                        f"{max(1, round(small[0] / 1e3))}–{max(1, round(small[-1] / 1e3))} kB |")
            if scenario == "showcase":
                movers = len(sim.get("obstacle_min_distances_m", []))
                _write("demo-cost", f"{wall:.0f} s wall ({cpu:.1f} s CPU, {rss:.0f} MiB peak; load {load:.1f} on "
                                    f"{os.cpu_count()} cores)")
                _write("demo-flight", f"a {sim['duration_s']:.0f} s flight of {sim['distance_m'] / 1000:.1f} km among "
                                      f"{movers} moving obstacles, mission of {_waypoints(folder)} waypoints, least "
                                      f"altitude {sim['min_altitude_m']:.1f} m, least obstacle distance "
                                      f"{sim['min_obstacle_distance_m']:.1f} m")
    head = ["| run | mission | least altitude by `mission check`: MOOS envelope / MOOS at 15° / 3D-line formats "
            "| `track.csv` | GeoJSON | KML | GPX | MOOS, `.plan`, YAML, CSV |",
            "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    _write("missions", "\n".join(head + rows) + f"\n\nMeasured by `tools/docs_figures.py measure` (load {load:.1f} on "
           f"{os.cpu_count()} cores); `mission check` reports OK on every file.")


def from_bench(folder: Path, name: str) -> None:
    """A Monte Carlo sweep's outcome (``auvplan bench`` ``rows.csv``) as one sentence."""
    with (folder / "rows.csv").open() as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{folder / 'rows.csv'}: no rows")
    status = [r["status"] for r in rows]
    collisions = sum(int(float(r.get("collisions") or 0)) > 0 for r in rows)
    escapes = sum(int(float(r.get("escapes") or 0)) for r in rows)
    dist = min(float(r["min_obstacle_distance_m"]) for r in rows if r.get("min_obstacle_distance_m"))
    alt = min(float(r["min_clearance_m"]) for r in rows if r.get("min_clearance_m"))
    cpu = sorted(float(r["cpu_s"]) for r in rows if r.get("cpu_s"))
    others = {s: status.count(s) for s in sorted(set(status)) if s not in ("EXACT", "APPROXIMATE")}
    arrived = len(rows) - sum(others.values())
    _write(name, f"{arrived}/{len(rows)} arrivals ({100 * arrived / len(rows):.1f} %), {collisions} runs with a "
                 f"collision" + "".join(f", {n} {s}" for s, n in others.items())
           + f", {escapes} escapes in total, least obstacle distance {dist:.2f} m, least clearance {alt:.1f} m, "
             f"{cpu[len(cpu) // 2]:.2f} s CPU median per mission")


def _heavy() -> dict[str, Callable[..., dict[str, str]]]:
    sys.path.insert(0, str(Path(__file__).parent))
    import figures_bench

    return figures_bench.HEAVY


def _fast() -> dict[str, Callable[[], dict[str, str]]]:
    sys.path.insert(0, str(Path(__file__).parent))
    import figures_fast

    return figures_fast.FAST


def main(argv: list[str] | None = None) -> int:
    """Command line: ``measure``, ``bench NAME...``, ``from-bench DIR --name NAME``, ``sync``, ``check``.

    Parameters
    ----------
    argv : list of str, optional
        Arguments.

    Returns
    -------
    int
        0, or 1 when ``check`` finds a problem.
    """
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("measure", help="run the demo, the mission table's scenarios and the quick figures")
    m.add_argument("names", nargs="*", metavar="NAME",
                   help="only these quick measurements (tools/figures_fast.py FAST) or 'missions'")
    b = sub.add_parser("from-bench", help="a bench folder's rows.csv as a figure")
    b.add_argument("folder", type=Path)
    b.add_argument("--name", required=True)
    h = sub.add_parser("bench", help="measure heavy figures (tools/figures_bench.py), one at a time")
    h.add_argument("names", nargs="+", metavar="NAME", help="a measurement of figures_bench.HEAVY")
    h.add_argument("--seeds", type=int, help="seeds instead of the documented number (stated in the figure)")
    sub.add_parser("sync", help="copy the figure files into the docs")
    sub.add_parser("check", help="exit 1 when a quoted figure differs from its file")
    args = ap.parse_args(argv)
    if args.cmd == "measure":
        fast = _fast()
        unknown = [n for n in args.names if n not in fast and n != "missions"]
        if unknown:
            ap.error(f"unknown figure {unknown[0]!r}; known: missions, {', '.join(sorted(fast))}")
        if not args.names or "missions" in args.names:
            measure()
        for name in args.names or list(fast):
            for figure, text in fast[name]().items() if name in fast else ():
                _write(figure, text)
    elif args.cmd == "bench":
        heavy = _heavy()
        unknown = [n for n in args.names if n not in heavy]
        if unknown:
            ap.error(f"unknown figure {unknown[0]!r}; known: {', '.join(sorted(heavy))}")
        for name in args.names:
            for figure, text in heavy[name](*([args.seeds] if args.seeds else [])).items():
                _write(figure, text)
    elif args.cmd == "from-bench":
        from_bench(args.folder, args.name)
    elif args.cmd == "sync":
        for doc in sync():
            print(f"updated {doc.relative_to(ROOT)}")
    found = problems()
    for p in found:
        print(p, file=sys.stderr)
    return 1 if found and args.cmd in ("check", "sync") else 0


if __name__ == "__main__":
    sys.exit(main())
