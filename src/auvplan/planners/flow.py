"""Potential-flow streamline planning around spheres and ellipsoids (document 000).

Lei 2024, "3D AUV path planning with potential functions"; METHODS.md §1 (corrections).
Convention: u = +∇φ; a sink of strength m at the target T has φ = m / (4π|p − T|), so its
velocity −m (p − T) / (4π|p − T|³) points at T.  Paths follow u/|u| (arc length).

Fields (all vectorised over points ``(..., 3)``):

* :func:`sphere_exact_velocity` — **default**, Weiss's sphere theorem: the image of the sink at
  distance b from a sphere (centre c, radius a) is a sink m a/b at the inverse point
  B* = c + (a²/b) e plus a uniform line source of density m/a from c to B*; |u·n| on the sphere is
  at round-off level and the field is harmonic.
* :func:`sphere_document_velocity` — the document's sink + θ-dependent dipole
  φ_P = (m/4π)[1/|p − T| + g(cos θ)/r²], differentiated in full (never the constant-moment dipole).
* :func:`rankine_velocity` — ellipsoid-like obstacles: source m at (−a₂, 0, 0), sink m at
  (a₂, 0, 0) and the target sink Q at (a₁, 0, 0) along the axis from the obstacle to the target;
  :func:`design_rankine_body` grows m until the real ellipsoid lies inside the dividing stream
  surface (Stokes stream function), since the document's ellipsoid sticks out of the body.
* :func:`uniform_dipole_velocity` — the document's reference [15]: uniform flow + dipole, which
  passes every obstacle but cannot reach a fixed goal (the baseline of its Fig. 5).
* several obstacles: u = Σ w_k u_k with normalised weights w_k = (1/d_k)/Σ(1/d_j) (**default**, they
  sum to 1) or the document's w_k = Π_{i≠k} d_i/(d_k + d_i); d_k the true distance to surface k
  (the document's ray distance to an ellipsoid as a variant).

:func:`integrate_streamlines` integrates many starts at once with classical RK4 in arc length,
the step adapted to the geometry (h ≤ ½ of the clearance, within [h_min, h_max]), with events:
arrival, obstacle contact, stagnation (|u| < ε), step limit.  Obstacles are inflated by the
vehicle's safety margin (clearance ≥ margin); starts collinear with an obstacle and the goal are
nudged sideways (they would stall at the rear stagnation point).  The flow knows nothing of the
seabed: a streamline that meets it is reported with status ``INFEASIBLE``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from .._types import Status
from ..world import Ellipsoid, Sphere, World
from .base import PlanResult
from .flow_params import FlowParams

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
    "design_rankine_body",
    "uniform_dipole_velocity",
    "blend_weights",
    "FlowField",
    "Streamlines",
    "integrate_streamlines",
    "plan_flow",
]

FOUR_PI = 4.0 * np.pi
MAX_CORRECTIONS = 50
"""A streamline pushed back onto a surface more often than this is stuck against it: ``contact``."""
SAG_PAD = 0.002
"""Relative inflation that keeps the chords between integration nodes outside the safety margin."""


# ---------------------------------------------------------------------- single-element kernels
def sink_velocity(p, target, m: float = 1.0) -> np.ndarray:
    """Velocity of a point sink of strength m at ``target``: −m (p − T) / (4π|p − T|³)."""
    r = np.asarray(p, dtype=float) - np.asarray(target, dtype=float)
    n = np.linalg.norm(r, axis=-1, keepdims=True)
    return -m * r / (FOUR_PI * np.maximum(n, 1e-300) ** 3)


def sphere_exact_velocity(p, center, radius: float, target, m: float = 1.0) -> np.ndarray:
    """Sink at ``target`` plus its exact image in the sphere (Weiss's sphere theorem)."""
    p = np.asarray(p, dtype=float)
    c = np.asarray(center, dtype=float)
    T = np.asarray(target, dtype=float)
    a = float(radius)
    b = float(np.linalg.norm(T - c))
    e = (T - c) / b
    L = a * a / b
    Bs = c + L * e
    q0 = p - c
    q1 = p - Bs
    R0 = np.linalg.norm(q0, axis=-1, keepdims=True)
    R1 = np.linalg.norm(q1, axis=-1, keepdims=True)
    S = R0 + R1
    u = sink_velocity(p, T, m)
    u = u - (m * a / (FOUR_PI * b)) * q1 / R1**3
    u = u + (m / (FOUR_PI * a)) * (2.0 * L / (S * S - L * L)) * (q0 / R0 + q1 / R1)
    return u


def _document_terms(p, center, radius: float, target):
    """Shared geometry of document 000's sphere field: p, T, e, q, r (keepdims), x = q·e, g, g′."""
    p = np.asarray(p, dtype=float)
    c = np.asarray(center, dtype=float)
    T = np.asarray(target, dtype=float)
    b = float(np.linalg.norm(T - c))
    e = (T - c) / b
    q = p - c
    r = np.linalg.norm(q, axis=-1, keepdims=True)
    x = (q @ e)[..., None]
    ct = x / r
    a = float(radius)
    D = a * a - 2 * a * b * ct + b * b
    g = -(a**4 - b * a**3 * ct) / (2.0 * D**1.5)
    gp = 0.5 * (b * a**3 * D**-1.5 - 3.0 * a * b * (a**4 - b * a**3 * ct) * D**-2.5)
    return p, T, e, q, r, x, g, gp


def sphere_document_potential(p, center, radius: float, target, m: float = 1.0) -> np.ndarray:
    """Document 000's potential φ_P = (m/4π)[1/|p − T| + g(cos θ)/r²]."""
    p, T, _, _, r, _, g, _ = _document_terms(p, center, radius, target)
    return m / FOUR_PI * (1.0 / np.linalg.norm(p - T, axis=-1) + (g / r**2)[..., 0])


def sphere_document_velocity(p, center, radius: float, target, m: float = 1.0) -> np.ndarray:
    """Gradient of the document's potential, differentiated in full (METHODS.md §1.1)."""
    p, T, e, q, r, x, g, gp = _document_terms(p, center, radius, target)
    u = sink_velocity(p, T, m)
    return u + m / FOUR_PI * (gp * (e / r - x * q / r**3) / r**2 - 2.0 * g * q / r**4)


def uniform_dipole_velocity(p, center, radius: float, direction, speed: float = 1.0) -> np.ndarray:
    """Uniform flow U ê past a sphere (its dipole): the document's reference [15] baseline."""
    p = np.asarray(p, dtype=float)
    e = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    q = p - np.asarray(center, dtype=float)
    r = np.linalg.norm(q, axis=-1, keepdims=True)
    # φ = U (x + a³ x / (2 r³)), x = q·e
    x = q @ e
    a3 = radius**3
    return speed * (e + a3 / 2.0 * (e / r**3 - 3.0 * x[..., None] * q / r**5))


# ---------------------------------------------------------------------- Rankine body
def rankine_velocity(p, m: float, a2: float, Q: float, a1: float) -> np.ndarray:
    """Body-frame velocity of source m at (−a₂,0,0), sink m at (a₂,0,0), target sink Q at (a₁,0,0)."""
    p = np.asarray(p, dtype=float)
    C = np.array([-a2, 0.0, 0.0])
    B = np.array([a2, 0.0, 0.0])
    A = np.array([a1, 0.0, 0.0])
    return sink_velocity(p, A, Q) - sink_velocity(p, C, m) + sink_velocity(p, B, m)


def rankine_indicator(p, m: float, a2: float, Q: float, a1: float) -> np.ndarray:
    """Stokes stream-function indicator: negative inside the body, zero on the dividing surface.

    F = m (cos α_B − cos α_C) + Q (1 + cos α_A), α_X the angle between +x and p − X.
    """
    p = np.asarray(p, dtype=float)

    def cos_alpha(x0):
        d = p - np.array([x0, 0.0, 0.0])
        return d[..., 0] / np.maximum(np.linalg.norm(d, axis=-1), 1e-300)

    return m * (cos_alpha(a2) - cos_alpha(-a2)) + Q * (1.0 + cos_alpha(a1))


def rankine_stagnation_points(m: float, a2: float, Q: float, a1: float) -> tuple[float, float]:
    """Front and rear stagnation points on the axis (METHODS.md §1.4 equations)."""

    def front(x):
        return Q / (x - a1) ** 2 - m / (x + a2) ** 2 + m / (x - a2) ** 2

    def rear(x):
        return Q / (x - a1) ** 2 - m / (x - a2) ** 2 + m / (x + a2) ** 2

    lo = -a2 - 1e-9 * a2
    far = -a2 - 1e6 * max(a2, 1.0)
    xf = brentq(front, far, lo, xtol=1e-14 * a2, rtol=1e-14)
    xr = brentq(rear, a2 * (1 + 1e-9), a1 * (1 - 1e-12), xtol=1e-14 * a2, rtol=1e-14)
    return xf, xr


def rankine_radius(m: float, a2: float, Q: float, a1: float) -> float:
    """Body radius R₀ at x = 0: (Q/2)(1 − a₁/√(a₁² + R²)) = m a₂/√(a₂² + R²)."""
    def f(R):
        return 0.5 * Q * (1.0 - a1 / np.hypot(a1, R)) - m * a2 / np.hypot(a2, R)

    return brentq(f, 1e-12 * a2, 1e6 * max(a1, a2), xtol=1e-13 * a2, rtol=1e-14)


def _ellipsoid_surface(e: Ellipsoid, n: int = 24) -> np.ndarray:
    th = np.linspace(0, np.pi, n)
    ph = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    TH, PH = np.meshgrid(th, ph)
    a = np.asarray(e.semi_axes)
    local = np.stack([a[0] * np.sin(TH) * np.cos(PH), a[1] * np.sin(TH) * np.sin(PH), a[2] * np.cos(TH)], -1)
    return local.reshape(-1, 3) @ e._rot.T + np.asarray(e.center)


def design_rankine_body(e: Ellipsoid, target, Q: float = 1.0, margin: float = 0.0) -> tuple[float, float, np.ndarray]:
    """Source strength m and half-spacing a₂ whose Rankine body contains the (inflated) ellipsoid.

    The body axis runs from the ellipsoid's centre towards ``target``.  Starting from a₂ at half
    the ellipsoid's extent along the axis and a small m, m grows by 25 % until every surface point
    of the ellipsoid inflated by ``margin`` (scaled by 1 + margin/A_min, which contains the offset
    surface) has F < 0, then once more for a gap.  Returns ``(m, a2, axis)``; raises ValueError
    when the body would swallow the target.
    """
    c = np.asarray(e.center)
    T = np.asarray(target, dtype=float)
    a1 = float(np.linalg.norm(T - c))
    axis = (T - c) / a1
    grown = Ellipsoid(e.center, tuple(np.asarray(e.semi_axes) * (1 + margin / min(e.semi_axes))), e.yaw, e.pitch,
                      e.roll)
    pts = _ellipsoid_surface(grown, 48)
    basis = _frame(axis)
    local = (pts - c) @ basis
    extent = float(np.abs(local[:, 0]).max())
    a2 = 0.5 * extent
    m = 0.05 * Q
    for _ in range(200):
        if np.all(rankine_indicator(local, m, a2, Q, a1) < 0):
            m *= 1.25  # one more growth step: a gap between the body and the sampled surface
            xf, xr = rankine_stagnation_points(m, a2, Q, a1)
            if xr >= a1 * 0.999:
                break
            return m, a2, basis
        m *= 1.25
    raise ValueError(f"the target is too close to the ellipsoid at {e.center}: no Rankine body contains it")


def _frame(axis: np.ndarray) -> np.ndarray:
    """Orthonormal basis (columns) whose first column is ``axis``."""
    x = axis / np.linalg.norm(axis)
    helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    z = np.cross(x, y)
    return np.column_stack([x, y, z])


# ---------------------------------------------------------------------- several obstacles
def blend_weights(d: np.ndarray, kind: str = "normalised") -> np.ndarray:
    """Weights ``(..., K)`` from surface distances ``d (..., K)``."""
    d = np.maximum(np.asarray(d, dtype=float), 1e-12)
    if kind == "normalised":
        inv = 1.0 / d
        return inv / inv.sum(axis=-1, keepdims=True)
    K = d.shape[-1]
    w = np.ones_like(d)
    for k in range(K):
        for i in range(K):
            if i != k:
                w[..., k] *= d[..., i] / (d[..., k] + d[..., i])
    return w


class FlowField:
    """The blended flow toward ``target`` around a World's spheres and ellipsoids (inflated by ``margin``).

    Spheres are evaluated together as arrays ``(N, K, 3)``; each ellipsoid gets its Rankine body.
    """

    def __init__(self, obstacles, target, params: FlowParams, margin: float = 0.0) -> None:
        self.target = np.asarray(target, dtype=float)
        self.params = params
        self.margin = float(margin)
        spheres = [ob for ob in obstacles if isinstance(ob, Sphere)]
        self.ellipsoids = [ob for ob in obstacles if isinstance(ob, Ellipsoid)]
        if len(spheres) + len(self.ellipsoids) != len(obstacles):
            raise TypeError("the flow planner handles spheres and ellipsoids only")
        self.spheres = spheres
        self.C = np.array([s.center for s in spheres]).reshape(-1, 3)
        # the pad 0.002 a covers the chord sag h²/(8a) of RK steps up to 0.05 a along a surface
        self.A = np.array([s.radius * (1.0 + SAG_PAD) + margin for s in spheres])
        self.rankine = []
        for ob in self.ellipsoids:
            m, a2, basis = design_rankine_body(ob, self.target, params.strength, margin + SAG_PAD * max(ob.semi_axes))
            a1 = float(np.linalg.norm(self.target - np.asarray(ob.center)))
            self.rankine.append((np.asarray(ob.center), m, a2, a1, basis))
        self.items = spheres + self.ellipsoids  # obstacle order of every (..., K) array

    def push_out(self, p: np.ndarray) -> np.ndarray:
        """Points moved just outside the nearest (inflated) surface along its normal."""
        p = np.array(p, dtype=float)
        d = self.distances(p, "true")
        k = d.argmin(axis=-1)
        for i in range(p.shape[0]):
            ob = self.items[k[i]]
            grad = ob.gradient(p[i])
            p[i] = p[i] + (-d[i, k[i]] + 1e-9) * grad
        return p

    def inside_body(self, p) -> np.ndarray:
        """True where points lie inside a Rankine body (fed by its own source: no streamline to the goal)."""
        p = np.asarray(p, dtype=float)
        out = np.zeros(p.shape[:-1], dtype=bool)
        for c, ms, a2, a1, basis in self.rankine:
            out |= rankine_indicator((p - c) @ basis, ms, a2, self.params.strength, a1) < 0
        return out

    def distances(self, p: np.ndarray, kind: str | None = None) -> np.ndarray:
        """Distance ``(..., K)`` of points to each (inflated) obstacle surface: spheres, then ellipsoids."""
        kind = kind or self.params.distance
        p = np.asarray(p, dtype=float)
        out = [np.linalg.norm(p[..., None, :] - self.C, axis=-1) - self.A] if self.spheres else []
        for ob in self.ellipsoids:
            d = ob.ray_distance(p) if kind == "ray" else ob.distance(p)
            out.append((d - self.margin - SAG_PAD * max(ob.semi_axes))[..., None])
        return np.concatenate(out, axis=-1) if out else np.zeros(p.shape[:-1] + (0,))

    def _sphere_parts(self, p: np.ndarray) -> np.ndarray:
        """Single-sphere fields of every sphere at once, ``(N, K, 3)``."""
        q = p[:, None, :] - self.C
        if self.params.field == "document":
            return np.stack([sphere_document_velocity(p, c, a, self.target, self.params.strength)
                             for c, a in zip(self.C, self.A)], axis=1)
        m = self.params.strength
        Tc = self.target - self.C
        b = np.linalg.norm(Tc, axis=-1)
        e = Tc / b[:, None]
        L = self.A**2 / b
        q1 = q - (L[:, None] * e)
        R0 = np.linalg.norm(q, axis=-1)[..., None]
        R1 = np.linalg.norm(q1, axis=-1)[..., None]
        S = R0 + R1
        image = -(m * self.A / (FOUR_PI * b))[:, None] * q1 / R1**3
        line = (m / (FOUR_PI * self.A) * 2.0 * L)[:, None] / (S * S - L[:, None] ** 2) * (q / R0 + q1 / R1)
        return sink_velocity(p, self.target, m)[:, None, :] + image + line

    def velocity(self, p) -> np.ndarray:
        """Blended velocity at points ``(..., 3)``."""
        p = np.asarray(p, dtype=float)
        shape = p.shape
        p = p.reshape(-1, 3)
        m = self.params.strength
        if not self.items:
            return sink_velocity(p, self.target, m).reshape(shape)
        fields = [self._sphere_parts(p)] if self.spheres else []
        for c, ms, a2, a1, basis in self.rankine:
            fields.append((rankine_velocity((p - c) @ basis, ms, a2, m, a1) @ basis.T)[:, None, :])
        parts = np.concatenate(fields, axis=1)
        if parts.shape[1] == 1:
            return parts[:, 0].reshape(shape)
        w = blend_weights(self.distances(p), self.params.weights)
        return np.einsum("nk,nki->ni", w, parts).reshape(shape)


# ---------------------------------------------------------------------- integration
@dataclass(frozen=True, eq=False)
class Streamlines:
    """Many integrated streamlines: one polyline and one status per start."""

    paths: list
    status: np.ndarray
    min_distance: np.ndarray
    steps: np.ndarray
    wall_time_s: float
    corrections: np.ndarray

    @property
    def arrived(self) -> np.ndarray:
        """True where the streamline reached the goal."""
        return self.status == "arrived"


def _nudge(starts: np.ndarray, field: FlowField) -> np.ndarray:
    """Move starts that lie on an obstacle-goal axis (behind the obstacle) slightly sideways."""
    s = starts.copy()
    for ob in field.items:
        c = np.asarray(ob.center)
        axis = field.target - c
        axis /= np.linalg.norm(axis)
        q = s - c
        along = q @ axis
        perp = q - along[:, None] * axis
        off = np.linalg.norm(perp, axis=1)
        size = ob.bounding_radius
        on_axis = (off < 1e-6 * size) & (along < 0)
        if on_axis.any():
            side = _frame(axis)[:, 1]
            s[on_axis] += 1e-3 * size * side
    return s


def integrate_streamlines(field: FlowField, starts, params: FlowParams | None = None) -> Streamlines:
    """Integrate dp/ds = u/|u| from every start at once (RK4, step ≤ ``step_factor`` × clearance).

    Statuses: ``arrived``, ``contact`` (a surface was crossed even with the step cut 4096-fold:
    the streamline stops there; a graze of at most 10⁻³ a is instead pushed back onto the surface
    and counted in ``corrections``), ``stagnation``, ``max_steps``, ``inside_body`` (the start lies
    inside a Rankine body, whose streamlines run from its source to its sink).
    """
    t0 = time.perf_counter()
    params = params or field.params
    sizes = [ob.radius for ob in field.spheres] + [min(ob.semi_axes) for ob in field.ellipsoids]
    h_min = params.h_min or (0.05 * (min(sizes) + field.margin) if sizes else 0.01)
    p = _nudge(np.asarray(starts, dtype=float).reshape(-1, 3), field)
    n = p.shape[0]
    cap = params.max_steps + 1
    track = np.full((cap, n, 3), np.nan)
    track[0] = p
    count = np.ones(n, dtype=np.intp)
    status = np.array(["max_steps"] * n, dtype=object)
    active = np.ones(n, dtype=bool)
    corrections = np.zeros(n, dtype=np.intp)
    trapped = field.inside_body(p)
    status[trapped] = "inside_body"
    active[trapped] = False
    min_d = np.full(n, np.inf)
    T = field.target

    def direction(x):
        u = field.velocity(x)
        sp = np.linalg.norm(u, axis=-1, keepdims=True)
        return u / np.maximum(sp, 1e-300), sp[..., 0]

    for k in range(1, cap):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        x = p[idx]
        d = field.distances(x, "true").min(axis=-1) if field.items else np.full(idx.size, np.inf)
        min_d[idx] = np.minimum(min_d[idx], d)
        dist_goal = np.linalg.norm(x - T, axis=1)
        arrived = dist_goal <= params.arrive
        h = np.clip(params.step_factor * np.minimum(d, dist_goal), h_min, max(params.h_max, h_min))
        k1, sp = direction(x)
        # stagnation relative to the bare sink's speed here (scale-free)
        stalled = sp < params.stagnation * params.strength / (FOUR_PI * np.maximum(dist_goal, 1e-300) ** 2)

        def rk4(x, k1, h):
            k2, _ = direction(x + 0.5 * h[:, None] * k1)
            k3, _ = direction(x + 0.5 * h[:, None] * k2)
            k4, _ = direction(x + h[:, None] * k3)
            nxt = x + h[:, None] / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
            return nxt, (field.distances(nxt, "true").min(axis=-1) if field.items else np.full(len(x), np.inf))

        nxt, d_next = rk4(x, k1, h)
        for _ in range(6):  # event: a step that would enter a surface is retried at a quarter of its size
            retry = d_next < 0
            if not retry.any():
                break
            h[retry] *= 0.25
            nxt[retry], d_next[retry] = rk4(x[retry], k1[retry], h[retry])
        graze = (d_next < 0) & (d_next > -1e-3 * h_min / 0.05)
        if graze.any():  # a graze of at most 1e-3 a after every retry: back onto the surface, counted
            g = np.flatnonzero(graze)
            nxt[g] = field.push_out(nxt[g])
            d_next[g] = field.distances(nxt[g], "true").min(axis=-1)
            corrections[idx[g]] += 1
        contact = (d_next < 0) | (corrections[idx] > MAX_CORRECTIONS)
        move = ~(arrived | stalled)
        p[idx[move]] = nxt[move]
        track[k, idx[move]] = nxt[move]
        count[idx[move]] += 1
        min_d[idx[move]] = np.minimum(min_d[idx[move]], d_next[move])
        status[idx[arrived]] = "arrived"
        status[idx[stalled & ~arrived]] = "stagnation"
        status[idx[contact & move]] = "contact"
        active[idx[arrived | stalled | (contact & move)]] = False
    paths = [track[: count[i], i].copy() for i in range(n)]
    for i in np.flatnonzero(status == "arrived"):
        if np.linalg.norm(paths[i][-1] - T) > 0:
            paths[i] = np.vstack([paths[i], T])
    return Streamlines(paths, status, min_d, count, time.perf_counter() - t0, corrections)


def plan_flow(problem, params: FlowParams) -> PlanResult:
    """Streamline from the problem's start to its goal in the world's obstacle field.

    ``EXACT`` when the streamline arrives without touching an obstacle (inflated by the World's
    obstacle margin) and passes the World's exact segment tests (seabed included);
    ``INFEASIBLE`` otherwise, with the reason.
    """
    t0 = time.perf_counter()
    world: World = problem.world
    from .swarm import check_endpoints

    bad = check_endpoints(problem)
    if bad is not None:
        return PlanResult(bad[0], np.empty((0, 3)), float("inf"), {}, 0, 0, 0.0, np.empty(0), "flow", None, bad[1])
    field = FlowField(world.obstacles, problem.goal, params, world.margins.obstacle)
    sl = integrate_streamlines(field, problem.start[None], params)
    path = sl.paths[0]
    length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
    st = sl.status[0]
    message = ""
    status = Status.EXACT
    if st != "arrived":
        status, message = Status.INFEASIBLE, f"the streamline ended by {st} after {sl.steps[0]} steps"
    elif not world.path_free(path):
        status = Status.INFEASIBLE
        message = "the streamline arrives but meets the seabed or leaves the bounds (the flow knows only the obstacles)"
    seg = np.stack([path[:-1], path[1:]], axis=1) if len(path) > 1 else np.stack([path, path], axis=1)
    clearance = float(sl.min_distance[0] + world.margins.obstacle) if world.obstacles else float("inf")
    if world.terrain is not None:
        clearance = min(clearance, float(world.terrain.segment_min_altitude(seg).min()))
    terms = {"length": length, "terrain": 0.0, "energy": 0.0, "length_m": length, "energy_j": float("nan"),
             "duration_s": length / problem.speed, "min_clearance_m": clearance,
             "violations": int(np.count_nonzero(~world.segments_free(seg, moving=False)))}
    terms["collisions"] = terms["violations"]  # deprecated alias (CHANGELOG 0.2.0)
    return PlanResult(status, path, length, terms, int(sl.steps[0]) * 4, int(sl.steps[0]),
                      time.perf_counter() - t0, np.empty(0), "flow", None, message)
