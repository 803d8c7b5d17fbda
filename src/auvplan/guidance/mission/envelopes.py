"""The envelope of a waypoint leg, tested exactly: the vertical rectangle spanned by the horizontal leg and
the depths of its two ends, where a vehicle flies the leg whether its executor holds the depth per leg or
ramps it (:mod:`auvplan.guidance.mission.waypoints`).  Its least altitude above the seabed is that of the
flat leg at the deeper end (:func:`leg_floors` gives the lowest safe depth over a leg); the obstacles are
tested against the rectangle exactly (:func:`envelope_hits`), the charted zones by their own exact test
(:func:`envelopes_free`), and the distance of a shape's surface to rectangles measured (:func:`rect_distance`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...geometry import as_points, point_segment_distance
from ...world import World
from ...world.obstacles import Ellipsoid, Shape, Sphere

__all__ = ["leg_floors", "envelope_corners", "envelope_hits", "envelopes_free", "rect_distance"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""


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


def envelope_corners(a: _F64, b: _F64) -> tuple[_F64, _F64, _F64]:
    """The envelope rectangles of legs ``a -> b``.

    Parameters
    ----------
    a, b : numpy.ndarray
        ``(K, 3)`` leg starts and ends (m).

    Returns
    -------
    o, e1, e2 : numpy.ndarray
        ``(K, 3)`` each: the origin (``a``'s horizontal position at the legs' lower z), the horizontal edge
        and the vertical edge (m).
    """
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
    o, e1, e2 = envelope_corners(a, b)
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


def rect_distance(shape: Shape, o: _F64, e1: _F64, e2: _F64) -> _F64:
    """Least distance from a shape's surface to envelope rectangles: exact for a sphere, over points 0.25 m
    apart on each rectangle for the other shapes.

    Parameters
    ----------
    shape : Shape
        A static obstacle.
    o, e1, e2 : numpy.ndarray
        ``(K, 3)`` the rectangles' origins and edges (m; :func:`envelope_corners`).

    Returns
    -------
    numpy.ndarray
        ``(K,)`` the distances (m).
    """
    if isinstance(shape, Sphere):
        return _sphere_rect_distance(shape, o, e1, e2)
    return _sampled_rect_distance(shape, o, e1, e2, 0.25)
