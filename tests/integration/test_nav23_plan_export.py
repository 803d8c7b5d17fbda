"""``export`` of a ``plan`` results folder (no flight) carries the planned position fixes, as a ``run`` folder does:
each surfacing a waypoint at depth 0 that the ``.plan`` holds ``surface_s`` (param 1) and ``mission.moos`` station-keeps
for (``docs/navigation.md``; helper nav, wave 17).

Oracle: the files read back by ``auvplan.io.missions`` (``read_mission``, ``read_dwells``), independently of the
planner: the surface waypoints are the fixes, the waits sit there and nowhere else, and ``mission check`` judges the
file within ``max_error_m``.  Before: the folder exported the route alone, ``mariana-nav``'s ``plan`` export read back
0 surface fixes and 1 010 m of predicted error (FAIL).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.missions.formats import read_mission
from auvplan.io.missions.readback.dwell import read_dwells
from auvplan.io.scenario import loader as sc


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    out = tmp_path_factory.mktemp("plan-export") / "nav"
    assert main(["plan", "mariana-nav", "--out", str(out)]) == 0
    assert main(["export", str(out), "--format", "plan", "moos"]) == 0
    return out


@pytest.mark.parametrize("fmt", ["plan", "moos"])
def test_a_plan_folder_exports_its_surfacings_and_their_waits(exported, fmt, capsys):
    world, mission = sc.build(sc.load("mariana-nav"))
    nav = mission.navigation
    path = exported / f"mission.{fmt}"
    points = read_mission(path, world.origin, world.seabed)[0]
    surface = np.flatnonzero(points[1:, 2] >= -0.5) + 1  # after the first (a .plan's home is on the surface)
    if fmt == "plan":
        surface = surface[surface > 1]  # the home and its first item: the launch
    assert surface.size >= 5  # mariana-nav needs its fixes (6 as run plans them)
    waits = read_dwells(path, points.shape[0])
    assert waits is not None
    expected = np.zeros(points.shape[0])
    expected[surface] = nav.surface_s
    np.testing.assert_array_equal(waits, expected)  # the wait at each surfacing and nowhere else
    capsys.readouterr()
    code = main(["mission", "check", str(path), "--scenario", "mariana-nav", "--json"])
    rec = json.loads(capsys.readouterr().out)
    rec = rec["files"][0] if "files" in rec else rec
    assert code == 0 and rec["navigation"]["ok"], rec["navigation"]["message"]
    assert rec["navigation"]["fixes"] == surface.size
    assert rec["navigation"]["nav_error_max_m"] <= nav.max_error_m


def test_a_plan_folder_with_usbl_fixes_refuses_in_one_line(tmp_path, capsys):
    """No mission format holds a USBL fix (taken at depth): only ``fixes.csv`` keeps it, which a ``plan`` folder
    lacks; exporting the waypoints without it would lose the fixes the budget rests on."""
    from test_nav import _USBL_TOML  # the oracles' USBL scene: the ship near the route, USBL fixes chosen

    toml = tmp_path / "usbl.toml"
    toml.write_text(_USBL_TOML)
    out = tmp_path / "usbl"
    assert main(["plan", str(toml), "--out", str(out)]) == 0
    capsys.readouterr()
    assert main(["export", str(out), "--format", "csv"]) == 2
    text = capsys.readouterr().err  # (the live progress line may come first, on a slow machine: issue 56)
    err = [line for line in text.splitlines() if line.startswith("auvplan: error:")]
    assert "Traceback" not in text and len(err) == 1, text
    assert "USBL fixes" in err[0] and "fixes.csv" in err[0] and str(out) in err[0], err
    assert not (out / "mission.csv").exists()


def _track_distance(points: np.ndarray, q) -> float:
    """Horizontal distance from a point to a polyline (its legs' traces)."""
    a, b = points[:-1, :2], points[1:, :2]
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", np.asarray(q, dtype=float) - a, d) / np.maximum((d * d).sum(1), 1e-12), 0, 1)
    return float(np.min(np.linalg.norm(a + t[:, None] * d - np.asarray(q, dtype=float), axis=1)))


def test_plan_and_run_budget_different_routes_and_each_file_checks(exported, mariana_nav_plan, capsys, tmp_path):
    """``plan mariana-nav`` plans start → goal with the global planner (74.5 km, 7 fixes); ``run mariana-nav`` flies
    the scenario's fixed ``[mission] route`` (79.0 km, 6 fixes): different routes, so different fixes, each file
    within E by ``mission check`` (``docs/navigation.md``, "plan and run"; helper nav2).  Oracle: the files' tracks
    against the two routes' own vertices (the fixed route's corner at (166, 50) km, the planned path's nodes), and
    the check of each file; the same scenario without a fixed route exports the very file ``run`` writes
    (``tests/heavy/test_nav24_plan_run.py``)."""
    from auvplan.io.results import records

    world, mission, route, plan = mariana_nav_plan
    corner = mission.route[1][:2]  # the fixed route's first corner
    path = records.read_run(exported)[0].plan.path  # the plan folder's planned path (path.csv)
    mine = read_mission(exported / "mission.plan", world.origin, world.seabed)[0][1:]  # its home first
    assert _track_distance(route, corner) < 1.0 and _track_distance(plan.points, corner) < 1.0  # run's: the route
    assert _track_distance(mine, corner) > 5000.0  # the plan folder's file does not fly the fixed route (9.0 km) ...
    assert max(_track_distance(mine, q) for q in path[::25, :2]) < 50.0  # ... but the planned path (15 m)
    from auvplan.io.missions import export
    from auvplan.sim.result import RunRecord

    export.write_exports(tmp_path, RunRecord("mariana-nav", 1, None, plan.points, np.empty((0, 3)), None, plan),
                         world.origin, mission.vehicle.speed, ("plan",))  # run's mission, as run exports it
    for path, fixes in ((exported / "mission.plan", 7), (tmp_path / "mission.plan", 6)):
        capsys.readouterr()
        assert main(["mission", "check", str(path), "--scenario", "mariana-nav", "--json"]) == 0
        rec = json.loads(capsys.readouterr().out)
        rec = rec["files"][0] if "files" in rec else rec
        assert rec["navigation"]["ok"] and rec["navigation"]["fixes"] == fixes, rec["navigation"]
        assert rec["navigation"]["nav_error_max_m"] <= mission.navigation.max_error_m
