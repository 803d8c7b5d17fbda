"""Streamline integration for document 000's flow fields, from any start outside the obstacles.

:func:`integrate_streamlines` integrates many starts at once: dp/ds = u/|u| with classical RK4 in arc
length, the step at most ``step_factor`` × the distance to the surface the field actually flows round
(the sphere or the Rankine-type body, not the smaller obstacle inside it) and to the goal, and at least
``h_min``.  Events: arrival, contact, stagnation, step limit.  Two rules make every start outside the
inflated obstacle usable:

* **Exit rule** — a start inside a body (but outside the inflated obstacle it wraps) first leaves along
  the body's outward normal: the straight segment to its nearest body point, continued 10⁻⁶ of the
  body's radius outside.  When that segment would come nearer the obstacle than the margin, it leaves
  along the obstacle's own outward normal instead (on which the distance to a convex obstacle grows
  linearly) until it is outside the body.  Then it follows the streamline.
* **Front stagnation rule** — on the axis from an obstacle to the target, upstream of it, the flow
  runs into the body's front stagnation point, where it divides and its direction is undefined.
  A streamline that comes within ``2 h_min`` (and 2 % of the body's radius) of a body, upstream of it
  and closer than 5 % of the body's radius to its axis, steps sideways, perpendicular to the axis, to
  6 % of the radius off the axis: in its own meridian plane, or, exactly on the axis, towards the side
  where the real obstacle is thinnest across the axis (the shortest way round; over the obstacle,
  +z, when the widths tie).  The step cannot enter the body (the front point is its most upstream
  point) and is checked.  Then it follows the streamline round the body.

A step whose end falls inside a flow surface is retried at a quarter of its size (six times); a graze
of at most 10⁻³ of the obstacle size left after that is pushed back onto the surface along its
normal and counted in ``corrections``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..._types import ArrayLike, BoolArray, FloatArray, IntArray
from ..core.params import FlowParams
from .field import FlowField, _norm

__all__ = ["Streamlines", "integrate_streamlines"]

FOUR_PI = 4.0 * np.pi
MAX_CORRECTIONS = 200
"""A streamline pushed back onto a surface more often than this is stuck against it: ``contact``."""
MAX_DEFLECTIONS = 20


@dataclass(frozen=True, eq=False)
class Streamlines:
    """Many integrated streamlines: one polyline and one status per start.

    ``status``: ``arrived``, ``contact``, ``stagnation``, ``max_steps``, ``missed`` (uniform flow:
    the streamline passed the goal's plane without reaching it), ``inside_obstacle`` (the start lies
    within the margin of an obstacle).  ``min_distance`` is the smallest clearance to the real
    obstacles minus the margin along the nodes.

    Parameters
    ----------
    paths : list of numpy.ndarray
        One polyline ``(N_i, 3)`` (m) per start.
    status : numpy.ndarray of str
        How each streamline ended (see above).
    min_distance : numpy.ndarray
        Least clearance to the real obstacles minus the margin (m).
    steps : numpy.ndarray
        Integration nodes per streamline.
    wall_time_s : float
        Time of the integration (s).
    corrections : numpy.ndarray
        Push-backs onto a flow surface per streamline.
    deflections : numpy.ndarray
        Sideways steps of the front stagnation rule per streamline.
    exits : numpy.ndarray of bool
        Streamlines that started inside a body and left it by the exit rule.
    """

    paths: list[FloatArray]
    status: npt.NDArray[np.object_]
    min_distance: FloatArray
    steps: IntArray
    wall_time_s: float
    corrections: IntArray
    deflections: IntArray
    exits: BoolArray

    @property
    def arrived(self) -> BoolArray:
        """Where the streamline reached the goal.

        Returns
        -------
        numpy.ndarray of bool
            One per start.
        """
        arrived: BoolArray = self.status == "arrived"
        return arrived


def _segment_clear(field: FlowField, a: FloatArray, b: FloatArray, n: int = 17) -> bool:
    t = np.linspace(0.0, 1.0, n)[:, None]
    return bool(np.all(field.clearance(a + t * (b - a)) >= 0.0))


def _exit_body(field: FlowField, p: FloatArray) -> list[FloatArray]:
    """Exit rule for one start inside a flow surface: the points it passes on its way out (may be empty)."""
    out: list[np.ndarray] = []
    ns = len(field.spheres)
    for _ in range(4):
        d = field.distances(p[None], "true")[0]
        j = int(d.argmin())
        if d[j] >= 0:
            return out
        if j < ns or j >= len(field.items):  # a sphere or the plane: its normal is the obstacle's normal
            q = field.push_out(p[None], 1e-6)[0]
        else:
            body = field.bodies[j - ns]
            q = p + (-d[j] + 1e-6 * body.radius) * body.normal(p[None])[0]
            if not _segment_clear(field, p, q) or body.inside(q[None])[0]:
                g = field.items[j].gradient(p)
                lo, hi = 0.0, 2.0 * body.radius
                for _ in range(60):
                    mid = 0.5 * (lo + hi)
                    lo, hi = (mid, hi) if body.inside((p + mid * g)[None])[0] else (lo, mid)
                q = p + (hi + 1e-6 * body.radius) * g
        if not _segment_clear(field, p, q) or (field.inside_body(q[None])[0] and len(field.items) > 1):
            q = _search_exit(field, p, q)  # the move would cross an obstacle or land in another flow surface
        out.append(q)
        p = q
    return out


EXIT_ANGLE = np.radians(30.0)
"""Angle to the flow surface at which :func:`_smooth_exit` climbs out while inside it."""
EXIT_CLEAR = 0.1
"""Distance outside the flow surface, in units of its radius, at which :func:`_smooth_exit` hands over."""
EXIT_STEP = 0.01
"""Step of :func:`_smooth_exit`, in units of the surface's radius."""
EXIT_TURN = np.radians(10.0)
"""Largest turn of :func:`_smooth_exit` per step where it turns from the surface flow to the normal."""


