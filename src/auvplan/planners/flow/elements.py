"""The single elements of document 000's potential flows, each in closed form.

Convention (as :mod:`auvplan.planners.flow`): u = +∇φ; a sink of strength m at the target T has
φ = m / (4π|p − T|).  All functions are vectorised over points ``(..., 3)``:

* :func:`sink_velocity` — the sink at the goal;
* :func:`sphere_exact_velocity` — Weiss's sphere theorem (the sink's image in a sphere: a sink at the
  inverse point plus a uniform line source), the field the planner uses by default;
* :func:`sphere_document_potential`, :func:`sphere_document_velocity` — the document's sink + θ-dependent
  dipole, differentiated in full;
* :func:`uniform_dipole_velocity` — uniform flow + dipole (the document's reference [15]);
* :func:`rankine_velocity`, :func:`rankine_indicator`, :func:`rankine_stagnation_points`,
  :func:`rankine_radius` — document 000's Rankine-type body (source m at −a₂, sink m at a₂, the target
  sink Q at a₁; closed forms of §4.1, corrected).

:class:`~auvplan.planners.flow.field.FlowField` blends them round several obstacles.
"""

from __future__ import annotations

import numpy as np

from ..._types import ArrayLike, FloatArray

__all__ = [
    "sink_velocity",
    "sphere_exact_velocity",
    "sphere_document_potential",
    "sphere_document_velocity",
    "uniform_dipole_velocity",
    "rankine_velocity",
    "rankine_indicator",
    "rankine_stagnation_points",
    "rankine_radius",
]

FOUR_PI = 4.0 * np.pi


# ---------------------------------------------------------------------- single-element kernels
def sink_velocity(p: ArrayLike, target: ArrayLike, m: float = 1.0) -> FloatArray:
    """Velocity of a point sink of strength m at ``target``: −m (p − T) / (4π|p − T|³).

    Parameters
    ----------
    p : array_like
        Points ``(..., 3)`` (m).
    target : array_like
        Sink position ``(3,)`` (m).
    m : float, default 1.0
        Sink strength (m³/s).

    Returns
    -------
    numpy.ndarray
        Velocity ``(..., 3)`` (m/s).
    """
    r = np.asarray(p, dtype=float) - np.asarray(target, dtype=float)
    n = np.sqrt(np.add.reduce(r * r, axis=-1, keepdims=True))  # np.linalg.norm's sum and root, without its wrapper
    u: FloatArray = -m * r / (FOUR_PI * np.maximum(n, 1e-300) ** 3)
    return u


def _toward(center: ArrayLike, target: ArrayLike) -> tuple[FloatArray, FloatArray, float, FloatArray]:
    """The sphere's centre ``c``, the target sink ``T``, their distance ``b`` and the unit vector ``e`` from ``c`` to
    ``T`` (the axis of both sphere fields)."""
    c = np.asarray(center, dtype=float)
    T = np.asarray(target, dtype=float)
    b = float(np.linalg.norm(T - c))
    return c, T, b, (T - c) / b


def sphere_exact_velocity(p: ArrayLike, center: ArrayLike, radius: float, target: ArrayLike,
                          m: float = 1.0) -> FloatArray:
    """Sink at ``target`` plus its exact image in the sphere (Weiss's sphere theorem).

    Parameters
    ----------
    p : array_like
        Points ``(..., 3)`` (m).
    center : array_like
        Sphere centre ``(3,)`` (m).
    radius : float
        Sphere radius a (m).
    target : array_like
        Target sink T ``(3,)`` (m).
    m : float, default 1.0
        Sink strength (m³/s).

    Returns
    -------
    numpy.ndarray
        Velocity ``(..., 3)`` (m/s); tangent to the sphere on its surface.
    """
    p = np.asarray(p, dtype=float)
    c, T, b, e = _toward(center, target)
    a = float(radius)
    L = a * a / b
    Bs = c + L * e
    q0 = p - c
    q1 = p - Bs
    R0 = np.linalg.norm(q0, axis=-1, keepdims=True)
    R1 = np.linalg.norm(q1, axis=-1, keepdims=True)
    S = R0 + R1
    u = sink_velocity(p, T, m)
    u = u - (m * a / (FOUR_PI * b)) * q1 / R1**3
    out: FloatArray = u + (m / (FOUR_PI * a)) * (2.0 * L / (S * S - L * L)) * (q0 / R0 + q1 / R1)
    return out


