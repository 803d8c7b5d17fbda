"""The clearance under the navigation error counts the charted no-go zones (``[[zones]]``), as it counts the seabed
and the obstacles: a leg whose predicted error reaches a zone's prism horizontally at the leg's depth is not clear,
in ``mission check`` and in ``run``'s budget alike (both ``auvplan.nav.check_navigation``; ``docs/navigation.md``,
"Clearance under the error"; helper nav, wave 17).

Oracle: one level leg of L = 8 km without bottom lock in still water, from a fix of σ = 3 m, 2 % of the distance,
2 σ: its error on arrival is 2 · hypot(3, 0.02 · 8000) = 320.06 m (closed form); a box zone north of its end at a
horizontal distance d (exact geometry) is within it for d = 310 m and not for d = 330 m; a band from 300 to 500 m
deep (the leg at 200 m) is never within it; a seabed band (1 000 m of water) up to 850 m above the seabed reaches the
leg's depth, up to 700 m does not.  Before: every one of them clear (``mission check`` OK at d = 310 m).
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

LEG = np.array([[1000.0, 3000.0, -200.0], [9000.0, 3000.0, -200.0]])
ERROR = 2.0 * math.hypot(3.0, 0.02 * 8000.0)


def _scenario(tmp_path, d: float, band: str) -> str:
    y0 = 3000.0 + d
    text = f"""
