"""The closed loop flies the launch's dive from the surface, so its clock is the navigation budget's (helper timing,
wave 18; ``docs/navigation.md``, "The launch" and "Simulated drift").

A mission with ``[navigation]`` starts at the surface above its first waypoint and dives to it (held over the point at
1.5 m/s through the water): the budget, the fixes' times, the exported time-out and a ``.plan``'s check count that
dive.  The simulation started at the first waypoint at t = 0, so in a current that changes in time it flew every leg
in the current of another hour.  Here a current along the route reverses within the mission (0.8 m/s east at the
launch, 0 at 5 000 s; ``test_nav24_fix_times``'s): after a 1 000 m dive the 10 km leg at 1.5 m/s arrives at 6 608.4 s
(the independent integration, the dive 766.4 s of it); the closed loop arrived at 5 332.5 s before (started at the
first waypoint at t = 0: without the dive's 766 s, and its leg 510 s shorter than the budget's, flown in the current
of the hour before), now at 6 608.5 s; and the simulated drift's error at the first waypoint is the budget's launch
drift (before: the fix's own error alone).

Oracle: ``test_nav24_fix_times``'s integration (Simpson steps of 0.05 s) of the dive held over the start, sinking at
sqrt(V² − u²), then of the leg at the ground speed V + u(t); the arrival radius reached at that ground speed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_nav24_fix_times import U0, V, _dive, _integrate, _u, _world

from auvplan.nav import NavParams
from auvplan.sim import Mission, SimParams, simulate
from auvplan.sim.navigation import launch_flight
from auvplan.vehicles import VehicleParams

ROUTE = np.array([[1000.0, 3000.0, -1000.0], [11000.0, 3000.0, -1000.0]])
NAV = NavParams(drift_pct=0.3, drift_pct_no_lock=1.0, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=3000.0,
                confidence=2.0, fixes="none", surface_s=60.0)
SIM = SimParams(dt=0.5, record_every=4, arrival_radius=10.0)


def _mission(**kw) -> Mission:
    return Mission("t", tuple(ROUTE[0]), tuple(ROUTE[-1]), vehicle=VehicleParams(speed=V, max_pitch_deg=30.0),
                   sim=SIM, **kw)


def _arrival(t0: float) -> float:
    """The leg flown from ``t0`` to the arrival radius: ∫ (V + u(t)) dt = length − radius."""
    length = float(ROUTE[1, 0] - ROUTE[0, 0]) - SIM.arrival_radius
    return _integrate(t0, lambda tt: (V + _u(tt)) / length)


def test_the_flown_clock_is_the_budgets_in_a_current_that_changes_in_time():
    world = _world()
    r = simulate(world, _mission(navigation=NAV), route=ROUTE, rng=3)
    assert r.arrived, r.events
    dive = _dive()
    expected, from_zero = _arrival(dive), _arrival(0.0)
    assert abs(expected - from_zero) > 300.0  # the hard case: the current's phase moves the arrival
    assert r.t[-1] == pytest.approx(expected, abs=2.0)
    budget = launch_flight(world, ROUTE, V)  # the clock the budget, the fixes' times and the time-out count
    assert budget is not None and budget.dive_s == pytest.approx(dive, abs=0.5)
    assert budget.dive_s + budget.times_s[-1] == pytest.approx(expected + SIM.arrival_radius / (V + _u(expected)),
                                                               abs=0.5)
    # the track: at the surface above the start, held there while it sinks, at the first waypoint by the dive's end
    assert r.position[0].tolist() == [1000.0, 3000.0, 0.0]
    diving = r.t < dive - 1.0
    assert diving.sum() > 300 and np.abs(r.position[diving, :2] - ROUTE[0, :2]).max() < 1e-9
    k = int(np.searchsorted(r.t, dive + 1.0))
    assert r.position[k, 2] == pytest.approx(-1000.0, abs=0.5) and r.position[k, 0] < 1000.0 + 2.0 * (V + U0)


def test_without_navigation_the_flight_starts_at_the_first_waypoint():
    """No ``[navigation]``: nothing budgets a launch, the flight starts at depth as before (every other scenario)."""
    r = simulate(_world(), _mission(), route=ROUTE, rng=3)
    assert r.arrived and r.position[0].tolist() == ROUTE[0].tolist()
    assert r.t[-1] == pytest.approx(_arrival(0.0), abs=2.0)


def test_the_dives_drift_is_the_budgets_launch_drift():
    """With a drifting estimate the error at the first waypoint is the launch's: D0 = w0 · drift_pct_no_lock / 100
    (w0 = ∫ |u| dt over the dive, no bottom lock 2 000 m above the seabed) in the drawn direction, on top of the fix's
    own error (σ 3 m): |e| within 3 σ_fix of D0 over the dive (w0 = 481 m: D0 = 4.8 m)."""
    from auvplan.sim.drift import NavDrift

    world = _world()
    dive = _dive()
    t = np.linspace(0.0, dive, 20001)
    w0 = float(np.sum(np.abs(_u((t[1:] + t[:-1]) / 2))) * (t[1] - t[0]))
    d0 = w0 * NAV.drift_pct_no_lock / 100.0
    r = simulate(world, _mission(navigation=NAV, nav_drift=True), route=ROUTE, rng=3)
    assert r.nav_error is not None
    k = int(np.searchsorted(r.t, dive))
    seed = int(np.random.default_rng(3).integers(2**63))  # the loop's own stream for the drift (no waves, no avoidance)
    probe = NavDrift(NAV, np.random.default_rng(seed))  # the same draws: the fix's error and the drift direction
    expected = np.hypot(*(probe.error + d0 * probe.u))
    assert math.isclose(r.nav_error[k], expected, rel_tol=0.02, abs_tol=0.05)
    assert r.nav_error[0] == pytest.approx(np.hypot(*probe.error), abs=1e-9)


def test_the_reports_error_against_time_puts_both_clocks_at_the_first_waypoint():
    """The report's navigation figure: the flown true error (now from the launch) is drawn on the planned time's
    origin, the arrival at the first waypoint: the two curves end together (the flight at its arrival radius)."""
    from auvplan.sim import RunRecord
    from auvplan.sim.navigation import navigation_plan
    from auvplan.viz.navview import figure_nav_error, nav_profile

    world = _world()
    mission = _mission(navigation=NAV, nav_drift=True)
    nav = navigation_plan(world, mission, ROUTE)
    assert nav is not None
    r = simulate(world, mission, route=ROUTE, rng=3)
    fig = figure_nav_error(nav_profile(world, nav), nav, RunRecord("t", 3, None, ROUTE, ROUTE, r, nav))
    (planned,) = [t for t in fig.data if t.meta and t.meta["kind"] == "nav_error"]
    (flown,) = [t for t in fig.data if t.meta and t.meta["kind"] == "nav_error_flown"]
    end = float(planned.x[-1]) * 3600.0
    assert end == pytest.approx(_arrival(_dive()) - _dive() + SIM.arrival_radius / (V + _u(end + _dive())), abs=0.5)
    # the flight arrives where it believes the goal is: within its estimate's error of it
    late = float(np.max(r.nav_error)) / (V + _u(end + _dive())) + 2.0
    assert float(flown.x[-1]) * 3600.0 == pytest.approx(end - SIM.arrival_radius / (V + _u(end + _dive())), abs=late)
    assert late < 60.0  # (the dive's 766 s would be far outside)
    assert float(flown.x[0]) * 3600.0 == pytest.approx(-_dive(), abs=2.0)  # the dive before the first waypoint
    # (recorded every 2 s)
