"""Closed bodies of revolution for document 000's ellipsoid case: sources and sinks on an axis.

Document 000 (§4.1) wraps an ellipsoid in the body formed by a source m at (−a₂, 0, 0), an equal
sink at (a₂, 0, 0) and the target sink Q at (a₁, 0, 0), and treats the ellipsoid with the body's
stagnation point x_s and mid-radius R₀ as its semi-axes.  The body is not that ellipsoid (METHODS.md
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
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from scipy.optimize import brentq

from .._jit import kernel
from .._types import ArrayLike, BoolArray, FloatArray
from ..world.obstacles import Ellipsoid, Shape

__all__ = [
    "AxialBody",
    "frame",
    "offset_surface",
    "design_line_body",
    "design_pair_body",
    "design_document_body",
    "design_body",
]

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


# ---------------------------------------------------------------------- design
def offset_surface(obstacle: Shape, margin: float, n: int = 60) -> FloatArray:
    """Points of the obstacle's surface moved out by ``margin`` along the normal (world frame).

    Parameters
    ----------
    obstacle : Sphere or Ellipsoid
        The obstacle.
    margin : float
        Offset along the outward normal (m).
    n : int, default 60
        Polar steps (``2 n`` azimuth steps).

    Returns
    -------
    numpy.ndarray
        Points ``(2 n (n + 1), 3)`` (m).
    """
    th = np.linspace(0.0, np.pi, n + 1)
    ph = np.linspace(0.0, 2 * np.pi, 2 * n, endpoint=False)
    TH, PH = np.meshgrid(th, ph)
    dirs = np.stack([np.sin(TH) * np.cos(PH), np.sin(TH) * np.sin(PH), np.cos(TH)], -1).reshape(-1, 3)
    if isinstance(obstacle, Ellipsoid):
        a = np.asarray(obstacle.semi_axes)
        local = dirs * a
        normal = local / a**2
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        rot = obstacle._rot
        moved: FloatArray = (local + margin * normal) @ rot.T + np.asarray(obstacle.center)
        return moved
    return np.asarray(obstacle.center) + (obstacle.radius + margin) * dirs


def _meridian(points: FloatArray, center: FloatArray, basis: FloatArray) -> tuple[FloatArray, FloatArray]:
    q = (points - center) @ basis
    return q[:, 0], np.hypot(q[:, 1], q[:, 2])


def _contains(body: AxialBody, x: FloatArray, rho: FloatArray, outer: bool = False) -> bool:
    """Whether the body contains the meridian points: F < 0 at all of them (and, with ``outer``, the
    outer-profile test of :meth:`AxialBody.inside`, which needs the profile)."""
    try:
        xf, xr = body.stagnation
    except (ValueError, IndexError):
        return False
    if not (x.min() > xf and x.max() < xr < body.a1):
        return False
    on_axis = rho < 1e-9 * (xr - xf)
    if not np.all((body.stream(x, rho) < 0) | on_axis):
        return False
    if not outer:
        return True
    return bool(body.inside(np.column_stack([x, rho, np.zeros_like(x)]) @ body.basis.T + body.center).all())


def _fit_line(x: FloatArray, rho: FloatArray, a1: float, Q: float, knots: FloatArray, delta: float,
              xc: float) -> FloatArray:
    """Least-squares densities whose dividing surface passes ``delta`` outside the shadow (x, ρ)."""
    th = np.arctan2(rho, x - xc)
    r = np.hypot(x - xc, rho)
    bins = np.linspace(0.0, np.pi, 91)
    idx = np.clip(np.digitize(th, bins) - 1, 0, 89)
    rmax = np.zeros(90)
    np.maximum.at(rmax, idx, r)
    ok = rmax > 0
    tc = 0.5 * (bins[:-1] + bins[1:])[ok]
    rt = rmax[ok] + delta
    tx, tr = xc + rt * np.cos(tc), rt * np.sin(tc)
    lo, hi = knots[:-1], knots[1:]
    psi, ux, _ = _line_terms(tx[:, None], tr[:, None], lo, hi)
    rhs = -Q * (1.0 + (tx - a1) / np.hypot(tx - a1, tr))
    # tips: zero axial velocity just outside the shadow's ends
    tips = np.array([x.min() - delta, x.max() + delta])
    _, uxt, _ = _line_terms(tips[:, None], np.zeros((2, 1)), lo, hi)
    uq = Q / FOUR_PI * np.sign(a1 - tips) / (a1 - tips) ** 2
    scale = np.abs(rhs).max() / max(np.abs(uq).max(), 1e-300)
    A = np.vstack([psi, scale * uxt])
    b = np.concatenate([rhs, -scale * uq])
    K = lo.size
    D = np.diff(np.eye(K), n=2, axis=0) * (1e-3 * np.linalg.norm(A) / max(K, 1))
    L = hi - lo
    # closure Σ λ L = 0 (a closed body), by the KKT system
    M = np.block([[A.T @ A + D.T @ D, L[:, None]], [L[None, :], np.zeros((1, 1))]])
    sol = np.linalg.lstsq(M, np.concatenate([A.T @ b, [0.0]]), rcond=None)[0]
    density: FloatArray = sol[:K]
    return density


def design_line_body(obstacle: Shape, target: ArrayLike, Q: float = 1.0, margin: float = 0.0,
                     pad: float = 0.0) -> AxialBody:
    """The smallest line-distribution body found that contains the obstacle inflated by ``margin + pad``.

    Parameters
    ----------
    obstacle : Sphere or Ellipsoid
        The obstacle to wrap.
    target : array_like
        The target sink's position ``(3,)`` (m); the body's axis points at it.
    Q : float, default 1.0
        Target sink strength (m³/s).
    margin : float, default 0.0
        Safety margin the body must contain around the obstacle (m).
    pad : float, default 0.0
        Extra inflation covering the chord sag of integration steps (m).

    Returns
    -------
    AxialBody
        The body (its ``kind`` says how it was sized).

    Raises
    ------
    ValueError
        If no fitted distribution contains the obstacle (the target too close to it).
    """
    c = np.asarray(obstacle.center, dtype=float)
    T = np.asarray(target, dtype=float)
    a1 = float(np.linalg.norm(T - c))
    basis = frame(T - c)
    # 0.1 % of the size on top: the surface between the sampled points (azimuth steps of 1.5°)
    x_all, rho_all = _meridian(offset_surface(obstacle, margin + pad + 1e-3 * obstacle.bounding_radius), c, basis)
    x, rho = _envelope(x_all, rho_all)
    xc = 0.5 * (x.min() + x.max())
    size = float(rho.max())
    best: AxialBody | None = None
    for K, frac in ((8, 0.8), (12, 0.85), (16, 0.9), (12, 0.7)):
        half = 0.5 * (x.max() - x.min())
        knots = np.linspace(xc - frac * half, xc + frac * half, K + 1)

        def build(delta: float, knots: FloatArray = knots) -> AxialBody:
            lam = _fit_line(x, rho, a1, Q, knots, delta, xc)
            return AxialBody(c, basis, a1, Q, knots=knots, density=lam, kind="line")

        lo, hi = 0.0, 0.25 * size
        good = build(hi)
        while not _contains(good, x, rho) and hi < 2.0 * size:
            lo, hi = hi, 2.0 * hi
            good = build(hi)
        if not _contains(good, x, rho):
            continue
        for _ in range(12):
            mid = 0.5 * (lo + hi)
            trial = build(mid)
            if _contains(trial, x, rho):
                hi, good = mid, trial
            else:
                lo = mid
        if (best is None or good.volume < best.volume) and _contains(good, x_all, rho_all, outer=True):
            best = good
    if best is None:
        raise ValueError(f"the target {tuple(T)} is too close to the obstacle at {tuple(c)}: no body contains it")
    return best


def _envelope(x: FloatArray, rho: FloatArray, bins: int = 160) -> tuple[FloatArray, FloatArray]:
    """Staircase upper envelope of meridian points: the largest ρ of each x bin at both bin edges.

    A body whose radius is concave in x contains every point when it contains these.
    """
    edges = np.linspace(x.min(), x.max(), bins + 1)
    k = np.clip(np.digitize(x, edges) - 1, 0, bins - 1)
    top = np.zeros(bins)
    np.maximum.at(top, k, rho)
    ex = np.concatenate([edges[:-1], edges[1:], [x.min(), x.max()]])
    return ex, np.concatenate([top, top, [0.0, 0.0]])


def _pair(c: FloatArray, basis: FloatArray, a1: float, Q: float, m: float, a2: float,
          kind: str = "pair") -> AxialBody:
    return AxialBody(c, basis, a1, Q, points=np.array([-a2, a2]), strengths=np.array([m, -m]), kind=kind)


def design_pair_body(obstacle: Shape, target: ArrayLike, Q: float = 1.0, margin: float = 0.0,
                     pad: float = 0.0) -> AxialBody:
    """The document's source/sink pair with m and a₂ both free: the smallest containing body on a search.

    Parameters
    ----------
    obstacle : Sphere or Ellipsoid
        The obstacle to wrap.
    target : array_like
        The target sink's position ``(3,)`` (m); the body's axis points at it.
    Q : float, default 1.0
        Target sink strength (m³/s).
    margin : float, default 0.0
        Safety margin the body must contain around the obstacle (m).
    pad : float, default 0.0
        Extra inflation covering the chord sag of integration steps (m).

    Returns
    -------
    AxialBody
        The body (its ``kind`` says how it was sized).

    Raises
    ------
    ValueError
        If no pair contains the obstacle (the target too close to it).
    """
    c = np.asarray(obstacle.center, dtype=float)
    T = np.asarray(target, dtype=float)
    a1 = float(np.linalg.norm(T - c))
    basis = frame(T - c)
    x, rho = _envelope(*_meridian(offset_surface(obstacle, margin + pad + 1e-3 * obstacle.bounding_radius), c, basis))
    half = 0.5 * (x.max() - x.min())
    best: AxialBody | None = None
    for a2 in half * np.linspace(0.1, 0.95, 10):
        lo, hi = 1e-6 * Q, 1e-6 * Q
        while not _contains(_pair(c, basis, a1, Q, hi, a2), x, rho):
            lo, hi = hi, hi * 2.0
            if hi > 1e6 * Q:
                break
        else:
            for _ in range(16):
                mid = np.sqrt(lo * hi)
                lo, hi = (lo, mid) if _contains(_pair(c, basis, a1, Q, mid, a2), x, rho) else (mid, hi)
            body = _pair(c, basis, a1, Q, hi, a2)
            if (best is None or body.volume < best.volume) and _contains(body, x, rho, outer=True):
                best = body
    if best is None:
        raise ValueError(f"the target {tuple(T)} is too close to the obstacle at {tuple(c)}: no body contains it")
    return best


def design_document_body(obstacle: Shape, target: ArrayLike, Q: float = 1.0, margin: float = 0.0,
                         pad: float = 0.0) -> AxialBody:
    """Document 000's sizing: front stagnation point and mid-radius R₀ equal to the inflated semi-axes.

    Along the axis the semi-axis is the inflated obstacle's extent; across it the largest radius of
    the meridian shadow.  Solves for (m, a₂) with the corrected flux equation (METHODS.md §1.4); the
    obstacle generally sticks out of this body.

    Parameters
    ----------
    obstacle : Sphere or Ellipsoid
        The obstacle to wrap.
    target : array_like
        The target sink's position ``(3,)`` (m); the body's axis points at it.
    Q : float, default 1.0
        Target sink strength (m³/s).
    margin : float, default 0.0
        Safety margin the body must contain around the obstacle (m).
    pad : float, default 0.0
        Extra inflation covering the chord sag of integration steps (m).

    Returns
    -------
    AxialBody
        The body (its ``kind`` says how it was sized).

    Raises
    ------
    ValueError
        If no (m, a₂) meets the two conditions.
    """
    c = np.asarray(obstacle.center, dtype=float)
    T = np.asarray(target, dtype=float)
    a1 = float(np.linalg.norm(T - c))
    basis = frame(T - c)
    x, rho = _meridian(offset_surface(obstacle, margin + pad, 40), c, basis)
    xs, R0 = float(-x.min()), float(rho.max())

    def m_for(a2: float) -> float:  # flux through the x = 0 disc of radius R0
        m: float = 0.5 * Q * (1.0 - a1 / np.hypot(a1, R0)) * np.hypot(a2, R0) / a2
        return m

    def front(a2: float) -> float:
        m = m_for(a2)
        return Q / (xs + a1) ** 2 - m / (a2 - xs) ** 2 + m / (xs + a2) ** 2

    grid = xs * np.geomspace(1e-4, 0.999, 200)
    vals = np.array([front(g) for g in grid])
    k = np.flatnonzero(np.diff(np.sign(vals)) != 0)
    if k.size == 0:
        raise ValueError(f"document sizing: no (m, a2) gives x_s = {xs:g} and R0 = {R0:g}")
    a2 = brentq(front, grid[k[0]], grid[k[0] + 1])
    return _pair(c, basis, a1, Q, m_for(a2), a2, kind="document")


def design_body(obstacle: Shape, target: ArrayLike, sizing: str, Q: float = 1.0, margin: float = 0.0,
                pad: float = 0.0) -> AxialBody:
    """Dispatch on ``sizing``: ``"line"`` (default), ``"pair"`` or ``"document"``.

    Parameters
    ----------
    obstacle : Sphere or Ellipsoid
        The obstacle to wrap.
    target : array_like
        The target sink's position ``(3,)`` (m).
    sizing : str
        ``"line"`` (falls back to ``"pair"`` when no line distribution contains the obstacle),
        ``"pair"`` or ``"document"``.
    Q : float, default 1.0
        Target sink strength (m³/s).
    margin : float, default 0.0
        Safety margin the body must contain around the obstacle (m).
    pad : float, default 0.0
        Extra inflation covering the chord sag of integration steps (m).

    Returns
    -------
    AxialBody
        The designed body.
    """
    if sizing == "line":
        try:
            return design_line_body(obstacle, target, Q, margin, pad)
        except ValueError:  # no fitted line distribution contains it: the two-parameter pair
            return design_pair_body(obstacle, target, Q, margin, pad)
    fn = {"pair": design_pair_body, "document": design_document_body}[sizing]
    return fn(obstacle, target, Q, margin, pad)
