"""Potential-flow streamline planning around spheres and ellipsoids (document 000).

Lei 2024, "3D AUV path planning with potential functions"; docs/methods.md §1 (corrections).
Convention: u = +∇φ; a sink of strength m at the target T has φ = m / (4π|p − T|), so its
velocity −m (p − T) / (4π|p − T|³) points at T.  Paths follow u/|u| (arc length).

Fields (all vectorised over points ``(..., 3)``):

* :func:`sphere_exact_velocity` — **default**, Weiss's sphere theorem: the image of the sink at
  distance b from a sphere (centre c, radius a) is a sink m a/b at the inverse point
  B* = c + (a²/b) e plus a uniform line source of density m/a from c to B*; |u·n| on the sphere is
  at round-off level and the field is harmonic.
* :func:`sphere_document_velocity` — the document's sink + θ-dependent dipole
  φ_P = (m/4π)[1/|p − T| + g(cos θ)/r²], differentiated in full (never the constant-moment dipole).
* :func:`rankine_velocity` — document 000's body: source m at (−a₂, 0, 0), sink m at (a₂, 0, 0) and the
  target sink Q at (a₁, 0, 0) (closed forms of §4.1, corrected).  For obstacles the field uses the
  bodies of :mod:`.flow_body`: by default a line distribution of sources and sinks on the axis from the
  ellipsoid to the target, fitted so the body contains the ellipsoid inflated by the margin with little
  excess volume (≤ 1.4× the inflated ellipsoid's on the (8, 4, 3) case, against 12× for a pair grown
  with a₂ fixed); the pair with m and a₂ both free, and the document's own sizing, are options.
* :func:`uniform_dipole_velocity` — the document's reference [15]: uniform flow + dipole, which
  passes every obstacle but cannot reach a fixed goal (the baseline of its Fig. 5).
* several obstacles: u = Σ w_k u_k with normalised weights w_k = (1/d_k)/Σ(1/d_j) (**default**, they
  sum to 1) or the document's w_k = Π_{i≠k} d_i/(d_k + d_i); d_k the true distance to surface k
  (the document's ray distance to an ellipsoid as a variant); d_k is the distance to the body the field
  actually flows round, so the blended field is tangent to every body.

:func:`integrate_streamlines` (:mod:`.flow_stream`) integrates many starts at once (RK4 in arc length, the
step tied to the distance to the surface the field flows round), from any start outside the inflated
obstacles: starts inside a body leave along its outward normal; on-axis starts are deflected by a
documented rule.  A flat seabed enters as a mirror plane (:func:`plan_flow`).
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray
from ...world import Ellipsoid, Sphere
from ...world.obstacles import Shape
from ..core.params import FlowParams
from .body import AxialBody, frame
from .design import design_body
from .elements import (
    rankine_indicator,
    rankine_radius,
    rankine_stagnation_points,
    rankine_velocity,
    sink_velocity,
    sphere_document_potential,
    sphere_document_velocity,
    sphere_exact_velocity,
    uniform_dipole_velocity,
)
from .ellipsoid import EllipsoidBody, design_ellipsoid_body

__all__ = [
    "FlowParams",
    "sink_velocity",
    "sphere_exact_velocity",
    "sphere_document_potential",
    "sphere_document_velocity",
    "rankine_velocity",
    "rankine_indicator",
    "rankine_stagnation_points",
    "rankine_radius",
    "AxialBody",
    "design_body",
    "uniform_dipole_velocity",
    "blend_weights",
    "FlowField",
]

FOUR_PI = 4.0 * np.pi
SAG_PAD = 0.002
"""Relative inflation that keeps the chords between integration nodes outside the safety margin."""
PUSH_DOUBLINGS = 25
"""Doublings of :meth:`FlowField.push_out`'s margin while a moved point is still inside its surface:
from 10⁻⁹ of the largest radius to past the 1 % band in which a body's inside test follows F."""


# ---------------------------------------------------------------------- several obstacles
def _norm(q: FloatArray) -> FloatArray:
    """``np.linalg.norm(q, axis=-1)`` without its wrapper (the same sum and root: the same bits)."""
    out: FloatArray = np.sqrt(np.add.reduce(q * q, axis=-1))
    return out


