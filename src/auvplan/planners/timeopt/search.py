"""Time-optimal planning in currents that change with time (tides): lattice search, then refinement.

1. **Lattice.**  Nodes every ``cell`` metres over the search box and ``levels`` depth levels over the
   allowed depth band; a node is free when :meth:`World.is_free` holds there.  Each node links to
   the 16 horizontal directions of the 5 × 5 stencil (offsets up to two cells, so headings are
   never more than 13.3° off) on its own level and the levels above and below, and straight up and
   down (50 legs); a leg exists when the World's exact segment test passes (the seabed's Lipschitz
   bound and the obstacles' distances clear most legs without it).
2. **Current table.**  The field is sampled once at every node every ``dt`` seconds over the
   departure and the horizon (:meth:`CurrentField.sample`; one matrix product for tidal fields;
   the table and the timed paths through it: :mod:`.timed`).
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
4. **Refinement** (:mod:`.band`).  The lattice path, resampled every half cell, is pulled by a time-aware
   elastic band: in turn the odd and even vertices try a pull towards their neighbours' midpoint and moves
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
from ...world import World
from ..grid.lattice import free_edges
from .band import refine
from .labels import fifo_holds, multi_search, single_search
from .timed import CurrentTable, TimedPath, drift_free, timed_traverse

__all__ = ["Lattice", "CurrentTable", "TimedPath", "time_search", "timed_traverse", "drift_free", "build_lattice",
           "build_table", "refine"]


def _stencil() -> IntArray:
    """The 50 leg offsets: 16 horizontal directions (5 × 5 stencil) on three levels, and up/down."""
    hor = [(i, j) for i in range(-2, 3) for j in range(-2, 3) if (i, j) != (0, 0) and math.gcd(abs(i), abs(j)) == 1]
    off = [(i, j, k) for (i, j) in hor for k in (-1, 0, 1)] + [(0, 0, -1), (0, 0, 1)]
    return np.array(off, dtype=np.int64)


_OFFSETS = _stencil()
_OPPOSITE = np.array([next(j for j, o in enumerate(_OFFSETS) if (o == -off).all()) for off in _OFFSETS],
                     dtype=np.int64)


@dataclass(frozen=True, eq=False)
class Lattice:
    """Free nodes and free legs of the search lattice.

    Attributes
    ----------
    origin, step : ndarray, shape (3,)
        First node and node spacing (m); a single level has ``step[2] = 1``.
    shape : tuple of int
        Nodes along x, y, z.
    free : ndarray of bool, shape (N,)
        Free nodes (flattened ``(ix * ny + iy) * nz + iz``).
    edge_ok : ndarray of bool, shape (50, N)
        Free legs from each node along each offset.
    """

    origin: FloatArray
    step: FloatArray
    shape: tuple[int, int, int]
    free: BoolArray
    edge_ok: BoolArray

    @property
    def xyz(self) -> FloatArray:
        """Node coordinates.

        Returns
        -------
        numpy.ndarray
            ``(N, 3)`` (m), in the flattened node order.
        """
        axes = [self.origin[d] + self.step[d] * np.arange(self.shape[d]) for d in range(3)]
        return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)

    @property
    def legs(self) -> int:
        """Number of free directed legs.

        Returns
        -------
        int
            Count of True entries of ``edge_ok``.
        """
        return int(self.edge_ok.sum())


def build_lattice(world: World, lower: ArrayLike, upper: ArrayLike, cell: float, levels: int,
                  z_single: float) -> Lattice:
    """The lattice over a box, its free nodes and free legs.

    Parameters
    ----------
    world : World
        The world whose exact tests decide the free nodes and legs (moving obstacles ignored).
    lower, upper : array_like
        Corners of the search box ``(3,)`` (m).
    cell : float
        Horizontal node spacing (m).
    levels : int
        Depth levels over the box's height; 1 for a single level.
    z_single : float
        Elevation of the single level when ``levels == 1`` (m).

    Returns
    -------
    Lattice
        Nodes centred in the box, with their free flags and free legs.
    """
    lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    n_xy = np.floor((upper[:2] - lower[:2]) / cell + 1e-9).astype(int) + 1
    origin = np.r_[lower[:2] + 0.5 * ((upper[:2] - lower[:2]) - (n_xy - 1) * cell), z_single]
    step = np.array([cell, cell, 1.0])
    nz = 1
    if levels > 1:
        eps = 1e-6 * max(1.0, upper[2] - lower[2])
        top, bottom = upper[2] - eps, lower[2] + eps
        nz = levels
        step[2] = (top - bottom) / (levels - 1)
        origin[2] = bottom
    shape = (int(n_xy[0]), int(n_xy[1]), nz)
    lat = Lattice(origin, step, shape, np.zeros(0, bool), np.zeros((0, 0), bool))
    xyz = lat.xyz
    slack = world.clearances(xyz, moving=False)
    free = np.minimum.reduce(list(slack.values())) >= 0.0
    alt = (slack["altitude"] + world.margins.min_altitude).reshape(shape)
    obs = np.minimum(slack["obstacles"], slack["zones"]).reshape(shape)  # both lower-bound a distance
    return Lattice(origin, step, shape, free, _legs(world, xyz, free.reshape(shape), alt, obs, step))


def _legs(world: World, xyz: FloatArray, free3: BoolArray, alt: FloatArray, obs: FloatArray,
          step: FloatArray) -> BoolArray:
    """``edge_ok (50, N)``: each offset's legs tested as array slices (bounds, then a provable
    clearance from the node values, then the exact segment test for the rest)."""
    shape = free3.shape
    ok = np.zeros((len(_OFFSETS), free3.size), dtype=bool)
    for slot, off in enumerate(_OFFSETS):
        if shape[2] == 1 and off[2] != 0:
            continue
        src, _ = free_edges(world, free3, alt, obs, step, off, xyz.__getitem__)
        ok[slot, src] = True
    return ok


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
