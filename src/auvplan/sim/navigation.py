"""A mission's navigation budget as it is flown (``[navigation]``, issue 52): the route's position fixes planned
(:func:`navigation_plan`) and checked again with each leg flown through the World's current at its own speed, its
drift without bottom lock over its distance through the water (:func:`timed_navigation`).  Both count the launch: the
dive from the surface above the start to it, flown as a ``.plan`` flies its launch from its home (a vertical leg at
:data:`~auvplan.nav.budget.LAUNCH_DIVE_MPS`), so that the budget planned is the one ``mission check`` finds in the
exported ``.plan`` (:func:`launch_flight`)."""

from __future__ import annotations

from dataclasses import replace
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ..endurance import EnergyModel, choose_speeds, traverse
from ..nav.budget import LAUNCH_DIVE_MPS, launch_drift, launch_point
from ..nav.fixes import best_period, route_profile
from ..nav.mission import NavPlan, plan_navigation, through_water
from ..world import World
from .mission import Mission

__all__ = ["navigation_plan", "timed_navigation", "launch_flight", "LaunchFlight", "with_leg_speeds"]


class LaunchFlight(NamedTuple):
    """A mission flown from its launch (:func:`launch_flight`); times and distances from the first waypoint.

    Attributes
    ----------
    launch_water_m : float
        The dive's horizontal distance through the water (m).
    leg_water_m : numpy.ndarray
        ``(N - 1,)`` each leg's (m).
    times_s : numpy.ndarray
        ``(N,)`` arrival at each waypoint (s from the arrival at the first, dwells included).
    node_s, node_t : numpy.ndarray
        The flight's sub-step nodes after the dive: distance along the mission (3D, m) and time (s), both from the
        first waypoint.
    dive_s : float
        The dive's duration (s): the arrival at the first waypoint after the launch.
    """

    launch_water_m: float
    leg_water_m: np.ndarray
    times_s: np.ndarray
    node_s: np.ndarray
    node_t: np.ndarray
    dive_s: float = 0.0


