"""The scenario pipeline (DESIGN.md §1): global plan → executable mission route → key waypoints →
closed-loop simulation (:func:`run_mission`), and its pieces."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import RngLike
from ..endurance import EnergyModel, choose_speeds
from ..guidance.local import key_waypoints
from ..guidance.mission import build_waypoints
from ..path import resample_polyline
from ..planners import plan as global_plan
from ..planners.base import PlanningProblem, PlanResult, Progress
from ..world import World
from .loop import simulate
from .mission import Mission
from .result import RunRecord

__all__ = ["planning_problem", "run_mission", "route_from_path", "mission_route", "planned_route", "with_leg_speeds"]


def planning_problem(world: World, mission: Mission) -> PlanningProblem:
    """Build the global planning problem of a mission in a world.

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        End points and vehicle figures (speed, hotel power, drag).

    Returns
    -------
    PlanningProblem
        Start, goal (m), speed (m/s), hotel power (W) and drag factor (W s³/m³) in the world.
    """
    v = mission.vehicle
    return PlanningProblem(world, np.asarray(mission.start, dtype=float), np.asarray(mission.goal, dtype=float),
                           v.speed, v.hotel_power, v.drag_k)


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


def mission_route(world: World, mission: Mission, path: ArrayLike) -> NDArray[np.float64]:
    """Build the executable mission of a planned path: the waypoints the simulation flies and every export carries.

    :func:`auvplan.guidance.mission.build_waypoints`: floors under rising seabed, 3D
    Douglas–Peucker where the exact envelope test decides what may be dropped.

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    mission : Mission
        The mission (unused today; kept for mission-specific settings).
    path : array_like
        ``(M, 3)`` dense planned path (m).

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m), safe under held and ramped depth semantics.
    """
    return build_waypoints(path, world)


def planned_route(world: World, mission: Mission, seed: RngLike,
                  progress: Progress | None = None) -> tuple[PlanResult | None, NDArray[np.float64] | None]:
    """The route a mission flies: its fixed route, or the global plan's (:func:`mission_route`).

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
        The plan (None for a fixed route) and the route ``(N, 3)`` (m), None when the plan failed.
    """
    if mission.route:
        return None, np.asarray(mission.route, dtype=float)
    planned = global_plan(planning_problem(world, mission), mission.planner, seed, progress)
    if not planned.status.ok:
        return planned, None
    return planned, mission_route(world, mission, planned.path)


def with_leg_speeds(world: World, mission: Mission, route: ArrayLike) -> Mission:
    """The mission with the speed of each leg of ``route`` chosen by ``[endurance] speeds`` (issue 38).

    Parameters
    ----------
    world : World
        Its currents.
    mission : Mission
        Vehicle, endurance settings and any leg speeds already set.
    route : array_like
        ``(N, 3)`` the route to fly (m).

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
    plan = choose_speeds(world, route, model, mission.vehicle.speed, e.speeds, e.deadline_s, 0.0, e.ds_m)
    sim = mission.sim
    if sim.max_time == 0:  # the loop's default allows 3× the route at the cruise speed: at the slowest leg speed
        length = float(np.linalg.norm(np.diff(np.asarray(route, dtype=float), axis=0), axis=1).sum())
        sim = replace(sim, max_time=3.0 * length / float(plan.speeds.min()) + 120.0)
    return replace(mission, leg_speeds=tuple(float(v) for v in plan.speeds), sim=sim)


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
    planned, route = planned_route(world, mission, seed, progress)
    if route is None:
        return RunRecord(mission.name, recorded, planned, np.empty((0, 3)), np.empty((0, 3)), None)
    keys = key_waypoints(route, world, mission.avoidance.collision_check)
    mission = with_leg_speeds(world, mission, route)
    result = simulate(world, mission, route=route, guidance=guidance, rng=seed, avoidance=avoidance, keys=keys,
                      progress=flight)
    return RunRecord(mission.name, recorded, planned, route, keys, result)
