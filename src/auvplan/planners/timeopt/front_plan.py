"""The front method of the time-optimal planner (``[planner.timeopt] method = "front"``): one departure.

:func:`front_flight` runs the reachable-set front (:mod:`.front`), backtracks the flight, refines it by
Zermelo's heading equation (:mod:`.zermelo`) and turns each candidate into a path with the duration
of a flight the vehicle can make through the World's own current:

* the polyline of the flight's positions, each leg's line held at V with the root of the crab
  equation its heading uses (``tail`` where the heading is against the leg; :func:`.timing.fly_times`),
  when every leg can be held that way;
* else (where the optimum turns its heading across its track, a line held at a crab angle of 90°
  is lost for the smallest change in the current) the *heading schedule* flown through the World's
  current (:func:`fly_headings`): the positions it reaches, closed by a last leg to the goal.

Either duration is that of a real flight, so no plan is below the least time (up to the
integrator's error).  The fastest candidate whose segments and drift pass the exact tests wins; the
caller falls back on the lattice search when none does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray
from ...world import World
from .front import Front, FrontGrid, backtrack, propagate
from .search import TimedPath, drift_free
from .timing import fly_times
from .zermelo import refine_shot

__all__ = ["FrontOutcome", "fly_headings", "front_flight"]


@dataclass(frozen=True, eq=False)
class FrontOutcome:
    """What the front method found for one departure.

    Attributes
    ----------
    path : TimedPath or None
        The best flyable candidate, timed through the World's current (None: none).
    front : Front
        The stored fronts (arrival time, reason when the goal was not reached).
    candidates : dict
        Duration (s) of every candidate by name (``backtrack``, ``zermelo``; ``inf`` when rejected).
    """

    path: TimedPath | None
    front: Front
    candidates: dict[str, float]


def _z(p2: FloatArray, times: FloatArray, grid: FrontGrid) -> FloatArray:
    """Depth along the path: the grid's schedule at the vertices' times, else linear in arc length
    from the start's to the goal's (the end points keep their own)."""
    if grid.schedule is not None:
        z = grid.depth(times)
        z[0], z[-1] = grid.z
        return np.column_stack([p2, z])
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p2, axis=0).T))])
    f = s / s[-1] if s[-1] > 0 else np.zeros_like(s)
    return np.column_stack([p2, grid.z[0] + f * (grid.z[1] - grid.z[0])])


def _zt(grid: FrontGrid, t: float) -> float:
    return float(grid.depth(t)) if grid.schedule is not None else 0.5 * (grid.z[0] + grid.z[1])


def _tails(p2: FloatArray, heads: FloatArray) -> BoolArray:
    d = np.diff(p2, axis=0)
    return np.asarray((d[:, 0] * np.cos(heads[:d.shape[0]]) + d[:, 1] * np.sin(heads[:d.shape[0]])) < 0.0)


def fly_headings(world: World, grid: FrontGrid, start: ArrayLike, goal: ArrayLike, times: FloatArray,
                 heads: FloatArray, speed: float, ds: float, t_limit: float) -> TimedPath:
    """A heading schedule flown through the World's current, closed by a held leg to the goal.

    Parameters
    ----------
    world : World
        The current field.
    grid : FrontGrid
        The depths of the start and the goal.
    start, goal : array_like
        End points ``(3,)`` (m).
    times : numpy.ndarray
        ``(M,)`` times of the schedule (s); heading ``heads[i]`` is flown from ``times[i]`` to ``times[i + 1]``.
    heads : numpy.ndarray
        ``(M - 1,)`` or more headings (mathematical angle, rad).
    speed : float
        Through-water speed V (m/s).
    ds : float
        Sub-step of the last leg's timing (m).
    t_limit : float
        A last leg not arrived by this time is rejected (s).

    Returns
    -------
    TimedPath
        Positions at the schedule's times then the goal; ``inf`` arrival when the last leg cannot be held.
    """
    p = np.empty((times.size, 2))
    p[0] = np.asarray(start, dtype=float)[:2]
    for i in range(times.size - 1):  # midpoint rule, two sub-steps per piece
        a = speed * np.array([math.cos(heads[i]), math.sin(heads[i])])
        x, t, h = p[i].copy(), float(times[i]), 0.5 * float(times[i + 1] - times[i])
        for _ in range(2):
            c = world.currents.velocity(np.array([x[0], x[1], _zt(grid, t)]), t)[:2]
            xm = x + 0.5 * h * (c + a)
            x = x + h * (world.currents.velocity(np.array([xm[0], xm[1], _zt(grid, t + 0.5 * h)]), t + 0.5 * h)[:2] + a)
            t += h
        p[i + 1] = x
    pts = _z(np.vstack([p, np.asarray(goal, dtype=float)[:2]]), np.append(times, times[-1]), grid)
    last, back = math.inf, np.zeros(1)
    for tail in (False, True):  # the last leg: whichever root holds it
        tt, bb = fly_times(world.currents, pts[-2:], float(times[-1]), speed, ds, t_limit, [tail])
        if tt[-1] < last:
            last, back = float(tt[-1]), bb
    return TimedPath(pts, np.append(times, last), speed, np.append(np.zeros(times.size - 1), back), timed=True)


def _as_path(world: World, grid: FrontGrid, p2: FloatArray, times: FloatArray, heads: FloatArray, speed: float,
             ds: float, t_limit: float) -> TimedPath:
    """The flight as a held polyline when every leg holds, else as its heading schedule (module notes)."""
    pts = _z(p2, times, grid)
    tail = _tails(p2, heads)
    t, back = fly_times(world.currents, pts, float(times[0]), speed, ds, t_limit, tail)
    if np.isfinite(t[-1]):
        return TimedPath(pts, t, speed, back, tail if tail.any() else None, timed=True)
    return fly_headings(world, grid, pts[0], pts[-1], times[:-1], heads, speed, ds, t_limit)


def front_flight(world: World, grid: FrontGrid, start: ArrayLike, goal: ArrayLike, depart: float, speed: float,
                 headings: int, ds: float, t_limit: float) -> FrontOutcome:
    """Front, backtracking and Zermelo refinement of one departure (module notes).

    Parameters
    ----------
    world : World
        The World (exact tests and its current).
    grid : FrontGrid
        Grid and current table.
    start, goal : array_like
        End points ``(3,)`` (m).
    depart : float
        Departure time (s).
    speed : float
        Through-water speed V (m/s).
    headings : int
        Headings tried per node and step of the front.
    ds : float
        Sub-step of the World timing (m).
    t_limit : float
        Latest arrival a timing accepts (s).

    Returns
    -------
    FrontOutcome
        The best candidate (or None), the fronts and every candidate's duration.
    """
    front = propagate(grid, start, goal, depart, speed, headings)
    if not math.isfinite(front.arrival):
        return FrontOutcome(None, front, {})
    p2, times, heads = backtrack(grid, front, start, goal, depart, speed)
    cands = {"backtrack": _as_path(world, grid, p2, times, heads, speed, ds, t_limit)}
    window = front.arrival + 0.05 * (front.arrival - depart) + 2.0 * front.step
    shot = refine_shot(grid, start, goal, depart, speed, float(heads[0]), min(window, grid.t1), 0.5 * front.step)
    if shot is not None:
        cands["zermelo"] = _as_path(world, grid, shot[0], shot[1], shot[2], speed, ds, t_limit)
    durations = {k: v.duration for k, v in cands.items()}
    ok = [c for c in cands.values() if np.isfinite(c.duration) and _free(world, c)]
    best = min(ok, key=lambda c: c.duration) if ok else None
    return FrontOutcome(best, front, durations)


def _free(world: World, tp: TimedPath) -> bool:
    seg = np.stack([tp.points[:-1], tp.points[1:]], axis=1)
    return bool(world.segments_free(seg, moving=False).all()) and drift_free(world, tp)
