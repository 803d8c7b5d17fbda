"""Closed bodies of revolution for document 000's ellipsoid case: sources and sinks on an axis.

Document 000 (§4.1) wraps an ellipsoid in the body formed by a source m at (−a₂, 0, 0), an equal
sink at (a₂, 0, 0) and the target sink Q at (a₁, 0, 0), and treats the ellipsoid with the body's
stagnation point x_s and mid-radius R₀ as its semi-axes.  The body is not that ellipsoid (docs/methods.md
§1.4): the real obstacle sticks out of it.  This module builds the same kind of flow — still
axisymmetric potential flow about the axis from the obstacle to the target, still the target sink
plus sources and sinks on that axis — but sized so that the body contains the obstacle inflated by
the safety margin with little excess volume:

* :func:`design_line_body` (**default**): a line distribution of sources and sinks (piecewise-constant
  density on K segments) fitted by regularised least squares so that its dividing stream surface
  passes a small gap δ outside the inflated obstacle's meridian shadow, with δ bisected to the
  smallest value whose body contains every sampled surface point; the smallest body over a few
  segment layouts wins.
* :func:`design_pair_body`: the document's source/sink pair with both m and a₂ free, the smallest
  containing body on a (a₂, m) search.
* :func:`design_document_body`: the document's own sizing — m and a₂ chosen so the front stagnation
  point and R₀ equal the ellipsoid's semi-axes along and across the axis (corrected 4π formulas);
  the obstacle is *not* contained (kept for comparison).

The body is described by the Stokes stream function of the whole flow (body frame, x along the axis,
ρ the distance from it): F = Q (1 + cos α_A) − Σ σᵢ cos αᵢ + Σ λⱼ (r_{j,1} − r_{j,0}), with
u_x = F_ρ / (4πρ), u_ρ = −F_x / (4πρ); F < 0 inside the body, F = 0 on it and on the axis outside
it.  Its meridian profile (a polyline of 721 points from rays about the body's centre) gives the
distance to the body that the planner's blend weights and step control use.

This module holds the body (:class:`AxialBody`); :mod:`.flow_design` sizes it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray
from ...runtime.jit import kernel

__all__ = ["AxialBody", "frame"]

FOUR_PI = 4.0 * np.pi
PROFILE_RAYS = 721


def frame(axis: ArrayLike) -> FloatArray:
    """Orthonormal basis (columns) whose first column is ``axis``.

    Parameters
    ----------
    axis : array_like
        Direction ``(3,)`` (any length but zero).

    Returns
    -------
    numpy.ndarray
        ``(3, 3)``: the unit axis and two unit normals, right-handed.
    """
    x = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])


@kernel
def _polyline_distance(x: FloatArray, rho: FloatArray, px: FloatArray,
                       pr: FloatArray) -> FloatArray:  # pragma: no cover - compiled
    """Distance of meridian points (x, ρ) to the polyline (px, pr)."""
    n = x.size
    out = np.empty(n)
    for i in range(n):
        best = 1e300
        for j in range(px.size - 1):
            dx = px[j + 1] - px[j]
            dr = pr[j + 1] - pr[j]
            ll = dx * dx + dr * dr
            t = ((x[i] - px[j]) * dx + (rho[i] - pr[j]) * dr) / ll if ll > 0 else 0.0
            t = min(1.0, max(0.0, t))
            ex = x[i] - px[j] - t * dx
            er = rho[i] - pr[j] - t * dr
            d = ex * ex + er * er
            if d < best:
                best = d
        out[i] = np.sqrt(best)
    return out


def _line_terms(x: FloatArray, rho: FloatArray, lo: FloatArray,
                hi: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Per-segment stream-function and velocity kernels of unit density on [lo, hi] (broadcast)."""
    X0, X1 = x - lo, x - hi
    r0, r1 = np.hypot(X0, rho), np.hypot(X1, rho)
    psi = r1 - r0
    s0, s1 = np.where(X0 >= 0, 1.0, -1.0), np.where(X1 >= 0, 1.0, -1.0)
    with np.errstate(divide="ignore", invalid="ignore"):  # on the segment itself (inside the body)
        ux = (1.0 / r1 - 1.0 / r0) / FOUR_PI
        same = s1 * (1.0 / (r1 * (r1 + np.abs(X1)))) - s0 * (1.0 / (r0 * (r0 + np.abs(X0))))
        direct = (X0 / r0 - X1 / r1) / (rho * rho)
    k: FloatArray = np.where(s0 == s1, same, direct) / FOUR_PI  # u_ρ / ρ, stable near the axis
    return psi, ux, k


