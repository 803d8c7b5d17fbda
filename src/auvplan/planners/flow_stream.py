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
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from .._types import ArrayLike, BoolArray, FloatArray, IntArray
from .flow_params import FlowParams

if TYPE_CHECKING:  # flow.py imports this module
    from .flow import FlowField

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
        out.append(q)
        p = q
    return out


def _deflect(field: FlowField, x: FloatArray, d: FloatArray, h_min: float) -> tuple[BoolArray, FloatArray]:
    """Front stagnation rule: ``(mask, moved points)`` for points ``x`` with flow distances ``d (N, K)``."""
    n = x.shape[0]
    moved = x.copy()
    mask = np.zeros(n, dtype=bool)
    K = len(field.items)
    if K == 0:
        return mask, moved
    j = d[:, :K].argmin(axis=1)
    for k in np.unique(j):
        sel = np.flatnonzero(j == k)
        c = np.asarray(field.items[k].center)
        e = field.axes[k]
        R = field.radii[k]
        q = x[sel] - c
        along = q @ e
        perp = q - along[:, None] * e
        rho = np.linalg.norm(perp, axis=1)
        near = (d[sel, k] < max(2.0 * h_min, 0.02 * R)) & (along < 0) & (rho < 0.05 * R)
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
    p = np.array(starts, dtype=float).reshape(-1, 3)
    n = p.shape[0]
    T = field.target
    status = np.array(["max_steps"] * n, dtype=object)
    active = np.ones(n, dtype=bool)
    blocked = field.clearance(p) < 0
    status[blocked] = "inside_obstacle"
    active[blocked] = False
    prefix: list[list[np.ndarray]] = [[] for _ in range(n)]
    exits = np.zeros(n, dtype=bool)
    for i in np.flatnonzero(field.inside_body(p) & active):
        prefix[i] = _exit_body(field, p[i].copy())
        exits[i] = True
        if prefix[i]:
            p[i] = prefix[i][-1]
    cap = params.max_steps + 1
    track = np.full((cap, n, 3), np.nan)
    track[0] = p
    count = np.ones(n, dtype=np.intp)
    corrections = np.zeros(n, dtype=np.intp)
    deflections = np.zeros(n, dtype=np.intp)
    min_d = np.where(blocked, field.clearance(p), np.inf)
    for i in np.flatnonzero(exits):  # the start and the exit rule's points are nodes of the path too
        min_d[i] = field.clearance(np.vstack([np.asarray(starts, dtype=float).reshape(-1, 3)[i], *prefix[i]])).min()
        if min_d[i] < 0:
            status[i] = "contact"
            active[i] = False

    def direction(x: FloatArray) -> tuple[FloatArray, FloatArray]:
        u = field.velocity(x)
        sp = np.linalg.norm(u, axis=-1, keepdims=True)
        return u / np.maximum(sp, 1e-300), sp[..., 0]

    def rk4(x: FloatArray, k1: FloatArray, h: FloatArray) -> tuple[FloatArray, FloatArray]:
        k2, _ = direction(x + 0.5 * h[:, None] * k1)
        k3, _ = direction(x + 0.5 * h[:, None] * k2)
        k4, _ = direction(x + h[:, None] * k3)
        nxt = x + h[:, None] / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        return nxt, _flow_distance(field, nxt)

    for k in range(1, cap):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        dall = field.distances(p[idx], "true")
        defl, moved = _deflect(field, p[idx], dall, h_min)
        defl &= (np.linalg.norm(p[idx] - T, axis=1) > params.arrive) & (deflections[idx] < MAX_DEFLECTIONS)
        if defl.any():  # the sideways step is this step of those streamlines
            j = idx[defl]
            p[j] = moved[defl]
            track[k, j] = p[j]
            count[j] += 1
            deflections[j] += 1
            min_d[j] = np.minimum(min_d[j], field.clearance(p[j]))
            idx, dall = idx[~defl], dall[~defl]
            if idx.size == 0:
                continue
        x = p[idx]
        d = dall.min(axis=-1) if dall.shape[-1] else np.full(idx.size, np.inf)
        min_d[idx] = np.minimum(min_d[idx], _clearance_below(field, x, d, min_d[idx]))
        dist_goal = np.linalg.norm(x - T, axis=1)
        arrived = dist_goal <= params.arrive
        h = np.clip(params.step_factor * np.minimum(d, dist_goal), h_min, max(params.h_max, h_min))
        k1, sp = direction(x)
        if field.direction is not None:
            ref = 1.0
            missed = ((x - T) @ field.direction > 0) & ~arrived
        else:
            ref = params.strength / (FOUR_PI * np.maximum(dist_goal, 1e-300) ** 2)
            missed = np.zeros(idx.size, dtype=bool)
        stalled = sp < params.stagnation * ref
        nxt, d_next = rk4(x, k1, h)
        for _ in range(6):  # event: a step that would enter a surface is retried at a quarter of its size
            retry = d_next < 0
            if not retry.any():
                break
            h[retry] *= 0.25
            nxt[retry], d_next[retry] = rk4(x[retry], k1[retry], h[retry])
        graze = (d_next < 0) & (d_next > -1e-3 * h_min / 0.05)
        if graze.any():
            g = np.flatnonzero(graze)
            nxt[g] = field.push_out(nxt[g])
            d_next[g] = _flow_distance(field, nxt[g])
            corrections[idx[g]] += 1
        clear_next = _clearance_below(field, nxt, d_next, min_d[idx])  # +inf: not below the current minimum
        contact = (d_next < 0) | (corrections[idx] > MAX_CORRECTIONS) | (clear_next < 0)
        stop = arrived | stalled | missed
        move = ~stop
        ok = move & ~contact
        p[idx[ok]] = nxt[ok]
        track[k, idx[ok]] = nxt[ok]
        count[idx[ok]] += 1
        min_d[idx[ok]] = np.minimum(min_d[idx[ok]], clear_next[ok])
        status[idx[arrived]] = "arrived"
        status[idx[stalled & ~arrived]] = "stagnation"
        status[idx[missed & ~stalled]] = "missed"
        status[idx[contact & move]] = "contact"
        active[idx[stop | (contact & move)]] = False
    return _collect(track, count, prefix, starts, status, min_d, corrections, deflections, exits, T, t0)


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