def blend_weights(d: FloatArray, kind: str = "normalised") -> FloatArray:
    """Blend weights of the obstacles' fields from their surface distances.

    Parameters
    ----------
    d : numpy.ndarray
        Distances to the K surfaces ``(..., K)`` (m; floored at 10⁻¹² m).
    kind : str, default "normalised"
        ``"normalised"`` (w_k = (1/d_k)/Σ(1/d_j), summing to 1) or ``"document"``
        (w_k = Π_{i≠k} d_i/(d_k + d_i)).

    Returns
    -------
    numpy.ndarray
        Weights ``(..., K)``.
    """
    d = np.maximum(np.asarray(d, dtype=float), 1e-12)
    if kind == "normalised":
        inv = 1.0 / d
        weights: FloatArray = inv / inv.sum(axis=-1, keepdims=True)
        return weights
    K = d.shape[-1]
    w = np.ones_like(d)
    for k in range(K):
        for i in range(K):
            if i != k:
                w[..., k] *= d[..., i] / (d[..., k] + d[..., i])
    return w


@lru_cache(maxsize=128)
def _cached_body(ob: Ellipsoid, target: tuple[float, ...], sizing: str, Q: float, margin: float,
                 pad: float) -> AxialBody | EllipsoidBody:
    if sizing == "ellipsoid":
        return design_ellipsoid_body(ob, np.array(target), Q, margin, pad)
    return design_body(ob, np.array(target), sizing, Q, margin, pad)


def _side(ob: Shape, axis: FloatArray) -> FloatArray:
    """Deflection side for on-axis streamlines: across ``axis``, where the obstacle is thinnest.

    The unit vector s ⊥ axis minimising the obstacle's half-width sᵀ M s (M = R diag(a²) Rᵀ for an
    ellipsoid): the shortest way round.  Ties (spheres, or equal widths) go to the direction closest
    to +z (over the obstacle, away from the seabed); a vertical axis then takes +x.
    """
    basis = frame(axis)
    up = np.array([0.0, 0.0, 1.0]) if abs(axis[2]) < 0.999 else np.array([1.0, 0.0, 0.0])
    default = up - (up @ axis) * axis
    default /= np.linalg.norm(default)
    if not isinstance(ob, Ellipsoid):
        return default
    M = ob._rot @ np.diag(np.asarray(ob.semi_axes) ** 2) @ ob._rot.T
    P = basis[:, 1:]
    w, v = np.linalg.eigh(P.T @ M @ P)
    if w[1] - w[0] <= 1e-9 * w[1]:
        return default
    s: FloatArray = P @ v[:, 0]
    return s if s @ default >= 0 else -s


