"""``mission check`` tests each piece of a leg (at most 50 m) under its own predicted error, not the whole leg under the
leg's largest, and the fix planner judges each interval as that test will (helper timing, wave 18;
``docs/navigation.md``, "Clearance under the error").

Oracle, independent of the code's pieces: one level leg of 8 km at 200 m without bottom lock in still water, from a fix
of σ = 3 m, 2 % of the distance, 2 σ: the error at ``s`` metres along it is ``2 · hypot(3, 0.02 s)`` (closed form); a
sphere (radius 50 m, margin 10 m) 150 m off the leg keeps every point clear when the error there stays within the
point's exact distance less radius and margin, tested every metre in numpy.  Near the start (0.5 km along) it is clear
by ~65 m; near the end (7.5 km) it is not.  Before, the check failed the leg for the sphere near its start (``leg 0:
within its predicted error 320.1 m a static obstacle comes within its margin 10 m``), and the planner spent a fix on it.
The planner now tests each interval at the error one piece past its end, so what it plans feasible the check passes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.nav import NavParams, check_navigation
from auvplan.sim import Mission
from auvplan.sim.navigation import navigation_plan
from auvplan.vehicles import VehicleParams
from auvplan.world import Bounds, Margins, Terrain, World
from auvplan.world.obstacles import Sphere

LEG = np.array([[1000.0, 3000.0, -200.0], [9000.0, 3000.0, -200.0]])
RADIUS, MARGIN = 50.0, 10.0
NAV = NavParams(drift_pct=0.5, drift_pct_no_lock=2.0, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=400.0,
                confidence=2.0, fixes="plan", surface_s=60.0)


def _world(centre) -> World:
    x, y = np.linspace(0.0, 12000.0, 25), np.linspace(0.0, 8000.0, 17)  # non-square grid
    return World(Bounds(0.0, 12000.0, 0.0, 8000.0, -2000.0, 0.0),
                 Terrain(x, y, np.full((17, 25), -1000.0), name="flat"), obstacles=[Sphere(tuple(centre), RADIUS)],
                 margins=Margins(min_altitude=20.0, min_depth=0.0, obstacle=MARGIN), name="flat")


def clear_every_metre(points: np.ndarray, kinds: tuple[str, ...], centre: np.ndarray) -> bool:
    """The oracle: every point of the mission (every metre) keeps its closed-form error off the sphere's margin."""
    since = 0.0
    for k in range(len(points) - 1):
        h = float(np.hypot(*(points[k + 1, :2] - points[k, :2])))
        f = np.linspace(0.0, 1.0, max(int(h), 1) + 1)
        q = points[k] + f[:, None] * (points[k + 1] - points[k])
        e = 2.0 * np.hypot(3.0, 0.02 * (since + f * h))
        if np.any(np.linalg.norm(q - centre, axis=1) - RADIUS - MARGIN < e):
            return False
        since = 0.0 if kinds[k + 1] else since + h
    return True


@pytest.mark.parametrize(("along", "clear"), [(500.0, True), (2000.0, True), (7500.0, False)])
def test_each_piece_is_tested_under_its_own_error(along, clear):
    centre = np.array([LEG[0, 0] + along, 3150.0, -200.0])
    assert clear_every_metre(LEG, ("", ""), centre) is clear
    c = check_navigation(_world(centre), LEG, ("", ""), NAV, first_leg=0)
    assert c.budget.leg_error_m[0] == pytest.approx(2.0 * math.hypot(3.0, 0.02 * 8000.0), rel=1e-9)  # 320.06 m
    assert c.ok is clear, c.message
    if not clear:
        assert c.message == "leg 0: within its predicted error 320.1 m a static obstacle comes within its margin 10 m"


@pytest.mark.parametrize("along", [500.0, 2000.0, 3500.0, 5000.0, 6500.0, 7500.0])
def test_what_the_planner_plans_feasible_the_check_passes(along):
    """Spheres all along the leg: the plan's own check passes and the oracle holds every metre; a sphere the leg
    alone keeps clear costs no fix (before: one whenever the leg's 320 m reached it)."""
    centre = np.array([LEG[0, 0] + along, 3150.0, -200.0])
    world = _world(centre)
    mission = Mission("t", tuple(LEG[0]), tuple(LEG[-1]), navigation=NAV,
                      vehicle=VehicleParams(speed=1.5, max_pitch_deg=20.0))
    plan = navigation_plan(world, mission, LEG)
    assert plan is not None and plan.ok, plan.message
    assert clear_every_metre(plan.points, plan.kinds, centre)
    alone = clear_every_metre(LEG, ("", ""), centre)
    assert (plan.fixes.count == 0) is alone
