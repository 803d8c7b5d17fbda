"""The quick documented figures (``make docs``): seconds each, measured or counted afresh every time.

Each function returns ``{figure name: text}``; ``tools/docs_figures.py measure`` writes them to
docs/figures/ with the demo's and the mission table's.  One alone::

    .venv/bin/python tools/docs_figures.py measure sim-hour shelf-survey
"""

from __future__ import annotations

import ast
import json
import os
import re
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # benchmarks/ and tools/ are folders of the repository, not of the package
    sys.path.insert(0, str(ROOT))

__all__ = ["sim_hour", "oracle_mutants", "fuzz_documents", "shelf_survey", "track_200km", "demo_report", "test_count",
           "FAST"]

AUVPLAN = Path(sys.executable).parent / "auvplan"


def _load() -> str:
    return f"load {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"


def _thousands(n: int) -> str:
    return f"{n:,}".replace(",", " ")


def sim_hour() -> dict[str, str]:
    """The simulator's wall time on a 1-hour mission, best of three (benchmarks/tracking.py's ``hour_mission``)."""
    from benchmarks import tracking

    best, loop, steps = tracking.hour_mission()
    return {"sim-hour": f"{_thousands(steps)} steps: {best:.2f} s wall, best of 3 ({best / steps * 1e6:.1f} µs per "
                        f"step; a bare one-numpy-op loop of the same length {loop:.3f} s; {_load()})"}


def _assigned_dict_len(path: Path, name: str) -> int:
    """Entries of the literal dict assigned to ``name`` in a Python file (read, not imported)."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.AnnAssign | ast.Assign):
            targets = [node.target] if isinstance(node, ast.AnnAssign) else node.targets
            if any(isinstance(t, ast.Name) and t.id == name for t in targets) and isinstance(node.value, ast.Dict):
                return len(node.value.keys)
    raise SystemExit(f"{path}: no dict {name}")


def oracle_mutants() -> dict[str, str]:
    """How many hand-written mutants tools/oracle_mutants.py plants (its ``MUTANTS`` catalogue)."""
    n = _assigned_dict_len(ROOT / "tools" / "oracle_mutants.py", "MUTANTS")
    return {"oracle-mutants": f"{n} catalogued bugs"}


def fuzz_documents() -> dict[str, str]:
    """How many hostile documents tests/test_fuzz_scenarios.py makes per run (its ``AUVPLAN_FUZZ_EXAMPLES`` default)."""
    text = (ROOT / "tests" / "test_fuzz_scenarios.py").read_text()
    m = re.search(r'AUVPLAN_FUZZ_EXAMPLES", "(\d+)"', text)
    if m is None:
        raise SystemExit("tests/test_fuzz_scenarios.py: no AUVPLAN_FUZZ_EXAMPLES default")
    return {"fuzz-documents": f"{_thousands(int(m.group(1)))} hostile documents"}


def shelf_survey() -> dict[str, str]:
    """``auvplan survey shelf-survey``: lines against a fixed lawnmower, coverage planned and flown."""
    with tempfile.TemporaryDirectory() as tmp:
        r = subprocess.run([str(AUVPLAN), "survey", "shelf-survey", "--out", str(Path(tmp) / "s"), "--json"],
                           capture_output=True, text=True, check=True)
    d = json.loads(r.stdout)
    lm = d["lawnmower"]
    return {"shelf-survey": f"{d['lines']} lines instead of the {lm['lines']} of a fixed lawnmower sized for the "
                            f"shallowest depth ({lm['line_length_saved_m'] / 1000:.1f} km of line saved), planned "
                            f"coverage {d['planned']['coverage_pct']:.1f} %, flown {d['flown']['coverage_pct']:.2f} % "
                            f"(`auvplan survey shelf-survey`, {d['status']}; {_load()})"}


def _size(n: int) -> str:
    return f"{n / 1e6:.2f} MB" if n >= 100_000 else f"{max(1, round(n / 1e3))} kB"


def track_200km() -> dict[str, str]:
    """Export sizes of a 200 km synthetic track (the one tests/test_mission.py holds under 2 MB)."""
    import numpy as np

    from auvplan._types import Status
    from auvplan.io.missions import export
    from auvplan.io.results import records
    from auvplan.sim import RunRecord, SimResult

    n = int(200_000 // 0.15)  # 200 km at 1.5 m/s, one sample every 0.1 s
    t = np.arange(n) * 0.1
    s = t * 1.5
    pos = np.column_stack([s * 0.8, s * 0.6, -500.0 + 100.0 * np.sin(s / 5000.0)])
    sim = SimResult(Status.EXACT, True, t, pos, *(np.zeros(n),) * 6, np.full(n, 80.0), np.empty((n, 0)), (),
                    "hybrid", 0.0)
    w = pos[:: n // 40]
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        export.write_exports(out, RunRecord("long", 0, None, w, w[[0, -1]], sim), (48.0, -125.0), 1.5)
        records.write_sim(out, sim, "long", 0)
        size = {p.name: p.stat().st_size for p in out.iterdir()}
        with (out / "mission.csv").open() as f:
            waypoints = sum(1 for _ in f) - 1
    small = sorted(size[f"mission.{e}"] for e in ("moos", "plan", "yaml", "csv"))
    return {"track-200km": f"{n / 1e6:.2f} M samples: {waypoints} waypoints, `track.csv` {_size(size['track.csv'])}, "
                           f"GeoJSON {_size(size['mission.geojson'])}, KML {_size(size['mission.kml'])}, GPX "
                           f"{_size(size['mission.gpx'])}, MOOS, `.plan`, YAML and CSV "
                           f"{max(1, round(small[0] / 1e3))}–{max(1, round(small[-1] / 1e3))} kB"}


def demo_report() -> dict[str, str]:
    """The size of the demo's ``report.html`` (``auvplan demo``)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "demo"
        subprocess.run([str(AUVPLAN), "-q", "demo", "--out", str(out)], capture_output=True, check=True)
        return {"demo-report": f"{_size((out / 'report.html').stat().st_size)} for the showcase demo"}


def test_count() -> dict[str, str]:
    """How many tests ``make test``'s pytest run collects (``pytest --collect-only``)."""
    r = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider"], cwd=ROOT,
                       capture_output=True, text=True, check=False)
    per_file = [int(n) for n in re.findall(r"^tests/\S+\.py: (\d+)$", r.stdout, re.M)]  # -qq: a count per file
    if r.returncode != 0 or not per_file:
        raise SystemExit(f"pytest --collect-only: exit {r.returncode}\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    return {"test-count": f"{_thousands(sum(per_file))} tests in {len(per_file)} files"}


FAST: dict[str, Callable[[], dict[str, str]]] = {
    "sim-hour": sim_hour,
    "oracle-mutants": oracle_mutants,
    "fuzz-documents": fuzz_documents,
    "shelf-survey": shelf_survey,
    "track-200km": track_200km,
    "demo-report": demo_report,
    "test-count": test_count,
}
"""Quick measurements by name, run by ``make docs`` after the demo and the mission table."""
