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