def _document_terms(p: ArrayLike, center: ArrayLike, radius: float,
                    target: ArrayLike) -> tuple[FloatArray, ...]:
    """Shared geometry of document 000's sphere field: p, T, e, q, r (keepdims), x = q·e, g, g′."""
    p = np.asarray(p, dtype=float)
    c, T, b, e = _toward(center, target)
    q = p - c
    r = np.linalg.norm(q, axis=-1, keepdims=True)
    x = (q @ e)[..., None]
    ct = x / r
    a = float(radius)
    D = a * a - 2 * a * b * ct + b * b
    g = -(a**4 - b * a**3 * ct) / (2.0 * D**1.5)
    gp = 0.5 * (b * a**3 * D**-1.5 - 3.0 * a * b * (a**4 - b * a**3 * ct) * D**-2.5)
    return p, T, e, q, r, x, g, gp


def sphere_document_potential(p: ArrayLike, center: ArrayLike, radius: float, target: ArrayLike,
                              m: float = 1.0) -> FloatArray:
    """Document 000's potential φ_P = (m/4π)[1/|p − T| + g(cos θ)/r²].

    Parameters
    ----------
    p : array_like
        Points ``(..., 3)`` (m).
    center : array_like
        Sphere centre ``(3,)`` (m).
    radius : float
        Sphere radius a (m).
    target : array_like
        Target sink T ``(3,)`` (m).
    m : float, default 1.0
        Sink strength (m³/s).

    Returns
    -------
    numpy.ndarray
        Potential ``(...)`` (m²/s).
    """
    p, T, _, _, r, _, g, _ = _document_terms(p, center, radius, target)
    phi: FloatArray = m / FOUR_PI * (1.0 / np.linalg.norm(p - T, axis=-1) + (g / r**2)[..., 0])
    return phi


def sphere_document_velocity(p: ArrayLike, center: ArrayLike, radius: float, target: ArrayLike,
                             m: float = 1.0) -> FloatArray:
    """Gradient of the document's potential, differentiated in full (docs/methods.md §1.1).

    Parameters
    ----------
    p : array_like
        Points ``(..., 3)`` (m).
    center : array_like
        Sphere centre ``(3,)`` (m).
    radius : float
        Sphere radius a (m).
    target : array_like
        Target sink T ``(3,)`` (m).
    m : float, default 1.0
        Sink strength (m³/s).

    Returns
    -------
    numpy.ndarray
        Velocity ``(..., 3)`` (m/s).
    """
    p, T, e, q, r, x, g, gp = _document_terms(p, center, radius, target)
    u = sink_velocity(p, T, m)
    return u + m / FOUR_PI * (gp * (e / r - x * q / r**3) / r**2 - 2.0 * g * q / r**4)


def uniform_dipole_velocity(p: ArrayLike, center: ArrayLike, radius: float, direction: ArrayLike,
                            speed: float = 1.0) -> FloatArray:
    """Uniform flow U ê past a sphere (its dipole): the document's reference [15] baseline.

    Parameters
    ----------
    p : array_like
        Points ``(..., 3)`` (m).
    center : array_like
        Sphere centre ``(3,)`` (m).
    radius : float
        Sphere radius (m).
    direction : array_like
        Direction ê of the uniform flow ``(3,)``.
    speed : float, default 1.0
        Free-stream speed U (m/s).

    Returns
    -------
    numpy.ndarray
        Velocity ``(..., 3)`` (m/s).
    """
    p = np.asarray(p, dtype=float)
    e = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    q = p - np.asarray(center, dtype=float)
    r = np.linalg.norm(q, axis=-1, keepdims=True)
    # φ = U (x + a³ x / (2 r³)), x = q·e
    x = q @ e
    a3 = radius**3
    u: FloatArray = speed * (e + a3 / 2.0 * (e / r**3 - 3.0 * x[..., None] * q / r**5))
    return u