@dataclass(frozen=True, eq=False)
class AxialBody:
    """Target sink Q at (a₁, 0, 0) plus point singularities and line segments on the body-frame x axis.

    Attributes
    ----------
    center, basis : ndarray
        Body-frame origin (world, m) and basis (columns: axis to the target, two normals).
    a1, Q : float
        Target distance along the axis (m) and target sink strength (m³/s).
    points, strengths : ndarray
        Point sources (σ > 0) and sinks (σ < 0) on the axis: body-frame x (m) and strengths (m³/s).
    knots, density : ndarray
        Segment ends ``(K + 1,)`` (m) and source densities ``(K,)`` per metre (m²/s; negative: sinks).
    kind : str
        How it was sized (``"line"``, ``"pair"``, ``"document"``).
    """

    center: FloatArray
    basis: FloatArray
    a1: float
    Q: float
    points: FloatArray = field(default_factory=lambda: np.zeros(0))
    strengths: FloatArray = field(default_factory=lambda: np.zeros(0))
    knots: FloatArray = field(default_factory=lambda: np.zeros(0))
    density: FloatArray = field(default_factory=lambda: np.zeros(0))
    kind: str = "line"

    # ------------------------------------------------------------------ flow
    def local(self, p: ArrayLike) -> FloatArray:
        """World points in the body frame.

        Parameters
        ----------
        p : array_like
            World points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Body-frame coordinates ``(..., 3)`` (m; x along the axis).
        """
        q: FloatArray = (np.asarray(p, dtype=float) - self.center) @ self.basis
        return q

    def stream(self, x: FloatArray, rho: FloatArray) -> FloatArray:
        """Stokes stream function F(x, ρ) (negative inside the body).

        Parameters
        ----------
        x : numpy.ndarray
            Body-frame coordinate along the axis (m).
        rho : numpy.ndarray
            Distance from the axis (m); broadcasts with ``x``.

        Returns
        -------
        numpy.ndarray
            F (m³/s), the broadcast shape.
        """
        x = np.asarray(x, dtype=float)[..., None]
        rho = np.abs(np.asarray(rho, dtype=float))[..., None]
        dA = x[..., 0] - self.a1
        F = self.Q * (1.0 + dA / np.maximum(np.hypot(dA, rho[..., 0]), 1e-300))
        if self.points.size:
            d = x - self.points
            F = F - (self.strengths * d / np.maximum(np.hypot(d, rho), 1e-300)).sum(-1)
        if self.density.size:
            psi, _, _ = _line_terms(x, rho, self.knots[:-1], self.knots[1:])
            F = F + (self.density * psi).sum(-1)
        stream: FloatArray = F
        return stream

    def stream_at(self, p: ArrayLike) -> FloatArray:
        """F at world points.

        Parameters
        ----------
        p : array_like
            World points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            F ``(...)`` (m³/s), negative inside the body.
        """
        q = self.local(p)
        return self.stream(q[..., 0], np.hypot(q[..., 1], q[..., 2]))

    def velocity_local(self, q: ArrayLike) -> FloatArray:
        """Velocity at body-frame points (target sink + axis singularities).

        Parameters
        ----------
        q : array_like
            Body-frame points ``(N, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Body-frame velocity ``(N, 3)`` (m/s).
        """
        q = np.asarray(q, dtype=float)
        A = np.array([self.a1, 0.0, 0.0])
        r = q - A
        u = -self.Q * r / (FOUR_PI * np.maximum(np.linalg.norm(r, axis=-1, keepdims=True), 1e-300) ** 3)
        for xs, s in zip(self.points, self.strengths):
            r = q - np.array([xs, 0.0, 0.0])
            u = u + s * r / (FOUR_PI * np.maximum(np.linalg.norm(r, axis=-1, keepdims=True), 1e-300) ** 3)
        if self.density.size:
            rho = np.hypot(q[:, 1], q[:, 2])[:, None]
            _, ux, k = _line_terms(q[:, :1], rho, self.knots[:-1], self.knots[1:])
            u[:, 0] += ux @ self.density
            u[:, 1:] += (k @ self.density)[:, None] * q[:, 1:]
        velocity: FloatArray = u
        return velocity

    def velocity(self, p: ArrayLike) -> FloatArray:
        """Velocity at world points.

        Parameters
        ----------
        p : array_like
            World points ``(N, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            World-frame velocity ``(N, 3)`` (m/s).
        """
        u: FloatArray = self.velocity_local(self.local(p)) @ self.basis.T
        return u

    def _axial_speed(self, x: float) -> float:
        return float(self.velocity_local(np.array([[x, 0.0, 0.0]]))[0, 0])

    # ------------------------------------------------------------------ geometry
    @cached_property
    def singular_range(self) -> tuple[float, float]:
        """Axial extent of the singularities.

        Returns
        -------
        tuple of float
            Smallest and largest body-frame x of the points and knots (m).
        """
        xs = np.concatenate([self.points, self.knots])
        return float(xs.min()), float(xs.max())

    @cached_property
    def stagnation(self) -> tuple[float, float]:
        """Front and rear stagnation points on the axis.

        Returns
        -------
        tuple of float
            Body-frame x of the front and rear stagnation points (m).
        """
        from scipy.optimize import brentq  # here: a plan round an ellipsoid never asks (scipy.optimize, ~0.3 s)

        lo, hi = self.singular_range
        span = max(hi - lo, 1e-9 * self.a1)
        xf = brentq(self._axial_speed, lo - 1e4 * max(span, 1.0), lo - 1e-9 * span, xtol=1e-13 * span)
        grid = hi + (self.a1 - hi) * np.geomspace(1e-9, 1.0 - 1e-9, 600)
        ux = self.velocity_local(np.column_stack([grid, np.zeros((grid.size, 2))]))[:, 0]
        k = np.flatnonzero((ux[:-1] < 0) & (ux[1:] >= 0))
        xr = brentq(self._axial_speed, grid[k[0]], grid[k[0] + 1], xtol=1e-13 * span)
        return xf, xr

    @cached_property
    def profile(self) -> np.ndarray:
        """Outer meridian profile ``(PROFILE_RAYS, 2)`` of (x, ρ), front to rear stagnation point.

        On each ray from the body's mid-point the outermost F = 0 crossing: a scan from outside
        inwards, then bisection.  (Alternating sources and sinks can leave closed regions with F > 0
        inside the body; they are inside it all the same.)

        Returns
        -------
        numpy.ndarray
            ``(PROFILE_RAYS, 2)`` body-frame (x, ρ) (m).
        """
        xf, xr = self.stagnation
        xm = 0.5 * (xf + xr)
        th = np.linspace(np.pi, 0.0, PROFILE_RAYS)
        c, s = np.cos(th), np.sin(th)
        reach = np.where(np.arange(th.size) < th.size // 2, xm - xf, xr - xm)
        top = 1.05 * max(xr - xf, 1e-9)
        r = np.linspace(0.0, top, 300)[None, :] * np.ones((th.size, 1))
        neg = self.stream(xm + r * c[:, None], r * s[:, None]) < 0
        neg[:, 0] = True
        last = neg.shape[1] - 1 - np.argmax(neg[:, ::-1], axis=1)
        lo = r[np.arange(th.size), last]
        hi = r[np.arange(th.size), np.minimum(last + 1, r.shape[1] - 1)]
        for _ in range(50):
            mid = 0.5 * (lo + hi)
            inside = self.stream(xm + mid * c, mid * s) < 0
            lo = np.where(inside, mid, lo)
            hi = np.where(inside, hi, mid)
        rr = 0.5 * (lo + hi)
        rr[0], rr[-1] = reach[0], reach[-1]
        return np.column_stack([xm + rr * c, rr * s])

    @cached_property
    def volume(self) -> float:
        """Volume of the body, from the profile (π ∫ ρ² dx over the polyline, exact for cones).

        Returns
        -------
        float
            Volume (m³).
        """
        x, r = self.profile[:, 0], self.profile[:, 1]
        return float(abs(np.sum(np.pi / 3.0 * np.diff(x) * (r[:-1] ** 2 + r[:-1] * r[1:] + r[1:] ** 2))))

    @cached_property
    def radius(self) -> float:
        """Largest radius of the body.

        Returns
        -------
        float
            Largest ρ of the profile (m).
        """
        return float(self.profile[:, 1].max())

    def inside(self, p: ArrayLike) -> BoolArray:
        """Where world points lie inside the body's outer surface.

        Well inside the profile (by 1 % of the radius) is inside; near it, the sign of F decides.

        Parameters
        ----------
        p : array_like
            World points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``, True inside.
        """
        q = self.local(p)
        xf, xr = self.stagnation
        rho = np.hypot(q[..., 1], q[..., 2])
        prof = self.profile
        R = np.interp(q[..., 0], prof[:, 0], prof[:, 1], left=0.0, right=0.0)
        tol = 0.01 * self.radius
        between = (q[..., 0] > xf) & (q[..., 0] < xr)
        near = self.stream(q[..., 0], rho) < 0
        # on the axis F vanishes between the end singularities and the stagnation points: use x there
        within: BoolArray = between & ((rho < R - tol) | ((near | (rho < 1e-9 * (xr - xf))) & (rho < R + tol)))
        return within

    def distance(self, p: ArrayLike) -> FloatArray:
        """Signed distance of world points to the body surface.

        Parameters
        ----------
        p : array_like
            World points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m), negative inside.
        """
        p = np.asarray(p, dtype=float)
        q = self.local(p).reshape(-1, 3)
        rho = np.hypot(q[:, 1], q[:, 2])
        prof = self.profile
        d = _polyline_distance(np.ascontiguousarray(q[:, 0]), rho, np.ascontiguousarray(prof[:, 0]),
                               np.ascontiguousarray(prof[:, 1]))
        signed: FloatArray = np.where(self.inside(p.reshape(-1, 3)), -d, d).reshape(p.shape[:-1])
        return signed

    def normal(self, p: ArrayLike) -> FloatArray:
        """Unit outward normal at the body point nearest to each world point.

        Parameters
        ----------
        p : array_like
            World points ``(N, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Unit normals ``(N, 3)`` (world frame).
        """
        q = self.local(p).reshape(-1, 3)
        rho = np.hypot(q[:, 1], q[:, 2])
        prof = self.profile
        mid = 0.5 * (prof[1:] + prof[:-1])
        j = np.argmin(np.hypot(q[:, None, 0] - mid[:, 0], rho[:, None] - mid[:, 1]), axis=1)
        t = prof[j + 1] - prof[j]
        n2 = np.column_stack([-t[:, 1], t[:, 0]])  # the profile runs front → rear above the axis: left is out
        n2 /= np.linalg.norm(n2, axis=1, keepdims=True)
        er = q[:, 1:] / np.where(rho > 0, rho, 1.0)[:, None]
        er[rho == 0] = (0.0, 1.0)
        n = np.column_stack([n2[:, 0], n2[:, 1:2] * er])
        world: FloatArray = n @ self.basis.T
        return world
