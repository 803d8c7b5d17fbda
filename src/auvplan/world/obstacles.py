"""Static and moving obstacles with vectorised signed distances.

* :class:`Sphere` and :class:`Ellipsoid` (semi-axes plus yaw/pitch/roll).
  ``distance`` is the true Euclidean signed distance to the surface (negative
  inside).  For the ellipsoid the foot point ``q_i = A_i² p_i / (A_i² + t)`` is
  found by bisection on the root of ``Σ (A_i p_i / (A_i² + t))² = 1``
  (docs/methods.md §1.5); document 000's radial-ray distance ``|p| (1 - 1/s)``,
  which overestimates the clearance, is :meth:`Ellipsoid.ray_distance`, and the
  guaranteed lower bound ``(s - 1) A_min`` is :meth:`Ellipsoid.lower_bound_distance`.

Moving obstacles (these shapes on a motion model) are in :mod:`auvplan.world.moving`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .._types import ArrayLike, BoolArray, FloatArray
from ..geometry import as_points, point_segment_distance, rotation_matrix
from .kernels.ellipsoid import foot_point

__all__ = [
    "Sphere",
    "Ellipsoid",
    "Shape",
]


@dataclass(frozen=True)
class Sphere:
    """Sphere of ``radius`` (m) about ``center``.

    Parameters
    ----------
    center : tuple of float
        Centre ``(x, y, z)`` (m).
    radius : float
        Radius (m), positive.

    Raises
    ------
    ValueError
        If the radius is not positive.
    """

    center: tuple[float, float, float]
    radius: float

    def __post_init__(self) -> None:
        if not self.radius > 0:
            raise ValueError(f"sphere radius must be positive, got {self.radius}")
        object.__setattr__(self, "center", tuple(float(c) for c in self.center))

    @property
    def bounding_radius(self) -> float:
        """Radius of a sphere about the centre that contains the shape.

        Returns
        -------
        float
            Radius (m).
        """
        return self.radius

    @property
    def z_range(self) -> tuple[float, float]:
        """Exact vertical extent: the lowest and highest z of the surface.

        Returns
        -------
        tuple of float
            ``(z_min, z_max)`` (m, up positive): the centre's z ∓ the radius.
        """
        zc = self.center[2]
        return zc - self.radius, zc + self.radius

    def distance(self, points: ArrayLike) -> FloatArray:
        """Signed distance from points to the surface.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m), negative inside.
        """
        p = as_points(points)
        d: FloatArray = np.linalg.norm(p - np.asarray(self.center), axis=-1) - self.radius
        return d

    def gradient(self, points: ArrayLike) -> FloatArray:
        """Unit outward direction of increasing distance.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Unit vectors ``(..., 3)`` (zero at the centre).
        """
        r = as_points(points) - np.asarray(self.center)
        n = np.linalg.norm(r, axis=-1, keepdims=True)
        g: FloatArray = r / np.where(n > 0, n, 1.0)
        return g

    def segments_hit(self, segments: ArrayLike, margin: ArrayLike = 0.0) -> BoolArray:
        """Exact test: where a segment comes closer than ``margin`` to the surface.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).
        margin : float or array_like, default 0.0
            Required distance from the surface (m): one for all, or one per segment (``(...)``).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True for segments that come closer than ``margin``.
        """
        s = np.asarray(segments, dtype=float)
        m = np.asarray(margin, dtype=float)
        return point_segment_distance(np.asarray(self.center), s[..., 0, :], s[..., 1, :]) < self.radius + m

    def segment_distance(self, segments: ArrayLike) -> FloatArray:
        """Least signed distance to the surface along each segment (exact): :meth:`segments_hit` at ``margin`` is
        this below ``margin``.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m), negative where the segment enters the sphere.
        """
        s = np.asarray(segments, dtype=float)
        out: FloatArray = point_segment_distance(np.asarray(self.center), s[..., 0, :], s[..., 1, :]) - self.radius
        return out

    def moved_to(self, center: ArrayLike) -> Sphere:
        """The same sphere about a new centre.

        Parameters
        ----------
        center : array_like
            New centre ``(3,)`` (m).

        Returns
        -------
        Sphere
            A copy with the new centre.
        """
        return replace(self, center=tuple(np.asarray(center, dtype=float)))


@dataclass(frozen=True)
class Ellipsoid:
    """Ellipsoid with ``semi_axes`` (m) along its body axes, oriented by yaw/pitch/roll (rad).

    Parameters
    ----------
    center : tuple of float
        Centre ``(x, y, z)`` (m).
    semi_axes : tuple of float
        Semi-axes along the body x, y, z axes (m), positive.
    yaw : float, default 0.0
        Turns the body x axis counter-clockwise from east about z (rad).
    pitch : float, default 0.0
        Lifts the body x axis towards +z (rad).
    roll : float, default 0.0
        Turns the body about its x axis (rad).

    Raises
    ------
    ValueError
        If ``semi_axes`` are not three positive lengths.
    """

    center: tuple[float, float, float]
    semi_axes: tuple[float, float, float]
    yaw: float = 0.0
    pitch: float = 0.0
    roll: float = 0.0
    _rot: FloatArray = field(init=False, repr=False, compare=False)
    _axes: FloatArray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        axes = tuple(float(a) for a in self.semi_axes)
        if len(axes) != 3 or min(axes) <= 0:
            raise ValueError(f"ellipsoid semi_axes must be three positive lengths, got {self.semi_axes}")
        object.__setattr__(self, "semi_axes", axes)
        object.__setattr__(self, "center", tuple(float(c) for c in self.center))
        object.__setattr__(self, "_rot", rotation_matrix(self.yaw, self.pitch, self.roll))
        object.__setattr__(self, "_axes", np.asarray(axes, dtype=float))

    @property
    def bounding_radius(self) -> float:
        """Radius of a sphere about the centre that contains the shape.

        Returns
        -------
        float
            Radius (m).
        """
        return max(self.semi_axes)

    @property
    def z_range(self) -> tuple[float, float]:
        """Exact vertical extent: the lowest and highest z of the surface.

        A surface point is ``c + R (a ∘ u)`` for a unit vector ``u`` (``R`` the body-to-world rotation,
        ``a`` the semi-axes), so its z is ``c_z + Σ_j R[2, j] a_j u_j``, whose extremes over the unit
        sphere are ``c_z ∓ sqrt(Σ_j (R[2, j] a_j)²)``.

        Returns
        -------
        tuple of float
            ``(z_min, z_max)`` (m, up positive).
        """
        half = float(np.linalg.norm(self._rot[2] * self._axes))
        zc = self.center[2]
        return zc - half, zc + half

    def to_body(self, points: ArrayLike) -> FloatArray:
        """World points in the ellipsoid's body frame.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Body-frame coordinates ``(..., 3)`` (m, origin at the centre).
        """
        pb: FloatArray = (as_points(points) - np.asarray(self.center)) @ self._rot
        return pb

    def _foot_point(self, pb: FloatArray) -> FloatArray:
        """Nearest surface point (body frame) for body-frame points ``(N, 3)`` (ellipsoid_kernels)."""
        foot: FloatArray = foot_point(self._axes, np.ascontiguousarray(pb, dtype=float))
        return foot

    def distance(self, points: ArrayLike) -> FloatArray:
        """True signed Euclidean distance to the surface.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m), negative inside.
        """
        pb = self.to_body(points)
        flat = pb.reshape(-1, 3)
        q = self._foot_point(flat)
        d = np.linalg.norm(flat - q, axis=-1)
        inside = ((flat / np.asarray(self.semi_axes)) ** 2).sum(axis=-1) < 1.0
        signed: FloatArray = np.where(inside, -d, d).reshape(pb.shape[:-1])
        return signed

    def gradient(self, points: ArrayLike) -> FloatArray:
        """Unit direction of increasing distance (from the foot point), world frame.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Unit vectors ``(..., 3)``.
        """
        pb = self.to_body(points)
        flat = pb.reshape(-1, 3)
        q = self._foot_point(flat)
        r = flat - q
        n = np.linalg.norm(r, axis=-1, keepdims=True)
        inside = ((flat / np.asarray(self.semi_axes)) ** 2).sum(axis=-1, keepdims=True) < 1.0
        normal = q / np.asarray(self.semi_axes) ** 2
        normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
        g = np.where(n > 1e-12, r / np.where(n > 0, n, 1.0) * np.where(inside, -1.0, 1.0), normal)
        world: FloatArray = (g @ self._rot.T).reshape(pb.shape)
        return world

    def ray_distance(self, points: ArrayLike) -> FloatArray:
        """Document 000's distance along the ray to the centre, ``|p| (1 - 1/s)`` (not conservative).

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m), negative inside; overestimates the true clearance.
        """
        pb = self.to_body(points)
        s = np.sqrt(((pb / np.asarray(self.semi_axes)) ** 2).sum(axis=-1))
        ray: FloatArray = np.linalg.norm(pb, axis=-1) * (1.0 - 1.0 / np.where(s > 0, s, 1.0))
        return ray

    def lower_bound_distance(self, points: ArrayLike) -> FloatArray:
        """Guaranteed lower bound of the distance outside: ``(s - 1) A_min``.

        Parameters
        ----------
        points : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m), never above the true distance outside.
        """
        pb = self.to_body(points)
        s = np.sqrt(((pb / np.asarray(self.semi_axes)) ** 2).sum(axis=-1))
        bound: FloatArray = (s - 1.0) * min(self.semi_axes)
        return bound

    def segments_hit(self, segments: ArrayLike, margin: ArrayLike = 0.0) -> BoolArray:
        """Exact test: where a segment comes closer than ``margin`` to the surface.

        Without a margin, the segment against the unit sphere in scaled coordinates.  With one, the
        ellipsoid scaled by ``1 + margin / A_min`` (which contains every point within ``margin``)
        rules out the clear segments; for the rest, the signed distance along the segment is convex
        in the segment parameter, so a golden-section search finds its minimum (to 10⁻⁹ of the
        segment's length) and decides.

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).
        margin : float or array_like, default 0.0
            Required distance from the surface (m): one for all, or one per segment (``(...)``).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True for segments that come closer than ``margin``.
        """
        s = np.asarray(segments, dtype=float)
        a = self.to_body(s[..., 0, :]) / np.asarray(self.semi_axes)
        b = self.to_body(s[..., 1, :]) / np.asarray(self.semi_axes)
        touch = point_segment_distance(np.zeros(3), a, b) < 1.0
        m = np.broadcast_to(np.asarray(margin, dtype=float), touch.shape)
        if not (m > 0).any():
            return touch
        scale = (1.0 + m / min(self.semi_axes))[..., None]
        near = (point_segment_distance(np.zeros(3), a / scale, b / scale) < 1.0) & ~touch & (m > 0)
        hit = touch.copy()
        if near.any():
            hit[near] = self._segment_min_distance(s[near]) < m[near]
        return hit

    def _segment_min_distance(self, seg: FloatArray) -> FloatArray:
        """Smallest signed distance to the surface along segments ``(N, 2, 3)`` (golden section)."""
        p0, d = seg[:, 0], seg[:, 1] - seg[:, 0]
        g = 0.5 * (np.sqrt(5.0) - 1.0)
        lo, hi = np.zeros(len(seg)), np.ones(len(seg))
        t1, t2 = hi - g * (hi - lo), lo + g * (hi - lo)
        f1 = self.distance(p0 + t1[:, None] * d)
        f2 = self.distance(p0 + t2[:, None] * d)
        for _ in range(44):  # 0.618^44 < 1e-9
            left = f1 < f2
            hi = np.where(left, t2, hi)
            lo = np.where(left, lo, t1)
            t2n = np.where(left, t1, lo + g * (hi - lo))
            t1n = np.where(left, hi - g * (hi - lo), t2)
            f2n = np.where(left, f1, np.nan)
            f1n = np.where(left, np.nan, f2)
            t1, t2 = t1n, t2n
            todo1, todo2 = np.isnan(f1n), np.isnan(f2n)
            if todo1.any():
                f1n[todo1] = self.distance(p0[todo1] + t1[todo1, None] * d[todo1])
            if todo2.any():
                f2n[todo2] = self.distance(p0[todo2] + t2[todo2, None] * d[todo2])
            f1, f2 = f1n, f2n
        ends = np.minimum(self.distance(seg[:, 0]), self.distance(seg[:, 1]))
        least: FloatArray = np.minimum(np.minimum(f1, f2), ends)
        return least

    def segment_distance(self, segments: ArrayLike) -> FloatArray:
        """Least signed distance to the surface along each segment: the golden-section minimum
        :meth:`segments_hit` decides a margin by (to 10⁻⁹ of the segment's length).

        Parameters
        ----------
        segments : array_like
            Start and end points ``(..., 2, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m), negative where the segment enters the ellipsoid.
        """
        s = np.asarray(segments, dtype=float)
        flat = s.reshape(-1, 2, 3)
        out: FloatArray = self._segment_min_distance(flat).reshape(s.shape[:-2]) if flat.shape[0] else \
            np.empty(s.shape[:-2])
        return out

    def moved_to(self, center: ArrayLike) -> Ellipsoid:
        """The same ellipsoid about a new centre.

        Parameters
        ----------
        center : array_like
            New centre ``(3,)`` (m).

        Returns
        -------
        Ellipsoid
            A copy with the new centre (same axes and orientation).
        """
        return replace(self, center=tuple(np.asarray(center, dtype=float)))


Shape = Sphere | Ellipsoid