# ---------------------------------------------------------------------- Rankine body
def rankine_velocity(p: ArrayLike, m: float, a2: float, Q: float, a1: float) -> FloatArray:
    """Body-frame velocity of source m at (−a₂,0,0), sink m at (a₂,0,0), target sink Q at (a₁,0,0).

    Parameters
    ----------
    p : array_like
        Body-frame points ``(..., 3)`` (m).
    m : float
        Source and sink strength (m³/s).
    a2 : float
        Half-spacing of the source/sink pair (m).
    Q : float
        Target sink strength (m³/s).
    a1 : float
        Target position on the axis (m).

    Returns
    -------
    numpy.ndarray
        Velocity ``(..., 3)`` (m/s).
    """
    p = np.asarray(p, dtype=float)
    C = np.array([-a2, 0.0, 0.0])
    B = np.array([a2, 0.0, 0.0])
    A = np.array([a1, 0.0, 0.0])
    return sink_velocity(p, A, Q) - sink_velocity(p, C, m) + sink_velocity(p, B, m)


def rankine_indicator(p: ArrayLike, m: float, a2: float, Q: float, a1: float) -> FloatArray:
    """Stokes stream-function indicator: negative inside the body, zero on the dividing surface.

    F = m (cos α_B − cos α_C) + Q (1 + cos α_A), α_X the angle between +x and p − X.

    Parameters
    ----------
    p : array_like
        Body-frame points ``(..., 3)`` (m).
    m : float
        Source and sink strength (m³/s).
    a2 : float
        Half-spacing of the source/sink pair (m).
    Q : float
        Target sink strength (m³/s).
    a1 : float
        Target position on the axis (m).

    Returns
    -------
    numpy.ndarray
        F ``(...)`` (m³/s).
    """
    p = np.asarray(p, dtype=float)

    def cos_alpha(x0: float) -> FloatArray:
        d = p - np.array([x0, 0.0, 0.0])
        cos: FloatArray = d[..., 0] / np.maximum(np.linalg.norm(d, axis=-1), 1e-300)
        return cos

    return m * (cos_alpha(a2) - cos_alpha(-a2)) + Q * (1.0 + cos_alpha(a1))


def rankine_stagnation_points(m: float, a2: float, Q: float, a1: float) -> tuple[float, float]:
    """Front and rear stagnation points on the axis (docs/methods.md §1.4 equations).

    Parameters
    ----------
    m : float
        Source and sink strength (m³/s).
    a2 : float
        Half-spacing of the source/sink pair (m).
    Q : float
        Target sink strength (m³/s).
    a1 : float
        Target position on the axis (m).

    Returns
    -------
    tuple of float
        Body-frame x of the front and rear stagnation points (m).
    """

    def front(x: float) -> float:
        return Q / (x - a1) ** 2 - m / (x + a2) ** 2 + m / (x - a2) ** 2

    def rear(x: float) -> float:
        return Q / (x - a1) ** 2 - m / (x - a2) ** 2 + m / (x + a2) ** 2

    lo = -a2 - 1e-9 * a2
    far = -a2 - 1e6 * max(a2, 1.0)
    from scipy.optimize import brentq  # here: a plan round an ellipsoid never asks (issue 56)

    xf = brentq(front, far, lo, xtol=1e-14 * a2, rtol=1e-14)
    xr = brentq(rear, a2 * (1 + 1e-9), a1 * (1 - 1e-12), xtol=1e-14 * a2, rtol=1e-14)
    return float(xf), float(xr)


def rankine_radius(m: float, a2: float, Q: float, a1: float) -> float:
    """Body radius R₀ at x = 0: (Q/2)(1 − a₁/√(a₁² + R²)) = m a₂/√(a₂² + R²).

    Parameters
    ----------
    m : float
        Source and sink strength (m³/s).
    a2 : float
        Half-spacing of the source/sink pair (m).
    Q : float
        Target sink strength (m³/s).
    a1 : float
        Target position on the axis (m).

    Returns
    -------
    float
        R₀ (m).
    """
    def f(R: float) -> float:
        value: float = 0.5 * Q * (1.0 - a1 / np.hypot(a1, R)) - m * a2 / np.hypot(a2, R)
        return value

    from scipy.optimize import brentq  # here: a plan round an ellipsoid never asks (issue 56)

    return float(brentq(f, 1e-12 * a2, 1e6 * max(a1, a2), xtol=1e-13 * a2, rtol=1e-14))
