"""The scenario pipeline (DESIGN.md §1): global plan → executable mission route → key waypoints →
closed-loop simulation (:func:`run_mission`), and its pieces."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import RngLike, Status
from ..guidance.avoidance.local import key_waypoints
from ..guidance.mission.fit import MissionFit, fit_mission, fit_turns
from ..guidance.mission.legs import merge_short_legs
from ..guidance.mission.waypoints import build_waypoints, default_tolerance
from ..path import resample_polyline
from ..path.legs import helm_check, shortest_leg
from ..planners import plan as global_plan
from ..planners.core.base import PlanResult, Progress
from ..world import World
from .band import altitude_band_metrics
from .loop import simulate
from .mission import Mission
from .navigation import navigation_plan, timed_navigation, with_leg_speeds  # (with_leg_speeds: re-exported)
from .problem import planning_problem, vehicle_limits
from .result import RunRecord
from .tracking import TrackingBound, contract_world, route_bound, route_keeps

__all__ = ["kept_fit", "CONTRACT_ROUNDS", "CONTRACT_ROOM",
           "vehicle_limits", "fitted_route", "planning_problem", "run_mission", "route_from_path",
           "mission_route", "timed_waypoints", "route_tail", "record_tail", "planned_route", "planned_fit",
           "with_leg_speeds"]


def route_from_path(path: ArrayLike, spacing: float) -> NDArray[np.float64]:
    """Resample a dense planned path into waypoints every ``spacing`` metres.

    The ends are kept; the result is not checked: use :func:`mission_route` for the mission a
    vehicle flies.

    Parameters
    ----------
    path : array_like
        ``(M, 3)`` dense path (m).
    spacing : float
        Distance between waypoints along the path (m).

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m).
    """
    return resample_polyline(path, spacing)


def fitted_route(world: World, mission: Mission, route: ArrayLike) -> MissionFit:
    """A mission's waypoints held to its vehicle's limits (:func:`auvplan.guidance.mission.fit.fit_mission`).

    Legs shorter than the shortest leg (:func:`auvplan.path.legs.shortest_leg`) lose an end where that is safe
    (:func:`auvplan.guidance.mission.legs.merge_short_legs`); a mission then within the limits leg by leg
    (:func:`auvplan.path.legs.helm_check`) and without ``follow_altitude_m`` is kept as it is; otherwise its
    depth schedule is fitted (terrain following, climbs within the pitch limit, fly-by turns).

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    mission : Mission
        The vehicle (its limits) and ``follow_altitude_m``.
    route : array_like
        ``(N, 3)`` waypoints (m).

    Returns
    -------
    MissionFit
        The waypoints, their limit report and whether the vehicle can fly them.
    """
    lim = vehicle_limits(mission.vehicle)
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    w = w[merge_short_legs(world, w, shortest_leg(lim), max_pitch_deg=lim.max_pitch_deg)]
    if mission.follow_altitude_m <= 0.0:
        report = helm_check(w, lim)
        if report.ok:
            return MissionFit(w, report, True, "")
    return fit_mission(w, world, lim, mission.follow_altitude_m)


def mission_route(world: World, mission: Mission, path: ArrayLike, times: ArrayLike | None = None,
                  speed: float | None = None, tail: ArrayLike | None = None) -> NDArray[np.float64]:
    """Build the executable mission of a planned path: the waypoints the simulation flies and every export carries.

    :func:`auvplan.guidance.mission.waypoints.build_waypoints`: floors under rising seabed, 3D
    Douglas–Peucker where the exact envelope test decides what may be dropped; corners whose
    fly-by turns do not fit dropped where the new leg is free
    (:func:`auvplan.guidance.mission.fit.fit_turns`); then :func:`fitted_route` (the vehicle's
    limits, terrain following).

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    mission : Mission
        The vehicle's limits and ``follow_altitude_m``.
    path : array_like
        ``(M, 3)`` dense planned path (m).
    times, speed : array_like and float, optional
        A timed plan's time at each vertex (s) and through-water speed (m/s): its waypoints keep
        its duration (:func:`timed_waypoints`).
    tail : array_like of bool, optional
        A timed plan's legs flown tail-first (``plan.tail``): then its own vertices are kept (the
        route's flags: :func:`route_tail`).

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m), safe under held and ramped depth semantics.
    """
    leg = shortest_leg(vehicle_limits(mission.vehicle))
    if tail is not None and np.any(tail) and times is not None:  # keep every vertex where the mode changes
        p, flags = np.asarray(path, dtype=float).reshape(-1, 3), np.asarray(tail, dtype=bool)
        cuts = np.r_[0, np.flatnonzero(flags[1:] != flags[:-1]) + 1, flags.size]
        parts = [build_waypoints(p[i:j + 1], world, tolerance=0.5, min_leg=leg)
                 for i, j in zip(cuts[:-1], cuts[1:], strict=True)]
        w = np.vstack([parts[0]] + [q[1:] for q in parts[1:]])
    else:
        w = build_waypoints(path, world, min_leg=leg) if times is None or speed is None else \
            timed_waypoints(world, path, times, speed, min_leg=leg)
    w = fit_turns(w, world, mission.vehicle.turn_radius_m)
    return fitted_route(world, mission, w).waypoints


def route_tail(route: ArrayLike, path: ArrayLike, tail: ArrayLike | None) -> NDArray[np.bool_] | None:
    """Which legs of a mission's route fly tail-first: those whose midpoint lies nearest a plan's tail-first leg.

    Parameters
    ----------
    route : array_like
        ``(N, 3)`` the route's waypoints (:func:`mission_route`) (m).
    path : array_like
        ``(M, 3)`` the plan's vertices (m).
    tail : array_like of bool or None
        ``(M - 1,)`` the plan's tail-first legs (``plan.tail``).

    Returns
    -------
    numpy.ndarray of bool or None
        ``(N - 1,)`` flags (None when the plan has none).
    """
    if tail is None or not np.any(tail):
        return None
    w, p = np.asarray(route, dtype=float).reshape(-1, 3), np.asarray(path, dtype=float).reshape(-1, 3)
    a, d = p[:-1, :2], np.diff(p[:, :2], axis=0)
    mid = 0.5 * (w[:-1, :2] + w[1:, :2])
    s = np.clip(np.einsum("lk,mlk->ml", d, mid[:, None, :] - a[None]) / np.maximum((d * d).sum(1), 1e-12), 0.0, 1.0)
    dist = np.linalg.norm(a[None] + s[..., None] * d[None] - mid[:, None, :], axis=2)
    flags: NDArray[np.bool_] = np.asarray(tail, dtype=bool)[dist.argmin(axis=1)]
    return flags


def record_tail(record: RunRecord) -> NDArray[np.bool_] | None:
    """The tail-first legs of a run's route (:func:`route_tail` of its plan), as the follower flew them.

    Parameters
    ----------
    record : RunRecord
        The run: its plan and route.

    Returns
    -------
    numpy.ndarray of bool or None
        ``(N - 1,)`` flags; None when no leg is flown tail-first.
    """
    p = record.plan
    return None if p is None or record.route.shape[0] < 2 else route_tail(record.route, p.path, p.tail)


def timed_waypoints(world: World, path: ArrayLike, times: ArrayLike, speed: float,
                    rel: float = 0.002, min_leg: float = 0.0) -> NDArray[np.float64]:
    """The key waypoints of a timed plan (``plan.times``, the time-optimal planner) that keep its duration.

    :func:`auvplan.guidance.mission.waypoints.build_waypoints` simplifies with a tolerance of 0.2 % of the
    length (up to 50 m, in 3D): in a current that changes with depth and place, the plan's small
    depth changes and bends are what make it fast, and dropping them can cost more than 1 % of its
    time (issue 36).  The tolerance is divided by 4 until the waypoints, flown through the World's
    current from the plan's departure (:func:`auvplan.planners.timeopt.timing.fly_times`), take
    at most ``rel`` longer than the plan (down to 0.5 m, where the plan's own vertices are kept).

    Parameters
    ----------
    world : World
        Seabed, obstacles, margins and the current.
    path : array_like
        ``(M, 3)`` the timed plan's vertices (m).
    times : array_like
        ``(M,)`` its time at each vertex (s).
    speed : float
        Its through-water speed (m/s).
    rel : float, default 0.002
        Largest relative increase of the duration.
    min_leg : float, default 0.0
        Shortest leg of the refinement next to obstacles (m; :func:`auvplan.path.legs.shortest_leg`).

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m).
    """
    from ..planners.timeopt.timing import fly_times

    t = np.asarray(times, dtype=float)
    depart, duration = float(t[0]), float(t[-1] - t[0])
    tol = default_tolerance(path)
    while True:
        w = build_waypoints(path, world, tolerance=tol, min_leg=min_leg)
        if tol <= 0.5:
            return w
        flown = fly_times(world.currents, w, depart, speed, 50.0, depart + 3.0 * duration + 3600.0)[0][-1] - depart
        if flown <= duration * (1.0 + rel):
            return w
        tol = max(0.25 * tol, 0.5)


def planned_route(world: World, mission: Mission, seed: RngLike,
                  progress: Progress | None = None) -> tuple[PlanResult | None, NDArray[np.float64] | None]:
    """The route a mission flies: :func:`planned_fit`'s waypoints.

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        What to do.
    seed : Generator, int or None
        Seed of the planner.
    progress : callable, optional
        ``progress(iteration, best)`` of a swarm planner.

    Returns
    -------
    tuple
        The plan (None for a fixed route the vehicle can fly) and the route ``(N, 3)`` (m), None when the plan
        or the fit failed.
    """
    planned, fit = planned_fit(world, mission, seed, progress)
    return planned, fit.waypoints if fit is not None else None


def planned_fit(world: World, mission: Mission, seed: RngLike,
                progress: Progress | None = None) -> tuple[PlanResult | None, MissionFit | None]:
    """The route a mission flies: its fixed route, or the global plan's (:func:`mission_route`).

    Either is held to the vehicle's limits (:func:`fitted_route`); a mission the vehicle cannot
    fly is an ``INFEASIBLE`` plan naming the leg and the limit, with no route.

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        What to do.
    seed : Generator, int or None
        Seed of the planner.
    progress : callable, optional
        ``progress(iteration, best)`` of a swarm planner.

    Returns
    -------
    tuple
        The plan (None for a fixed route the vehicle can fly) and the fitted route (:class:`MissionFit`: its
        waypoints ``(N, 3)`` (m) and altitude band), None when the plan or the fit failed.
    """
    if mission.route:
        fit = fitted_route(world, mission, mission.route)
        if fit.ok:
            return None, fit
        route = np.asarray(mission.route, dtype=float)
        return PlanResult(Status.INFEASIBLE, route, float("inf"), {}, 0, 0, 0.0, np.empty(0), "route",
                          message=f"the vehicle cannot fly the [mission] route: {fit.message}"), None
    planned = global_plan(planning_problem(world, mission), mission.planner, seed, progress)
    if not planned.status.ok:
        return planned, None
    if planned.tail is not None and planned.times is not None:  # tail-first legs: every mode change kept
        w = mission_route(world, mission, planned.path, planned.times, float(planned.cost_terms["speed_m_s"]),
                          planned.tail)
    else:
        leg = shortest_leg(vehicle_limits(mission.vehicle))
        w = build_waypoints(planned.path, world, min_leg=leg) if planned.times is None else \
            timed_waypoints(world, planned.path, planned.times, float(planned.cost_terms["speed_m_s"]), min_leg=leg)
    fit = fitted_route(world, mission, fit_turns(w, world, mission.vehicle.turn_radius_m))
    if not fit.ok:
        return replace(planned, status=Status.INFEASIBLE,
                       message=f"the vehicle cannot fly the mission built from the plan: {fit.message}"), None
    return planned, fit


CONTRACT_ROUNDS = 3
"""Re-plans with a raised margin before the clearance contract gives up (:func:`kept_fit`)."""
CONTRACT_ROOM = 0.01
"""How far inside the start's or the goal's own clearance a raised margin stays (m; :func:`kept_fit`)."""


def kept_fit(world: World, mission: Mission, seed: RngLike, progress: Progress | None = None,
             follower: str | None = None) -> tuple[PlanResult | None, MissionFit | None]:
    """The planned route under the clearance contract between planner and follower (issue 57 item 2).

    The route of :func:`planned_fit` is flown by the follower without obstacles
    (:func:`auvplan.sim.tracking.route_bound`); when a leg comes closer to a static obstacle than the
    mission's margin plus its bound, the plan is made again with the margin raised by the route's largest bound
    (:func:`auvplan.sim.tracking.contract_world`; at most to :data:`CONTRACT_ROOM` inside the start's and the
    goal's own clearance, so that they stay free), up to :data:`CONTRACT_ROUNDS` times.  A plan that cannot
    keep the clearance (its start or goal inside the raised margin, no route, or no round that keeps it)
    is returned with its status (``INVALID_START``, ``INVALID_GOAL``, ``INFEASIBLE``) and a message naming
    the follower, the bound and the margin.  A fixed route and a world without static obstacles are
    returned as :func:`planned_fit` gives them.  A kept plan's ``cost_terms`` carry ``tracking_bound_m``.

    Parameters
    ----------
    world : World
        Environment (the margin raised only for planning).
    mission : Mission
        What to do.
    seed : Generator, int or None
        Seed of the planner.
    progress : callable, optional
        ``progress(iteration, best)`` of a swarm planner.
    follower : str, optional
        The path follower that flies the route; the mission's ``guidance`` by default.

    Returns
    -------
    tuple
        The plan and the fitted route (:class:`MissionFit`: its waypoints ``(N, 3)`` (m) and altitude band),
        None when the plan or the contract failed.
    """
    planned, fit = planned_fit(world, mission, seed, progress)
    if fit is None or planned is None or mission.route or not world.obstacles:
        return planned, fit
    route = fit.waypoints
    margin, name = world.margins.obstacle, follower or mission.guidance
    ends = np.array([mission.start, mission.goal], dtype=float)
    room = float(np.min([ob.distance(ends) for ob in world.obstacles])) - margin - CONTRACT_ROOM
    raised = 0.0
    for rounds in range(CONTRACT_ROUNDS + 1):
        bound = route_bound(world, mission, route, name)
        leg = route_keeps(world, route, margin + bound.per_leg_m)
        if leg < 0:
            return replace(planned, cost_terms={**planned.cost_terms, "tracking_bound_m": bound.total_m}), fit
        why = _too_close(name, leg, bound, margin)
        if rounds == CONTRACT_ROUNDS:
            break
        raised = min(max(raised, bound.total_m), room)  # the start and the goal stay outside the raised margin
        if raised <= 0.0:
            break
        planned, fit = planned_fit(contract_world(world, raised), mission, seed, progress)
        if fit is None or planned is None:
            msg = f"clearance contract: {why}; planned again with the obstacle margin {margin + raised:.2f} m: "
            return (None if planned is None else replace(planned, message=msg + planned.message)), None
        route = fit.waypoints
    tried = f"{rounds} plans with a raised margin did not keep it" if rounds else \
        f"the start or the goal lies within {margin + CONTRACT_ROOM:g} m of an obstacle: no room to raise the margin"
    return replace(planned, status=Status.INFEASIBLE, message=f"clearance contract: {why}; {tried}"), None


def _too_close(name: str, leg: int, bound: TrackingBound, margin: float) -> str:
    """Why a route breaks the clearance contract at ``leg``: the follower's bound there and the margin."""
    return (f"the {name} follower leaves this route's leg {leg} by up to {bound.per_leg_m[leg]:.2f} m (flown "
            "without obstacles" + (f", + its push bound {bound.push_m:g} m" if bound.push_m else "")
            + f"), and the leg passes closer than the {margin:g} m margin + that to an obstacle")


def run_mission(world: World, mission: Mission, rng: RngLike = None,
                progress: Progress | None = None, guidance: str | None = None,
                avoidance: str | None = None, flight: Callable[[float, float], object] | None = None) -> RunRecord:
    """Scenario pipeline: global plan → key waypoints → closed-loop simulation (DESIGN.md §1).

    A mission with a fixed route skips the planner.  A failed plan is returned with no
    simulation (its status says why).

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        What to do.
    rng : Generator, int or None
        Seed of the planner and of the simulation (the mission's seed by default).
    progress : callable, optional
        ``progress(iteration, best)`` of a swarm planner.
    flight : callable, optional
        The simulation's progress callback (see :func:`simulate`).
    guidance, avoidance : str, optional
        Override the mission's path follower and local avoidance.

    Returns
    -------
    RunRecord
        Plan, route, key waypoints and simulation.
    """
    seed = mission.seed if rng is None else rng
    recorded = int(seed) if isinstance(seed, int | np.integer) else -1
    planned, fit = kept_fit(world, mission, seed, progress, guidance)
    if fit is None:
        return RunRecord(mission.name, recorded, planned, np.empty((0, 3)), np.empty((0, 3)), None)
    route = fit.waypoints
    nav = navigation_plan(world, mission, route)
    if nav is not None:  # the fixes are part of the mission: surfacings (depth 0) and USBL fix waypoints
        route = nav.points
        if not nav.ok:
            return RunRecord(mission.name, recorded, planned, route, np.empty((0, 3)), None, nav)
    keys = key_waypoints(route, world, mission.avoidance.collision_check)
    tail = route_tail(route, planned.path, planned.tail) if planned is not None else None
    mission = with_leg_speeds(world, mission, route, tail)
    if nav is not None and mission.leg_speeds:  # the fixes' times at the speeds chosen for the legs
        nav = timed_navigation(world, mission, nav, tail)
    if planned is not None and (planned.cost_terms.get("drift_back_m", 0.0) > 0.0  # a timed plan the tide pushes
                                or planned.cost_terms.get("tail_first_legs", 0) > 0):  # (or carries slowly)
        wait = max(mission.sim.deadlock_time, float(planned.cost_terms["duration_s"]))  # back a while: no deadlock
        mission = replace(mission, sim=replace(mission.sim, deadlock_time=wait))
    result = simulate(world, mission, route=route, guidance=guidance, rng=seed, avoidance=avoidance, keys=keys,
                      progress=flight, tail=tail, fix_kinds=nav.kinds if nav is not None else None)
    altitude = altitude_band_metrics(world.terrain, route, fit.band, (result.progress, result.altitude)) \
        if world.terrain is not None and fit.band.target_m > 0.0 else None
    return RunRecord(mission.name, recorded, planned, route, keys, result, nav, altitude)