def _smooth_exit(field: FlowField, p: FloatArray) -> list[FloatArray]:
    """Smooth exit for a start inside one flow surface (sphere or body): the points it passes (empty: none).

    It flies with the flow along the surface while it climbs: its direction is the flow's direction at
    the surface point nearest to it (tangent to the surface) turned outward by :data:`EXIT_ANGLE`, the
    angle easing to a fifth of it over the last :data:`EXIT_CLEAR` × R, where it hands over to the
    streamline at 0.8 × EXIT_CLEAR × R (about 6° to the flow there, where a straight exit along the normal
    met it at 90° on the surface itself).  Where the surface flow turns by more than EXIT_ANGLE from one step
    to the next (near a rear stagnation point it flips from side to side) the exit turns towards the outward
    normal instead, at most :data:`EXIT_TURN` a step.  Steps of :data:`EXIT_STEP` × R, each checked to keep the margin
    and out of every other flow surface; any failure (or a start inside several surfaces, or under the
    plane) leaves the start to :func:`_exit_body`.
    """
    d = field.distances(p[None], "true")[0]
    j = int(d.argmin())
    if int((d < 0).sum()) != 1 or j >= len(field.items):
        return []
    ns = len(field.spheres)
    R = float(field.radii[j])
    clear, h = EXIT_CLEAR * R, EXIT_STEP * R
    out: list[FloatArray] = []
    x = p
    prev: FloatArray | None = None
    prev_t = p
    rear = False
    for _ in range(int(4.0 * (clear - d[j]) / (h * np.sin(0.2 * EXIT_ANGLE))) + 8):
        if d[j] >= 0.8 * clear:
            return out
        if j < ns:
            n = (x - field.C[j]) / max(float(np.linalg.norm(x - field.C[j])), 1e-300)
        else:
            n = field.bodies[j - ns].normal(x[None])[0]
        foot = x - d[j] * n
        u = field.velocity((foot + 1e-3 * R * n)[None])[0]
        t = u - (u @ n) * n
        if np.linalg.norm(t) < 1e-12 * max(float(np.linalg.norm(u)), 1e-300):
            return []  # at a stagnation point of the surface: no flow direction to follow
        t /= np.linalg.norm(t)
        a = EXIT_ANGLE * min(1.0, max(0.2, 1.0 - max(float(d[j]), 0.0) / clear))
        v = np.cos(a) * t + np.sin(a) * n
        if prev is not None and (rear or t @ prev_t < np.cos(EXIT_ANGLE)):
            # near a rear stagnation point the surface flow flips from side to side: from there on the exit
            # turns towards the outward normal (downstream there) by at most EXIT_TURN a step
            rear = True
            w = n - (n @ prev) * prev
            turn = min(EXIT_TURN, float(np.arccos(np.clip(n @ prev, -1.0, 1.0))))
            v = np.cos(turn) * prev + np.sin(turn) * w / max(float(np.linalg.norm(w)), 1e-300)
        prev, prev_t = v, t
        nxt = x + h * v
        dn = field.distances(nxt[None], "true")[0]
        others = np.arange(dn.size) != j
        if (dn[others] < 0).any() or not _segment_clear(field, x, nxt, 5):
            return []
        out.append(nxt)
        x, d = nxt, dn
    return []