class FlowField:
    """The blended flow toward ``target`` around spheres and ellipsoids inflated by ``margin``.

    Spheres take the exact image field (or the document's, or uniform flow + dipole); each ellipsoid
    the axisymmetric body of :mod:`.flow_body` sized by ``params.rankine``.  ``plane`` (a height) adds
    a flat seabed as a mirror image of the target sink: the plane is then a stream surface.
    ``direction`` is the uniform flow's direction for ``field = "uniform"``.

    Two distances per obstacle: :meth:`distances`, to the surface the field actually flows round
    (sphere or body; the blend weights and step control use it), and :meth:`clearance`, to the
    real obstacle inflated by the margin (safety).

    Parameters
    ----------
    obstacles : sequence of Sphere or Ellipsoid
        The static obstacles.
    target : array_like
        The goal, where the sink sits ``(3,)`` (m).
    params : FlowParams
        Field, body sizing, weights, distances and integration settings.
    margin : float, default 0.0
        Obstacle safety margin (m).
    direction : array_like, optional
        Direction of the uniform flow for ``params.field == "uniform"`` (default: towards ``target``).
    plane : float, optional
        Height of a flat seabed modelled as a mirror plane (m).

    Raises
    ------
    TypeError
        If an obstacle is neither a sphere nor an ellipsoid.
    ValueError
        If the uniform field is asked for with ellipsoids.
    """

    def __init__(self, obstacles: Sequence[Shape], target: ArrayLike, params: FlowParams, margin: float = 0.0,
                 direction: ArrayLike | None = None, plane: float | None = None) -> None:
        self.target = np.asarray(target, dtype=float)
        self.params = params
        self.margin = float(margin)
        self.spheres = [ob for ob in obstacles if isinstance(ob, Sphere)]
        self.ellipsoids = [ob for ob in obstacles if isinstance(ob, Ellipsoid)]
        if len(self.spheres) + len(self.ellipsoids) != len(obstacles):
            raise TypeError("the flow planner handles spheres and ellipsoids only")
        if params.field == "uniform" and self.ellipsoids:
            raise ValueError("field = 'uniform' (uniform flow + dipole, document 000 Fig. 5) takes spheres only")
        self.items = self.spheres + self.ellipsoids  # obstacle order of every (..., K) array
        self.C = np.array([s.center for s in self.spheres]).reshape(-1, 3)
        # the pad covers the chord sag h²/(8a) of steps up to 0.05 a along a surface
        self.R = np.array([s.radius + margin for s in self.spheres])
        self.A = self.R + SAG_PAD * np.array([s.radius for s in self.spheres])
        self.direction: FloatArray | None = None
        if params.field == "uniform":
            d = np.asarray(direction if direction is not None else self.target, dtype=float)
            self.direction = d / np.linalg.norm(d)
        self.bodies = [_cached_body(ob, tuple(self.target), params.rankine, params.strength, self.margin,
                                    SAG_PAD * max(ob.semi_axes)) for ob in self.ellipsoids]
        self.plane = plane
        self.axes: list[np.ndarray] = []
        self.sides: list[np.ndarray] = []
        self.anchors: list[np.ndarray] = []  # where the front stagnation rule's axis passes (centre or front point)
        self.bands: list[float] = []  # the rule's reach off that axis, in units of the radius
        radii: list[float] = []
        for i, ob in enumerate(self.items):
            c = np.asarray(ob.center)
            e = self.direction if self.direction is not None else (self.target - c) / np.linalg.norm(self.target - c)
            anchor, band = c, 0.05
            body = self.bodies[i - len(self.spheres)] if i >= len(self.spheres) else None
            if isinstance(body, EllipsoidBody):  # the flow divides at a regular point off the axis
                anchor, normal = body.front
                e, band = -normal, 1e-3
            self.axes.append(e)
            self.anchors.append(anchor)
            self.bands.append(band)
            self.sides.append(_side(ob, e))
            radii.append(self.A[i] if i < len(self.spheres) else self.bodies[i - len(self.spheres)].radius)
        self.radii = np.asarray(radii)

    @property
    def contained(self) -> bool:
        """Whether every body contains its obstacle (not for the document's sizing).

        Returns
        -------
        bool
            False for ``params.rankine == "document"``.
        """
        return self.params.rankine != "document"

    # ------------------------------------------------------------------ distances
    def distances(self, p: ArrayLike, kind: str | None = None) -> FloatArray:
        """Distance to each surface the field flows round (spheres, bodies[, plane]).

        Parameters
        ----------
        p : array_like
            Points ``(..., 3)`` (m).
        kind : str, optional
            ``"true"`` or ``"ray"`` (for the document's bodies); ``params.distance`` when omitted.

        Returns
        -------
        numpy.ndarray
            ``(..., K)``, or ``(..., K + 1)`` with the plane (m; negative inside).
        """
        kind = kind or self.params.distance
        p = np.asarray(p, dtype=float)
        out = [_norm(p[..., None, :] - self.C) - self.A] if self.spheres else []
        for ob, body in zip(self.ellipsoids, self.bodies):
            if self.contained:
                d = body.distance(p)
            else:  # the document's body: its ellipsoid stands for it
                d = (ob.ray_distance(p) if kind == "ray" else ob.distance(p)) - self.margin
            out.append(d[..., None])
        if self.plane is not None:
            out.append((p[..., 2] - self.plane)[..., None])
        dist: FloatArray = np.concatenate(out, axis=-1) if out else np.zeros(p.shape[:-1] + (0,))
        return dist

    def clearance(self, p: ArrayLike) -> FloatArray:
        """Distance to the nearest real obstacle (or the plane) minus the margin.

        Parameters
        ----------
        p : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(...)`` (m); negative = penetration.
        """
        p = np.asarray(p, dtype=float)
        d = np.full(p.shape[:-1], np.inf)
        if self.spheres:
            d = np.minimum(d, (np.linalg.norm(p[..., None, :] - self.C, axis=-1) - self.R).min(axis=-1))
        for ob in self.ellipsoids:
            lb = ob.lower_bound_distance(p) - self.margin
            near = lb < max(ob.semi_axes)  # the exact distance where it matters, the cheap lower bound elsewhere
            if near.any():
                lb[near] = ob.distance(p[near]) - self.margin
            d = np.minimum(d, lb)
        if self.plane is not None:
            d = np.minimum(d, p[..., 2] - self.plane)
        return d

    def inside_body(self, p: ArrayLike) -> BoolArray:
        """Where points lie inside a surface the field flows round (a body, sphere or below the plane).

        Parameters
        ----------
        p : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(...)``.
        """
        d = self.distances(np.asarray(p, dtype=float), "true")
        return np.asarray((d < 0).any(axis=-1) if d.shape[-1] else np.zeros(d.shape[:-1], dtype=bool))

    def push_out(self, p: ArrayLike, eps: float = 1e-9) -> FloatArray:
        """Points moved just outside the nearest flow surface along its outward normal.

        Each point moves by its depth plus a margin of ``eps`` times the largest radius; where the
        moved point is still inside that surface (a line-distribution body's surface, F = 0, lies a
        little outside the profile polyline the depth is measured to), the margin is doubled, up to
        :data:`PUSH_DOUBLINGS` times, until it is not.

        Parameters
        ----------
        p : array_like
            Points ``(N, 3)`` (m).
        eps : float, default 1e-9
            Distance left outside, relative to the largest body radius (at least 1 m).

        Returns
        -------
        numpy.ndarray
            Moved points ``(N, 3)`` (m).
        """
        p = np.array(p, dtype=float).reshape(-1, 3)
        d = self.distances(p, "true")
        k = d.argmin(axis=-1)
        ns = len(self.spheres)
        n = np.empty_like(p)
        for i in range(p.shape[0]):
            j = k[i]
            if j < ns:
                n[i] = (p[i] - self.C[j]) / max(np.linalg.norm(p[i] - self.C[j]), 1e-300)
            elif j < len(self.items):
                n[i] = (self.bodies[j - ns].normal(p[i:i + 1])[0] if self.contained
                        else self.items[j].gradient(p[i]))
            else:
                n[i] = (0.0, 0.0, 1.0)
        rows = np.arange(p.shape[0])
        depth = -d[rows, k]
        scale = max(self.radii.max(initial=1.0), 1.0)
        margin = np.full(p.shape[0], eps * scale)
        q: FloatArray = p + (depth + margin)[:, None] * n
        todo = rows
        for _ in range(PUSH_DOUBLINGS):  # a body's surface (F = 0) lies a little outside its profile polyline
            inside = self.distances(q[todo], "true")[np.arange(todo.size), k[todo]] < 0
            todo = todo[inside]
            if not todo.size:
                break
            margin[todo] *= 2.0
            q[todo] = p[todo] + (depth[todo] + margin[todo])[:, None] * n[todo]
        return q

    # ------------------------------------------------------------------ velocity
    def _sphere_parts(self, p: FloatArray) -> FloatArray:
        """Single-sphere fields of every sphere at once, ``(N, K, 3)``."""
        m = self.params.strength
        if self.params.field == "document":
            return np.stack([sphere_document_velocity(p, c, a, self.target, m) for c, a in zip(self.C, self.A)], 1)
        if self.params.field == "uniform":
            assert self.direction is not None  # set by the constructor for the uniform field
            return np.stack([uniform_dipole_velocity(p, c, a, self.direction) for c, a in zip(self.C, self.A)], 1)
        q = p[:, None, :] - self.C
        consts = self.__dict__.get("_image_consts")
        if consts is None:  # the images' fixed figures, once per field (they were the bulk of a small call)
            Tc = self.target - self.C
            b = np.linalg.norm(Tc, axis=-1)
            e = Tc / b[:, None]
            L = self.A**2 / b
            consts = self._image_consts = ((L[:, None] * e), -(m * self.A / (FOUR_PI * b))[:, None],
                                           (m / (FOUR_PI * self.A) * 2.0 * L)[:, None], L[:, None] ** 2)
        shift, k_image, k_line, L2 = consts
        q1 = q - shift
        R0 = _norm(q)[..., None]
        R1 = _norm(q1)[..., None]
        S = R0 + R1
        image = k_image * q1 / R1**3
        line = k_line / (S * S - L2) * (q / R0 + q1 / R1)
        parts: FloatArray = sink_velocity(p, self.target, m)[:, None, :] + image + line
        return parts

    def _free(self, p: FloatArray) -> FloatArray:
        """The field without obstacles: the target sink (with its mirror in the plane), or the uniform flow."""
        if self.direction is not None:
            return np.broadcast_to(self.direction, p.shape).copy()
        u = sink_velocity(p, self.target, self.params.strength)
        if self.plane is not None:
            mirror = self.target * np.array([1.0, 1.0, -1.0]) + np.array([0.0, 0.0, 2.0 * self.plane])
            u = u + sink_velocity(p, mirror, self.params.strength)
        return u

    def velocity(self, p: ArrayLike) -> FloatArray:
        """Blended velocity at points.

        Parameters
        ----------
        p : array_like
            Points ``(..., 3)`` (m).

        Returns
        -------
        numpy.ndarray
            Velocity ``(..., 3)`` (m/s).
        """
        p = np.asarray(p, dtype=float)
        shape = p.shape
        p = p.reshape(-1, 3)
        if not self.items:
            return self._free(p).reshape(shape)
        fields = [self._sphere_parts(p)] if self.spheres else []
        for body in self.bodies:
            fields.append(body.velocity(p)[:, None, :])
        if self.plane is not None:
            fields.append(self._free(p)[:, None, :])
        parts = np.concatenate(fields, axis=1)
        if parts.shape[1] == 1:
            return parts[:, 0].reshape(shape)
        w = blend_weights(self.distances(p), self.params.weights)
        blended: FloatArray = np.einsum("nk,nki->ni", w, parts).reshape(shape)
        return blended
