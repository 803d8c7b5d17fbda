"""The streamline planner (document 000): the flow field round the world's obstacles, the seabed as a
mirror plane where it is flat enough, one streamline from the start to the goal, checked exactly."""

from __future__ import annotations

import time

import numpy as np

from ..._types import ArrayLike, Status
from ...path import polyline_length
from ...world import World
from ..core.base import PlanningProblem, PlanResult
from ..core.common import check_endpoints
from ..core.params import FlowParams
from .field import FlowField
from .stream import Streamlines, integrate_streamlines
from .turning import flyable_path

__all__ = ["seabed_plane", "plan_flow"]


def seabed_plane(world: World, start: ArrayLike, goal: ArrayLike, buffer: float) -> tuple[float | None, str]:
    """The flat seabed the flow can model: ``(height, "")``, or ``(None, reason)`` when it is not flat enough.

    The plane lies at the highest seabed elevation within ``buffer`` of the straight start–goal line
    (sampled every ~1/200 of its length on five parallel lines) plus the minimum altitude: a mirror
    image of the target sink in it makes it a stream surface.  Start and goal must lie above it.

    Parameters
    ----------
    world : World
        The seabed and the minimum altitude.
    start, goal : array_like
        The end points ``(3,)`` (m).
    buffer : float
        Half-width of the strip about the start-goal line that is sampled (m).

    Returns
    -------
    tuple of (float or None, str)
        The plane's height (m) and ``""``; ``(None, "")`` without a seabed; ``(None, reason)`` when the
        seabed is not flat enough.
    """
    if world.terrain is None:
        return None, ""
    a, b = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    d = b[:2] - a[:2]
    n = np.array([-d[1], d[0]]) / max(np.linalg.norm(d), 1e-9)
    t = np.linspace(0.0, 1.0, 201)[:, None]
    xy = np.concatenate([a[:2] + t * d + o * buffer * n for o in (-1.0, -0.5, 0.0, 0.5, 1.0)])
    top = float(np.nanmax(world.seabed(xy[:, 0], xy[:, 1])))
    plane = top + world.margins.min_altitude
    low = min(a[2], b[2])
    if low <= plane:
        which = "start" if a[2] <= b[2] else "goal"
        return None, (f"the seabed is not locally flat: it rises to {top:.1f} m within {buffer:.0f} m of the "
                      f"start-goal line, so its mirror plane (+ min altitude {world.margins.min_altitude:g} m) lies "
                      f"above the {which} (z = {low:.1f} m); the flow planner models the seabed as one flat plane "
                      f"- plan with iabc or grid")
    return plane, ""


def plan_flow(problem: PlanningProblem, params: FlowParams) -> PlanResult:
    """Streamline from the problem's start to its goal in the world's obstacle field.

    When the seabed is in the way of the obstacle flow, the flow sees it as a flat mirror plane
    (:func:`seabed_plane`), or, when the seabed is not flat enough for that, the plan is
    ``INFEASIBLE`` with that reason.

    Parameters
    ----------
    problem : PlanningProblem
        World (spheres and ellipsoids, seabed, margins), start, goal and speed.
    params : FlowParams
        Field, body sizing and integration settings.

    Returns
    -------
    PlanResult
        ``EXACT`` when the streamline arrives without touching an obstacle (inflated by the World's
        obstacle margin) and passes the World's exact segment tests (seabed included);
        ``INFEASIBLE`` otherwise, with the reason.  With ``params.path = "flyable"`` (default) and a turn
        radius in ``problem.limits``, the path is the turn-limited one along the flow
        (:func:`~auvplan.planners.flow.turning.flyable_path`), ``INFEASIBLE`` where it cannot follow the flow.
    """
    t0 = time.perf_counter()
    world: World = problem.world
    bad = check_endpoints(problem)
    if bad is None and params.field == "uniform":
        bad = (Status.INFEASIBLE,
               "field = 'uniform' has no sink at the goal (document 000 Fig. 5 baseline): use it in benchmarks")
    if bad is not None:
        return PlanResult.failure(bad[0], bad[1], "flow")
    field, sl, plane, why = _streamline(problem, params)
    path = sl.paths[0]
    length = float(polyline_length(path))
    status, message = _checked(world, sl, plane, why)
    clearance = float(sl.min_distance[0] + world.margins.obstacle) if world.obstacles else float("inf")
    radius = problem.limits.turn_radius_m if problem.limits is not None else 0.0
    if status is Status.EXACT and params.path == "flyable" and radius > 0:
        fly = flyable_path(field.velocity, lambda s: world.segments_free(s, moving=False), problem.start,
                           problem.goal, radius, params.arrive)
        if fly.status == "arrived":
            path = fly.path
            length = float(polyline_length(path))
            clearance = float(field.clearance(path).min() + world.margins.obstacle) if world.obstacles else clearance
        else:
            status = Status.INFEASIBLE
            message = (f"the streamline arrives, but a vehicle turning at most 1/{radius:g} m⁻¹ cannot follow it "
                       f"within the margins ({fly.status} near {np.round(fly.path[-1], 1).tolist()}); "
                       f"[planner.flow] path = 'streamline' gives the pure streamline")
    return PlanResult(status, path, length, _terms(world, path, length, clearance, problem.speed),
                      int(sl.steps[0]) * 4, int(sl.steps[0]), time.perf_counter() - t0, np.empty(0), "flow", None,
                      message)


