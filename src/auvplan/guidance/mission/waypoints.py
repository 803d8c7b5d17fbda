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
whose envelopes are free is safe under both semantics: one mission for every format.

:func:`build_waypoints` makes such a mission from a dense planned path: densify to the terrain
cell, raise each waypoint to the floor of its two legs (max seabed along the leg +
``min_altitude``: this inserts waypoints where the seabed rises, and takes the safe depth where a
leg's depth is held), then simplify by Douglas–Peucker in 3D where the exact envelope test
decides which points may be dropped.  :func:`fly_check` re-flies a waypoint list under a
semantics and reports the least altitude and the least obstacle distance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...geometry import as_points, point_segment_distance
from ...path import polyline_length
from ...world import World
from ...world.obstacles import Ellipsoid, Shape, Sphere
from .limits import WaypointLimits, WaypointLimitsDict, waypoint_limits

__all__ = [
    "SEMANTICS",
    "MissionCheck",
    "MissionCheckDict",
    "leg_floors",
    "envelope_hits",
    "envelopes_free",
    "build_waypoints",
    "default_tolerance",
    "fly_check",
    "held_track",
    "leg_figures",
    "segment_figures",
]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""

SEMANTICS = ("held", "ramp")
"""Depth semantics of a waypoint executor: depth held per leg (MOOS-IvP) or ramped along it."""


# ---------------------------------------------------------------------- envelope tests
def leg_floors(world: World, a: ArrayLike, b: ArrayLike) -> _F64:
    """Return the lowest safe z over each horizontal leg ``a -> b``.

    Parameters
    ----------
    world : World
        Seabed and margins.
    a, b : array_like
        ``(K, 3)`` leg starts and ends (m); only their horizontal positions matter.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` the highest seabed under each leg (exact, bilinear) plus ``min_altitude`` (m, up
        positive); ``-inf`` without terrain.
    """
    a, b = as_points(a).reshape(-1, 3), as_points(b).reshape(-1, 3)
    if world.terrain is None:
        return np.full(a.shape[0], -np.inf)
    flat_a, flat_b = a.copy(), b.copy()
    flat_a[:, 2] = flat_b[:, 2] = 0.0
    # a flat segment at z = 0 has least altitude -max(zb) along it
    return -world.terrain.min_altitude_between(flat_a, flat_b) + world.margins.min_altitude


def _unit_frame(shape: Shape, p: _F64, margin: float) -> _F64:
    """Points in the frame where the shape inflated by ``margin`` is the unit ball (affine map)."""
    if isinstance(shape, Sphere):
        unit: _F64 = (p - np.asarray(shape.center)) / (shape.radius + margin)
        return unit
    if isinstance(shape, Ellipsoid):  # the same conservative inflation as Ellipsoid.segments_hit
        return shape.to_body(p) / (np.asarray(shape.semi_axes) * (1.0 + margin / min(shape.semi_axes)))
    raise TypeError(f"unknown obstacle shape {type(shape).__name__}")


def _parallelogram_distance(o: _F64, e1: _F64, e2: _F64) -> _F64:
    """Distance from the origin to the parallelograms ``o + s e1 + t e2``, ``s, t in [0, 1]``
    (``(K, 3)`` each; degenerate ones are segments)."""
    a11 = (e1 * e1).sum(-1)
    a22 = (e2 * e2).sum(-1)
    a12 = (e1 * e2).sum(-1)
    r1, r2 = -(o * e1).sum(-1), -(o * e2).sum(-1)
    det = a11 * a22 - a12 * a12
    ok = det > 1e-12 * np.maximum(a11 * a22, 1e-300)
    safe = np.where(ok, det, 1.0)
    s = (r1 * a22 - r2 * a12) / safe
    t = (r2 * a11 - r1 * a12) / safe
    inside = ok & (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
    plane = np.linalg.norm(o + s[:, None] * e1 + t[:, None] * e2, axis=-1)
    zero = np.zeros(3)
    edges = [(o, o + e1), (o, o + e2), (o + e1, o + e1 + e2), (o + e2, o + e1 + e2)]
    d = np.minimum.reduce([point_segment_distance(zero, p, q) for p, q in edges])
    dist: _F64 = np.where(inside, np.minimum(plane, d), d)
    return dist


def _corners(a: _F64, b: _F64) -> tuple[_F64, _F64, _F64]:
    """The envelope rectangle of legs ``a -> b``: origin (a's xy at the lower depth) and edges."""
    lo = np.minimum(a[:, 2], b[:, 2])
    hi = np.maximum(a[:, 2], b[:, 2])
    o = np.column_stack([a[:, :2], lo])
    e1 = np.column_stack([b[:, :2] - a[:, :2], np.zeros(len(a))])
    e2 = np.zeros_like(o)
    e2[:, 2] = hi - lo
    return o, e1, e2


def envelope_hits(shape: Shape, a: ArrayLike, b: ArrayLike, margin: float = 0.0) -> NDArray[np.bool_]:
    """Test exactly where the envelope rectangle of a leg ``a -> b`` comes within ``margin`` of a shape.

    Parameters
    ----------
    shape : Sphere or Ellipsoid
        The obstacle (an ellipsoid uses its conservative inflated test, exact at margin 0).
    a, b : array_like
        ``(K, 3)`` leg starts and ends (m).
    margin : float, optional
        Clearance required from the shape's surface (m).

    Returns
    -------
    numpy.ndarray
        ``(K,)`` bool, True where the leg's envelope is within ``margin``.
    """
    a, b = as_points(a).reshape(-1, 3), as_points(b).reshape(-1, 3)
    o, e1, e2 = _corners(a, b)
    uo = _unit_frame(shape, o, margin)
    ue1 = _unit_frame(shape, o + e1, margin) - uo
    ue2 = _unit_frame(shape, o + e2, margin) - uo
    return _parallelogram_distance(uo, ue1, ue2) < 1.0


def envelopes_free(world: World, a: ArrayLike, b: ArrayLike) -> NDArray[np.bool_]:
    """Test where the envelope of each leg ``a -> b`` satisfies every static constraint.

    Seabed (exact, flat leg at the deeper end), depth limits and bounds (at the ends: the envelope's
    corners), static obstacles (exact rectangle test with the obstacle margin), charted zones (exact).

    Parameters
    ----------
    world : World
        Seabed, static obstacles, bounds and margins.
    a, b : array_like
        ``(K, 3)`` leg starts and ends (m).

    Returns
    -------
    numpy.ndarray
        ``(K,)`` bool, True where the leg's envelope is free.
    """
    a, b = as_points(a).reshape(-1, 3), as_points(b).reshape(-1, 3)
    m = world.margins
    ends = np.stack([a, b], axis=1)
    ok: NDArray[np.bool_] = np.all((-ends[..., 2] >= m.min_depth) & (-ends[..., 2] <= m.max_depth), axis=-1)
    ok &= world.bounds.contains(ends).all(axis=-1)
    if world.terrain is not None:
        ok &= np.minimum(a[:, 2], b[:, 2]) >= leg_floors(world, a, b)
    for shape in world.obstacles:
        ok &= ~envelope_hits(shape, a, b, m.obstacle)
    if world.zones:  # charted no-go zones, exact (Zones.envelopes_enter)
        ok &= ~world.zones.envelopes_enter(a, b)
    return ok


# ---------------------------------------------------------------------- building a mission
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


def _refine(world: World, p: np.ndarray, rounds: int = 10) -> np.ndarray:
    """Halve the legs whose envelope meets an obstacle: each half's envelope lies inside the
    whole leg's, and they shrink onto the 3D leg, which is free when the path was."""
    for _ in range(rounds):
        bad = ~envelopes_free(world, p[:-1], p[1:])
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
                    slack: float = 0.05) -> _F64:
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
    p = _refine(world, p)
    kept: _F64 = p[_douglas_peucker(world, p, tol)].copy()
    return kept


# ---------------------------------------------------------------------- re-flying a mission
class MissionCheckDict(TypedDict):
    """JSON form of a :class:`MissionCheck` (:meth:`MissionCheck.as_dict`); lengths in m, angles in degrees.

    Attributes
    ----------
    semantics : str
        ``"held"`` or ``"ramp"``.
    ok : bool
        Whether the mission keeps the altitude and obstacle margins.
    min_altitude_m, required_altitude_m, min_obstacle_distance_m, obstacle_margin_m : float
        As in :class:`MissionCheck`.
    min_altitude_leg, obstacle_hits, legs, executor_obstacle_hits : int
        As in :class:`MissionCheck`; ``legs`` the number of legs.
    pitch_deg, executor_min_altitude_m : float
        The executor model's pitch and least altitude.
    limits : WaypointLimitsDict or None
        The waypoints above the surface, outside the depth band or outside the bounds
        (:class:`~auvplan.guidance.mission.limits.WaypointLimits`).
    """

    semantics: str
    ok: bool
    min_altitude_m: float
    min_altitude_leg: int
    required_altitude_m: float
    min_obstacle_distance_m: float
    obstacle_hits: int
    obstacle_margin_m: float
    legs: int
    pitch_deg: float
    executor_min_altitude_m: float
    executor_obstacle_hits: int
    limits: WaypointLimitsDict | None


@dataclass(frozen=True, eq=False)
class MissionCheck:
    """A waypoint mission re-flown under an executor's depth semantics (static world only).

    Attributes
    ----------
    semantics : str
        ``"held"`` or ``"ramp"``.
    min_altitude_m : float
        Least altitude above the seabed over every leg (exact; ``inf`` without terrain).
    min_altitude_leg : int
        Leg where it occurs (-1 without legs or terrain).
    min_obstacle_distance_m : float
        Least distance to a static obstacle surface (``inf`` without one within 200 m of an envelope).
    obstacle_hits : int
        Legs whose swept region comes within the obstacle margin of an obstacle (exact test).
    leg_altitude_m : ndarray (K,)
        Least altitude per leg.
    required_altitude_m, obstacle_margin_m : float
        The world's margins.
    pitch_deg : float
        Pitch of the depth changes of the executor model (``"held"``; ``nan`` when not flown).
    executor_min_altitude_m : float
        ``"held"``: least altitude of a vehicle that steers towards each leg's depth at
        ``pitch_deg`` from wherever the previous leg left it (exact, on its polyline track);
        ``inf`` when not flown.
    executor_obstacle_hits : int
        Segments of that track within the obstacle margin of an obstacle.
    limits : WaypointLimits or None
        The sea surface, the depth band and the bounds at every waypoint (:func:`fly_check` sets it).
    """

    semantics: str
    min_altitude_m: float
    min_altitude_leg: int
    min_obstacle_distance_m: float
    obstacle_hits: int
    leg_altitude_m: _F64
    required_altitude_m: float
    obstacle_margin_m: float
    pitch_deg: float = float("nan")
    executor_min_altitude_m: float = float("inf")
    executor_obstacle_hits: int = 0
    limits: WaypointLimits | None = None

    @property
    def ok(self) -> bool:
        """True when the least altitude (envelope and executor) is at least the required one, no
        leg meets an obstacle and every waypoint keeps the surface, depth band and bounds."""
        alt = min(self.min_altitude_m, self.executor_min_altitude_m)
        return alt >= self.required_altitude_m - 1e-6 and self.obstacle_hits == 0 and self.executor_obstacle_hits == 0 \
            and (self.limits is None or self.limits.ok)

    def as_dict(self) -> MissionCheckDict:
        """Summarise the check as plain JSON.

        Returns
        -------
        MissionCheckDict
            The scalar attributes, ``ok`` and the number of legs.
        """
        return {"semantics": self.semantics, "ok": self.ok, "min_altitude_m": self.min_altitude_m,
                "min_altitude_leg": self.min_altitude_leg, "required_altitude_m": self.required_altitude_m,
                "min_obstacle_distance_m": self.min_obstacle_distance_m, "obstacle_hits": self.obstacle_hits,
                "obstacle_margin_m": self.obstacle_margin_m, "legs": int(self.leg_altitude_m.size),
                "pitch_deg": self.pitch_deg, "executor_min_altitude_m": self.executor_min_altitude_m,
                "executor_obstacle_hits": self.executor_obstacle_hits,
                "limits": None if self.limits is None else self.limits.as_dict()}


def _sphere_rect_distance(shape: Sphere, o: _F64, e1: _F64, e2: _F64) -> _F64:
    """Exact distance from a sphere's surface to the envelope rectangles."""
    d = _parallelogram_distance(o - np.asarray(shape.center), e1, e2)
    return d - shape.radius


def _sampled_rect_distance(shape: Shape, o: _F64, e1: _F64, e2: _F64, step: float) -> _F64:
    """Least distance to the shape's surface over a grid of points ``step`` apart on each rectangle."""
    out = np.empty(len(o))
    for k in range(len(o)):
        ns = int(np.clip(np.ceil(np.linalg.norm(e1[k]) / step), 1, 2000)) + 1
        nt = int(np.clip(np.ceil(np.linalg.norm(e2[k]) / step), 0, 500)) + 1
        s, t = np.meshgrid(np.linspace(0, 1, ns), np.linspace(0, 1, nt), indexing="ij")
        pts = o[k] + s[..., None] * e1[k] + t[..., None] * e2[k]
        out[k] = float(shape.distance(pts.reshape(-1, 3)).min())
    return out


def held_track(waypoints: ArrayLike, pitch_deg: float) -> _F64:
    """Return the track of a vehicle flying ``waypoints`` with depth held per leg (MOOS-IvP).

    On leg i it changes depth towards that of point i + 1 at ``pitch_deg`` (a straight climb or
    dive) and then holds it; a change not finished at the end of a leg carries on into the next.

    Parameters
    ----------
    waypoints : array_like
        ``(N, 3)`` waypoints (m).
    pitch_deg : float
        Pitch angle of the depth changes (degrees).

    Returns
    -------
    numpy.ndarray
        ``(M, 3)`` polyline track (m), with a corner where each depth change ends.
    """
    w = as_points(waypoints).reshape(-1, 3)
    slope = math.tan(math.radians(min(float(pitch_deg), 89.99)))
    out = [w[0]]
    z = float(w[0, 2])
    for a, b in zip(w[:-1], w[1:]):
        length = float(np.hypot(*(b[:2] - a[:2])))
        need = abs(float(b[2]) - z) / slope
        if 0.0 < need < length:  # the change ends inside the leg: a corner there
            f = need / length
            out.append(np.r_[a[:2] + f * (b[:2] - a[:2]), b[2]])
            z = float(b[2])
        elif need > 0.0:
            z += math.copysign(length * slope, float(b[2]) - z)
        out.append(np.r_[b[:2], z])
    return np.vstack(out)


def leg_figures(world: World, a: ArrayLike, b: ArrayLike, semantics: str = "held") -> tuple[_F64, NDArray[np.bool_],
                                                                                          _F64]:
    """Check each leg ``a -> b`` on its own, as :func:`fly_check` does: each leg's figures depend on its
    two ends only, so a mission edited at a few waypoints needs only its changed legs re-checked.

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    a, b : array_like
        ``(K, 3)`` leg starts and ends (m).
    semantics : {'held', 'ramp'}, optional
        ``"held"``: the leg's envelope; ``"ramp"``: the straight 3D leg.

    Returns
    -------
    altitude : numpy.ndarray
        ``(K,)`` least altitude above the seabed (m; ``inf`` without terrain).
    hits : numpy.ndarray
        ``(K,)`` bool, the leg comes within the obstacle margin of a static obstacle.
    distance : numpy.ndarray
        ``(K,)`` least distance to a static obstacle's surface (m; ``inf`` without one within 200 m).
    """
    a, b = as_points(a).reshape(-1, 3), as_points(b).reshape(-1, 3)
    m = world.margins
    if semantics == "held":
        fa, fb = a.copy(), b.copy()
        fa[:, 2] = fb[:, 2] = np.minimum(a[:, 2], b[:, 2])
        o, e1, e2 = _corners(a, b)
    else:
        fa, fb = a, b
        o, e1, e2 = a, b - a, np.zeros_like(a)
    alt = world.terrain.min_altitude_between(fa, fb) if world.terrain is not None and len(a) else \
        np.full(len(a), np.inf)
    dist = np.full(len(a), np.inf)
    hits = np.zeros(len(a), dtype=bool)
    for shape in world.obstacles:
        if not len(a):
            break
        hits |= shape.segments_hit(np.stack([a, b], axis=1), m.obstacle) if semantics == "ramp" else \
            envelope_hits(shape, a, b, m.obstacle)
        near = point_segment_distance(np.asarray(shape.center), o, o + e1) - shape.bounding_radius \
            < 200.0 + np.linalg.norm(e2, axis=-1)
        if not near.any():
            continue
        if isinstance(shape, Sphere):
            d = _sphere_rect_distance(shape, o[near], e1[near], e2[near])
        else:
            d = _sampled_rect_distance(shape, o[near], e1[near], e2[near], 0.25)
        dist[near] = np.minimum(dist[near], d)
    return np.asarray(alt, dtype=float), hits, dist


def segment_figures(world: World, a: ArrayLike, b: ArrayLike) -> tuple[_F64, NDArray[np.int64]]:
    """Least altitude and obstacle contacts of each straight segment ``a -> b`` (an executor's track).

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    a, b : array_like
        ``(K, 3)`` segment starts and ends (m).

    Returns
    -------
    altitude : numpy.ndarray
        ``(K,)`` least altitude above the seabed (m; ``inf`` without terrain).
    hits : numpy.ndarray
        ``(K,)`` number of static obstacles each segment comes within the obstacle margin of.
    """
    a, b = as_points(a).reshape(-1, 3), as_points(b).reshape(-1, 3)
    seg = np.stack([a, b], axis=1)
    alt = world.terrain.segment_min_altitude(seg) if world.terrain is not None and len(a) else \
        np.full(len(a), np.inf)
    hits = np.zeros(len(a), dtype=np.int64)
    for sh in world.obstacles:
        if len(a):
            hits += sh.segments_hit(seg, world.margins.obstacle).astype(np.int64)
    return np.asarray(alt, dtype=float), hits


def fly_check(world: World, waypoints: ArrayLike, semantics: str = "held", pitch_deg: float = 15.0,
              launch: bool = False) -> MissionCheck:
    """Re-fly ``waypoints (N, 3)`` under ``semantics`` against the seabed and static obstacles.

    ``"held"``: on each leg the vehicle lies anywhere between the depths of its two ends (the
    envelope; altitude of the flat leg at the deeper end), and the executor model
    (:func:`held_track` at ``pitch_deg``) is flown too, since a vehicle still changing depth when
    a leg ends is outside the next leg's envelope.  ``"ramp"``: on the straight 3D leg.
    Altitudes are exact (:meth:`Terrain.segment_min_altitude`); obstacle contact is the exact
    rectangle / segment test; obstacle distances are exact for spheres and sampled every 0.25 m
    near ellipsoids.  The sea surface, the depth band and the bounds are tested at every waypoint
    (:func:`~auvplan.guidance.mission.limits.waypoint_limits`: convex, so the ends decide each leg).

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    waypoints : array_like
        ``(N, 3)`` mission waypoints (m).
    semantics : {'held', 'ramp'}, optional
        The executor's depth semantics.
    pitch_deg : float, optional
        Pitch of the executor model's depth changes (degrees, in (0, 90]; ``"held"`` only).
    launch : bool, optional
        Waypoint 0 is a launch point on the surface (a QGroundControl ``.plan``'s home): exempt
        from the depth band.

    Returns
    -------
    MissionCheck
        Least altitudes, obstacle distance and hits, and the waypoints' limits.

    Raises
    ------
    ValueError
        For an unknown semantics, a pitch outside (0, 90] or fewer than two waypoints.
    """
    if semantics not in SEMANTICS:
        raise ValueError(f"semantics = {semantics!r}: choose one of {SEMANTICS}")
    if not 0.0 < pitch_deg <= 90.0:
        raise ValueError(f"pitch_deg = {pitch_deg}: must be in (0, 90] degrees")
    w = as_points(waypoints).reshape(-1, 3)
    m = world.margins
    if len(w) < 2:
        raise ValueError(f"a mission needs at least 2 waypoints (a start and a goal), got {len(w)}")
    limits = waypoint_limits(world, w, launch)
    alt, hits, leg_dist = leg_figures(world, w[:-1], w[1:], semantics)
    dist = float(leg_dist.min()) if leg_dist.size else np.inf
    k = int(np.argmin(alt)) if np.isfinite(alt).any() else -1
    extra: dict[str, float | int] = {}
    if semantics == "held":
        trk = held_track(w, pitch_deg)
        seg_alt, seg_hits = segment_figures(world, trk[:-1], trk[1:])
        ex_alt = float(seg_alt.min()) if world.terrain is not None else np.inf
        extra = {"pitch_deg": float(pitch_deg), "executor_min_altitude_m": ex_alt,
                 "executor_obstacle_hits": int(seg_hits.sum())}
    return MissionCheck(semantics, float(alt.min()), k, dist, int(hits.sum()), alt, m.min_altitude, m.obstacle,
                        limits=limits, **extra)  # type: ignore[arg-type]