EXIT_DIRECTIONS = 400
"""Directions tried by :func:`_search_exit` (a Fibonacci sphere)."""


def _search_exit(field: FlowField, p: FloatArray, fallback: FloatArray) -> FloatArray:
    """The shortest straight way out of every flow surface that stays clear of every inflated obstacle.

    Where the body's and the obstacle's normals lead into a neighbouring obstacle or its flow surface (flow
    surfaces can overlap when a body is large), each of :data:`EXIT_DIRECTIONS` directions is marched in
    steps of 0.5 % of the largest radius to its first point outside every flow surface (then 0.5 % on); the
    shortest move whose segment keeps the margin wins.  ``fallback`` when none does.
    """
    n = EXIT_DIRECTIONS
    i = np.arange(n) + 0.5
    polar, azim = np.arccos(1.0 - 2.0 * i / n), np.pi * (1.0 + 5.0**0.5) * i
    dirs = np.column_stack([np.cos(azim) * np.sin(polar), np.sin(azim) * np.sin(polar), np.cos(polar)])
    reach = 3.0 * float(field.radii.max(initial=1.0))
    t = np.linspace(0.0, reach, 601)[1:]
    pts = p + t[None, :, None] * dirs[:, None, :]
    free = ~field.inside_body(pts.reshape(-1, 3)).reshape(n, t.size)
    first = np.where(free.any(axis=1), free.argmax(axis=1), t.size - 1)
    ends = p + t[np.minimum(first + 1, t.size - 1), None] * dirs
    order = np.argsort(np.where(free.any(axis=1), t[first], np.inf))
    for k in order[:64]:
        if not free[k].any():
            break
        if _segment_clear(field, p, ends[k], 33) and not field.inside_body(ends[k][None])[0]:
            q: FloatArray = ends[k]
            return q
    return fallback


def _deflect(field: FlowField, x: FloatArray, d: FloatArray, h_min: float) -> tuple[BoolArray, FloatArray]:
    """Front stagnation rule: ``(mask, moved points)`` for points ``x`` with flow distances ``d (N, K)``."""
    n = x.shape[0]
    moved = x.copy()
    mask = np.zeros(n, dtype=bool)
    K = len(field.items)
    if K == 0 or not (d[:, :K] < max(2.0 * h_min, 0.02 * float(field.radii.max()))).any():
        return mask, moved  # no point near enough to any surface for the rule (the usual step)
    j = d[:, :K].argmin(axis=1)
    for k in np.unique(j):
        sel = np.flatnonzero(j == k)
        c = field.anchors[k]
        e = field.axes[k]
        R = field.radii[k]
        q = x[sel] - c
        along = q @ e
        perp = q - along[:, None] * e
        rho = np.linalg.norm(perp, axis=1)
        near = (d[sel, k] < max(2.0 * h_min, 0.02 * R)) & (along < 0) & (rho < field.bands[k] * R)
        if not near.any():
            continue
        s = np.where((rho > 1e-9 * R)[:, None], perp / np.maximum(rho, 1e-300)[:, None], field.sides[k])
        cand = c + along[:, None] * e + 0.06 * R * s
        for i, ok in zip(sel[near], np.flatnonzero(near)):
            if (field.distances(cand[ok][None], "true").min() > 0
                    and field.distances(0.5 * (x[i] + cand[ok])[None], "true").min() > 0):
                mask[i] = True
                moved[i] = cand[ok]
    return mask, moved


def integrate_streamlines(field: FlowField, starts: ArrayLike, params: FlowParams | None = None) -> Streamlines:
    """Integrate dp/ds = u/|u| from every start at once (RK4, step ≤ ``step_factor`` × distance).

    Parameters
    ----------
    field : FlowField
        The blended flow toward the target.
    starts : array_like
        Start points ``(N, 3)`` or one ``(3,)`` (m).
    params : FlowParams, optional
        Integration settings; the field's own when omitted.

    Returns
    -------
    Streamlines
        One polyline and one status per start.
    """
    t0 = time.perf_counter()
    params = params or field.params
    sizes = [ob.radius for ob in field.spheres] + [min(ob.semi_axes) for ob in field.ellipsoids]
    h_min = params.h_min or (0.05 * (min(sizes) + field.margin) if sizes else 0.01)
    run = _Run.start(field, np.array(starts, dtype=float).reshape(-1, 3), params.max_steps + 1)
    for k in range(1, params.max_steps + 1):
        idx = np.flatnonzero(run.active)
        if idx.size == 0:
            break
        dall = field.distances(run.p[idx], "true")
        idx, dall = run.sideways(field, k, idx, dall, h_min, params.arrive)
        if idx.size:
            run.step(field, k, idx, dall, h_min, params)
    return _collect(run.track, run.count, run.prefix, starts, run.status, run.min_d, run.corrections,
                    run.deflections, run.exits, field.target, t0)