def launch_flight(world: World, points: ArrayLike, speeds: ArrayLike | float, tail: ArrayLike | None = None,
                  dwell: ArrayLike | None = None) -> LaunchFlight | None:
    """The mission flown from its launch, as a ``.plan`` is (``mission check``): the dive from the surface above the
    first waypoint at :data:`~auvplan.nav.budget.LAUNCH_DIVE_MPS`, then its legs, one flight through the current.

    Parameters
    ----------
    world : World
        Its currents.
    points : array_like
        ``(N, 3)`` the mission's waypoints (m), N ≥ 2.
    speeds : array_like or float
        Each leg's speed ``(N - 1,)`` or one (m/s).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first.
    dwell : array_like, optional
        ``(N,)`` time held at each waypoint (s).

    Returns
    -------
    LaunchFlight or None
        The launch's and each leg's horizontal distance through the water, and the legs' times, flown in the current
        as it is once the dive is over (from the first waypoint); None where the current beats the vehicle.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    legs = p.shape[0] - 1
    v = np.r_[LAUNCH_DIVE_MPS, np.broadcast_to(np.asarray(speeds, dtype=float), (legs,))]
    back = None if tail is None else np.r_[False, np.asarray(tail, dtype=bool).reshape(-1)]
    held = None if dwell is None else np.r_[0.0, np.asarray(dwell, dtype=float).reshape(-1)]
    tr = traverse(world, np.vstack([launch_point(p), p]), v, 0.0, tail=back, dwell=held)
    if not tr.ok:
        return None
    w = tr.leg_water_m()
    dive = float(np.linalg.norm(p[0] - launch_point(p)))
    after = tr.node_s >= dive - 1e-9  # the nodes from the first waypoint on
    return LaunchFlight(float(w[0]), w[1:], tr.times[1:] - tr.times[1], tr.node_s[after] - dive,
                        tr.node_t[after] - tr.times[1], float(tr.times[1] - tr.times[0]))


def navigation_plan(world: World, mission: Mission, route: ArrayLike) -> NavPlan | None:
    """The route's position fixes and navigation budget (``[navigation]``; :func:`auvplan.nav.plan_navigation`).

    Parameters
    ----------
    world : World
        Seabed, obstacles, margins.
    mission : Mission
        Its ``navigation`` settings and vehicle (pitch limit, speed).
    route : array_like
        ``(N, 3)`` the route (m).

    Returns
    -------
    NavPlan or None
        None for a mission without ``[navigation]`` (perfect navigation).
    """
    nav = mission.navigation
    if nav is None:
        return None
    v = mission.vehicle
    p = np.asarray(route, dtype=float).reshape(-1, 3)
    ratio, d0, flight = None, 0.0, None
    if p.shape[0] >= 2:  # the drift without bottom lock over the water distance: the route flown at the speeds it is
        speeds = _flown_speeds(world, mission, p)  # flown at ([endurance] speeds), launched from the surface
        flown = launch_flight(world, p, speeds)
        h = np.hypot(*np.diff(p[:, :2], axis=0).T)
        if flown is not None:  # the periodic fixes' timer through the current on the same flight, after the dive
            ratio = np.where(h > 0.0, flown.leg_water_m / np.where(h > 0.0, h, 1.0), 1.0)
            d0 = launch_drift(world, p[0], nav, flown.launch_water_m)
            flight = (flown.node_s, flown.node_t)
        else:
            tr = traverse(world, p, speeds)  # the current beats the dive, not the route: no launch counted
            if tr.ok:
                flight = (tr.node_s, tr.node_t)
                ratio = np.where(h > 0.0, tr.leg_water_m() / np.where(h > 0.0, h, 1.0), 1.0)
    budget = nav
    for _ in range(4):  # the planner's water distances are its route legs'; the check flies the mission's own legs
        planned = plan_navigation(world, p, budget, v.max_pitch_deg, v.speed, nav.usbl_xy, water_ratio=ratio,
                                  compare=False, launch_m=d0, flight=flight)
        # checked at the speeds the mission with its fixes is flown at ([endurance] speeds), as run times it
        timed = timed_navigation(world, _with_speeds(world, mission, planned.points), replace(planned, params=nav))
        over = timed.check.budget.max_error_m / nav.max_error_m
        if timed.ok or not planned.fixes.ok or over <= 1.0:
            break
        budget = replace(budget, max_error_m=budget.max_error_m / over * (1.0 - 1e-3))  # plan within E / overshoot
    if nav.fixes == "plan" and planned.fixes.ok:  # the best fixed period with the planned fixes' largest error
        prof = route_profile(world, p, nav, v.max_pitch_deg, v.speed, water_ratio=ratio, launch_m=d0, flight=flight)
        timed = replace(timed, fixed_period=best_period(prof, nav, v.speed, planned.fixes.max_error_m))
    return timed


def with_leg_speeds(world: World, mission: Mission, route: ArrayLike, tail: ArrayLike | None = None) -> Mission:
    """The mission with the speed of each leg of ``route`` chosen by ``[endurance] speeds`` (issue 38).

    Parameters
    ----------
    world : World
        Its currents.
    mission : Mission
        Vehicle, endurance settings and any leg speeds already set.
    route : array_like
        ``(N, 3)`` the route to fly (m).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first (:func:`auvplan.sim.pipeline.route_tail`).

    Returns
    -------
    Mission
        ``mission`` itself for ``speeds = "fixed"`` or when it has leg speeds; else with ``leg_speeds``
        from :func:`auvplan.endurance.choose_speeds` from the start time.
    """
    e = mission.endurance
    if e.speeds == "fixed" or mission.leg_speeds:
        return mission
    model = EnergyModel.from_vehicle(mission.vehicle)
    plan = choose_speeds(world, route, model, mission.vehicle.speed, e.speeds, e.deadline_s, 0.0, e.ds_m, tail=tail)
    sim = mission.sim
    if sim.max_time == 0:  # the loop's default allows 3× the route at the cruise speed: at the slowest leg speed
        length = float(np.linalg.norm(np.diff(np.asarray(route, dtype=float), axis=0), axis=1).sum())
        sim = replace(sim, max_time=3.0 * length / float(plan.speeds.min()) + 120.0)
    return replace(mission, leg_speeds=tuple(float(v) for v in plan.speeds), sim=sim)


def _with_speeds(world: World, mission: Mission, points: np.ndarray) -> Mission:
    """The mission with the leg speeds ``[endurance] speeds`` chooses for ``points`` (``run``'s:
    :func:`with_leg_speeds`); itself for ``speeds = "fixed"``."""
    if mission.endurance.speeds == "fixed" or points.shape[0] < 2:
        return mission
    return with_leg_speeds(world, replace(mission, leg_speeds=()), points)


def _flown_speeds(world: World, mission: Mission, points: np.ndarray) -> np.ndarray | float:
    """The speed of each leg of ``points`` as it will be flown (:func:`_with_speeds`), or the cruise speed."""
    m = _with_speeds(world, mission, points)
    return np.asarray(m.leg_speeds) if len(m.leg_speeds) == points.shape[0] - 1 else mission.vehicle.speed


def timed_navigation(world: World, mission: Mission, nav: NavPlan, tail: ArrayLike | None = None) -> NavPlan:
    """The fixes' planned times through the World's current at each leg's speed (``fixes.csv`` ``t_s``), and
    the budget checked again with each leg's drift without bottom lock over its distance through the water
    (:func:`auvplan.nav.mission.through_water`), the launch's dive counted, flown first (:func:`launch_flight`).
    The times are those of that one flight (in a current that changes in time, the legs flown once the dive is
    over, as the exported ``.plan``'s check flies them), counted from the arrival at the first waypoint.

    Parameters
    ----------
    world : World
        Its currents.
    mission : Mission
        Its leg speeds (one per leg of ``nav.points``; else the cruise speed).
    nav : NavPlan
        The mission's waypoints, fixes and dwells.
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first.

    Returns
    -------
    NavPlan
        ``nav`` with its waypoints' arrival times (:meth:`~auvplan.nav.NavPlan.timed`) and its legs' water
        distances; unchanged where the current beats the vehicle on a leg (the endurance check says so).
    """
    p = nav.points
    if p.shape[0] < 2:
        return nav
    legs = p.shape[0] - 1
    speeds = mission.leg_speeds if len(mission.leg_speeds) == legs else mission.vehicle.speed
    back = None if tail is None or np.asarray(tail).size != legs else tail
    tr = traverse(world, p, speeds, 0.0, tail=back, dwell=nav.dwell_s)
    if not tr.ok:
        return nav
    flown = launch_flight(world, p, speeds, back, nav.dwell_s)
    if flown is None:  # the current beats the dive: the legs' own water distances, the launch not counted
        return through_water(world, nav.timed(tr.times), tr.leg_water_m())
    # the times of the flight the budget counts (and the .plan's check flies): the legs after the launch's dive
    return through_water(world, nav.timed(flown.times_s), flown.leg_water_m, launch_water_m=flown.launch_water_m)
