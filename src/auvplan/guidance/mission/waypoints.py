"""The executable waypoint mission: built from a plan, safe under every executor's depth semantics.

A vehicle executing a waypoint mission does not fly the planner's curve.  Two depth semantics
cover the executors auvplan exports to:

* ``"ramp"`` — the depth changes linearly along each leg (ArduSub / QGroundControl ``.plan``:
  WPNav flies the 3D line between waypoints; GPX routes, KML, GeoJSON, CSV, ROS ``nav_msgs/Path``
  are polylines);
* ``"held"`` — a depth is *held* per leg and changed at the waypoint (MOOS-IvP: one
  ``BHV_ConstantDepth`` per leg, switched by the ``WPT_INDEX`` that ``BHV_Waypoint`` posts; the
  depth of leg i is that of its end waypoint).  A real vehicle changes depth at a finite pitch
  rate, monotonically, so on leg i it lies anywhere between the depths of the leg's two ends.

auvplan therefore checks every leg's **envelope**: the vertical rectangle spanned by the
horizontal leg and the two end depths.  Its least altitude above the seabed is the altitude of
the *flat* leg at the deeper end (the seabed is a height field), computed by the exact
segment-versus-seabed walk (:meth:`Terrain.segment_min_altitude`); obstacles are tested against
the rectangle exactly (:func:`envelope_hits`).  The ramp lies inside the envelope, so a mission
whose envelopes are free is safe under both semantics: one mission for every format (the envelope tests:
:mod:`.envelopes`).

:func:`build_waypoints` makes such a mission from a dense planned path: densify to the terrain
cell, raise each waypoint to the floor of its two legs (max seabed along the leg +
``min_altitude``: this inserts waypoints where the seabed rises, and takes the safe depth where a
leg's depth is held), then simplify by Douglas–Peucker in 3D where the exact envelope test
decides which points may be dropped.  :func:`~auvplan.guidance.mission.flycheck.fly_check`
(:mod:`.flycheck`) re-flies a waypoint list under a semantics and reports the least altitude and the least
obstacle distance.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...geometry import as_points, point_segment_distance
from ...path import polyline_length
from ...world import World
from .envelopes import envelopes_free, leg_floors

__all__ = ["build_waypoints", "default_tolerance"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""


def default_tolerance(path: ArrayLike) -> float:
    """Return the Douglas–Peucker tolerance for a path: 0.2 % of its length, within [0.5, 50] m.

    Parameters
    ----------
    path : array_like
        ``(M, 3)`` path (m).

    Returns
    -------
    float
        Tolerance (m).
    """
    p = as_points(path).reshape(-1, 3)
    length = float(polyline_length(p)) if len(p) > 1 else 0.0
    return float(np.clip(0.002 * length, 0.5, 50.0))


def _densify(p: np.ndarray, spacing: float) -> np.ndarray:
    """Insert points so that no leg is longer than ``spacing`` horizontally."""
    out = [p[:1]]
    for a, b in zip(p[:-1], p[1:]):
        n = max(int(np.ceil(np.hypot(*(b[:2] - a[:2])) / spacing)), 1)
        out.append(a + (b - a) * (np.arange(1, n + 1) / n)[:, None])
    return np.vstack(out)


def _raise_to_floors(world: World, p: np.ndarray) -> np.ndarray:
    """Lift interior points to the floors of their two legs (start and goal are kept: a vertical
    leg joins them to a lifted neighbour); legs whose floor is above ``min_depth`` are split."""
    ceiling = -world.margins.min_depth
    for _ in range(12):
        f = leg_floors(world, p[:-1], p[1:])
        bad = np.flatnonzero(f > ceiling)
        if bad.size == 0 or np.hypot(*(p[bad[0] + 1, :2] - p[bad[0], :2])) < 1e-3:
            break
        mids = 0.5 * (p[bad] + p[bad + 1])
        p = np.insert(p, bad + 1, mids, axis=0)
    if f.size != p.shape[0] - 1:  # the loop ran out after a split: the floors of the final legs
        f = leg_floors(world, p[:-1], p[1:])
    need = np.maximum(np.r_[f, -np.inf], np.r_[-np.inf, f])
    q = p.copy()
    q[1:-1, 2] = np.maximum(p[1:-1, 2], need[1:-1])
    rows = [q[:1]]
    if q[0, 2] < f[0]:  # climb above the start before the first leg
        rows.append(np.array([[q[0, 0], q[0, 1], f[0]]]))
    rows.append(q[1:-1])
    if q[-1, 2] < f[-1]:  # arrive above the goal, then descend onto it
        rows.append(np.array([[q[-1, 0], q[-1, 1], f[-1]]]))
    rows.append(q[-1:])
    return np.vstack(rows)


def _refine(world: World, p: np.ndarray, rounds: int = 10, min_leg: float = 0.0) -> np.ndarray:
    """Halve the legs whose envelope meets an obstacle: each half's envelope lies inside the
    whole leg's, and they shrink onto the 3D leg, which is free when the path was.  A leg is halved
    only while its halves are at least ``min_leg`` long (issue 49: a leg that grazes an obstacle's
    margin was halved ten times, into thousands of millimetre legs)."""
    for _ in range(rounds):
        bad = ~envelopes_free(world, p[:-1], p[1:])
        bad &= np.linalg.norm(np.diff(p, axis=0), axis=1) > 2.0 * min_leg * (1.0 + 1e-6)
        if bad.any():  # halving cannot help a leg that is itself blocked
            bad &= world.segments_free(np.stack([p[:-1], p[1:]], axis=1), moving=False)
        split = np.flatnonzero(bad)
        if split.size == 0:
            break
        p = np.insert(p, split + 1, 0.5 * (p[split] + p[split + 1]), axis=0)
    return p


def _deviation(p: np.ndarray, i: int, j: int) -> tuple[float, int]:
    """Largest 3D distance of ``p[i+1:j]`` from the chord ``p[i] -> p[j]`` and where it is."""
    if j - i < 2:
        return 0.0, i
    d = point_segment_distance(p[i + 1:j], p[i], p[j])
    k = int(np.argmax(d))
    return float(d[k]), i + 1 + k


def _deviations(p: np.ndarray, i: NDArray[np.int64], j: NDArray[np.int64]) -> tuple[_F64, NDArray[np.int64]]:
    """:func:`_deviation` of many chords ``p[i] -> p[j]`` (``j - i >= 2``) in one array pass: the largest
    distance of each chord's interior points and the first index where it is reached."""
    n = j - i - 1
    grp = np.repeat(np.arange(len(i)), n)
    idx = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n) + np.repeat(i + 1, n)
    d = point_segment_distance(p[idx], p[i][grp], p[j][grp])
    starts = np.cumsum(n) - n
    top = np.maximum.reduceat(d, starts)
    at = np.flatnonzero(d == top[grp])
    _, first = np.unique(grp[at], return_index=True)
    return top, idx[at[first]]