@dataclass(eq=False)
class _Run:
    """The streamlines' state while they are integrated (one entry per start)."""

    p: FloatArray
    status: npt.NDArray[np.object_]
    active: BoolArray
    prefix: list[list[FloatArray]]
    exits: BoolArray
    track: FloatArray
    count: IntArray
    corrections: IntArray
    deflections: IntArray
    min_d: FloatArray

    @classmethod
    def start(cls, field: FlowField, starts: FloatArray, cap: int) -> _Run:
        """The starts: inside an obstacle's margin (stopped), inside a flow surface (the exit rule's
        points first; stopped as ``contact`` if one of them lies within the margin), or free."""
        p = starts.copy()
        n = p.shape[0]
        status = np.array(["max_steps"] * n, dtype=object)
        blocked = field.clearance(p) < 0
        status[blocked] = "inside_obstacle"
        active = ~blocked
        prefix: list[list[FloatArray]] = [[] for _ in range(n)]
        exits = np.zeros(n, dtype=bool)
        for i in np.flatnonzero(field.inside_body(p) & active):
            prefix[i] = _smooth_exit(field, p[i].copy()) or _exit_body(field, p[i].copy())
            exits[i] = True
            if prefix[i]:
                p[i] = prefix[i][-1]
        track = np.full((cap, n, 3), np.nan)
        track[0] = p
        min_d = np.where(blocked, field.clearance(p), np.inf)
        for i in np.flatnonzero(exits):  # the start and the exit rule's points are nodes of the path too
            min_d[i] = field.clearance(np.vstack([starts[i], *prefix[i]])).min()
            if min_d[i] < 0:
                status[i] = "contact"
                active[i] = False
        return cls(p, status, active, prefix, exits, track, np.ones(n, dtype=np.intp), np.zeros(n, dtype=np.intp),
                   np.zeros(n, dtype=np.intp), min_d)

    def advance(self, k: int, j: IntArray, to: FloatArray, clearance: FloatArray) -> None:
        """Streamlines ``j`` take node ``k`` at ``to``, whose clearance is ``clearance``."""
        self.p[j] = to
        self.track[k, j] = to
        self.count[j] += 1
        self.min_d[j] = np.minimum(self.min_d[j], clearance)

    def sideways(self, field: FlowField, k: int, idx: IntArray, dall: FloatArray, h_min: float,
                 arrive: float) -> tuple[IntArray, FloatArray]:
        """The front stagnation rule's sideways step as step ``k`` (:func:`_deflect`); returns the
        streamlines left to integrate and their flow distances."""
        defl, moved = _deflect(field, self.p[idx], dall, h_min)
        if defl.any():
            far = np.linalg.norm(self.p[idx] - field.target, axis=1) > arrive
            defl &= far & (self.deflections[idx] < MAX_DEFLECTIONS)
        if defl.any():
            j = idx[defl]
            self.advance(k, j, moved[defl], field.clearance(moved[defl]))
            self.deflections[j] += 1
        return idx[~defl], dall[~defl]

    def step(self, field: FlowField, k: int, idx: IntArray, dall: FloatArray, h_min: float,
             params: FlowParams) -> None:
        """One RK4 step of streamlines ``idx`` and the events at its end (arrival, stagnation, a missed
        goal, contact)."""
        x, T = self.p[idx], field.target
        d = dall.min(axis=-1) if dall.shape[-1] else np.full(idx.size, np.inf)
        self.min_d[idx] = np.minimum(self.min_d[idx], _clearance_below(field, x, d, self.min_d[idx]))
        dist_goal = _norm(x - T)
        arrived = dist_goal <= params.arrive
        h = np.clip(params.step_factor * np.minimum(d, dist_goal), h_min, max(params.h_max, h_min))
        k1, sp = _direction(field, x)
        if field.direction is not None:
            ref: float | FloatArray = 1.0
            missed = ((x - T) @ field.direction > 0) & ~arrived
        else:
            ref = params.strength / (FOUR_PI * np.maximum(dist_goal, 1e-300) ** 2)
            missed = np.zeros(idx.size, dtype=bool)
        stalled = sp < params.stagnation * ref
        nxt, d_next, graze = _guarded_rk4(field, x, k1, h, h_min)
        self.corrections[idx[graze]] += 1
        clear_next = _clearance_below(field, nxt, d_next, self.min_d[idx])  # +inf: not below the current minimum
        contact = (d_next < 0) | (self.corrections[idx] > MAX_CORRECTIONS) | (clear_next < 0)
        stop = arrived | stalled | missed
        move = ~stop
        ok = move & ~contact
        self.advance(k, idx[ok], nxt[ok], clear_next[ok])
        self.status[idx[arrived]] = "arrived"
        self.status[idx[stalled & ~arrived]] = "stagnation"
        self.status[idx[missed & ~stalled]] = "missed"
        self.status[idx[contact & move]] = "contact"
        self.active[idx[stop | (contact & move)]] = False