name = "zone-nav"
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
[[zones]]
name = "range"
polygon = [[8500.0, {y0}], [9500.0, {y0}], [9500.0, {y0 + 500.0}], [8500.0, {y0 + 500.0}]]
{band}
[mission]
start = [1000.0, 3000.0, -200.0]
goal = [9000.0, 3000.0, -200.0]
min_depth_m = 0.0
[vehicle]
speed = 1.5
max_depth_m = 2000.0
[navigation]
drift_pct = 0.5
drift_pct_no_lock = 2.0
dvl_range_m = 100.0
fix_error_m = 3.0
max_error_m = 5000.0
confidence = 2.0
fixes = "none"
[avoidance]
name = "none"
"""
    path = tmp_path / f"zone-{d:g}-{len(band)}.toml"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize(("d", "band", "within"), [
    (310.0, "", True), (330.0, "", False),  # surface to seabed: exact against the closed-form error
    (310.0, "top_m = 300.0\nbottom_m = 500.0", False),  # below the leg: never within, however near
    (310.0, "above_seabed_m = 850.0", True), (310.0, "above_seabed_m = 700.0", False),  # from the seabed up
])
def test_a_zone_within_the_predicted_error_fails_the_leg(tmp_path, capsys, d, band, within):
    path = _scenario(tmp_path, d, band)
    world, mission = sc.build(sc.load(path))
    nav = mission.navigation
    c = check_navigation(world, LEG, ("", ""), nav)
    assert c.budget.leg_error_m[0] == pytest.approx(ERROR, rel=1e-12)
    assert c.ok is (not within) and bool(c.leg_clear[0]) is (not within)
    if within:
        assert "no-go zone 'range'" in c.message and f"{ERROR:.1f} m" in c.message
    # mission check of the same leg in a file says the same
    csv = tmp_path / "m.csv"
    csv.write_text(mission_csv(LEG, world.origin, 1.5))
    capsys.readouterr()
    code = main(["mission", "check", str(csv), "--scenario", path, "--json"])
    rec = json.loads(capsys.readouterr().out)
    rec = rec["files"][0] if "files" in rec else rec
    assert rec["navigation"]["ok"] is (not within), rec["navigation"]
    assert rec["navigation"]["legs"][0]["clear"] is (not within)
    assert code == (1 if within else 0)
    assert all(not z["entered_legs"] for z in rec["zones"])  # the nominal leg enters no zone


def test_the_fix_planner_keeps_the_error_off_a_zone(tmp_path):
    """``fixes = "plan"`` with E = 400 m: the leg alone (320 m at its end) keeps E, but a surface-to-seabed zone
    200 m off its end needs the error there under 200 m: one surfacing before it (before: none, and the plan's own
    check failed the leg on the zone)."""
    from dataclasses import replace

    from auvplan.sim.navigation import navigation_plan

    world, mission = sc.build(sc.load(_scenario(tmp_path, 200.0, "")))
    nav = replace(mission.navigation, fixes="plan", max_error_m=400.0, surface_s=60.0)
    plan = navigation_plan(world, replace(mission, navigation=nav), LEG)
    assert plan is not None and plan.ok, plan.message
    assert plan.fixes.count == 1 and plan.check.ok and plan.check.leg_clear.all()
    # the closed form: from the fix to the leg's end (the dive back, then level) the error stays under 200 m there
    end = plan.check.budget.leg_error_m[-1]
    assert end < 200.0
    assert check_navigation(world, plan.points, plan.kinds, nav).ok


def test_a_surfacing_keeps_its_climb_out_of_reach_of_a_shallow_zone(tmp_path):
    """A zone from the surface to 50 m deep, 150 m north of a 14 km leg at 200 m between x = 4 and 7 km: the leg
    never reaches its band, a surfacing's climb does.  The fewest fixes is one, and the earliest that reaches the goal
    within E = 400 m (about x = 5.2 km, 168 m of error on arrival) would climb 150 m from the zone: the planner surfaces
    where its climb's error keeps the zone out of reach (before: there, and its own check failed the climb's leg)."""
    from dataclasses import replace

    import shapely

    from auvplan.sim.navigation import navigation_plan

    text = open(_scenario(tmp_path, 150.0, "top_m = 0.0\nbottom_m = 50.0")).read()
    text = text.replace("[[8500.0, 3150.0], [9500.0, 3150.0], [9500.0, 3650.0], [8500.0, 3650.0]]",
                        "[[4000.0, 3150.0], [7000.0, 3150.0], [7000.0, 3650.0], [4000.0, 3650.0]]")
    text = text.replace("x = [0.0, 12000.0]", "x = [0.0, 16000.0]").replace("goal = [9000.0", "goal = [15000.0")
    path = tmp_path / "shallow.toml"
    path.write_text(text)
    world, mission = sc.build(sc.load(str(path)))
    nav = replace(mission.navigation, fixes="plan", max_error_m=400.0, surface_s=60.0)
    leg = np.array([[1000.0, 3000.0, -200.0], [15000.0, 3000.0, -200.0]])
    plan = navigation_plan(world, replace(mission, navigation=nav), leg)
    assert plan is not None and plan.ok, plan.message
    assert plan.fixes.count == 1 and plan.check.ok
    # independently: every leg of the mission that reaches the band (0-50 m deep) keeps the zone farther than its
    # predicted error (the band's part of the leg, its horizontal distance to the footprint)
    zone = shapely.Polygon([(4000.0, 3150.0), (7000.0, 3150.0), (7000.0, 3650.0), (4000.0, 3650.0)])
    p = plan.points
    for k in range(len(p) - 1):
        a, b = p[k], p[k + 1]
        if max(a[2], b[2]) < -50.0:
            continue
        t0 = 0.0 if a[2] >= -50.0 else (-50.0 - a[2]) / (b[2] - a[2])
        t1 = 1.0 if b[2] >= -50.0 else (-50.0 - a[2]) / (b[2] - a[2])
        q0, q1 = a[:2] + t0 * (b[:2] - a[:2]), a[:2] + t1 * (b[:2] - a[:2])
        part = shapely.LineString([q0, q1]) if np.hypot(*(q1 - q0)) > 0 else shapely.Point(q0)
        assert part.distance(zone) > plan.check.budget.leg_error_m[k], k


@pytest.mark.parametrize(("d", "fixes"), [(330.0, 0), (200.0, 1)])
def test_the_fix_planner_plans_near_a_seabed_band(tmp_path, d, fixes):
    """A band from the seabed up to 850 m (the leg at 800 m above the seabed is in its height) whose footprint is
    ``d`` off the leg's end: at 330 m the bare leg passes the check (320 m of error at its end), so the planner needs
    no fix; at 200 m one.  Before (mutants24), ``zone_safe_radius`` tested the band's height without the footprint's
    distance: a safe radius of 0 along the whole leg, and the planner refused both ("within 0 m horizontally of the
    leg, less than confidence × fix_error_m = 6 m")."""
    from dataclasses import replace

    from auvplan.sim.navigation import navigation_plan

    world, mission = sc.build(sc.load(_scenario(tmp_path, d, "above_seabed_m = 850.0")))
    nav = replace(mission.navigation, fixes="plan", max_error_m=400.0, surface_s=60.0)
    assert check_navigation(world, LEG, ("", ""), nav).ok is (fixes == 0)
    plan = navigation_plan(world, replace(mission, navigation=nav), LEG)
    assert plan is not None and plan.ok, plan.message
    assert plan.fixes.count == fixes and plan.check.ok
    assert check_navigation(world, plan.points, plan.kinds, nav).ok
