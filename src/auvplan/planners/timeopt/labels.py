"""Several arrival labels per lattice node: the time-dependent search where the current can beat the vehicle.

Why one label per node is not enough there.  The single-label search (:func:`single_search`)
keeps only the earliest arrival at each node, which is exact when leaving a node later never
arrives anywhere earlier (the FIFO property).  That holds whenever the current is slower than the
vehicle everywhere it flies: then the ground speed along every leg, ``g = c·ŝ + √(V² − |c⊥|²)``, is
positive, every leg can be held at every time, and the solutions of ``ds/dt = g(s, t)`` cannot
overtake one another.  Where the current is stronger than the vehicle (U > V) it fails twice:
a leg that drifts the vehicle back behind its start lets a later departure arrive first, and a leg
that no heading can hold at one time (``|c⊥| > V``) opens later.  In a strong *rotating* tidal
current the optimum (the constant heading of Zermelo's problem in a uniform current) loops with
the water and passes the same places at different times; the earliest arrival at a node is often
not the one from which the goal stays reachable once the current turns, and the single-label
search then fails although a path exists.

The search here keeps one label per node and *arrival-time bucket* of width ``width`` seconds from
the departure (label ``node * B + bucket``): a node may be reached, left and reached again at
different times, and a later arrival survives as long as no earlier one falls in its bucket.  It
is the same label-setting (Dijkstra) order on arrival times, so it stops as soon as no open label
can beat the goal's arrival; as ``width`` shrinks it tends to the exact earliest arrival over all
lattice paths (loops included).  Memory is bounded: ``B`` is chosen so that ``N × B`` stays within
``max_labels`` (the width grows instead).  Nodes from which no leg can meet water as fast as the
vehicle during the search keep a single bucket: there the vehicle can also hold station, so an
earlier arrival is never worse than a later one.

:func:`fifo_holds` says when the single-label search is provably enough (the fast path): the
table's largest current speed over the lattice and the departure's horizon is below the
vehicle's speed.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from ..._types import BoolArray, FloatArray, IntArray
from ...runtime.jit import kernel
from ...world.kernels.edt import window_any
from .kernels import Float32Array, leg_reach, leg_time
from .tail import tail_leg

__all__ = ["fifo_holds", "strong_nodes", "label_width", "label_search", "label_chain", "single_search", "multi_search"]


def _speeds(cur: Float32Array, t0: float, dt: float, depart: float, t_end: float) -> FloatArray:
    """Largest current speed at each node ``(nx, ny, nz)`` over the table's slices covering ``[depart, t_end]``."""
    nt = cur.shape[0]
    i0 = min(max(int(math.floor((depart - t0) / dt)), 0), nt - 1)
    i1 = min(max(int(math.ceil((t_end - t0) / dt)), i0), nt - 1)
    sp = np.zeros(cur.shape[1:4], dtype=np.float32)
    for i in range(i0, i1 + 1):  # slice by slice: the table may be tens of megabytes
        np.maximum(sp, np.sqrt((cur[i].astype(np.float32) ** 2).sum(axis=-1)), out=sp)
    return sp.astype(float)


def fifo_holds(cur: Float32Array, t0: float, dt: float, depart: float, t_end: float, speed: float) -> bool:
    """Whether every leg is FIFO from ``depart`` to ``t_end``: the single-label search is then exact.

    The table's current inside a cell and between slices is a convex combination of node values,
    so its speed never exceeds the largest node speed; below ``speed`` every leg can be held at
    every time with a positive ground speed, and leaving later never arrives earlier.

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    t0, dt : float
        First time and time step of the table (s).
    depart, t_end : float
        The span the search can reach (s).
    speed : float
        Through-water speed (m/s).

    Returns
    -------
    bool
        True when the largest tabulated speed over the span is below ``speed``.
    """
    return bool(_speeds(cur, t0, dt, depart, t_end).max() < speed)


