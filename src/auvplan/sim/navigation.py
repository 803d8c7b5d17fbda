"""A mission's navigation budget as it is flown (``[navigation]``, issue 52): the route's position fixes planned
(:func:`navigation_plan`) and checked again with each leg flown through the World's current at its own speed, its
drift without bottom lock over its distance through the water (:func:`timed_navigation`)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from ..endurance import traverse
from ..nav.fixes import best_period, route_profile
from ..nav.mission import NavPlan, plan_navigation, through_water
from ..world import World
from .mission import Mission

__all__ = ["navigation_plan", "timed_navigation"]


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
    ratio = None
    if p.shape[0] >= 2:  # the drift without bottom lock over the water distance: the route flown at the cruise speed
        tr = traverse(world, p, v.speed)
        h = np.hypot(*np.diff(p[:, :2], axis=0).T)
        ratio = np.where(h > 0.0, tr.leg_water_m() / np.where(h > 0.0, h, 1.0), 1.0) if tr.ok else None
    budget = nav
    for _ in range(4):  # the planner's water distances are its route legs'; the check flies the mission's own legs
        planned = plan_navigation(world, p, budget, v.max_pitch_deg, v.speed, nav.usbl_xy, water_ratio=ratio,
                                  compare=False)
        timed = timed_navigation(world, mission, replace(planned, params=nav))
        over = timed.check.budget.max_error_m / nav.max_error_m
        if timed.ok or not planned.fixes.ok or over <= 1.0:
            break
        budget = replace(budget, max_error_m=budget.max_error_m / over * (1.0 - 1e-3))  # plan within E / overshoot
    if nav.fixes == "plan" and planned.fixes.ok:  # the best fixed period with the planned fixes' largest error
        prof = route_profile(world, p, nav, v.max_pitch_deg, v.speed, water_ratio=ratio)
        timed = replace(timed, fixed_period=best_period(prof, nav, v.speed, planned.fixes.max_error_m))
    return timed


def timed_navigation(world: World, mission: Mission, nav: NavPlan, tail: ArrayLike | None = None) -> NavPlan:
    """The fixes' planned times through the World's current at each leg's speed (``fixes.csv`` ``t_s``), and
    the budget checked again with each leg's drift without bottom lock over its distance through the water
    (:func:`auvplan.nav.mission.through_water`).

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
    return through_water(world, nav.timed(tr.times), tr.leg_water_m()) if tr.ok else nav
