"""Time-optimal paths that drift and curl with the current: the reachable set's front, then backtracking.

Method (the level-set reachability of Lolla, Lermusiaux et al. 2014, "Time-optimal path planning in
dynamic flows using level set equations", on a dynamic-programming grid scheme):

1. **Grid.**  A horizontal grid of spacing ``h`` over the search box at the mission's depth (the
   start's; where the goal is at another depth, the path changes depth linearly along its length and
   a node must be free at both depths and half-way).  ``g`` is the obstacle function: the signed
   distance to the blocked nodes
   (positive in the seabed and the obstacles), half-way between a free and a blocked node; where
   two blocked nodes touch only diagonally one of the two free nodes beside them is blocked too
   (:func:`_sealed`: the bilinear g would let the front through between them).  The current is
   tabulated on the grid every ``dt``.
2. **Front.**  The reachable set at time t is ``R(t) = {φ(·, t) ≤ 0}``; it starts as the disc of
   radius ``V τ`` about ``start + c τ`` one step after the departure and advances by the
   semi-Lagrangian step of :func:`.front_kernels.front_step` (steps of a cell's flight at ``V + U``),
   the seabed entering as ``φ ≥ g``.  The goal is reached at the first step where ``φ(goal) ≤ 0``; the
   arrival time is interpolated linearly between the two steps.  The set need not grow: where the
   current beats the vehicle it moves away from points it covered (the goal must be *in* it).
3. **Backtracking.**  From the goal at the arrival time, step back through the stored fronts: at
   each step the heading whose characteristic foot has the least φ on the earlier front (the
   dynamic programme's own minimiser), the foot the previous point.  The backtracked points are the
   optimal flight sampled every step, with the heading flown on each.

The path it gives is refined by Zermelo's heading equation (:mod:`.zermelo`); the planner reports
the time of the path flown through the World's own current (:func:`.planner.flown`), so neither
the front's interpolation nor the table makes a plan optimistic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..._types import ArrayLike, BoolArray, FloatArray
from ...world import World
from ...world.kernels.edt import dilate_cross, distance_transform
from .front_kernels import CAP, best_heading, cubic, current2, front_step, mid_current
from .kernels import Float32Array

__all__ = ["FrontGrid", "Front", "build_grid", "propagate", "backtrack"]


@dataclass(frozen=True, eq=False)
class FrontGrid:
    """The horizontal grid, its obstacle functions and current table.

    Attributes
    ----------
    origin : numpy.ndarray
        First node ``(2,)`` (m).
    h : float
        Node spacing (m).
    free : numpy.ndarray of bool
        ``(L, nx, ny)`` free nodes at each depth the flight uses.
    g : numpy.ndarray
        ``(L, nx, ny)`` obstacle function at each of those depths (m; > 0 blocked), float32.
    level : numpy.ndarray of int
        ``(nt,)`` which depth each table slice's time is flown at.
    cur : numpy.ndarray
        ``(nt, nx, ny, 2)`` horizontal current (m/s) at the depth of each slice's time, float32.
    t0, dt : float
        First time and time step of the table (s).
    z : tuple of float
        Depth of the start and of the goal (m, z up).
    schedule : tuple of numpy.ndarray, optional
        ``(times, z)``: the depth flown against time (the lattice plan's); None: the depth goes
        linearly in arc length from the start's to the goal's.
    """

    origin: FloatArray
    h: float
    free: BoolArray
    g: Float32Array
    level: npt.NDArray[np.int64]
    cur: Float32Array
    t0: float
    dt: float
    z: tuple[float, float]
    schedule: tuple[FloatArray, FloatArray] | None = None

    @property
    def t1(self) -> float:
        """Last time of the table (s).

        Returns
        -------
        float
            ``t0 + dt (nt - 1)``.
        """
        return float(self.t0 + self.dt * (self.cur.shape[0] - 1))

    def table_args(self) -> tuple[Float32Array, float, float, float, float, float]:
        """The kernels' leading table arguments.

        Returns
        -------
        tuple
            ``(cur, ox, oy, h, t0, dt)``.
        """
        return self.cur, float(self.origin[0]), float(self.origin[1]), self.h, self.t0, self.dt

    def g_at(self, t: float) -> Float32Array:
        """The obstacle function at the depth flown at time ``t``.

        Parameters
        ----------
        t : float
            Time (s).

        Returns
        -------
        numpy.ndarray
            ``(nx, ny)``.
        """
        k = int(min(max(round((t - self.t0) / self.dt), 0), self.level.size - 1))
        out: Float32Array = self.g[self.level[k]]
        return out

    def depth(self, t: ArrayLike) -> FloatArray:
        """Depth flown at times (the schedule's; None: the start's).

        Parameters
        ----------
        t : array_like
            Times (s).

        Returns
        -------
        numpy.ndarray
            z (m).
        """
        if self.schedule is None:
            return np.full(np.shape(t), self.z[0])
        out: FloatArray = np.interp(np.asarray(t, dtype=np.float64), self.schedule[0], self.schedule[1])
        return np.asarray(out, dtype=np.float64)


def _obstacle(free: BoolArray, h: float) -> Float32Array:
    """Signed distance to the blocked nodes (m; module notes, 1)."""
    free = _sealed(free)
    if free.all():
        return np.full(free.shape, -1e9, dtype=np.float32)
    inside = distance_transform(~free)  # scipy.ndimage's distance_transform_edt, bit for bit
    outside = distance_transform(free)
    return np.asarray(np.where(free, 0.5 - outside, inside - 0.5) * h, dtype=np.float32)


def build_grid(world: World, lower: ArrayLike, upper: ArrayLike, h: float, z: tuple[float, float], t0: float,
               t1: float, dt: float, schedule: tuple[FloatArray, FloatArray] | None = None) -> FrontGrid:
    """Grid, obstacle functions and current table over a horizontal box (module notes, 1).

    Parameters
    ----------
    world : World
        Seabed, obstacles and current.
    lower, upper : array_like
        Corners of the box (m; the first two coordinates are used).
    h : float
        Node spacing (m).
    z : tuple of float
        Depth (z, m) of the start and of the goal.
    t0, t1 : float
        Times the table covers (s).
    dt : float
        Time step of the table (s).
    schedule : tuple of numpy.ndarray, optional
        ``(times, z)``: fly depth ``z(t)`` (each table slice at its depth, rounded to the metre);
        default one depth (module notes, 1).

    Returns
    -------
    FrontGrid
        The grid.
    """
    lo, hi = np.asarray(lower, dtype=float)[:2], np.asarray(upper, dtype=float)[:2]
    n = np.maximum(np.floor((hi - lo) / h + 1e-9).astype(int) + 1, 2)
    xs, ys = lo[0] + h * np.arange(n[0]), lo[1] + h * np.arange(n[1])
    xx, yy = np.meshgrid(xs, ys, indexing="ij")
    nt = max(int(math.ceil((t1 - t0) / dt)), 1) + 1
    times = t0 + dt * np.arange(nt)

    def free_at(depths: list[float]) -> BoolArray:
        ok = np.ones(xx.shape, dtype=bool)
        for zz in depths:
            ok &= world.is_free(np.stack([xx.ravel(), yy.ravel(), np.full(xx.size, zz)], axis=1),
                                moving=False).reshape(xx.shape)
        return ok

    if schedule is None:
        frees = [free_at(sorted({z[0], 0.5 * (z[0] + z[1]), z[1]}))]
        level = np.zeros(nt, dtype=np.int64)
        mid = np.stack([xx.ravel(), yy.ravel(), np.full(xx.size, 0.5 * (z[0] + z[1]))], axis=1)
        cur = world.currents.sample(mid, times)[..., :2]
    else:
        zt = np.round(np.interp(times, schedule[0], schedule[1]))
        depths, level = np.unique(zt, return_inverse=True)
        frees = [free_at([float(d)]) for d in depths]
        cur = np.empty((nt, xx.size, 2))
        for k, d in enumerate(depths):  # the slices at one depth in one call (the field's own series)
            at = np.flatnonzero(level == k)
            cur[at] = world.currents.sample(np.stack([xx.ravel(), yy.ravel(), np.full(xx.size, d)], axis=1),
                                            times[at])[..., :2]
    return FrontGrid(lo, float(h), np.stack(frees), np.stack([_obstacle(f, h) for f in frees]),
                     np.asarray(level, dtype=np.int64), np.ascontiguousarray(cur.reshape(nt, n[0], n[1], 2),
                                                                             dtype=np.float32),
                     float(t0), float(dt), (float(z[0]), float(z[1])), schedule)


def _sealed(free: BoolArray) -> BoolArray:
    """``free`` with every diagonal-only contact of blocked nodes closed (module notes, 1)."""
    free = free.copy()
    while True:
        b = ~free
        d1 = b[:-1, :-1] & b[1:, 1:] & free[1:, :-1] & free[:-1, 1:]
        d2 = b[1:, :-1] & b[:-1, 1:] & free[:-1, :-1] & free[1:, 1:]
        if not (d1.any() or d2.any()):
            return free
        free[1:, :-1] &= ~d1
        free[:-1, :-1] &= ~d2


@dataclass(frozen=True, eq=False)
class Front:
    """The stored fronts of one departure.

    Attributes
    ----------
    phi : numpy.ndarray
        ``(K, nx, ny)`` level-set function at ``times`` (float32; the set is ``φ ≤ 0``).
    times : numpy.ndarray
        ``(K,)`` times of the fronts (s).
    arrival : float
        Interpolated time the goal enters the set (s; ``inf`` when it does not within the table).
    step : float
        Time step (s).
    headings : int
        Headings tried per node and step.
    reason : str
        Why the goal was not reached (empty when it was).
    exhausted : bool
        The goal was not reached before the table's end (a longer table may reach it).
    """

    phi: Float32Array
    times: FloatArray
    arrival: float
    step: float
    headings: int
    reason: str
    exhausted: bool = False


def propagate(grid: FrontGrid, start: ArrayLike, goal: ArrayLike, depart: float, speed: float,
              headings: int = 32, t_end: float | None = None) -> Front:
    """Advance the reachable set from ``start`` at ``depart`` until it holds ``goal`` (module notes, 2).

    Parameters
    ----------
    grid : FrontGrid
        Grid and table.
    start, goal : array_like
        End points (m; x and y used).
    depart : float
        Departure time (s).
    speed : float
        Through-water speed V (m/s).
    headings : int, default 32
        Headings tried per node and step (and one more at the parabola's vertex).
    t_end : float, optional
        Stop at this time (default the table's end).

    Returns
    -------
    Front
        The stored fronts and the arrival time.
    """
    s, q = np.asarray(start, dtype=float)[:2], np.asarray(goal, dtype=float)[:2]
    umax = float(np.sqrt((grid.cur.astype(np.float64) ** 2).sum(axis=-1)).max())
    step = grid.h / (speed + umax)
    t_end = grid.t1 if t_end is None else min(t_end, grid.t1)
    cur, ox, oy, h, t0, dt = grid.table_args()
    xs, ys = ox + h * np.arange(grid.g.shape[1]), oy + h * np.arange(grid.g.shape[2])
    cap, reach = (CAP - 1e-3) * h, 3  # nodes farther than 3 cells from the front keep their value
    tau = max(step, 2.0 * h / speed)  # the first front: a disc two cells wide (the current's drift over it)
    c0 = np.array(_current(grid, s, depart + 0.5 * tau))
    centre = s + tau * c0
    disc = np.hypot(xs[:, None] - centre[0], ys[None, :] - centre[1]) - speed * tau
    g0 = grid.g_at(depart + tau)
    phis = [np.where(g0 > 0.0, CAP * h, np.clip(np.maximum(disc, g0), -CAP * h, CAP * h)).astype(np.float32)]
    times = [depart + tau]
    arrival, reason = math.inf, ""
    if cubic(phis[0], ox, oy, h, q[0], q[1]) <= 0.0:
        arrival = times[0]
    while not math.isfinite(arrival) and times[-1] + step <= t_end:
        out = np.empty_like(phis[-1])
        active = dilate_cross(np.abs(phis[-1]) < cap, reach)  # scipy.ndimage's binary_dilation
        front_step(phis[-1], out, grid.g_at(times[-1] + step), active, cur, ox, oy, h, t0, dt,
                   times[-1] + 0.5 * step, step, speed, *_trig(headings))
        a, b = cubic(phis[-1], ox, oy, h, q[0], q[1]), cubic(out, ox, oy, h, q[0], q[1])
        phis.append(out)
        times.append(times[-1] + step)
        if b <= 0.0:
            arrival = times[-1] - step * (b / (b - a) if math.isfinite(a) and a > b else 0.0)
        elif not (out <= h).any():
            reason = (f"the reachable set vanished at {times[-1] - depart:.0f} s after departure (the current "
                      "carries every point the vehicle can reach onto the seabed or out of the search box)")
            break
    if not math.isfinite(arrival) and not reason:
        reason = (f"the goal is not in the reachable set within {times[-1] - depart:.0f} s of the departure "
                  "(the current table's end)")
    exhausted = not math.isfinite(arrival) and reason.endswith("(the current table's end)")
    return Front(np.stack(phis), np.array(times), arrival, step, headings, reason, exhausted)


def _trig(k: int) -> tuple[FloatArray, FloatArray]:
    a = 2.0 * np.pi * np.arange(k) / k
    return np.cos(a), np.sin(a)


def _current(grid: FrontGrid, p: FloatArray, t: float) -> tuple[float, float]:
    return current2(*grid.table_args(), float(p[0]), float(p[1]), float(t))


def backtrack(grid: FrontGrid, front: Front, start: ArrayLike, goal: ArrayLike, depart: float,
              speed: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The optimal flight recovered from the stored fronts (module notes, 3).

    Parameters
    ----------
    grid : FrontGrid
        Grid and table.
    front : Front
        Fronts that reach the goal.
    start, goal : array_like
        End points (m).
    depart : float
        Departure time (s).
    speed : float
        Through-water speed V (m/s).

    Returns
    -------
    points : numpy.ndarray
        ``(M, 2)`` horizontal positions from the start to the goal (m).
    times : numpy.ndarray
        ``(M,)`` times at them (s).
    headings : numpy.ndarray
        ``(M - 1,)`` heading flown on each piece (mathematical angle, rad).
    """
    cur, ox, oy, h, t0, dt = grid.table_args()
    x = np.asarray(goal, dtype=float)[:2].copy()
    t = front.arrival
    k = int(np.searchsorted(front.times, t, side="left")) - 1  # the last front before the arrival
    pts, ts, ths = [x.copy()], [t], []
    while k >= 0:
        step = t - front.times[k]
        if step > 1e-9:
            cu, cv = mid_current(cur, ox, oy, h, t0, dt, x[0], x[1], t - 0.5 * step, step)
            _, th = best_heading(front.phi[k], ox, oy, h, x[0], x[1], cu, cv, step, speed, *_trig(front.headings))
            x = x - step * np.array([cu + speed * math.cos(th), cv + speed * math.sin(th)])
            t = float(front.times[k])
            pts.append(x.copy())
            ts.append(t)
            ths.append(th)
        k -= 1
    s = np.asarray(start, dtype=float)[:2]
    d = pts[-1] - s - (ts[-1] - depart) * np.array(_current(grid, s, 0.5 * (depart + ts[-1])))
    ths.append(math.atan2(d[1], d[0]))
    pts.append(s.copy())
    ts.append(depart)
    return np.array(pts[::-1]), np.array(ts[::-1]), np.array(ths[::-1])
