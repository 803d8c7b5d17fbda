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
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # benchmarks/ and tools/ are folders of the repository, not of the package
    sys.path.insert(0, str(ROOT))

__all__ = ["sim_hour", "oracle_mutants", "fuzz_documents", "shelf_survey", "shelf_survey_table", "track_200km",
           "demo_report", "test_count", "terrain_follow", "lofoten_robust",
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
    """How many hostile documents tests/property/test_fuzz_scenarios.py makes per run (its
    ``AUVPLAN_FUZZ_EXAMPLES`` default)."""
    text = (ROOT / "tests" / "property" / "test_fuzz_scenarios.py").read_text()
    m = re.search(r'AUVPLAN_FUZZ_EXAMPLES", "(\d+)"', text)
    if m is None:
        raise SystemExit("tests/property/test_fuzz_scenarios.py: no AUVPLAN_FUZZ_EXAMPLES default")
    return {"fuzz-documents": f"{_thousands(int(m.group(1)))} hostile documents"}


def shelf_survey() -> dict[str, str]:
    """``auvplan survey shelf-survey``: lines against a fixed lawnmower, coverage planned and flown; then the
    same survey without ``heading_deg`` (auvplan chooses the line direction)."""
    with tempfile.TemporaryDirectory() as tmp:
        r = subprocess.run([str(AUVPLAN), "survey", "shelf-survey", "--out", str(Path(tmp) / "s"), "--json"],
                           capture_output=True, text=True, check=True)
        d = json.loads(r.stdout)
        toml = (ROOT / "src" / "auvplan" / "data" / "scenarios" / "shelf-survey.toml").read_text()
        free = Path(tmp) / "shelf-survey-free-heading.toml"  # the same survey with the line direction left free
        free.write_text(re.sub(r"^heading_deg\s*=.*$", "", toml, flags=re.M))
        r = subprocess.run([str(AUVPLAN), "survey", str(free), "--out", str(Path(tmp) / "f"), "--json"],
                           capture_output=True, text=True, check=True)
        f = json.loads(r.stdout)
    lm = d["lawnmower"]
    return {"shelf-survey": f"{d['lines']} lines instead of the {lm['lines']} of a fixed lawnmower sized for the "
                            f"shallowest depth ({lm['line_length_saved_m'] / 1000:.1f} km of line saved), planned "
                            f"coverage {d['planned']['coverage_pct']:.1f} %, flown {d['flown']['coverage_pct']:.2f} % "
                            f"(`auvplan survey shelf-survey`, {d['status']}; {_load()})",
            "shelf-survey-table": shelf_survey_table(d) + f"\n\nFrom `auvplan survey shelf-survey --json` "
                                  f"(`coverage.json`; {d['status']}, deterministic; {_load()}).",
            "shelf-survey-free-heading": f"heading {f['heading_deg']:.0f}°, {f['lines']} lines, "
                                         f"{f['survey_length_m'] / 1000:.1f} km of survey "
                                         f"({(d['survey_length_m'] - f['survey_length_m']) / 1000:.1f} km shorter than "
                                         f"along the isobaths), flown {f['flown']['coverage_pct']:.3f} %; the fixed "
                                         f"lawnmower would need {f['lawnmower']['lines']} ({f['status']})"}


def _pairs(pairs: list[dict[str, float]]) -> tuple[float, float, float, float]:
    """Least minimum, range of the medians and largest maximum of the adjacent pairs' overlaps (%)."""
    med = [p["median_pct"] for p in pairs]
    return (min(p["min_pct"] for p in pairs), min(med), max(med), max(p["max_pct"] for p in pairs))


def shelf_survey_table(d: dict[str, Any]) -> str:
    """docs/survey.md's table: the depth-adaptive survey against the fixed lawnmower, planned and flown."""
    lm, pl, fl, tu = d["lawnmower"], d["planned"], d["flown"], d["turns"]
    own = lm["line_length_m"] - lm["line_length_saved_m"]
    p_lo, _, _, p_hi = _pairs(pl["pairs"])
    f_lo, m_lo, m_hi, f_hi = _pairs(fl["pairs"])
    kinds = f"{tu['count'] - tu['omega']} U-turns" + (f", {tu['omega']} omega turns" if tu["omega"] else "")
    return "\n".join([
        f"| | depth-adaptive (auvplan) | fixed lawnmower for the shallowest {lm['shallowest_m']:.0f} m |",
        "| --- | --- | --- |",
        f"| lines | **{d['lines']}** | {lm['lines']} (spacing {lm['spacing_m']:.0f} m) |",
        f"| line length | {own / 1000:.1f} km | {lm['line_length_m'] / 1000:.1f} km "
        f"(**{lm['line_length_saved_m'] / 1000:.1f} km saved**, "
        f"{100 * lm['line_length_saved_m'] / lm['line_length_m']:.0f} %) |",
        f"| planned coverage | {pl['coverage_pct']:.2f} % (every adjacent overlap {p_lo:.1f}–{p_hi:.1f} %) | |",
        f"| flown coverage (closed loop, current) | **{fl['coverage_pct']:.2f} %** ({fl['gaps']} "
        f"gap{'' if fl['gaps'] == 1 else 's'}, {_thousands(round(fl['gap_area_m2']))} m² in all) | |",
        f"| flown overlap per pair | min {f_lo:.1f} %, median {m_lo:.0f}–{m_hi:.0f} %, max {f_hi:.0f} % | |",
        f"| survey (lines + turns) | {d['survey_length_m'] / 1000:.1f} km, {d['survey_time_s'] / 3600:.1f} h; whole "
        f"mission with the transits {d['mission_length_m'] / 1000:.1f} km, {d['mission_time_s'] / 3600:.1f} h | |",
        f"| turns | {kinds}, least radius {tu['least_radius_m']:.1f} m (vehicle's {tu['radius_m']:.0f} m) | |"])


def _size(n: int) -> str:
    return f"{n / 1e6:.2f} MB" if n >= 100_000 else f"{max(1, round(n / 1e3))} kB"


def track_200km() -> dict[str, str]:
    """Export sizes of a 200 km synthetic track (the one tests/integration/test_mission.py holds under 2 MB)."""
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


def terrain_follow() -> dict[str, str]:
    """``auvplan run marcus-terrain-follow``, then ``mission check --pitch 12`` of its exports (docs/missions.md)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "tf"
        subprocess.run([str(AUVPLAN), "-q", "run", "marcus-terrain-follow", "--out", str(out)], capture_output=True,
                       check=True)
        files = sorted(str(p) for p in out.glob("mission.*"))
        r = subprocess.run([str(AUVPLAN), "mission", "check", *files, "--scenario", "marcus-terrain-follow",
                            "--pitch", "12", "--json"], capture_output=True, text=True, check=False)
        checks = json.loads(r.stdout)
        sim = json.loads((out / "sim_metrics.json").read_text())
    v = checks[0]["vehicle"]
    lines = [c for c in checks if c["semantics"] != "held"]
    held = [c for c in checks if c["semantics"] == "held"]
    ok = all(c["check_ok"] for c in checks)  # the re-flown check (altitude); "ok" is every check
    vehicle_ok = all(c["vehicle"]["ok"] for c in checks)
    violations = sum(len(c["vehicle"]["violations"]) for c in checks)
    alt = (f"least {min(c['min_altitude_m'] for c in lines):.2f} m on the 3D-line formats"
           + (f", {min(c['min_altitude_m'] for c in held):.2f} m over MOOS envelopes and "
              f"{min(c['executor_min_altitude_m'] for c in held):.2f} m flown held at 12°" if held else ""))
    return {"terrain-follow": "\n".join([
        "| figure | value |", "| --- | --- |",
        f"| mission | {_thousands(checks[0]['legs'] + 1)} waypoints; largest pitch {v['max_pitch_deg']:.1f}° (limit "
        f"{v['limits']['max_pitch_deg']:g}°); tightest turn {_thousands(round(v['tightest_turn_m']))} m (limit "
        f"{v['limits']['turn_radius_m']:g} m); {violations or 'no'} violation{'' if violations == 1 else 's'} |",
        f"| `mission check`, all {len(checks)} exports | altitude {'OK' if ok else 'FAILED'}: {alt}; vehicle "
        f"{'OK' if vehicle_ok else 'FAILED'} |",
        f"| closed-loop flight ({sim['guidance']} guidance, {sim['avoidance']} avoidance) | {sim['status']}; least "
        f"altitude {sim['min_altitude_m']:.1f} m; cross-track RMS {sim['cross_track_rms_m']:.2f} m, max "
        f"{sim['cross_track_max_m']:.2f} m |",
        "", f"Measured by `tools/docs_figures.py measure terrain-follow` (`auvplan run marcus-terrain-follow`, seed "
            f"{sim['seed']}, then `mission check --pitch 12`; {_load()})."])}


def lofoten_robust() -> dict[str, str]:
    """The robust plan against the nominal one in both models of ``lofoten-two-models`` (``auvplan plan
    lofoten-two-models --json``'s choice; the member times of both plans from
    :func:`auvplan.sim.ensemble.robust.plan_robust`)."""
    from auvplan.io.scenario import loader as scenario
    from auvplan.io.scenario.inputs.members import scenario_members
    from auvplan.sim.ensemble.robust import plan_robust

    sc = scenario.load("lofoten-two-models")
    world, mission = scenario.build(sc)
    r = plan_robust(world, mission, scenario_members(sc, world), "p90", seed=sc.seed)
    nom, rob = r.nominal.score, r.chosen.score
    if nom is None or rob is None:
        raise SystemExit("lofoten-two-models: a plan failed")
    (fc, lo), (truth, hi) = [(m.name, m.arrival_s) for m in nom.members]
    a, b = (m.arrival_s for m in rob.members)
    ok = "both succeed in both members" if rob.success_probability == 1.0 and nom.success_probability == 1.0 \
        else f"success {rob.success_probability:.0%} robust, {nom.success_probability:.0%} nominal"
    return {"lofoten-robust": f"the nominal plan: {lo / 3600:.1f} h in `{fc}`, {hi / 3600:.1f} h in `{truth}`, P90 "
                              f"{nom.arrival_p90_s / 3600:.1f} h; the robust plan (the `{r.chosen.label}` "
                              f"candidate): {a / 3600:.1f} h and {b / 3600:.1f} h, **P90 "
                              f"{rob.arrival_p90_s / 3600:.1f} h**, "
                              f"{(nom.arrival_p90_s - rob.arrival_p90_s) / 3600:.1f} h below the nominal plan's, "
                              f"and {(hi - b) / 3600:.1f} h faster in `{truth}` (the truth); {ok} (`auvplan plan "
                              f"lofoten-two-models --json`, seed {sc.seed})"}


FAST: dict[str, Callable[[], dict[str, str]]] = {
    "lofoten-robust": lofoten_robust,
    "terrain-follow": terrain_follow,
    "sim-hour": sim_hour,
    "oracle-mutants": oracle_mutants,
    "fuzz-documents": fuzz_documents,
    "shelf-survey": shelf_survey,
    "track-200km": track_200km,
    "demo-report": demo_report,
    "test-count": test_count,
}
"""Quick measurements by name, run by ``make docs`` after the demo and the mission table."""
