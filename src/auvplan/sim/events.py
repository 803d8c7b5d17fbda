"""The closed loop's event rules, pure functions of one step: distances to the obstacles, contact
(collision or unavoidable), arrival, progress and deadlock, and the launch's dive.  :func:`auvplan.sim.simulate` and
:mod:`auvplan.sim.formation` apply them.

The launch's dive (``[navigation]``; ``docs/navigation.md``, "The launch").  A mission with ``[navigation]`` starts at
the surface above its first waypoint, with its GPS fix there, and dives to it: the vertical leg the navigation budget,
the fixes' times, the exported time-out and a ``.plan``'s check all count
(:func:`auvplan.sim.navigation.launch_flight`),
held over the point at :data:`~auvplan.nav.budget.LAUNCH_DIVE_MPS` through the water, so that it sinks at the ground
speed ``c·e + sqrt(V² − |c|² + (c·e)²)`` along ``e`` straight down (:func:`auvplan.endurance.ground_speed`;
``sqrt(V² − |c_h|²) − w`` for a current ``c = (c_h, w)``) and moves ``|c_h| dt`` through the water each step
(:func:`_dive_step`).  The closed loop flies it as it holds a surface dwell: a kinematic phase (the torpedo model cannot
hover), its clock, its drift without bottom lock over the water distance and its energy (propulsion at ``V``) those of
the flight the budget counts; steering starts at the first waypoint, as before (:func:`_launch_depth`)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._types import Status
from ..endurance import ground_speed, traverse
from ..nav.budget import LAUNCH_DIVE_MPS, launch_point
from ..nav.params import NavParams
from ..world import World
from ..world.obstacles import Shape

__all__: list[str] = []  # the rules are private to auvplan.sim and auvplan.sim.formation


FAR = 60.0
"""Obstacle distances beyond this (m) are recorded as the lower bound |p - c| - bounding radius
(beyond the reach of every guidance law: APF radius 30 m, hybrid influence 25 m by default)."""


def _distance(item: tuple[Shape, tuple[float, ...]] | None, pos: NDArray[np.float64], far: float = FAR) -> float:
    """Distance to a placed shape's surface, exact within ``far`` (a cheap lower bound beyond)."""
    if item is None:
        return math.inf
    shape, c = item
    bound = math.dist((pos[0], pos[1], pos[2]), c) - shape.bounding_radius
    if bound > far:
        return bound
    # the shape is defined about its own centre: move the query point instead of the shape
    return shape.distance(pos - c + np.asarray(shape.center)).item()


def _obstacle_shapes(world: World, t: float, centres: Sequence[Sequence[float] | NDArray[np.float64]] | None = None
                     ) -> list[tuple[Any, tuple[float, ...]] | None]:
    """(shape, centre) of every static and active moving obstacle at ``t`` (None when inactive);
    ``centres`` are the moving obstacles' centres at ``t`` when the caller has them."""
    items: list[tuple[Any, tuple[float, ...]] | None] = [(o, o.center) for o in world.obstacles]
    if centres is None:
        centres = [o.center(t) for o in world.moving]
    items += [(o.shape, tuple(c)) if o.active(t) else None for o, c in zip(world.moving, centres)]
    return items


PROGRESS_STEP = 1.0
"""Route progress (m) that counts as progress for the deadlock watch: the best progress so far must
be exceeded by more than this."""


def _contact_event(alt: float, dists: Sequence[float], pos: NDArray[np.float64], t: float,
                   moving: Sequence[Any], speed: float) -> tuple[Status, str] | None:
    """The collision at one step: ``(status, what was hit)``, or None.

    Contact means penetration: an altitude below 0 (under the seabed) or a distance below 0 (inside an
    obstacle); touching at exactly 0 m is not a collision, as a point with zero clearance is free for
    :meth:`World.clearances`.  The seabed is named first; else the obstacle the vehicle is deepest in
    (``dists`` lists the static obstacles, then ``moving``).  Hitting a moving obstacle is UNAVOIDABLE
    when it is at least as fast as the vehicle (``speed``) and closing in, its velocity pointing towards
    the vehicle (``v_o · (p - c) > 0``: tangential motion does not close in), else a COLLISION.
    """
    if alt < 0.0:
        return Status.COLLISION, "the seabed"
    if not any(d < 0.0 for d in dists):
        return None
    i = int(np.argmin(dists))
    what = f"obstacle {i}"
    j = i - (len(dists) - len(moving))
    if j >= 0:
        v_o = moving[j].velocity(t)
        closing = float(np.dot(v_o, pos - moving[j].center(t))) > 0.0
        if np.linalg.norm(v_o) >= speed and closing:
            return Status.UNAVOIDABLE, what + f" (moving at {np.linalg.norm(v_o):.2f} m/s, faster than the vehicle, " \
                "closing in)"
    return Status.COLLISION, what


def _arrived(last: bool, pos: Sequence[float], goal: Sequence[float] | NDArray[np.float64], radius: float) -> bool:
    """Arrival: on the last leg and within ``radius`` of the goal (at exactly ``radius``: arrived)."""
    return last and math.dist(pos, goal) <= radius


def _progressed(progress: float, best: float) -> bool:
    """Whether the route progress beats the best so far by more than :data:`PROGRESS_STEP`."""
    return progress > best + PROGRESS_STEP


def _deadlocked(t: float, best_time: float, deadlock_time: float, stalled: Callable[[], bool] | None) -> bool:
    """Deadlock: no progress for more than ``deadlock_time`` since ``best_time`` and, with local avoidance,
    its escapes given up (``stalled()`` is False; it is asked only once the time is up, as it runs them)."""
    return t - best_time > deadlock_time and (stalled is None or not stalled())



_DOWN = np.array([0.0, 0.0, -1.0])
"""The launch dive's direction (unit, up positive)."""


def _launch_depth(world: World, navigation: NavParams | None, waypoints: NDArray[np.float64]) -> float:
    """The depth the flight dives to from the surface before its first leg (m below the surface): ``-z`` of the first
    waypoint for a mission with ``[navigation]`` whose dive the current lets the vehicle hold over the point (the
    budget's rule); 0 otherwise (the flight starts at the first waypoint, as one without ``[navigation]`` always
    does)."""
    w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
    if navigation is None or w.shape[0] < 2 or not w[0, 2] < -1e-9:
        return 0.0
    return float(-w[0, 2]) if traverse(world, np.vstack([launch_point(w), w[0]]), LAUNCH_DIVE_MPS).ok else 0.0


def _dive_step(z: float, target: float, current: NDArray[np.float64], dt: float) -> tuple[float, float]:
    """One step of the dive held over the point from height ``z`` to ``target`` (m, up positive) in ``current``
    (m/s): the height after it (never below ``target``; unchanged where the current beats the dive) and the horizontal
    distance moved through the water over the part of the step spent diving (m)."""
    g = ground_speed(np.asarray(current, dtype=float), _DOWN, LAUNCH_DIVE_MPS)
    if not g > 0.0:  # the current beats the dive: no headway
        return z, 0.0
    used = min(dt, (z - target) / g)
    return max(z - g * dt, target), math.hypot(float(current[0]), float(current[1])) * used