def strong_nodes(cur: Float32Array, t0: float, dt: float, depart: float, t_end: float, speed: float,
                 reach: int) -> BoolArray:
    """Nodes from which a leg may meet water at least as fast as the vehicle over the span.

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    t0, dt : float
        First time and time step of the table (s).
    depart, t_end : float
        The span the search can reach (s).
    speed : float
        Through-water speed (m/s).
    reach : int
        Longest leg in cells (the stencil's); a node is strong when a node within ``reach + 1``
        cells (the cells a leg and its drift back cross) is.

    Returns
    -------
    numpy.ndarray of bool
        ``(N,)`` in the lattice's flattened order.
    """
    fast = _speeds(cur, t0, dt, depart, t_end) >= speed
    size = (2 * reach + 3, 2 * reach + 3, 3)
    grown: BoolArray = window_any(fast, size).reshape(-1)  # scipy.ndimage.maximum_filter, mode "nearest"
    return grown


def label_width(n_nodes: int, span: float, width: float, max_labels: int) -> tuple[float, int]:
    """The bucket width and count: ``width`` unless ``n_nodes × B`` would pass ``max_labels``.

    Parameters
    ----------
    n_nodes : int
        Lattice nodes.
    span : float
        Time from the departure to the table's end (s).
    width : float
        Wanted bucket width (s).
    max_labels : int
        Largest number of labels.

    Returns
    -------
    width : float
        Bucket width (s).
    buckets : int
        Buckets per node (the last one takes every later arrival).
    """
    buckets = max(1, min(int(math.ceil(span / width)) + 1, max_labels // max(n_nodes, 1)))
    return max(width, span / max(buckets - 1, 1)), buckets


@kernel
def label_search(cur: Float32Array, org: FloatArray, step: FloatArray, t0: float, dt: float, shape: IntArray,
                 offsets: IntArray, opposite: IntArray, edge_ok: BoolArray, start_ids: IntArray,
                 start_arr: FloatArray, goal_link: BoolArray, goal: FloatArray, speed: float, ds: float,
                 depart: float, width: float, multi: BoolArray, arrival: FloatArray,
                 pred: IntArray, tail: bool, mode: IntArray) -> tuple[float, np.int64]:
    """Label-setting search on arrival times with one label per node and time bucket (module notes).

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    org, step : numpy.ndarray
        First node and node spacing of the lattice ``(3,)`` (m).
    t0, dt : float
        First time and time step of the table (s).
    shape : numpy.ndarray
        Nodes along x, y, z ``(3,)``.
    offsets, opposite : numpy.ndarray
        Leg offsets ``(M, 3)`` and the slot of each one's reverse ``(M,)``.
    edge_ok : numpy.ndarray of bool
        ``(M, N)`` free legs.
    start_ids, start_arr : numpy.ndarray
        Nodes linked to the start and their arrival times (s).
    goal_link : numpy.ndarray of bool
        ``(N,)``, nodes with a free leg to the goal.
    goal : numpy.ndarray
        The goal ``(3,)`` (m).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest integration sub-step (m).
    depart : float
        Departure time, the start of bucket 0 (s).
    width : float
        Bucket width (s).
    multi : numpy.ndarray of bool
        ``(N,)``: nodes that keep a label per bucket (the others keep bucket 0 only).
    arrival : numpy.ndarray
        ``(N * B,)`` filled with ``inf``; receives each label's arrival (s).
    pred : numpy.ndarray
        ``(N * B,)``; receives each label's predecessor label (``-1``: linked to the start).
    tail : bool
        Also fly each leg from a strong node tail-first (:mod:`.tail`) where it can be.
    mode : numpy.ndarray
        ``(N * B,)``; receives 1 where a label's leg in is flown tail-first, else 0.

    Returns
    -------
    best : float
        Arrival at the goal (s); ``inf`` when unreachable.
    last : int
        The label the goal is reached from (``-1`` when unreachable).
    """
    ny, nz = shape[1], shape[2]
    nb = arrival.size // edge_ok.shape[1]
    heap = [(0.0, np.int64(0))]
    heap.pop()
    for k in range(start_ids.size):
        n = start_ids[k]
        b = min(int((start_arr[k] - depart) / width), nb - 1) if multi[n] else 0
        lab = n * nb + max(b, 0)
        if start_arr[k] < arrival[lab]:
            arrival[lab] = start_arr[k]
            pred[lab] = -1
            heapq.heappush(heap, (start_arr[k], np.int64(lab)))
    best, last = math.inf, np.int64(-1)
    done = np.zeros(arrival.size, dtype=np.bool_)
    while heap:
        t, lab = heapq.heappop(heap)
        if done[lab] or t > arrival[lab]:
            continue
        if t >= best:
            break
        done[lab] = True
        n = lab // nb
        iz = n % nz
        iy = (n // nz) % ny
        ix = n // (nz * ny)
        x, y, z = org[0] + ix * step[0], org[1] + iy * step[1], org[2] + iz * step[2]
        if goal_link[n]:
            tg = leg_time(cur, org, step, t0, dt, x, y, z, goal[0], goal[1], goal[2], t, speed, ds)
            if tg < best:
                best, last = tg, lab
        for m in range(offsets.shape[0]):
            if not edge_ok[m, n]:
                continue
            jx, jy, jz = ix + offsets[m, 0], iy + offsets[m, 1], iz + offsets[m, 2]
            q = (jx * ny + jy) * nz + jz
            if not multi[q] and done[q * nb]:  # (its only label is settled: no leg to time)
                continue
            qx, qy, qz = org[0] + jx * step[0], org[1] + jy * step[1], org[2] + jz * step[2]
            tq, back = leg_reach(cur, org, step, t0, dt, x, y, z, qx, qy, qz, t, speed, ds,
                                 math.sqrt((qx - x) ** 2 + (qy - y) ** 2 + (qz - z) ** 2))
            if back > 0.0 and not edge_ok[opposite[m], n]:
                tq = math.inf
            for k in range(2 if tail and multi[n] else 1):
                if k == 1:
                    tq = tail_leg(cur, org, step, t0, dt, x, y, z, qx, qy, qz, t, speed, ds)
                if not tq < math.inf:
                    continue
                b = min(int((tq - depart) / width), nb - 1) if multi[q] else 0
                lq = q * nb + b
                if not done[lq] and tq < arrival[lq]:
                    arrival[lq] = tq
                    pred[lq] = lab
                    mode[lq] = k
                    heapq.heappush(heap, (tq, np.int64(lq)))
    return best, last


def label_chain(pred: IntArray, last: int, buckets: int) -> tuple[IntArray, IntArray]:
    """The labels from the start to ``last`` and their nodes.

    Parameters
    ----------
    pred : numpy.ndarray
        Predecessor labels from :func:`label_search`.
    last : int
        The label the goal is reached from.
    buckets : int
        Buckets per node.

    Returns
    -------
    labels, nodes : numpy.ndarray
        In flying order (a node may appear more than once: the path may loop with the current).
    """
    chain = [int(last)]
    while pred[chain[-1]] >= 0:
        chain.append(int(pred[chain[-1]]))
    labels = np.array(chain[::-1], dtype=np.int64)
    return labels, labels // buckets


def single_search(args: tuple[Float32Array, FloatArray, FloatArray, float, float], shape: tuple[int, int, int],
                  offsets: IntArray, opposite: IntArray, edge_ok: BoolArray, start_ids: IntArray,
                  start_arr: FloatArray, goal_link: BoolArray, goal: FloatArray, speed: float,
                  ds: float) -> tuple[float, IntArray, FloatArray]:
    """Run the one-label search on a lattice and read its path back: :func:`label_search` with one
    bucket per node (no node keeps more than its earliest arrival).

    Parameters
    ----------
    args : tuple
        The table's kernel arguments ``(cur, origin, step, t0, dt)``.
    shape : tuple of int
        Nodes along x, y, z.
    offsets, opposite, edge_ok : numpy.ndarray
        The stencil, its reverses and the free legs ``(M, N)``.
    start_ids, start_arr : numpy.ndarray
        Nodes linked to the start and their arrival times (s).
    goal_link : numpy.ndarray of bool
        Nodes with a free leg to the goal.
    goal : numpy.ndarray
        The goal ``(3,)`` (m).
    speed, ds : float
        Through-water speed (m/s) and largest integration sub-step (m).

    Returns
    -------
    best : float
        Arrival at the goal (s; ``inf`` when unreachable).
    nodes : numpy.ndarray
        The path's nodes in flying order (empty when unreachable).
    times : numpy.ndarray
        The arrival at each of them (s).
    """
    n = int(np.prod(shape))
    arrival = np.full(n, np.inf)
    pred = np.full(n, -2, dtype=np.int64)
    best, last = label_search(*args, np.array(shape, dtype=np.int64), offsets, opposite, edge_ok,
                              start_ids.astype(np.int64), start_arr, goal_link, goal, float(speed), float(ds), 0.0,
                              math.inf, np.zeros(n, dtype=np.bool_), arrival, pred, False,
                              np.zeros(n, dtype=np.int64))
    if not np.isfinite(best):
        return math.inf, np.zeros(0, dtype=np.int64), np.zeros(0)
    labels, nodes = label_chain(pred, int(last), 1)
    return float(best), nodes, arrival[labels]


def multi_search(args: tuple[Float32Array, FloatArray, FloatArray, float, float], shape: tuple[int, int, int],
                 offsets: IntArray, opposite: IntArray, edge_ok: BoolArray, start_ids: IntArray,
                 start_arr: FloatArray, goal_link: BoolArray, goal: FloatArray, speed: float, ds: float,
                 depart: float, width: float, max_labels: int,
                 tail: bool = False) -> tuple[float, IntArray, FloatArray, IntArray]:
    """Run :func:`label_search` on a lattice: buckets sized, strong nodes found, path read back.

    Parameters
    ----------
    args : tuple
        The table's kernel arguments ``(cur, origin, step, t0, dt)``.
    shape : tuple of int
        Nodes along x, y, z.
    offsets, opposite, edge_ok : numpy.ndarray
        The stencil, its reverses and the free legs ``(M, N)``.
    start_ids, start_arr : numpy.ndarray
        Nodes linked to the start and their arrival times (s).
    goal_link : numpy.ndarray of bool
        Nodes with a free leg to the goal.
    goal : numpy.ndarray
        The goal ``(3,)`` (m).
    speed, ds : float
        Through-water speed (m/s) and largest integration sub-step (m).
    depart : float
        Departure time (s).
    width : float
        Wanted bucket width (s).
    max_labels : int
        Largest number of labels.
    tail : bool, default False
        Also fly legs tail-first (:mod:`.tail`).

    Returns
    -------
    best : float
        Arrival at the goal (s; ``inf`` when unreachable).
    nodes : numpy.ndarray
        The path's nodes in flying order (empty when unreachable).
    times : numpy.ndarray
        The arrival at each of them (s).
    modes : numpy.ndarray
        1 where the leg into each of them is flown tail-first, else 0.
    """
    cur, _, _, t0, dt = args
    t1 = t0 + dt * (cur.shape[0] - 1)
    n = int(np.prod(shape))
    reach = int(np.abs(offsets[:, :2]).max())
    multi = strong_nodes(cur, t0, dt, depart, t1, speed, reach)
    w, nb = label_width(n, max(t1 - depart, width), width, max_labels)
    arrival = np.full(n * nb, np.inf)
    pred = np.full(n * nb, -2, dtype=np.int64)
    mode = np.zeros(n * nb, dtype=np.int64)
    best, last = label_search(*args, np.array(shape, dtype=np.int64), offsets, opposite, edge_ok,
                              start_ids.astype(np.int64), start_arr, goal_link, goal, float(speed), float(ds),
                              float(depart), float(w), multi, arrival, pred, bool(tail), mode)
    if not np.isfinite(best):
        return math.inf, np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0, dtype=np.int64)
    labels, nodes = label_chain(pred, int(last), nb)
    return float(best), nodes, arrival[labels], mode[labels]
