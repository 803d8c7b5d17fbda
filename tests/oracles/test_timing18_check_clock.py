"""``mission check`` of a file that starts at its first waypoint (every format but a ``.plan``) flies its legs on the
navigation budget's clock: departing the first waypoint when the launch's dive from the surface above it ends, not at
the scenario's start time (helper timing, wave 18; ``docs/navigation.md``, "The launch").

In a current that changes in time the check flew the legs ~770 s early, in another current: a 12 km leg west at
1 000 m against the reversing current of ``test_nav24_fix_times`` (0.8 m/s east at the launch, 0 at 5 000 s) read back
258.98 m of error at 2 σ from its ``.csv`` and ``.moos`` while the plan budgets 255.63 m (its launch's drift
included); the documented invariant, the file's check without the launch at most the planned error, did not hold.
Now 244.31 m, the closed form.

Oracle: on a level leg against a current ``u(t)`` along it the ground speed is ``V − u`` and the water run ``V T``, so
the check's error at the goal is ``2 · hypot(3, 0.01 · V · T)``, ``T`` the flight from the dive's end (integrated:
``∫ (V − u) dt = L``); the plan's adds the launch's drift ``0.01 ∫ |u| dt`` over the dive.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from test_nav24_fix_times import V, _dive, _integrate, _u, _world

from auvplan.app.check import navigation_check
from auvplan.io.missions.energy import file_energy_flight
from auvplan.io.missions.formats import mission_csv, read_mission, to_moos
from auvplan.nav import NavParams
from auvplan.sim import Mission
from auvplan.sim.navigation import navigation_plan
from auvplan.vehicles import VehicleParams

ROUTE = np.array([[13000.0, 3000.0, -1000.0], [1000.0, 3000.0, -1000.0]])  # west, against the current
NAV = NavParams(drift_pct=0.3, drift_pct_no_lock=1.0, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=1000.0,
                confidence=2.0, fixes="none", surface_s=60.0)


@pytest.mark.parametrize("fmt", ["csv", "moos"])
def test_a_files_check_flies_its_legs_after_the_launch(tmp_path, fmt):
    world = dataclasses.replace(_world(), origin=(10.0, 150.0))
    mission = Mission("t", tuple(ROUTE[0]), tuple(ROUTE[-1]), navigation=NAV,
                      vehicle=VehicleParams(speed=V, max_pitch_deg=30.0))
    plan = navigation_plan(world, mission, ROUTE)
    assert plan is not None and plan.ok
    f = tmp_path / f"mission.{fmt}"
    f.write_text(mission_csv(plan.points, world.origin, V) if fmt == "csv" else to_moos(plan.points, V))
    _, _, _, held, water = file_energy_flight(world, mission, f)
    points = read_mission(f, world.origin, None)[0]
    rec, ok, _ = navigation_check(world, NAV, points, f, first=0, held_water_m=held, water_m=water)
    dive = _dive()
    length = float(ROUTE[0, 0] - ROUTE[1, 0])
    legs = _integrate(dive, lambda t: (V - _u(t)) / length) - dive
    expected = 2.0 * math.hypot(3.0, 0.01 * V * legs)
    d0 = 0.01 * _integrate_abs_u(dive)
    assert ok and rec["nav_error_max_m"] == pytest.approx(expected, abs=0.02)
    assert plan.check.budget.max_error_m == pytest.approx(2.0 * math.hypot(3.0, d0 + 0.01 * V * legs), abs=0.05)
    assert rec["nav_error_max_m"] <= plan.check.budget.max_error_m  # the file's check, without the launch: at most
    from_zero = 2.0 * math.hypot(3.0, 0.01 * V * _integrate(0.0, lambda t: (V - _u(t)) / length))
    assert from_zero - expected > 10.0  # the hard case: the legs flown from t = 0 read back more than planned


def _integrate_abs_u(t1: float) -> float:
    """∫ |u| dt over the dive (midpoints of 0.05 s steps)."""
    t = np.arange(0.0, t1, 0.05) + 0.025
    return float(np.abs(_u(t)).sum() * 0.05)
