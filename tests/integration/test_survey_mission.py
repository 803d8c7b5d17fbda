"""Survey missions (issue 37): flyable turns, the CLI contract (lines.csv, coverage.json), every export
re-checked by `mission check`, the coverage measured on the closed-loop flight, and bad input."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.files.manifest import written
from auvplan.survey.turns import dubins, sample_turn

SCENARIO = """
name = "plane-survey"
seed = 3
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 2000.0]
y = [0.0, 1500.0]
z = [-200.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 40.0
slope = [-0.03, 0.0]      # deepens eastwards: 40 m at x = 0, 100 m at x = 2000
cell_m = 20.0
[currents]
uniform = [0.15, 0.0, 0.0]
[mission]
start = [300.0, 250.0, -2.0]
goal = [300.0, 250.0, -2.0]
min_altitude_m = 5.0
min_depth_m = 2.0
max_depth_m = 200.0
[vehicle]
speed = 1.5
[planner]
name = "iabc"
population = 20
iterations = 20
control_points = 3
samples = 60
[sim]
dt = 0.5
arrival_radius = 10.0
[survey]
{area}
sensor = "multibeam"
opening_deg = 120.0
mounting = "{mounting}"
{extra}
overlap = [0.10, 0.20]
heading_deg = 0.0
"""

AREA = "polygon_xy = [[400.0, 400.0], [1400.0, 400.0], [1400.0, 1000.0], [400.0, 1000.0]]"


def _write(tmp_path, area=AREA, mounting="surface", extra=""):
    path = tmp_path / "survey.toml"
    path.write_text(SCENARIO.format(area=area, mounting=mounting, extra=extra))
    return path


@pytest.mark.parametrize("gap", [60.0, 20.0, 12.0, 5.0])
def test_turns_fit_the_radius(gap):
    r = 10.0
    turn = dubins((0.0, 0.0, math.pi / 2), (gap, 0.0, -math.pi / 2), r)
    pts = sample_turn(turn, 0.5)
    np.testing.assert_allclose(pts[-1], [gap, 0.0, -math.pi / 2], atol=1e-9)
    if gap >= 2 * r:  # a U-turn: two quarter... half circles and the straight between them
        assert turn.word in ("RSR", "LSL") and turn.length == pytest.approx(math.pi * r + gap - 2 * r)
    else:  # closer than 2R: an omega (keyhole) turn, a loop of three arcs, longer than the half circle
        assert turn.word in ("RLR", "LRL") and turn.length > math.pi * r
    a, b, c = pts[:-2, :2], pts[1:-1, :2], pts[2:, :2]
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    ok = cross > 1e-12
    radius = (np.linalg.norm(b - a, axis=1) * np.linalg.norm(c - b, axis=1) * np.linalg.norm(a - c, axis=1))[ok] \
        / (2 * cross[ok])
    assert radius.min() >= r * (1 - 1e-6)


def test_survey_cli_contract_and_every_export_passes_mission_check(tmp_path, capsys):
    scen = _write(tmp_path, extra="tie_lines = 2")
    out = tmp_path / "out"
    assert main(["-q", "survey", str(scen), "--out", str(out), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    cov = json.loads((out / "coverage.json").read_text())
    for key in ("coverage_pct", "overlap_min_pct", "overlap_max_pct"):
        assert math.isfinite(cov[key]) and cov[key] == rec[key]
    assert cov["measured_on"] == "flight" and cov["status"] == "EXACT"
    assert cov["planned"]["coverage_pct"] >= 99.5 and cov["coverage_pct"] >= 99.0
    assert 10.0 - 1e-6 <= cov["planned"]["overlap_min_pct"] <= cov["planned"]["overlap_max_pct"] <= 20.0 + 1e-6
    assert cov["turns"]["least_radius_m"] >= 10.0 * (1 - 1e-6)
    with (out / "lines.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["line", "kind", "x", "y", "z", "lat", "lon"]
    lines = sorted({int(r["line"]) for r in rows if r["kind"] == "main"})
    assert lines == list(range(cov["lines"]))
    ties = sorted({int(r["line"]) for r in rows if r["kind"] == "tie"})
    assert ties == [cov["lines"], cov["lines"] + 1]  # the tie lines, after the main lines
    report = (out / "report.html").read_text()
    assert "id='survey-lines'" in report and "data:image/png;base64," in report and report.count("<td>tie</td>") == 2
    assert all(abs(float(r["lat"]) - 48.0) < 0.05 and abs(float(r["lon"]) + 125.0) < 0.05 for r in rows)
    # the launch and recovery point is the same and the mission returns to it
    route = np.loadtxt(out / "route.csv", delimiter=",", skiprows=1, usecols=(0, 1, 2))
    np.testing.assert_allclose(route[0], route[-1], atol=1e-6)
    exports = sorted(out.glob("mission.*"))
    assert {p.suffix for p in exports} == {".geojson", ".kml", ".csv", ".moos", ".plan", ".gpx", ".yaml"}
    assert main(["mission", "check", *map(str, exports), "--scenario", str(scen), "--json"]) == 0
    checks = json.loads(capsys.readouterr().out)
    assert len(checks) == 7 and all(c["ok"] for c in checks)
    assert (out / "coverage.png").stat().st_size > 10_000
    # every file the survey wrote is in the folder's manifest, so the same command can write the folder again
    # (coverage.png was written around it: `survey --out D` twice refused its own coverage.png)
    assert {"coverage.png", "lines.csv", "coverage.json", "gaps.geojson", "report.html"} <= written(out)


def test_auv_mounting_holds_the_altitude(tmp_path, capsys):
    scen = _write(tmp_path, mounting="auv", extra="altitude_m = 25.0")
    out = tmp_path / "auv"
    assert main(["-q", "survey", str(scen), "--out", str(out), "--json"]) == 0
    cov = json.loads(capsys.readouterr().out)
    with (out / "lines.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    x, z = (np.array([float(r[k]) for r in rows]) for k in ("x", "z"))
    seabed = -(40.0 + 0.03 * x)
    np.testing.assert_allclose(z - seabed, 25.0, atol=1e-3)  # a plane: held exactly (csv rounds to 1 mm)
    assert cov["planned"]["coverage_pct"] >= 99.5 and cov["coverage_pct"] >= 99.0
    assert cov["max_pitch_deg"] <= 15.0


@pytest.mark.parametrize(("area", "needle"), [
    ("polygon_xy = [[400.0, 400.0], [1400.0, 400.0]]", "at least three corners"),
    ("polygon_xy = [[400.0, 400.0], [2400.0, 400.0], [2400.0, 1000.0]]", "not inside the [bounds]"),
    ("polygon = [[48.0, -125.0], [48.01, -125.0], [48.0, -124.99]]\npolygon_xy = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]",
     "exactly one of"),
    ('file = "missing.geojson"', "not found"),
])
def test_bad_survey_input_is_one_line_exit_2(tmp_path, capsys, area, needle):
    scen = _write(tmp_path, area=area)
    assert main(["survey", str(scen)]) == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1 and "[survey]" in err


KML = """<?xml version="1.0" encoding="UTF-8"?>
<kml xmlns="http://www.opengis.net/kml/2.2"><Document><Placemark><name>area</name><Polygon><outerBoundaryIs>
<LinearRing><coordinates>{coords}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark></Document></kml>
"""


@pytest.mark.parametrize("fmt", ["geojson", "kml"])
def test_area_from_a_vector_file(tmp_path, capsys, fmt):
    from auvplan.io.data.geo import LocalFrame

    lon, lat = LocalFrame(48.0, -125.0).inverse(np.array([400.0, 1400.0, 1400.0, 400.0, 400.0]),
                                                np.array([400.0, 400.0, 1000.0, 1000.0, 400.0]))
    ring = [[float(a), float(b)] for a, b in zip(lon, lat)]
    if fmt == "geojson":
        text = json.dumps({"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [ring]}}]})
    else:
        text = KML.format(coords=" ".join(f"{a:.9f},{b:.9f},0" for a, b in ring))
    (tmp_path / f"area.{fmt}").write_text(text)
    scen = _write(tmp_path, area=f'file = "area.{fmt}"')
    assert main(["-q", "survey", str(scen), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["area_m2"] == pytest.approx(600_000.0, rel=1e-3)


def test_a_line_through_an_obstacle_is_a_failed_status_naming_it(tmp_path, capsys):
    scen = _write(tmp_path)
    scen.write_text(scen.read_text() + "\n[[obstacles]]\ntype = \"sphere\"\ncenter = [850.0, 700.0, -2.0]\n"
                    "radius = 20.0\n")
    assert main(["-q", "survey", str(scen), "--json"]) == 1
    rec = json.loads(capsys.readouterr().out)
    assert rec["status"] == "INFEASIBLE" and "on line 2 " in rec["message"] and rec["flown"] is None


def test_run_of_a_survey_scenario_is_the_survey(tmp_path, capsys):
    scen = _write(tmp_path, area="polygon_xy = [[400.0, 400.0], [900.0, 400.0], [900.0, 700.0], [400.0, 700.0]]")
    assert main(["-q", "run", str(scen), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["measured_on"] == "flight" and rec["coverage_pct"] >= 99.0 and rec["lines"] >= 2
