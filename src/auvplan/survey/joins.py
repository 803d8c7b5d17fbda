"""Turns that join a survey's pieces as a helm flies them: from one line to the next
(:func:`turn_between`), from a line to a transit of the global planner and back (:func:`join_transit`), and
into and out of the transits that bridge a line's gap round a charted zone (:func:`join_bridges`).

Every turn is a Dubins path of the turn radius sampled so that each fly-by waypoint fits the radius as
``mission check`` judges it (:func:`auvplan.path.legs.helm_check`), and is kept only when clear of the
seabed, obstacles and zones (else the corner stays, and the mission's checks report it).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..path.flyable import VehicleLimits
from ..path.legs import helm_check
from ..world import World
from .turns import dubins, sample_turn

__all__ = ["turn_between", "join_transit", "join_bridges"]

_WIDEN_TRIES = 40
"""Turns re-drawn 3 % wider at most this often (a factor 3.3) before the last one is kept."""


_HALF_STEP_RAD = 1.0
"""Largest turn of the sampled arcs between two waypoints of a survey turn (rad): coarse enough that
each waypoint lies more than ``TRACK_FRACTION`` · R off its neighbours' chord, so the check of
:func:`auvplan.path.flyable.check_limits` judges the waypoints as given, not a simplified track."""


def turn_between(a: NDArray[np.float64], b: NDArray[np.float64], radius: float) -> tuple[NDArray[np.float64], str]:
    """Inner points of the turn from the end of line points ``a`` to the start of ``b`` (z interpolated along it).

    Parameters
    ----------
    a : numpy.ndarray
        ``(>= 2, 3)`` points whose last leg gives the heading the turn starts from (m).
    b : numpy.ndarray
        ``(>= 2, 3)`` points whose first leg gives the heading the turn ends with (m).
    radius : float
        The vehicle's turn radius (m).

    Returns
    -------
    tuple
        The turn's inner points ``(K, 3)`` (m) and its Dubins word.
    """
    h0 = math.atan2(a[-1, 1] - a[-2, 1], a[-1, 0] - a[-2, 0])
    h1 = math.atan2(b[1, 1] - b[0, 1], b[1, 0] - b[0, 0])
    # sampled every radian at most, the arcs' chords turn by up to 1 rad at each vertex; a fly-by
    # turn there fits r cos(0.5) only, so the arcs are drawn at r / cos(0.5) and the waypoints a
    # vehicle flies by fit ``radius`` (the check of ``mission check``, :func:`auvplan.path.flyable.check_limits`)
    # Where a short arc meets the next one (an LRL turn between lines a little over 2R apart) the chords
    # at the junction may turn by more than that: the turn is re-drawn 3 % wider until every waypoint of
    # line end, turn and next line start fits ``radius`` as a helm flies it (issue #49's leg-by-leg check).
    r = radius / math.cos(_HALF_STEP_RAD / 2.0) * (1.0 + 1e-9)
    for _ in range(_WIDEN_TRIES):
        t = dubins((a[-1, 0], a[-1, 1], h0), (b[0, 0], b[0, 1], h1), r)
        pts = sample_turn(t, r * _HALF_STEP_RAD)[1:-1]
        # z along the turn's horizontal length, not by its vertices' count: a 0.5 m chord beside a 170 m one
        # took as much of the depth change (81 degrees of pitch, docwalk20)
        xy = np.vstack([a[-1:, :2], pts[:, :2], b[:1, :2]])
        run = np.r_[0.0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
        frac = run[1:-1] / run[-1] if run[-1] > 0.0 else np.linspace(0.0, 1.0, pts.shape[0] + 2)[1:-1]
        inner = np.column_stack([pts[:, :2], a[-1, 2] + frac * (b[0, 2] - a[-1, 2])])
        around = np.vstack([a[-2:], inner, b[:2]])
        if helm_check(around, VehicleLimits(90.0, radius), min_leg=0.0).tightest_turn_m >= radius:
            break
        r *= 1.03
    return inner, t.word


def join_transit(world: World, a: NDArray[np.float64], b: NDArray[np.float64], radius: float,
          home: bool) -> NDArray[np.float64]:
    """The turn that joins a line's end ``a`` to a transit ``b`` (or a transit ``a`` to a line's start ``b``).

    The transit's vertex next to the line (``b[1]`` home, ``a[-2]`` out) is reached by the survey's own turn
    (:func:`turn_between`) instead of a corner at the line's end, so that every fly-by turn fits ``radius`` as a helm
    flies it; kept only when the turn is clear of the seabed and obstacles (else the corner stays, and the
    mission's checks report it).

    Parameters
    ----------
    world : World
        Seabed, obstacles and zones.
    a, b : numpy.ndarray
        ``(N, 3)`` the line's points and the transit's (home), or the transit's and the line's (out) (m).
    radius : float
        The vehicle's turn radius (m).
    home : bool
        From a line's end to a transit (True) or from a transit to a line's start (False).

    Returns
    -------
    numpy.ndarray
        The turn's inner points ``(K, 3)`` (m; possibly none).
    """
    if a.shape[0] < 2 or b.shape[0] < 2:
        return np.empty((0, 3))
    if home:  # from the line's end to the transit's second vertex
        head = a[-2:]
        tail = b[1:3] if b.shape[0] >= 3 else np.stack([b[1], 2.0 * b[1] - b[0]])
        turn, _ = turn_between(head, tail, radius)
        whole = np.vstack([head[-1:], turn, tail[:1]])
    else:  # out: from the transit's last-but-one vertex to the line's start
        head = a[-3:-1] if a.shape[0] >= 3 else np.stack([2.0 * a[0] - a[1], a[0]])
        turn, _ = turn_between(head, b[:2], radius)
        whole = np.vstack([head[-1:], turn, b[:1]])
    return turn if world.path_free(whole) else np.empty((0, 3))


def _fits(world: World, whole: NDArray[np.float64], radius: float) -> bool:
    """Whether every fly-by turn of ``whole`` fits ``radius`` and its inner legs (all but the first and the
    last, flown already) are clear."""
    tight = helm_check(whole, VehicleLimits(90.0, radius), min_leg=0.0).tightest_turn_m
    return bool(tight >= radius * (1.0 - 1e-9) and world.path_free(whole[1:-1]))


def _bridge(world: World, seq: NDArray[np.float64], radius: float) -> NDArray[np.float64] | None:
    """The inner points of a bridge ``seq`` = line vertex, line end ``a``, the transit's vertices, line start
    ``b``, line vertex, joined by turns: into the first transit vertex that a clear turn reaches with the
    transit's heading there, out of the last one, else one turn from ``a`` to ``b``; None when none fits."""
    head, tail, d = seq[:2], seq[-2:], seq[1:-1]
    m = d.shape[0]
    for k in range(1, m - 1):
        t_in, _ = turn_between(head, d[k:k + 2], radius)
        if not _fits(world, np.vstack([head, t_in, d[k:k + 2]]), radius):
            continue
        for j in range(m - 2, k, -1):
            t_out, _ = turn_between(d[j - 1:j + 1], tail, radius)
            inner = np.vstack([t_in, d[k:j + 1], t_out])
            if _fits(world, np.vstack([head, inner, tail]), radius):
                return inner
        break
    direct, _ = turn_between(head, tail, radius)
    return direct if _fits(world, np.vstack([head, direct, tail]), radius) else None


def join_bridges(world: World, route: NDArray[np.float64], labels: NDArray[np.int64], transit: int,
                 radius: float) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Join the transits that bridge a line's gap round a zone to their lines by turns instead of corners.

    A bridge is a run of ``transit`` vertices between two line vertices; its vertices next to the lines are
    replaced by the survey's turns (:func:`turn_between`) into and out of the run where its corners do not
    fly as turns of ``radius``: the nearest ones that fit it as a helm flies them and are clear of the seabed,
    obstacles and zones (one turn from line to line when none do); a bridge no turn fits keeps its corners
    (the mission's checks report them).

    Parameters
    ----------
    world : World
        Seabed, obstacles and zones.
    route : numpy.ndarray
        ``(N, 3)`` lines, turns and bridges (m).
    labels : numpy.ndarray of int
        ``(N,)`` their labels.
    transit : int
        The label of a bridge's vertices.
    radius : float
        The vehicle's turn radius (m).

    Returns
    -------
    tuple
        The route and its labels with the bridges joined.
    """
    idx = np.flatnonzero(labels == transit)
    if idx.size == 0:
        return route, labels
    parts, labs, last = [], [], 0
    before = route[0]  # the vertex the joined route has before ``route[last]`` (read when a bridge was joined)
    for run in np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1):
        a, b = int(run[0]) - 1, int(run[-1]) + 1
        if a < 1 or b > route.shape[0] - 2:  # no line leg on one side to turn from or onto
            continue
        # the vertex flown before ``a``: the joined route's (a bridge ending at ``a`` was replaced), not the input's
        seq = np.vstack([route[a - 1] if a - 1 >= last else before, route[a:b + 2]])
        if _fits(world, seq, radius):  # its corners already fly as turns of the radius
            continue
        inner = _bridge(world, seq, radius)
        if inner is None:
            continue
        parts += [route[last:a + 1], inner]
        labs += [labels[last:a + 1], np.full(inner.shape[0], transit, dtype=np.int64)]
        before = inner[-1] if inner.shape[0] else route[a]
        last = b
    parts.append(route[last:])
    labs.append(labels[last:])
    return np.vstack(parts), np.concatenate(labs).astype(np.int64)