def _douglas_peucker(world: World, p: np.ndarray, tolerance: float) -> np.ndarray:
    """Indices kept by Douglas–Peucker where a chord replaces its points only when it is within
    ``tolerance`` of them *and* its envelope is free (:func:`envelopes_free`).

    Breadth first: every open chord of one level is measured and envelope-tested in one array call
    (each chord's outcome depends on its ends only, so the kept points are those of the recursion)."""
    keep = np.zeros(len(p), dtype=bool)
    keep[[0, -1]] = True
    i, j = np.array([0]), np.array([len(p) - 1])
    while i.size:
        wide = j - i >= 2
        i, j = i[wide], j[wide]
        if not i.size:
            break
        dev, k = _deviations(p, i, j)
        done = dev <= tolerance
        if done.any():
            done[done] = envelopes_free(world, p[i[done]], p[j[done]])
        k = np.where(dev > 0.0, k, (i + j) // 2)[~done]
        i, j = i[~done], j[~done]
        keep[k] = True
        i, j = np.r_[i, k], np.r_[k, j]
    return np.flatnonzero(keep)


def build_waypoints(path: ArrayLike, world: World, tolerance: float | None = None, spacing: float | None = None,
                    slack: float = 0.05, min_leg: float = 0.0) -> _F64:
    """Build the executable mission ``(N, 3)`` for a planned ``path (M, 3)``.

    Parameters
    ----------
    path : array_like (M, 3)
        Dense planned path (B-spline samples, streamline, lattice path).
    world : World
        Seabed, static obstacles and margins.
    tolerance : float, optional
        Douglas–Peucker tolerance (m); :func:`default_tolerance` of the path by default.
    spacing : float, optional
        Longest horizontal leg before simplification (m); the smaller terrain cell by default.
    slack : float
        Extra altitude (m) the mission keeps beyond ``min_altitude``, and distance off the charted
        zones (the zones themselves, not the planners' pad), so that the rounding of exported
        coordinates (≤ 0.0005 m in the local formats) cannot take it below or inside.
    min_leg : float, default 0.0
        Shortest leg the refinement next to obstacles may make (m; :func:`auvplan.path.legs.shortest_leg`).

    Returns
    -------
    ndarray (N, 3)
        Waypoints from the start to the goal.  Every leg whose dense pieces had a free envelope
        keeps a free envelope (:func:`envelopes_free`), so the mission is safe when flown with
        depth held per leg or ramped along it.
    """
    p = as_points(path).reshape(-1, 3)
    keep = np.r_[True, np.linalg.norm(np.diff(p, axis=0), axis=1) > 1e-9]
    p = p[keep]
    if len(p) < 2:
        return p.copy()
    tol = default_tolerance(p) if tolerance is None else float(tolerance)
    m = world.margins
    world = replace(world, margins=replace(m, min_altitude=m.min_altitude + slack),
                    zones=world.zones.with_pad(slack) if world.zones else world.zones)  # the same slack off zones
    if world.terrain is not None:
        step = min(world.terrain.dx, world.terrain.dy) if spacing is None else float(spacing)
        p = _raise_to_floors(world, _densify(p, step))
    p = _refine(world, p, min_leg=min_leg)
    kept: _F64 = p[_douglas_peucker(world, p, tol)].copy()
    return kept