def _streamline(problem: PlanningProblem, params: FlowParams) -> tuple[FlowField, Streamlines, float | None, str]:
    """The flow field and the streamline from the start; again with the seabed as a mirror plane when the seabed
    may be in the way and is flat enough (the plane's height, or why not)."""
    world: World = problem.world
    field = FlowField(world.obstacles, problem.goal, params, world.margins.obstacle)
    sl = integrate_streamlines(field, problem.start[None], params)
    plane, why = None, ""
    if world.terrain is not None and not (sl.arrived[0] and world.path_free(sl.paths[0])):
        # the seabed may be in the way: the flow with the seabed as a mirror plane, if it is flat enough
        sizes = [ob.bounding_radius for ob in world.obstacles]
        buffer = max(sizes + [0.05 * float(np.linalg.norm(problem.goal - problem.start))])
        plane, why = seabed_plane(world, problem.start, problem.goal, buffer)
        if plane is not None:
            field = FlowField(world.obstacles, problem.goal, params, world.margins.obstacle, plane=plane)
            sl = integrate_streamlines(field, problem.start[None], params)
    return field, sl, plane, why


def _checked(world: World, sl: Streamlines, plane: float | None, why: str) -> tuple[Status, str]:
    """``EXACT``, or ``INFEASIBLE`` and why: the streamline ended before the goal, or a leg of it is not free."""
    path = sl.paths[0]
    st = sl.status[0]
    if st != "arrived":
        return Status.INFEASIBLE, f"the streamline ended by {st} after {sl.steps[0]} steps"
    if world.path_free(path):
        return Status.EXACT, ""
    seg = np.stack([path[:-1], path[1:]], axis=1)
    bad_seg = int(np.flatnonzero(~world.segments_free(seg, moving=False))[0])
    message = (f"the streamline arrives but its leg {bad_seg} near {np.round(path[bad_seg], 1).tolist()} meets the "
               f"seabed, an obstacle margin or the bounds")
    message += f" ({why})" if why else (f" (the flow sees the seabed as a plane at z = {plane:.1f} m)"
                                         if plane is not None else "")
    return Status.INFEASIBLE, message


def _terms(world: World, path: np.ndarray, length: float, clearance: float, speed: float) -> dict[str, float]:
    """The plan's cost terms: length, duration, least clearance (the seabed's too) and the legs not free."""
    seg = np.stack([path[:-1], path[1:]], axis=1) if len(path) > 1 else np.stack([path, path], axis=1)
    if world.terrain is not None:
        clearance = min(clearance, float(world.terrain.segment_min_altitude(seg).min()))
    terms = {"length": length, "terrain": 0.0, "energy": 0.0, "length_m": length, "energy_j": float("nan"),
             "duration_s": length / speed, "min_clearance_m": clearance,
             "violations": int(np.count_nonzero(~world.segments_free(seg, moving=False)))}
    terms["collisions"] = terms["violations"]  # deprecated alias (CHANGELOG 0.2.0)
    return terms
