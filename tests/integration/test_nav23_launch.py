"""What the planner budgets is what ``mission check`` finds in the exported ``.plan``: the launch's dive from the
surface above the start (the ``.plan``'s home) is counted in the drift ``D`` by both (``docs/navigation.md``,
"The launch"; helper nav, wave 17).

Oracles: the check of the file read back (home first, its launch flown at ArduSub's descent speed) against the
planner's own largest error, to the record's rounding; and the launch's drift in closed form: a vertical dive of
depth ``d`` at through-water speed ``V`` held over a point in a uniform current ``c`` sinks at ``sqrt(V² − c²)``
and moves ``w0 = c · d / sqrt(V² − c²)`` through the water, without bottom lock ``D0 = w0 · drift_pct_no_lock / 100``.
Before: the planner started at depth with ``σ = fix_error_m`` and ``D = 0``; ``mariana-nav``'s ``.plan`` read back
300.4 m against 299.7 m planned (FAIL); the synthetic case below (a 1 500 m launch across 1 m/s) planned one fix
for 297.2 m and read back 337.4 m (FAIL), now two fixes for 297.2 m, the file's check the same.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.missions import export
from auvplan.io.scenario import loader as sc
from auvplan.sim.navigation import navigation_plan
from auvplan.sim.result import RunRecord

SYNTHETIC = """
name = "deep-launch"
seed = 1
[origin]
lat = -12.0
lon = 179.9
[bounds]
x = [0.0, 30000.0]
y = [0.0, 12000.0]
z = [-4000.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 3000.0
cell_m = 1000.0
[currents]
uniform = [0.0, 1.0, 0.0]
[mission]
start = [2000.0, 5000.0, -1500.0]
goal = [19000.0, 5000.0, -1500.0]
route = [[2000.0, 5000.0, -1500.0], [19000.0, 5000.0, -1500.0]]
min_depth_m = 0.0
[vehicle]
speed = 2.0
max_pitch_deg = 20.0
max_depth_m = 2000.0
[navigation]
drift_pct = 0.3
drift_pct_no_lock = 1.0
dvl_range_m = 200.0
fix_error_m = 5.0
max_error_m = 300.0
confidence = 3.0
fixes = "plan"
surface_s = 60.0
[avoidance]
name = "none"
"""


LAUNCH_DIVE_MPS = 1.5  # ArduSub's WPNAV_SPEED_DN default: a .plan's launch from its home


def _exported_check(world, mission, plan, scenario: str, out, capsys) -> dict:
    record = RunRecord(mission.name or "t", 1, None, plan.points, np.empty((0, 3)), None, plan)
    export.write_exports(out, record, world.origin, mission.vehicle.speed, ("plan",))
    code = main(["mission", "check", str(out / "mission.plan"), "--scenario", scenario, "--json"])
    rec = json.loads(capsys.readouterr().out)
    rec = rec["files"][0] if "files" in rec else rec
    return {"code": code, **rec["navigation"]}


@pytest.fixture(scope="module")
def deep_launch(tmp_path_factory):
    path = tmp_path_factory.mktemp("nav23") / "deep-launch.toml"
    path.write_text(SYNTHETIC)
    world, mission = sc.build(sc.load(str(path)))
    route = np.array([[2000.0, 5000.0, -1500.0], [19000.0, 5000.0, -1500.0]])
    return str(path), world, mission, navigation_plan(world, mission, route)


def test_mariana_nav_plan_export_passes_its_own_check_with_the_planned_error(mariana_nav_plan, tmp_path, capsys):
    world, mission, _, plan = mariana_nav_plan
    assert plan is not None and plan.ok
    got = _exported_check(world, mission, plan, "mariana-nav", tmp_path, capsys)
    assert got["ok"] and got["code"] == 0, got
    assert got["nav_error_max_m"] == pytest.approx(plan.check.budget.max_error_m, abs=1e-3)
    assert got["nav_error_max_m"] <= mission.navigation.max_error_m
    # the launch: 1 500 m dived over home in the uniform (-0.05, 0.01) m/s current, held over the point
    c, d = math.hypot(-0.05, 0.01), 1500.0
    assert plan.launch_water_m == pytest.approx(c * d / math.sqrt(LAUNCH_DIVE_MPS ** 2 - c * c), rel=1e-6)


def test_deep_launch_in_a_strong_cross_current(deep_launch, tmp_path, capsys):
    path, world, mission, plan = deep_launch
    nav = mission.navigation
    assert plan.ok and plan.fixes.count >= 1
    got = _exported_check(world, mission, plan, path, tmp_path, capsys)
    assert got["ok"] and got["code"] == 0, got
    assert got["nav_error_max_m"] == pytest.approx(plan.check.budget.max_error_m, abs=1e-3)
    # the dive: 1 500 m at 1.5 m/s across 1.0 m/s, 3 000 m of water (no lock at either end)
    c, d = 1.0, 1500.0
    w0 = c * d / math.sqrt(LAUNCH_DIVE_MPS ** 2 - c * c)
    assert plan.launch_water_m == pytest.approx(w0, rel=1e-6)
    d0 = w0 * nav.rate(False)
    assert plan.check.budget.error_m[0] == pytest.approx(nav.confidence * math.hypot(nav.fix_error_m, d0), rel=1e-6)
    # the first stretch is planned to the budget: without the launch's 13.4 m it would be over it
    assert plan.check.budget.max_error_m > nav.max_error_m - 3.0


def test_the_page_band_counts_the_launch_as_the_check_does(deep_launch):
    """``serve``'s band under the mission being edited: its largest error is the planner's and the ``.plan``'s."""
    from auvplan.serve.session import nav_band

    _, world, mission, plan = deep_launch
    got = nav_band(world, mission, plan.points)
    assert got is not None and got["fixes"] == plan.fixes.count
    assert got["max_error_m"] == pytest.approx(plan.check.budget.max_error_m, abs=0.01)
    i = plan.kinds.index("gps")  # the mission up to its first fix: the launch's drift in the error on arrival there
    first = nav_band(world, mission, plan.points[:i + 1])
    assert first is not None
    assert first["max_error_m"] == pytest.approx(plan.check.budget.leg_error_m[i - 1], abs=0.01)
