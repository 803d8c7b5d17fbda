"""Flow past a triaxial ellipsoid in a stream from any direction (Lamb, *Hydrodynamics* §§111-115).

A uniform stream U past a fixed ellipsoid with semi-axes (a₁, a₂, a₃) (its own frame) has the
disturbance potential

    φ_d = Σᵢ Uᵢ Kᵢ xᵢ Iᵢ(λ),   Iᵢ(λ) = ∫_λ^∞ ds / ((aᵢ² + s) Δ(s)) = (2/3) R_D(aⱼ² + λ, aₖ² + λ, aᵢ² + λ),

Δ(s) = √((a₁² + s)(a₂² + s)(a₃² + s)), λ ≥ 0 the ellipsoidal coordinate of the point (the largest root of
Σ xᵢ² / (aᵢ² + λ) = 1), R_D Carlson's symmetric integral, and Kᵢ = a₁a₂a₃ / (2 − αᵢ) with
αᵢ = a₁a₂a₃ Iᵢ(0), fixed by zero normal velocity on the surface (λ = 0).  The sphere's limit is the
doublet U x a³ / (2 r³).  The stream's dividing surface *is* the ellipsoid.

:class:`EllipsoidBody` wraps an obstacle in the smallest ellipsoid b = a + δ (same axes) that contains the
obstacle inflated by the margin, and flows round it with the target sink's own velocity as the stream:
u(p) = u_s(p) + u_d(p; U = u_s(p)).  The stream is frozen at each point, so the normal velocity vanishes
on the whole surface exactly (to round-off) for any sink position; the price is that the field is not
exactly irrotational near the body (it is the sink's field plus a 1/r³ disturbance far from it).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray
from ...runtime.jit import kernel
from ...world import Ellipsoid

__all__ = ["carlson_rd", "ellipsoid_coefficients", "ellipsoid_disturbance", "EllipsoidBody", "design_ellipsoid_body"]

FOUR_PI = 4.0 * np.pi


@kernel
def carlson_rd(x: float, y: float, z: float) -> float:  # pragma: no cover - compiled
    """Carlson's R_D(x, y, z) = (3/2) ∫₀^∞ dt / ((t + z)^{3/2} √((t + x)(t + y))) (duplication, Carlson 1995).

    Parameters
    ----------
    x, y : float
        Non-negative, at most one zero.
    z : float
        Positive.

    Returns
    -------
    float
        R_D to about 1e-15 relative.
    """
    s = 0.0
    fac = 1.0
    for _ in range(100):
        sx, sy, sz = np.sqrt(x), np.sqrt(y), np.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        s += fac / (sz * (z + lam))
        fac *= 0.25
        x = 0.25 * (x + lam)
        y = 0.25 * (y + lam)
        z = 0.25 * (z + lam)
        mu = 0.2 * (x + y + 3.0 * z)
        dx, dy, dz = (mu - x) / mu, (mu - y) / mu, (mu - z) / mu
        if max(abs(dx), abs(dy), abs(dz)) < 1e-4:
            break
    ea = dx * dy
    eb = dz * dz
    ec = ea - eb
    ed = ea - 6.0 * eb
    ee = ed + ec + ec
    c1, c2, c3, c4, c5, c6 = 3.0 / 14.0, 1.0 / 6.0, 9.0 / 22.0, 3.0 / 26.0, 0.25 * 9.0 / 22.0, 1.5 * 3.0 / 26.0
    series = 1.0 + ed * (-c1 + c5 * ed - c6 * dz * ee) + dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea))
    value: float = 3.0 * s + fac * series / (mu * np.sqrt(mu))
    return value


def ellipsoid_coefficients(a: ArrayLike) -> FloatArray:
    """Kᵢ = a₁a₂a₃ / (2 − αᵢ) of the three stream components (αᵢ = a₁a₂a₃ Iᵢ(0), Σ αᵢ = 2).

    Parameters
    ----------
    a : array_like
        Semi-axes ``(3,)`` (m).

    Returns
    -------
    numpy.ndarray
        ``(3,)`` (m³).
    """
    a = np.asarray(a, dtype=float)
    abc = float(np.prod(a))
    a2 = a * a
    alpha = np.array([abc * 2.0 / 3.0 * carlson_rd(a2[(i + 1) % 3], a2[(i + 2) % 3], a2[i]) for i in range(3)])
    out: FloatArray = abc / (2.0 - alpha)
    return out


@kernel
def _disturbance(q: FloatArray, U: FloatArray, a: FloatArray, K: FloatArray) -> FloatArray:  # pragma: no cover
    """Disturbance velocity at body-frame points q ``(N, 3)`` for streams U ``(N, 3)`` (λ = 0 inside)."""
    n = q.shape[0]
    out = np.zeros((n, 3))
    a2 = a * a
    amax, amin = a2.max(), a2.min()
    for k in range(n):
        x0, x1, x2 = q[k, 0], q[k, 1], q[k, 2]
        r2 = x0 * x0 + x1 * x1 + x2 * x2
        lam = 0.0
        inside = x0 * x0 / a2[0] + x1 * x1 / a2[1] + x2 * x2 / a2[2] < 1.0 - 1e-10  # on it: the outer limit
        if not inside:
            lam = max(0.0, r2 - amax)  # f(λ) ≥ 0 here; f convex decreasing: Newton climbs to the root
            hi = r2 - amin
            for _ in range(100):
                d0, d1, d2 = a2[0] + lam, a2[1] + lam, a2[2] + lam
                f = x0 * x0 / d0 + x1 * x1 / d1 + x2 * x2 / d2 - 1.0
                fp = -(x0 * x0 / (d0 * d0) + x1 * x1 / (d1 * d1) + x2 * x2 / (d2 * d2))
                step = -f / fp
                lam = max(min(lam + step, hi), 0.0)
                if step <= 1e-15 * (lam + amax):
                    break
        d = (a2[0] + lam, a2[1] + lam, a2[2] + lam)
        delta = np.sqrt(d[0] * d[1] * d[2])
        integ = (2.0 / 3.0 * carlson_rd(d[1], d[2], d[0]), 2.0 / 3.0 * carlson_rd(d[2], d[0], d[1]),
                 2.0 / 3.0 * carlson_rd(d[0], d[1], d[2]))
        xs = (x0, x1, x2)
        g = (0.0, 0.0, 0.0)  # inside, λ ≡ 0: the constant interior field W
        if not inside:
            s = x0 * x0 / (d[0] * d[0]) + x1 * x1 / (d[1] * d[1]) + x2 * x2 / (d[2] * d[2])
            g = (2.0 * x0 / (d[0] * s), 2.0 * x1 / (d[1] * s), 2.0 * x2 / (d[2] * s))
        for i in range(3):
            c = U[k, i] * K[i]
            out[k, i] += c * integ[i]
            dI = -1.0 / (d[i] * delta)
            for j in range(3):
                out[k, j] += c * xs[i] * dI * g[j]
    return out


def ellipsoid_disturbance(q: ArrayLike, U: ArrayLike, a: ArrayLike) -> FloatArray:
    """Disturbance velocity ∇φ_d of a stream U past the ellipsoid with semi-axes ``a`` (its own frame).

    Parameters
    ----------
    q : array_like
        Body-frame points ``(N, 3)`` (m).
    U : array_like
        Stream ``(3,)`` or one per point ``(N, 3)`` (m/s), body frame.
    a : array_like
        Semi-axes ``(3,)`` (m).

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` (m/s); U + this is tangent to the surface on it.
    """
    q = np.ascontiguousarray(np.asarray(q, dtype=float).reshape(-1, 3))
    U = np.require(np.broadcast_to(np.asarray(U, dtype=float), q.shape), requirements=("C", "W"))  # writable as below
    a = np.asarray(a, dtype=float)
    out: FloatArray = _disturbance(q, U, a, ellipsoid_coefficients(a))
    return out


@dataclass(frozen=True, eq=False)
class EllipsoidBody:
    """The ellipsoid ``shape`` (the obstacle's axes, grown to contain it with the margin) in the sink's flow.

    Attributes
    ----------
    shape : Ellipsoid
        The flow surface (world frame).
    target : numpy.ndarray
        The target sink ``(3,)`` (m).
    Q : float
        Sink strength (m³/s).
    kind : str
        ``"ellipsoid"``.
    """

    shape: Ellipsoid
    target: FloatArray
    Q: float
    kind: str = "ellipsoid"

    @cached_property
    def _K(self) -> FloatArray:
        return ellipsoid_coefficients(self.shape.semi_axes)

    @property
    def radius(self) -> float:
        """Largest semi-axis (m).

        Returns
        -------
        float
            The body's largest radius (m).
        """
        return float(max(self.shape.semi_axes))

    @property
    def volume(self) -> float:
        """Volume enclosed by the dividing surface, the ellipsoid itself (m³).

        Returns
        -------
        float
            4π/3 b₁b₂b₃ (m³).
        """
        return float(4.0 / 3.0 * np.pi * np.prod(self.shape.semi_axes))

    def velocity(self, p: ArrayLike) -> FloatArray:
        """Sink velocity plus the ellipsoid's disturbance for that velocity as the stream, at world points.

        Parameters
        ----------
        p : array_like
            World points ``(N, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(N, 3)`` (m/s).
        """
        p = np.asarray(p, dtype=float).reshape(-1, 3)
        r = p - self.target
        n = np.sqrt(np.add.reduce(r * r, axis=-1, keepdims=True))
        us = -self.Q * r / (FOUR_PI * np.maximum(n, 1e-300) ** 3)
        rot = self.shape._rot
        q = np.ascontiguousarray((p - np.asarray(self.shape.center)) @ rot)
        ud = _disturbance(q, np.ascontiguousarray(us @ rot), np.asarray(self.shape.semi_axes), self._K)
        u: FloatArray = us + ud @ rot.T
        return u

    @cached_property
    def front(self) -> tuple[FloatArray, FloatArray]:
        """Front stagnation point and the unit normal there (world frame).

        On the surface the flow is the tangential part of W = ((1 + Kᵢ Iᵢ(0)) Uᵢ): it stagnates where the
        normal is parallel to W, the front point where W points inwards; U = u_s there, found by fixed-point
        iteration from U = u_s(centre).

        Returns
        -------
        tuple of numpy.ndarray
            The point ``(3,)`` (m) and its outward normal ``(3,)``.
        """
        b = np.asarray(self.shape.semi_axes)
        rot = self.shape._rot
        c = np.asarray(self.shape.center)
        gain = 1.0 + self._K * np.array([2.0 / 3.0 * carlson_rd(b[(i + 1) % 3] ** 2, b[(i + 2) % 3] ** 2, b[i] ** 2)
                                         for i in range(3)])
        x = c
        for _ in range(50):
            r = x - self.target
            U = (-r / np.linalg.norm(r) ** 3) @ rot
            W = gain * U
            local = -b**2 * W / np.sqrt(np.sum(b**2 * W**2))
            x = c + local @ rot.T
        n = local / b**2
        normal: FloatArray = (n / np.linalg.norm(n)) @ rot.T
        return x, normal

    def distance(self, p: ArrayLike) -> FloatArray:
        """Signed distance to the body's surface (m, negative inside).

        Parameters
        ----------
        p : array_like
            World points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m).
        """
        return self.shape.distance(p)

    def inside(self, p: ArrayLike) -> BoolArray:
        """Whether world points lie inside the body.

        Parameters
        ----------
        p : array_like
            World points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``.
        """
        q = self.shape.to_body(p)
        within: BoolArray = ((q / np.asarray(self.shape.semi_axes)) ** 2).sum(axis=-1) < 1.0
        return within

    def normal(self, p: ArrayLike) -> FloatArray:
        """Unit outward normal at the surface point nearest to each world point.

        Parameters
        ----------
        p : array_like
            World points ``(N, 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(N, 3)``.
        """
        pb = self.shape.to_body(np.asarray(p, dtype=float).reshape(-1, 3))
        foot = self.shape._foot_point(pb)
        nb = foot / np.asarray(self.shape.semi_axes) ** 2
        nb /= np.linalg.norm(nb, axis=-1, keepdims=True)
        world: FloatArray = nb @ self.shape._rot.T
        return world


def design_ellipsoid_body(obstacle: Ellipsoid, target: ArrayLike, Q: float = 1.0, margin: float = 0.0,
                          pad: float = 0.0, n: int = 120) -> EllipsoidBody:
    """The smallest ellipsoid a + δ (same centre and axes) holding the obstacle's margin offset, grown by ``pad``.

    δ ≥ margin is bisected (50 halvings) until every point of the offset surface sampled on a
    ``n × 2n`` grid lies inside; ``pad`` (the chord-sag allowance) covers the sampling gap.

    Parameters
    ----------
    obstacle : Ellipsoid
        The obstacle.
    target : array_like
        The target sink ``(3,)`` (m).
    Q : float, default 1.0
        Sink strength (m³/s).
    margin : float, default 0.0
        Safety margin (m).
    pad : float, default 0.0
        Extra growth of every semi-axis (m).
    n : int, default 120
        Polar samples of the offset surface.

    Returns
    -------
    EllipsoidBody
        The body.
    """
    a = np.asarray(obstacle.semi_axes)
    th = np.linspace(0.0, np.pi, n + 1)
    ph = np.linspace(0.0, 2 * np.pi, 2 * n, endpoint=False)
    TH, PH = np.meshgrid(th, ph)
    dirs = np.stack([np.sin(TH) * np.cos(PH), np.sin(TH) * np.sin(PH), np.cos(TH)], -1).reshape(-1, 3)
    local = dirs * a
    nrm = local / a**2
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    pts = local + margin * nrm
    def holds(delta: float) -> bool:
        return bool((((pts / (a + delta)) ** 2).sum(axis=1) <= 1.0).all())

    lo, hi = margin, 2.0 * margin + 1e-12
    while not holds(hi):
        lo, hi = hi, 2.0 * hi
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if holds(mid):
            hi = mid
        else:
            lo = mid
    grown = a + hi + pad
    b = (float(grown[0]), float(grown[1]), float(grown[2]))
    shape = Ellipsoid(obstacle.center, b, obstacle.yaw, obstacle.pitch, obstacle.roll)
    return EllipsoidBody(shape, np.asarray(target, dtype=float), float(Q))
