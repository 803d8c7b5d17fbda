"""Time-optimal planning in currents that change with time (tides): lattice search, then refinement.

1. **Lattice** (:mod:`.lattice`).  Nodes every ``cell`` metres over the search box and ``levels`` depth levels over the
   allowed depth band; a node is free when :meth:`World.is_free` holds there.  Each node links to
   the 16 horizontal directions of the 5 × 5 stencil (offsets up to two cells, so headings are
   never more than 13.3° off) on its own level and the levels above and below, and straight up and
   down (50 legs); a leg exists when the World's exact segment test passes (the seabed's Lipschitz
   bound and the obstacles' distances clear most legs without it).
2. **Current table.**  The field is sampled once at every node every ``dt`` seconds over the
   departure and the horizon (:meth:`CurrentField.sample`; one matrix product for tidal fields).
3. **Search: label-setting on arrival times** (time-dependent Dijkstra; Dreyfus 1969, Kaufman and
   Smith 1993).  A leg's travel time is integrated through the table while the current changes
   (:mod:`.timeopt_kernels`).  Why this and not a level-set / fast-marching front: the vehicle
   holds a track at constant through-water speed, so along one leg its position obeys a scalar ODE
   ``ds/dt = g(s, t)`` whose solutions cannot overtake each other — leaving later never arrives
   earlier (the FIFO property).  On a FIFO network the earliest arrival at each node is all the
   search needs to keep, so Dijkstra on arrival times is exact for the lattice, needs no time
   discretisation of the state (times are continuous), answers in one pass, and reuses the
   World's exact collision tests on every leg, which a grid PDE front cannot do for 3D seabed.
   Where the along-track current beats the vehicle (U > V) the vehicle holds the leg's line heading
   to make the most headway and drifts back on it until the current eases (:mod:`.kernels`; the
   leg behind its start must be free too); only legs no heading can hold (cross current above V)
   are not taken at that time.  The vehicle does not wait (it cannot hold station against a
   current faster than itself).  Drifting back and legs that open later break FIFO, and one label
   per node then fails where the current turns (issue 36): where the table's current can reach
   the vehicle's speed the search keeps a label per node and arrival-time bucket instead
   (:mod:`.labels`; ``labels = "auto"``), exact for the lattice as the buckets shrink.
4. **Refinement.**  The lattice path, resampled every half cell, is pulled by a time-aware elastic
   band: in turn the odd and even vertices try a pull towards their neighbours' midpoint and moves
   of ±δ across the path (horizontally and vertically), and keep the move that brings the vehicle
   earliest to the *next* vertex from the previous one (by FIFO, an earlier arrival there can only
   bring the rest of the path earlier) and whose two segments pass the exact test.  A sweep whose
   moves together made the arrival later is undone; steps halve where nothing helps.
5. **Objective.**  ``"time"``: earliest arrival at the vehicle's speed.  ``"energy"``: with the
   power ``P(V) = P_hotel + k V³`` at a constant through-water speed V the energy is ``P(V) T(V)``,
   so for each speed in ``speeds`` × V the time-optimal path is also the energy-optimal one; the
   planner searches each speed and keeps the least energy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray, IntArray
from ...path import densify, polyline_length, resample_polyline
from ...world import World
from .kernels import Float32Array, polyline_times, two_legs
from .labels import fifo_holds, multi_search, single_search
from .lattice import _OFFSETS, _OPPOSITE, Lattice, build_lattice

__all__ = ["Lattice", "CurrentTable", "TimedPath", "time_search", "timed_traverse", "drift_free", "build_lattice",
           "build_table", "refine"]


@dataclass(frozen=True, eq=False)
class CurrentTable:
    """The field at the lattice nodes every ``dt`` seconds from ``t0``: ``cur (nt, nx, ny, nz, 3)``
    (single precision: a tidal table of a 50 km strait over a day is tens of megabytes).

    Parameters
    ----------
    cur : numpy.ndarray
        Current ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    origin, step : numpy.ndarray
        First node and node spacing of the lattice ``(3,)`` (m).
    t0 : float
        Time of the first slice (s).
    dt : float
        Time between slices (s).
    """

    cur: Float32Array
    origin: FloatArray
    step: FloatArray
    t0: float
    dt: float

    @property
    def t1(self) -> float:
        """Last time of the table.

        Returns
        -------
        float
            ``t0 + dt (nt - 1)`` (s).
        """
        t1: float = self.t0 + self.dt * (self.cur.shape[0] - 1)
        return t1

    def args(self) -> tuple[Float32Array, FloatArray, FloatArray, float, float]:
        """The leading arguments of the kernels.

        Returns
        -------
        tuple
            ``(cur, origin, step, t0, dt)``.
        """
        return self.cur, self.origin, self.step, self.t0, self.dt


def build_table(world: World, lattice: Lattice, t0: float, t1: float, dt: float) -> CurrentTable:
    """Sample the World's current at the lattice nodes from ``t0`` to at least ``t1``.

    Parameters
    ----------
    world : World
        Source of the current field.
    lattice : Lattice
        The nodes to sample at.
    t0, t1 : float
        First and last time to cover (s).
    dt : float
        Time step (s).

    Returns
    -------
    CurrentTable
        The field at every node every ``dt`` seconds, float32.
    """
    nt = max(int(math.ceil((t1 - t0) / dt)), 1) + 1
    times = t0 + dt * np.arange(nt)
    cur = world.currents.sample(lattice.xyz, times).astype(np.float32)
    return CurrentTable(np.ascontiguousarray(cur.reshape(nt, *lattice.shape, 3)), lattice.origin.copy(),
                        lattice.step.copy(), float(t0), float(dt))


@dataclass(frozen=True, eq=False)
class TimedPath:
    """A path with the time the vehicle reaches each vertex.

    Parameters
    ----------
    points : numpy.ndarray
        Vertices ``(N, 3)`` (m).
    times : numpy.ndarray
        Arrival at each vertex ``(N,)`` (s after the mission's start time).
    speed : float
        Through-water speed (m/s).
    back : numpy.ndarray, optional
        How far behind its start the current pushed the vehicle on each leg ``(N - 1,)`` (m;
        None: not known, as for a lattice path).
    tail : numpy.ndarray of bool, optional
        ``(N - 1,)``: the legs flown tail-first (:mod:`.tail`; None: none).
    timed : bool, default False
        The times are already those of a flight through the World's own current (the front method,
        :mod:`.front_plan`): :func:`.planner.flown` keeps them.
    """

    points: FloatArray
    times: FloatArray
    speed: float
    back: FloatArray | None = None
    tail: BoolArray | None = None
    timed: bool = False

    @property
    def duration(self) -> float:
        """Travel time.

        Returns
        -------
        float
            Last minus first time (s); ``inf`` when the current blocks the path somewhere.
        """
        return float(self.times[-1] - self.times[0]) if self.times.size else math.inf


def timed_traverse(table: CurrentTable, points: ArrayLike, depart: float, speed: float, ds: float) -> TimedPath:
    """Times along a polyline flown at a through-water speed (holding the track).

    Parameters
    ----------
    table : CurrentTable
        The time-varying current.
    points : array_like
        Vertices ``(N, 3)`` (m).
    depart : float
        Departure time from the first vertex (s).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest integration sub-step (m).

    Returns
    -------
    TimedPath
        The polyline with its arrival times (``inf`` after a rejected leg) and each leg's drift.
    """
    p = np.ascontiguousarray(np.asarray(points, dtype=float))
    out, back = np.empty(p.shape[0]), np.zeros(max(p.shape[0] - 1, 0))
    polyline_times(*table.args(), p, float(depart), float(speed), float(ds), out, back)
    return TimedPath(p, out, float(speed), back)


def drift_free(world: World, tp: TimedPath) -> bool:
    """Whether the water behind each leg's start that the current pushes the vehicle back into is free.

    Parameters
    ----------
    world : World
        The world of the exact segment tests.
    tp : TimedPath
        A path with its drifts (``back``; None passes).

    Returns
    -------
    bool
        True when every leg's stretch ``[start - back ŝ, start]`` passes the exact segment test.
    """
    if tp.back is None or not (tp.back > 0.0).any():
        return True
    i = np.flatnonzero(tp.back > 0.0)
    d = tp.points[i + 1] - tp.points[i]
    e = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
    seg = np.stack([tp.points[i] - tp.back[i, None] * e, tp.points[i]], axis=1)
    return bool(world.segments_free(seg, moving=False).all())


def _links(world: World, lattice: Lattice, point: FloatArray, reach: float) -> IntArray:
    """Free nodes within ``reach`` of ``point`` joined to it by a free straight segment."""
    xyz = lattice.xyz
    near = np.flatnonzero(lattice.free & (np.linalg.norm((xyz - point)[:, :2], axis=1) <= reach))
    if near.size == 0:
        return near
    seg = np.stack([np.broadcast_to(point, (near.size, 3)), xyz[near]], axis=1)
    linked: IntArray = near[world.segments_free(seg, moving=False)]
    return linked


def time_search(world: World, lattice: Lattice, table: CurrentTable, start: ArrayLike, goal: ArrayLike,
                depart: float, speed: float, ds: float, labels: str = "auto", label_dt: float = 0.0,
                max_labels: int = 4_000_000, tail: bool = False) -> TimedPath | None:
    """Earliest-arrival lattice path from start to goal.

    Parameters
    ----------
    world : World
        The world of the exact segment tests.
    lattice : Lattice
        Nodes and free legs.
    table : CurrentTable
        The time-varying current.
    start, goal : array_like
        End points ``(3,)`` (m).
    depart : float
        Departure time (s).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest integration sub-step (m).
    labels : str, default "auto"
        ``"single"``: one label per node (:func:`.labels.single_search`); ``"multi"``: one per node and
        arrival-time bucket (:mod:`.labels`); ``"auto"``: single where FIFO provably holds (the
        table's current slower than the vehicle from ``depart`` on), else multi.
    label_dt : float, default 0
        Bucket width of the multi-label search (s; 0 = a cell's still-water leg time).
    max_labels : int, default 4 000 000
        Most labels of the multi-label search (the bucket width grows to stay within it).
    tail : bool, default False
        Let the multi-label search also fly legs tail-first (:mod:`.tail`).

    Returns
    -------
    TimedPath or None
        The earliest-arrival path (the straight leg when it is free and no later), ``None`` when
        the goal cannot be reached.
    """
    start, goal = np.asarray(start, float), np.asarray(goal, float)
    reach = 2.01 * lattice.step[0]
    xyz = lattice.xyz
    s_ids = _links(world, lattice, start, reach)
    g_ids = _links(world, lattice, goal, reach)
    args = table.args()
    s_legs = [timed_traverse(table, [start, xyz[i]], depart, speed, ds) for i in s_ids]
    s_arr = np.array([leg.times[-1] if drift_free(world, leg) else np.inf for leg in s_legs])
    goal_link = np.zeros(xyz.shape[0], dtype=bool)
    goal_link[g_ids] = True
    common = (args, lattice.shape, _OFFSETS, _OPPOSITE, lattice.edge_ok, s_ids, s_arr, goal_link, goal, float(speed),
              float(ds))
    modes = None
    if labels == "single" or (labels == "auto" and fifo_holds(table.cur, table.t0, table.dt, depart, table.t1, speed)):
        best, nodes, at = single_search(*common)
    else:
        best, nodes, at, modes = multi_search(*common, float(depart), label_dt or float(lattice.step[0]) / speed,
                                              max_labels, tail)
    straight = timed_traverse(table, [start, goal], depart, speed, ds)
    if world.path_free(straight.points) and drift_free(world, straight) and straight.times[-1] <= best:
        return straight
    if not np.isfinite(best):
        return None
    tails = None if modes is None or not modes.any() else np.r_[modes > 0, False]
    return TimedPath(np.vstack([start, xyz[nodes], goal]), np.r_[depart, at, best], float(speed), tail=tails)


def _normals(p: FloatArray, i: IntArray) -> tuple[FloatArray, FloatArray]:
    """Unit horizontal normal of the chord ``p[i+1] - p[i-1]`` and the vertical."""
    t = p[i + 1] - p[i - 1]
    n1 = np.column_stack([-t[:, 1], t[:, 0], np.zeros(len(i))])
    n1 /= np.maximum(np.linalg.norm(n1, axis=1, keepdims=True), 1e-12)
    return n1, np.broadcast_to(np.array([0.0, 0.0, 1.0]), n1.shape)


def refine(world: World, table: CurrentTable, path: TimedPath, cell: float, vstep: float, ds: float,
           iterations: int) -> TimedPath:
    """The time-aware elastic band of the module notes, coarse to fine.

    The path is resampled every 16, 8, 4, 2, 1 and 1/2 cells (levels longer than a quarter of the
    path skipped) and relaxed at each level with steps of that spacing, so that whole stretches
    move before the detail settles.

    Parameters
    ----------
    world : World
        The world of the exact segment tests.
    table : CurrentTable
        The time-varying current.
    path : TimedPath
        The path to improve.
    cell : float
        Lattice spacing (m).
    vstep : float
        Largest vertical move (m).
    ds : float
        Largest integration sub-step (m).
    iterations : int
        Sweeps per level (0 returns ``path``).

    Returns
    -------
    TimedPath
        A free path never arriving later than ``path``.
    """
    best = path
    total = float(polyline_length(path.points))
    if iterations == 0 or not np.isfinite(path.duration) or path.tail is not None:
        return path  # (the band times legs forward: a path with tail-first legs is kept as the lattice made it)
    for level in (16.0, 8.0, 4.0, 2.0, 1.0, 0.5):
        spacing = level * cell
        if spacing > 0.25 * total and level > 0.5:
            continue
        p = resample_polyline(best.points, spacing)
        if not world.path_free(p):
            p = densify(best.points, spacing)
        trial = _relax(world, table, timed_traverse(table, p, path.times[0], path.speed, ds), spacing,
                       min(vstep, spacing), ds, iterations)
        if trial.duration <= best.duration:
            best = trial
    return best


def _relax(world: World, table: CurrentTable, best: TimedPath, step: float, vstep: float, ds: float,
           iterations: int) -> TimedPath:
    """One level of the elastic band with moves of ``step`` across and ``vstep`` up/down."""
    p = best.points
    n = p.shape[0]
    if n < 3 or not np.isfinite(best.duration):
        return best
    alpha = np.full(n, 0.5)
    delta = np.full(n, 0.5 * step)
    dz = np.full(n, 0.5 * vstep)
    args = table.args()
    for _ in range(iterations):
        for parity in (1, 2):
            i = np.arange(parity, n - 1, 2)
            i = i[(alpha[i] > 1e-3) | (delta[i] > 1e-3 * step)]
            if i.size == 0:
                continue
            a, b, c = p[i - 1], p[i], p[i + 1]
            n1, n2 = _normals(p, i)
            d, e = delta[i, None], dz[i, None]
            cand = np.stack([b, b + alpha[i, None] * (0.5 * (a + c) - b), b + d * n1, b - d * n1, b + e * n2,
                             b - e * n2], axis=1)
            arr = np.empty(cand.shape[:2])
            two_legs(*args, np.ascontiguousarray(a), np.ascontiguousarray(cand), np.ascontiguousarray(c),
                     best.times[i - 1], best.speed, ds, arr)
            arr[:, 1:][arr[:, 1:] >= arr[:, :1] - 1e-9] = np.inf
            first = np.stack([np.broadcast_to(a[:, None], cand.shape), cand], axis=2)
            second = np.stack([cand, np.broadcast_to(c[:, None], cand.shape)], axis=2)
            free = world.segments_free(first, moving=False) & world.segments_free(second, moving=False)
            arr[:, 1:][~free[:, 1:]] = np.inf
            k = np.argmin(arr, axis=1)
            win = k > 0
            trial = p.copy()
            trial[i[win]] = cand[win, k[win]]
            timed = timed_traverse(table, trial, best.times[0], best.speed, ds)
            if win.any() and timed.times[-1] < best.times[-1]:
                p, best = trial, timed
            else:
                win[:] = False
            lose = i[~win]
            alpha[lose] *= 0.5
            delta[lose] *= 0.5
            dz[lose] *= 0.5
        if np.all(delta[1:-1] <= 1e-3 * step) and np.all(alpha[1:-1] <= 1e-3):
            break
    return best