def _direction(field: FlowField, x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Unit flow direction and flow speed at ``x``."""
    u = field.velocity(x)
    sp = np.linalg.norm(u, axis=-1, keepdims=True)
    return u / np.maximum(sp, 1e-300), sp[..., 0]


def _rk4(field: FlowField, x: FloatArray, k1: FloatArray, h: FloatArray) -> tuple[FloatArray, FloatArray]:
    """One RK4 step of the unit direction field from ``x`` (``k1`` its direction there) by ``h``; the
    end points and their flow distances."""
    k2, _ = _direction(field, x + 0.5 * h[:, None] * k1)
    k3, _ = _direction(field, x + 0.5 * h[:, None] * k2)
    k4, _ = _direction(field, x + h[:, None] * k3)
    nxt = x + h[:, None] / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    return nxt, _flow_distance(field, nxt)


def _guarded_rk4(field: FlowField, x: FloatArray, k1: FloatArray, h: FloatArray,
                 h_min: float) -> tuple[FloatArray, FloatArray, IntArray]:
    """An RK4 step that does not enter a flow surface: a step whose end would is retried at a quarter
    of its size (six times); a graze left after that (at most 10⁻³ of the obstacle size) is pushed
    back out along the surface's normal.  Returns the end points, their flow distances and the
    indices of the grazes corrected (``h`` is shortened in place)."""
    nxt, d_next = _rk4(field, x, k1, h)
    for _ in range(6):
        retry = d_next < 0
        if not retry.any():
            break
        h[retry] *= 0.25
        nxt[retry], d_next[retry] = _rk4(field, x[retry], k1[retry], h[retry])
    graze = np.flatnonzero((d_next < 0) & (d_next > -1e-3 * h_min / 0.05))
    if graze.size:
        nxt[graze] = field.push_out(nxt[graze])
        d_next[graze] = _flow_distance(field, nxt[graze])
    return nxt, d_next, graze


def _clearance_below(field: FlowField, x: FloatArray, d: FloatArray, current: FloatArray) -> FloatArray:
    """Clearance where it may fall below ``current``, +inf elsewhere.

    Every flow surface contains its inflated obstacle, so outside the surfaces the clearance is at
    least the flow distance ``d``: it needs computing only where ``d < current`` (for the document's
    body, which does not contain its obstacle, everywhere).
    """
    need = (d < current) | (not field.contained)
    out = np.full(x.shape[0], np.inf)
    if need.any():
        out[need] = field.clearance(x[need])
    return out


def _flow_distance(field: FlowField, x: FloatArray) -> FloatArray:
    d = field.distances(x, "true")
    least: FloatArray = d.min(axis=-1) if d.shape[-1] else np.full(x.shape[0], np.inf)
    return least


def _collect(track: FloatArray, count: IntArray, prefix: list[list[FloatArray]], starts: ArrayLike,
             status: npt.NDArray[np.object_], min_d: FloatArray, corrections: IntArray, deflections: IntArray,
             exits: BoolArray, T: FloatArray, t0: float) -> Streamlines:
    starts = np.asarray(starts, dtype=float).reshape(-1, 3)
    paths = []
    for i in range(len(count)):
        body = track[: count[i], i]
        if prefix[i]:
            body = np.vstack([starts[i][None], np.asarray(prefix[i])[:-1], body])
        if status[i] == "arrived" and np.linalg.norm(body[-1] - T) > 0:
            body = np.vstack([body, T])
        paths.append(body.copy())
    return Streamlines(paths, status, min_d, count, time.perf_counter() - t0, corrections, deflections, exits)
