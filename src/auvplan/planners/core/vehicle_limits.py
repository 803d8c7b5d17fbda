"""Every planner's result against the vehicle's limits: pitch (repaired), turn radius and depth rating.

:func:`enforce_limits` runs after any planner (:func:`auvplan.planners.plan`).  A plan whose legs
are steeper than ``max_pitch_deg`` is *repaired* in the vertical plane: its depth profile along
the horizontal track becomes :func:`auvplan.path.pitch.pitch_profile` (the plan's own depths where
they are flyable; climbs started early enough to clear every leg's highest seabed plus
``min_altitude``; the start and goal kept), and the exact segment test of the world decides
whether the repaired plan stands.  A plan whose turns do not fit ``turn_radius_m`` (the fly-by
condition of :mod:`auvplan.path.flyable`), that goes deeper than the depth rating, or whose repair
fails is ``INFEASIBLE`` with a message naming the leg and the limit — never ``EXACT``.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..._types import FloatArray, Status
from ...path.flyable import PITCH_SLACK_DEG, check_limits
from ...path.pitch import pitch_profile
from ...world import World
from .base import PlannerSpec, PlanningProblem, PlanResult
from .common import path_cost
from .registry import has

__all__ = ["enforce_limits", "repair_pitch", "vertex_floors"]


def vertex_floors(world: World, path: FloatArray) -> FloatArray:
    """Lowest safe z at each vertex: the highest seabed under either of its legs + ``min_altitude``.

    A leg whose two ends are at or above their floors clears the seabed by ``min_altitude`` all
    along (its z is between its ends' and both exceed the leg's highest seabed + the margin).

    Parameters
    ----------
    world : World
        Seabed and margins.
    path : numpy.ndarray
        ``(N, 3)`` polyline (m).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` z floors (m; ``-inf`` without terrain).
    """
    if world.terrain is None or len(path) < 2:
        return np.full(len(path), -np.inf)
    a, b = path[:-1].copy(), path[1:].copy()
    a[:, 2] = b[:, 2] = 0.0
    leg = -world.terrain.min_altitude_between(a, b) + world.margins.min_altitude
    out: FloatArray = np.maximum(np.r_[leg, -np.inf], np.r_[-np.inf, leg])
    return out


def repair_pitch(world: World, path: FloatArray, max_pitch_deg: float, slack: float = 0.05) -> FloatArray | None:
    """Re-shape a path's depth profile to the pitch limit (horizontal track unchanged).

    Parameters
    ----------
    world : World
        Seabed and margins.
    path : numpy.ndarray
        ``(N, 3)`` polyline (m).
    max_pitch_deg : float
        Pitch limit (degrees).
    slack : float, optional
        Extra altitude kept above ``min_altitude`` (m).

    Returns
    -------
    numpy.ndarray or None
        The repaired path, or None when no profile within the limit meets the start, the goal,
        the floors and the ceiling.
    """
    p = np.asarray(path, dtype=float)
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p[:, :2], axis=0).T))]
    m = world.margins
    floor = vertex_floors(world, p) + slack
    floor[[0, -1]] = -np.inf  # the ends are pinned where they are
    slope = math.tan(math.radians(max(max_pitch_deg - PITCH_SLACK_DEG, 0.5 * max_pitch_deg)))
    z, ok = pitch_profile(s, p[:, 2], floor, slope, float(p[0, 2]),
                          float(p[-1, 2]), ceiling=-m.min_depth, deepest=-m.max_depth)
    if not ok:
        return None
    out = p.copy()
    out[:, 2] = z
    out[[0, -1], 2] = p[[0, -1], 2]
    return out


def enforce_limits(problem: PlanningProblem, spec: PlannerSpec, result: PlanResult) -> PlanResult:
    """Hold a planner's result to the vehicle's limits (``problem.limits``; none: unchanged).

    Parameters
    ----------
    problem : PlanningProblem
        World, end points and the vehicle's limits.
    spec : PlannerSpec
        The cost function (to re-cost a repaired plan).
    result : PlanResult
        Any planner's result.

    Returns
    -------
    PlanResult
        ``result`` when it is within the limits or failed already; the pitch-repaired plan
        (re-costed, its message saying so); or ``INFEASIBLE`` naming the leg and the limit.
    """
    lim = problem.limits
    if lim is None or not result.status.ok or result.path.shape[0] < 2:
        return result
    report = check_limits(result.path, lim)
    if report.ok:
        return result
    steep = any(v.limit == "max_pitch_deg" for v in report.violations)
    if steep and result.times is None:
        fixed = repair_pitch(problem.world, result.path, lim.max_pitch_deg)
        if fixed is not None and problem.world.path_free(fixed):
            after = check_limits(fixed, lim)
            if after.ok:
                note = (f"depth profile repaired to max_pitch_deg = {lim.max_pitch_deg:g} (was "
                        f"{report.max_pitch_deg:.1f}° on leg {report.max_pitch_leg})")
                out = replace(result, path=fixed, message="; ".join(x for x in (result.message, note) if x))
                if has(result.planner, "path_cost"):
                    terms = path_cost(problem, spec, fixed)
                    total = terms.pop("total")
                    out = replace(out, cost=float(total), cost_terms={**result.cost_terms, **terms},
                                  control_points=None)
                return out
            report = after
        elif fixed is not None:
            return replace(result, status=Status.INFEASIBLE, message=(
                f"the plan's legs exceed max_pitch_deg = {lim.max_pitch_deg:g} (leg {report.max_pitch_leg}: "
                f"{report.max_pitch_deg:.1f}°) and the profile within the limit meets the seabed or an obstacle"))
    return replace(result, status=Status.INFEASIBLE, message=f"the vehicle cannot fly this plan: {report.message}")
