"""The fix planner keeps the static obstacles (spheres, ellipsoids) out of reach of the predicted error, as it keeps the
seabed and the charted zones (one safe radius for every hazard, ``auvplan.nav.clearance.hazard_safe_radius``), and
as ``mission check`` tests them: each piece of a leg under its own error, on arrival at its end
(``docs/navigation.md``, "Clearance under the error"; helper nav2, wave 17; per piece since wave 18).

Oracle, independent of the planner: one level leg of 8 km at 200 m without bottom lock in still water, from a fix of
σ = 3 m, 2 % of the distance, 2 σ: the error is ``2 · hypot(3, 0.02 · h)`` (closed form), ``h`` the
horizontal distance flown since the last fix; a sphere of radius 50 m (margin 10 m) whose centre lies 260 m off the
leg, at its depth, mid-way along it.  Every point of the plan, every metre, must keep the obstacle's margin plus its
error there (the distance in numpy); the leg alone reaches 320.06 m, so at least one fix is needed.  Since wave 18
``mission check`` tests each 50 m piece under its own error (not the leg's largest): the one fix at 0.75 km (3.25 km
before), its 6.7 km leg after it within 170 m of error by the sphere.  Before: the
planner ignored the obstacle (no fix: 320.1 m is within E = 400 m) and the plan's own check failed the leg
(``leg 1: within its predicted error 320.1 m a static obstacle comes within its margin 10 m``); with the obstacle in
its safe radius but each interval judged at its own error (not its leg's on arrival, as the check does), one fix at
0.75 km and the check failed the 5.2 km leg after it (290.1 m).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.missions.formats import mission_csv
from auvplan.io.scenario import loader as sc
from auvplan.nav import check_navigation
from auvplan.sim.navigation import navigation_plan

LEG = np.array([[1000.0, 3000.0, -200.0], [9000.0, 3000.0, -200.0]])
CENTRE = np.array([6000.0, 3260.0, -200.0])
RADIUS, MARGIN = 50.0, 10.0
SPHERE = f'type = "sphere"\ncenter = [{CENTRE[0]}, {CENTRE[1]}, {CENTRE[2]}]\nradius = {RADIUS}'
ELLIPSOID = ('type = "ellipsoid"\ncenter = [6000.0, 3400.0, -200.0]\nsemi_axes = [400.0, 150.0, 100.0]\n'
             'yaw_deg = 20.0')


def _scenario(tmp_path, obstacle: str) -> str:
    text = f"""
name = "obstacle-nav"
seed = 1
[origin]
lat = 10.0
lon = 150.0
[bounds]
x = [0.0, 12000.0]
y = [0.0, 8000.0]
z = [-2000.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 1000.0
cell_m = 500.0
[[obstacles]]
{obstacle}
[mission]
start = [1000.0, 3000.0, -200.0]
goal = [9000.0, 3000.0, -200.0]
min_depth_m = 0.0
obstacle_margin_m = {MARGIN}
[vehicle]
speed = 1.5
max_depth_m = 2000.0
[navigation]
drift_pct = 0.5
drift_pct_no_lock = 2.0
dvl_range_m = 100.0
fix_error_m = 3.0
max_error_m = 400.0
confidence = 2.0
fixes = "plan"
surface_s = 60.0
[avoidance]
name = "none"
"""
    path = tmp_path / f"obstacle-{len(obstacle)}.toml"
    path.write_text(text)
    return str(path)


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    d = b - a
    t = float(np.clip(np.dot(p - a, d) / max(float(np.dot(d, d)), 1e-12), 0.0, 1.0))
    return float(np.linalg.norm(a + t * d - p))


def test_the_fix_planner_keeps_the_error_off_a_sphere(tmp_path):
    path = _scenario(tmp_path, SPHERE)
    world, mission = sc.build(sc.load(path))
    nav = mission.navigation
    assert not check_navigation(world, LEG, ("", ""), nav).ok  # the leg alone: the obstacle within its 320 m
    plan = navigation_plan(world, mission, LEG)
    assert plan is not None and plan.ok, plan.message
    assert plan.fixes.count == 1
    p, kinds = plan.points, plan.kinds
    h = np.hypot(*np.diff(p[:, :2], axis=0).T)
    since = 0.0
    for k in range(p.shape[0] - 1):  # the closed-form error along each leg against the exact distance, every metre
        err = 2.0 * math.hypot(3.0, 0.02 * (since + h[k]))
        assert plan.check.budget.leg_error_m[k] == pytest.approx(err, rel=1e-9)
        f = np.linspace(0.0, 1.0, max(int(h[k]), 1) + 1)
        q = p[k] + f[:, None] * (p[k + 1] - p[k])
        e = 2.0 * np.hypot(3.0, 0.02 * (since + f * h[k]))  # the error at each point (wave 18: not the leg's largest)
        assert np.all(np.linalg.norm(q - CENTRE, axis=1) - RADIUS - MARGIN >= e), k
        since = 0.0 if kinds[k + 1] else since + h[k]


@pytest.mark.parametrize("obstacle", [SPHERE, ELLIPSOID], ids=["sphere", "ellipsoid"])
def test_what_the_planner_plans_feasible_mission_check_passes(tmp_path, capsys, obstacle):
    path = _scenario(tmp_path, obstacle)
    world, mission = sc.build(sc.load(path))
    plan = navigation_plan(world, mission, LEG)
    assert plan is not None and plan.ok, plan.message
    csv = tmp_path / "m.csv"
    csv.write_text(mission_csv(plan.points, world.origin, 1.5))
    capsys.readouterr()
    code = main(["mission", "check", str(csv), "--scenario", path, "--json"])
    rec = json.loads(capsys.readouterr().out)
    rec = rec["files"][0] if "files" in rec else rec
    assert rec["navigation"]["ok"], rec["navigation"]["message"]
    assert rec["navigation"]["fixes"] == plan.fixes.count >= 1
    assert all(leg["clear"] for leg in rec["navigation"]["legs"])
    assert code == 0


@pytest.mark.parametrize("obstacle", [SPHERE, ELLIPSOID], ids=["sphere", "ellipsoid"])
def test_the_obstacles_safe_radius_is_the_inverse_of_the_checks_test(tmp_path, obstacle):
    """``obstacle_safe_radius`` (the planner's) against ``obstacle_within`` (the check's), pieces of the leg: clear
    at the radius, hit a centimetre beyond it; for the sphere, the closed form ``distance − R − margin``."""
    from auvplan.nav.clearance import obstacle_safe_radius, obstacle_within, pieces

    world, _ = sc.build(sc.load(_scenario(tmp_path, obstacle)))
    a, b, _ = pieces(LEG, 250.0)
    r = obstacle_safe_radius(world, a, b, 400.0)
    seg = np.stack([a, b], axis=1)
    near = np.isfinite(r)
    assert 0 < near.sum() < r.size
    assert np.all(obstacle_within(world, seg[near], r[near]) < 0)
    assert np.all(obstacle_within(world, seg[near], r[near] + 0.01) >= 0)
    assert np.all(obstacle_within(world, seg[~near], 400.0) < 0)
    if obstacle == SPHERE:
        exact = np.array([_segment_distance(CENTRE, p, q) for p, q in zip(a, b, strict=True)]) - RADIUS - MARGIN
        np.testing.assert_allclose(r[near], exact[near], atol=1e-5)
