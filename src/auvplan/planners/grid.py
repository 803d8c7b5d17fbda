"""Deterministic reference planner on a 3D lattice: the yardstick of every other planner.

1. A lattice over the search box (the World's bounds and depth band); a node is free
   when :meth:`World.is_free` holds there (static constraints only).
2. 26-connected edges between free nodes whose straight segment passes the World's
   exact segment test; each edge is weighted by the planner's own cost function
   (``w_L`` length + ``w_E`` energy in the current field, :func:`auvplan.cost.segment_energy`)
   in its own direction, or by length alone.
3. One Dijkstra search from the goal on the reversed graph gives the cost-to-go of every node;
   any start is then answered without searching again (:class:`GridReference`, "plan once,
   query many").  The search is compiled and generates the edges on the fly from one bit per
   direction and node (which edges are free) and the node currents, so the lattice needs a
   few words per node instead of 26 stored edges.
4. For the ``"length"`` objective the lattice path is shortened by document 004's
   key-waypoint rule (keep a waypoint only where the straight segment to the next would
   collide, exact test), pulled taut by an elastic band whose moves must lower the cost and
   keep both segments free, and shortened again.  For the ``"cost"`` objective the
   shortcuts would throw away detours that ride a current, so the lattice path goes straight
   to the elastic band (which removes the lattice's zig-zags only where that pays).  The band
   works coarse to fine (:func:`_refine`) and also tries sideways moves, so that it can
   shift whole stretches of path into a better current.  The
   straight segment, when free and cheaper, wins; a clamped cubic B-spline over the result
   is tried last and kept only when it is free and cheaper.

Statuses: ``EXACT``; ``INVALID_START`` / ``INVALID_GOAL`` for end points that are not free;
``INFEASIBLE`` with a message when no free lattice path joins them.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from typing import Any

import numpy as np
import numpy.typing as npt

from .._jit import kernel
from .._types import ArrayLike, BoolArray, FloatArray, IntArray, Status
from ..cost import CostModel, energy_kernel, evaluate_paths, propulsion_power, segment_energy
from ..guidance.local import key_waypoints
from ..path import polyline_length, resample_polyline, sample_population
from ..world import World
from .base import SWARM, GridParams, PlannerSpec, PlanningProblem, PlanResult
from .swarm_problem import check_endpoints, cost_model_for, plan_terms, search_box

__all__ = ["GridReference", "plan_grid", "auto_cell", "densify", "edge_cost", "free_edges", "on_cost_function",
           "path_cost", "with_reference"]

_HALF = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)
                  if (i, j, k) > (0, 0, 0)])
"""The 13 lattice offsets with a positive first non-zero component (the other 13 are their reverses)."""

_OFFSETS = np.concatenate([_HALF, -_HALF]).astype(np.int64)
"""The 26 lattice directions; bit ``s`` of a node's edge mask is the edge along ``_OFFSETS[s]``."""


@kernel
def _edge_weight(u: int, v: int, s: int, vec: FloatArray, current: FloatArray, use_cost: bool, w_length: float,
                 w_energy: float, speed: float, power: float, document: bool) -> float:
    """Cost of the lattice edge ``u -> v`` along direction ``s``: its length, or ``w_L`` length +
    ``w_E`` energy with the current at the midpoint taken as the mean of the two nodes'
    (:func:`auvplan.cost.segment_energy`'s model); ``inf`` where the current beats the vehicle."""
    ex, ey, ez = vec[s, 0], vec[s, 1], vec[s, 2]
    ds = math.sqrt(ex * ex + ey * ey + ez * ez)
    if not use_cost:
        return ds
    cx = 0.5 * (current[u, 0] + current[v, 0])
    cy = 0.5 * (current[u, 1] + current[v, 1])
    cz = 0.5 * (current[u, 2] + current[v, 2])
    units, _, _, blocked = energy_kernel(ex, ey, ez, ds, cx, cy, cz, speed, power, document)
    if blocked:
        return np.inf
    weight: float = max(w_length * ds + w_energy * units, 1e-12)
    return weight


@kernel
def _sift_up(heap: IntArray, pos: IntArray, key: FloatArray, i: int) -> None:
    node = heap[i]
    while i > 0:
        parent = (i - 1) >> 1
        if key[heap[parent]] <= key[node]:
            break
        heap[i] = heap[parent]
        pos[heap[i]] = i
        i = parent
    heap[i] = node
    pos[node] = i


@kernel
def _sift_down(heap: IntArray, pos: IntArray, key: FloatArray, i: int, size: int) -> None:
    node = heap[i]
    while True:
        c = 2 * i + 1
        if c >= size:
            break
        if c + 1 < size and key[heap[c + 1]] < key[heap[c]]:
            c += 1
        if key[heap[c]] >= key[node]:
            break
        heap[i] = heap[c]
        pos[heap[i]] = i
        i = c
    heap[i] = node
    pos[node] = i


@kernel
def _search(shape: IntArray, bits: npt.NDArray[np.uint32], offsets: IntArray, vec: FloatArray, current: FloatArray,
            use_cost: bool, w_length: float, w_energy: float, speed: float, power: float, document: bool,
            near: IntArray, w_goal: FloatArray, goal: int, dist: FloatArray, nxt: IntArray) -> None:
    """Dijkstra from the goal over the reversed lattice, edges generated on the fly.

    ``dist[u]`` becomes the cheapest cost from node ``u`` to the goal and ``nxt[u]`` the next
    node on that path (``goal`` for the nodes linked to it directly).  An indexed binary heap
    with decrease-key keeps the memory at a few words per node.
    """
    n = goal
    nx, ny, nz = shape[0], shape[1], shape[2]
    pos = np.full(n, -1, dtype=np.int64)  # -1 never queued, -2 settled
    heap = np.empty(n, dtype=np.int64)
    size = 0
    for k in range(near.size):
        u = near[k]
        if w_goal[k] < dist[u]:
            dist[u] = w_goal[k]
            nxt[u] = goal
            if pos[u] == -1:
                heap[size] = u
                pos[u] = size
                size += 1
            _sift_up(heap, pos, dist, pos[u])
    while size > 0:
        v = heap[0]
        pos[v] = -2
        size -= 1
        if size > 0:
            heap[0] = heap[size]
            pos[heap[0]] = 0
            _sift_down(heap, pos, dist, 0, size)
        k = v % nz
        j = (v // nz) % ny
        i = v // (nz * ny)
        for s in range(26):
            # the edge u -> v along direction s starts at u = v - offsets[s]
            ui, uj, uk = i - offsets[s, 0], j - offsets[s, 1], k - offsets[s, 2]
            if ui < 0 or ui >= nx or uj < 0 or uj >= ny or uk < 0 or uk >= nz:
                continue
            u = (ui * ny + uj) * nz + uk
            if pos[u] == -2 or not (bits[u] >> s) & 1:
                continue
            alt = dist[v] + _edge_weight(u, v, s, vec, current, use_cost, w_length, w_energy, speed, power,
                                         document)
            if alt < dist[u]:
                dist[u] = alt
                nxt[u] = v
                if pos[u] == -1:
                    heap[size] = u
                    pos[u] = size
                    size += 1
                _sift_up(heap, pos, dist, pos[u])


def auto_cell(world: World, lower: FloatArray, upper: FloatArray, params: GridParams) -> tuple[float, float]:
    """Horizontal and vertical cell sizes.

    ``params.cell`` / ``params.cell_z`` when given.  Otherwise cubes of
    ``(volume / target_nodes)^(1/3)``, the vertical cell shrunk where needed so that the depth
    band holds at least ``params.levels`` levels (the horizontal cell grows to keep the node
    count), and the horizontal cell never finer than the terrain grid.

    Parameters
    ----------
    world : World
        Its terrain spacing bounds the horizontal cell from below.
    lower, upper : numpy.ndarray
        Search box ``(3,)`` (m).
    params : GridParams
        Cell settings, node target and levels.

    Returns
    -------
    tuple of float
        ``(cell, cell_z)`` (m).
    """
    ext = np.maximum(upper - lower, 1e-9)
    cell = params.cell
    if cell <= 0:
        cell = float(np.cbrt(np.prod(ext) / params.target_nodes))
        if ext[2] / cell < params.levels:
            cell = float(np.sqrt(ext[0] * ext[1] * params.levels / params.target_nodes))
        if world.terrain is not None:
            t = world.terrain
            cell = max(cell, float(min(t.dx, t.dy)))
    cell_z = params.cell_z if params.cell_z > 0 else min(cell, float(ext[2]) / params.levels)
    if params.cell_z <= 0 and params.cell > 0:
        cell_z = min(params.cell, float(ext[2]) / params.levels)
    return cell, cell_z


def edge_cost(world: World, a: FloatArray, b: FloatArray, model: CostModel, objective: str,
              current: ArrayLike | None = None) -> FloatArray:
    """Cost of travelling straight segments.

    Parameters
    ----------
    world : World
        Source of the current field.
    a, b : numpy.ndarray
        Segment starts and ends ``(..., 3)`` (m).
    model : CostModel
        Weights and vehicle figures.
    objective : str
        ``"length"`` (the length in m) or ``"cost"`` (the cost function's ``w_L`` length + ``w_E`` energy).
    current : array_like, optional
        The current at the midpoints ``(..., 3)`` (m/s) when the caller has it.

    Returns
    -------
    numpy.ndarray
        ``(...)``; ``inf`` where the current beats the vehicle.
    """
    length: FloatArray = np.linalg.norm(b - a, axis=-1)
    if objective == "length":
        return length
    units, _, _, blocked = segment_energy(world, a, b, model, current)
    cost = model.w_length * length + model.w_energy * model.scale * units
    return np.where(blocked, np.inf, cost)


def densify(points: ArrayLike, spacing: float) -> FloatArray:
    """The polyline with extra points so that no segment exceeds ``spacing`` (every vertex kept).

    Parameters
    ----------
    points : array_like
        Vertices ``(N, 3)`` (m).
    spacing : float
        Longest segment allowed (m).

    Returns
    -------
    numpy.ndarray
        Vertices ``(M, 3)``, ``M >= N`` (m).
    """
    p = np.asarray(points, dtype=float)
    if p.shape[0] < 2:
        return p.copy()
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    n = np.maximum(np.ceil(seg / spacing).astype(int), 1)
    t = np.concatenate([np.arange(k) / k for k in n])
    i = np.repeat(np.arange(len(n)), n)
    out = p[i] + t[:, None] * (p[i + 1] - p[i])
    return np.vstack([out, p[-1]])


def free_edges(world: World, ids: npt.NDArray[np.integer[Any]], free: BoolArray, altitude: FloatArray,
               obstacle: FloatArray, xyz: FloatArray, steps: FloatArray,
               off: IntArray) -> tuple[npt.NDArray[np.integer[Any]], npt.NDArray[np.integer[Any]]]:
    """The free lattice edges ``src -> src + off`` between free nodes, as node ids ``(src, dst)``.

    One offset has one length and direction, so its edges are tested as 3D array slices: the
    seabed's Lipschitz bound and the obstacles' 1-Lipschitz distance clear most edges from the
    node values alone, and only the others go through the World's exact segment test.

    Parameters
    ----------
    world : World
        The world of the exact segment test (static constraints).
    ids : numpy.ndarray
        Node ids (int32 or int64) in the lattice's shape.
    free : numpy.ndarray of bool
        Free nodes, lattice shape.
    altitude : numpy.ndarray
        Node altitudes above the seabed (m), lattice shape.
    obstacle : numpy.ndarray
        Node distances to the static obstacles minus the margin (m), lattice shape.
    xyz : numpy.ndarray
        Node coordinates ``(N, 3)`` (m).
    steps : numpy.ndarray
        Node spacing along x, y, z ``(3,)`` (m).
    off : numpy.ndarray
        The offset in nodes ``(3,)``.

    Returns
    -------
    src, dst : numpy.ndarray
        Node ids of the free edges' ends.
    """
    shape = free.shape
    a = tuple(slice(max(0, -d), n - max(0, d)) for d, n in zip(off, shape))
    b = tuple(slice(max(0, d), n - max(0, -d)) for d, n in zip(off, shape))
    both = free[a] & free[b]
    src, dst = ids[a][both], ids[b][both]
    d = np.asarray(off) * steps
    length = float(np.linalg.norm(d))
    sure = np.minimum(obstacle[a][both], obstacle[b][both]) >= 0.5 * length
    if world.terrain is not None:
        lb = world.terrain.altitude_lower_bound(altitude[a][both], altitude[b][both], d[2], np.hypot(d[0], d[1]))
        sure &= lb >= world.margins.min_altitude
    unsure = np.flatnonzero(~sure)
    if unsure.size:
        seg = np.stack([xyz[src[unsure]], xyz[dst[unsure]]], axis=1)
        sure[unsure] = world.segments_free(seg, moving=False, ends_free=True)
    return src[sure], dst[sure]


class GridReference:
    """Cost-to-go field to one goal over a 3D lattice; answers :meth:`query` for any start.

    Parameters
    ----------
    world : World
        Environment (static constraints only).
    goal : array_like, shape (3,)
        Goal point (must be free).
    model : CostModel
        The cost function whose length and energy terms weigh the edges.
    lower, upper : ndarray, shape (3,)
        Search box.
    params : GridParams
        Cell sizes, node cap and objective.

    Attributes
    ----------
    axes : tuple of ndarray
        Node coordinates along x, y and z.
    free : ndarray of bool, shape (nx, ny, nz)
        Free nodes.
    cost_to_go : ndarray, shape (nx, ny, nz)
        Cost from each node to the goal (``inf`` where unreachable or not free).
    edges : int
        Directed edges in the graph.

    Raises
    ------
    ValueError
        If the lattice would exceed ``params.max_nodes``.
    """

    def __init__(self, world: World, goal: ArrayLike, model: CostModel, lower: ArrayLike, upper: ArrayLike,
                 params: GridParams) -> None:
        self.world, self.model, self.params = world, model, params
        self.goal = np.asarray(goal, dtype=float).reshape(3)
        lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
        cell, cell_z = auto_cell(world, lower, upper, params)
        steps = np.array([cell, cell, cell_z])
        n = np.floor((upper - lower) / steps + 1e-9).astype(int) + 1
        if np.prod(n) > params.max_nodes:
            raise ValueError(f"a lattice of {n.tolist()} nodes at {cell:g} m x {cell_z:g} m cells exceeds "
                             f"max_nodes = {params.max_nodes}; raise [planner.grid] cell")
        offset = lower + 0.5 * ((upper - lower) - (n - 1) * steps)
        self.cell, self.cell_z, self.shape = cell, cell_z, tuple(int(v) for v in n)
        self.axes: tuple[FloatArray, ...] = tuple(offset[d] + steps[d] * np.arange(n[d]) for d in range(3))
        xyz = np.stack(np.meshgrid(*self.axes, indexing="ij"), axis=-1).reshape(-1, 3)
        slack = world.clearances(xyz, moving=False)
        self.free = (np.minimum.reduce(list(slack.values())) >= 0.0).reshape(self.shape)
        current = world.currents.velocity(xyz) if params.objective == "cost" else np.zeros((0, 3))
        bits = self._lattice_edges(xyz, slack["altitude"] + world.margins.min_altitude, slack["obstacles"])
        del xyz, slack
        near, w_goal = self._connect(self.goal, towards=True)
        keep = np.isfinite(w_goal)
        near, w_goal = near[keep], np.maximum(w_goal[keep], 1e-12)
        self.edges = int(np.bitwise_count(bits).sum()) + int(near.size)
        self._goal_id = self.nodes
        self._dist, self._next = np.full(self.nodes + 1, np.inf), np.full(self.nodes + 1, -9999, dtype=np.int64)
        self._dist[self._goal_id] = 0.0
        steps = np.array([cell, cell, cell_z])
        _search(np.array(self.shape, dtype=np.int64), bits, _OFFSETS, _OFFSETS * steps, current,
                params.objective == "cost", model.w_length, model.w_energy * model.scale, model.speed,
                propulsion_power(model), model.energy == "document",
                near.astype(np.int64), w_goal, self._goal_id, self._dist, self._next)
        self.cost_to_go = self._dist[:self._goal_id].reshape(self.shape)

    # ------------------------------------------------------------------ lattice
    def _coords(self, ids: IntArray) -> FloatArray:
        i, j, k = np.unravel_index(np.asarray(ids), self.shape)
        return np.stack([self.axes[0][i], self.axes[1][j], self.axes[2][k]], axis=-1)

    def _lattice_edges(self, xyz: FloatArray, altitude: FloatArray, obstacle: FloatArray) -> npt.NDArray[np.uint32]:
        """Free edges as one bit per lattice direction and node (``uint32 (N,)``; bit ``s`` of
        node ``u`` set when the edge ``u -> u + _OFFSETS[s]`` is free).

        The edges of each offset come from :func:`free_edges`.  Costs are not stored: the search
        computes each edge's cost when it relaxes it, so memory grows with the nodes, not with
        26 × the nodes.
        """
        w = self.world
        itype: type[np.signedinteger[Any]] = np.int32 if self.nodes < 2**31 else np.int64
        ids = np.arange(self.nodes, dtype=itype).reshape(self.shape)
        steps = np.array([self.cell, self.cell, self.cell_z])
        alt = altitude.reshape(self.shape)
        obs = obstacle.reshape(self.shape)
        bits = np.zeros(self.nodes, dtype=np.uint32)
        for slot, off in enumerate(_HALF):
            src, dst = free_edges(w, ids, self.free, alt, obs, xyz, steps, off)
            bits[src] |= np.uint32(1 << slot)
            bits[dst] |= np.uint32(1 << (13 + slot))
        return bits

    def _connect(self, point: FloatArray, towards: bool) -> tuple[IntArray, FloatArray]:
        """Free nodes within two cells of ``point`` joined to it by a free segment, and the
        cost of that segment (node -> point when ``towards``, else point -> node)."""
        lo = [max(0, int(np.searchsorted(ax, point[d] - 2.01 * s))) for d, (ax, s) in
              enumerate(zip(self.axes, (self.cell, self.cell, self.cell_z)))]
        hi = [int(np.searchsorted(ax, point[d] + 2.01 * s)) for d, (ax, s) in
              enumerate(zip(self.axes, (self.cell, self.cell, self.cell_z)))]
        box = np.s_[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]]
        ids = np.arange(self.nodes).reshape(self.shape)[box][self.free[box]]
        q = self._coords(ids)
        p = np.broadcast_to(point, q.shape)
        ok = self.world.segments_free(np.stack([p, q], axis=1), moving=False)
        ids, q, p = ids[ok], q[ok], p[ok]
        w = edge_cost(self.world, q, p, self.model, self.params.objective) if towards else \
            edge_cost(self.world, p, q, self.model, self.params.objective)
        return ids, w

    # ------------------------------------------------------------------ queries
    @property
    def nodes(self) -> int:
        """Lattice nodes.

        Returns
        -------
        int
            ``nx * ny * nz``.
        """
        return int(np.prod(self.shape))

    def query(self, start: ArrayLike) -> FloatArray:
        """The cheapest lattice path from a start to the goal.

        Parameters
        ----------
        start : array_like
            Start point ``(3,)`` (m).

        Returns
        -------
        numpy.ndarray
            ``(N, 3)`` (m), start and goal included; the straight segment when only that is free,
            or an empty ``(0, 3)`` array when the goal cannot be reached.
        """
        start = np.asarray(start, dtype=float).reshape(3)
        ids, w = self._connect(start, towards=False)
        total = w + self._dist[ids] if ids.size else np.empty(0)
        best = int(np.argmin(total)) if total.size else -1
        if best < 0 or not np.isfinite(total[best]):
            straight = np.stack([start, self.goal])
            return straight if self.world.path_free(straight) else np.empty((0, 3))
        chain = [int(ids[best])]
        while chain[-1] != self._goal_id:
            chain.append(int(self._next[chain[-1]]))
        return np.vstack([start, self._coords(np.array(chain[:-1])), self.goal])


def _normals(p: FloatArray, i: IntArray) -> tuple[FloatArray, FloatArray]:
    """Two unit vectors perpendicular to the chord ``p[i+1] - p[i-1]`` and to each other."""
    t = p[i + 1] - p[i - 1]
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-12)
    ref = np.where(np.abs(t[:, 2:3]) < 0.9, np.array([[0.0, 0.0, 1.0]]), np.array([[1.0, 0.0, 0.0]]))
    n1 = np.cross(t, ref)
    n1 /= np.linalg.norm(n1, axis=1, keepdims=True)
    return n1, np.cross(t, n1)


def _relax(world: World, p: FloatArray, model: CostModel, objective: str, iterations: int,
           step: float) -> FloatArray:
    """Elastic band with pattern search: each interior point tries a pull towards its
    neighbours' midpoint and moves of ``±δ`` along two normals of the path, and takes the
    best move that lowers the cost of its two segments and keeps both free (odd and even
    points in turn, so that the moves are independent).  Failed points halve their steps."""
    p = p.copy()
    n = p.shape[0]
    if n < 3 or iterations == 0:
        return p
    alpha = np.full(n, 0.5)
    delta = np.full(n, 0.5 * step)
    tol = 1e-3 * step

    def cost(a: FloatArray, b: FloatArray) -> FloatArray:
        return edge_cost(world, a, b, model, objective)

    for _ in range(iterations):
        for parity in (1, 2):
            i = np.arange(parity, n - 1, 2)
            i = i[(alpha[i] > 1e-3) | (delta[i] > tol)]
            if i.size == 0:
                continue
            a, b, c = p[i - 1], p[i], p[i + 1]
            n1, n2 = _normals(p, i)
            d = delta[i, None]
            cand = np.stack([b + alpha[i, None] * (0.5 * (a + c) - b), b + d * n1, b - d * n1, b + d * n2, b - d * n2])
            old = cost(a, b) + cost(b, c)
            new = cost(a, cand) + cost(cand, c)
            seg = np.stack([np.stack(np.broadcast_arrays(a, cand), axis=-2),
                            np.stack(np.broadcast_arrays(cand, c), axis=-2)], axis=-3)
            better = new < old - 1e-9 * np.abs(old)
            better &= world.segments_free(seg, moving=False).all(axis=-1) | ~better
            new = np.where(better, new, np.inf)
            k = np.argmin(new, axis=0)
            ok = np.isfinite(new[k, np.arange(i.size)])
            p[i[ok]] = cand[k[ok], np.flatnonzero(ok)]
            pulled = ok & (k == 0)
            alpha[i[pulled]] = np.minimum(alpha[i[pulled]] * 1.5, 1.0)
            pushed = ok & (k > 0)
            delta[i[pushed]] = np.minimum(delta[i[pushed]] * 1.5, step)
            alpha[i[~pulled]] *= 0.5
            delta[i[~pushed]] *= 0.5
        if np.all(alpha[1:-1] <= 1e-3) and np.all(delta[1:-1] <= tol):
            break
    return p


def _refine(world: World, raw: FloatArray, model: CostModel, objective: str, cell: float,
            iterations: int) -> FloatArray:
    """Coarse-to-fine elastic band: the path is resampled every 16, 8, 4, 2, 1 and 1/2 cells
    (levels longer than a quarter of the path are skipped, as are resamplings that would cut
    into an obstacle) and relaxed at each level with steps of that spacing, so that whole
    stretches move together before the detail is settled."""
    path = raw
    total = float(polyline_length(raw))
    for level in (16.0, 8.0, 4.0, 2.0, 1.0, 0.5):
        spacing = level * cell
        if spacing > 0.25 * total and level > 0.5:
            continue
        coarse = resample_polyline(path, spacing)
        if not world.path_free(coarse):
            coarse = densify(path, spacing)
        path = _relax(world, coarse, model, objective, iterations, spacing)
    return path


def _converge(problem: PlanningProblem, spec: PlannerSpec, path: FloatArray, model: CostModel, cell: float,
              iterations: int, tol: float) -> tuple[FloatArray, float, int]:
    """Refine until the cost stops improving: resample the path at half the last spacing (or
    densify it, every vertex kept, where resampling would cut a corner into an obstacle), relax
    it with steps of that spacing (and, for the length objective, drop the vertices that hold
    nothing up), and keep it only when cheaper; stop when two levels in a row improve the cost
    by less than ``tol`` (relative) or the spacing falls below 1/2000 of the path.

    Returns the path, its cost and the number of levels run.
    """
    world, objective = problem.world, spec.grid.objective
    best, best_cost = path, path_cost(problem, spec, path)["total"]
    floor = float(polyline_length(path)) / 2000.0
    spacing, levels, small = 0.5 * cell, 0, 0
    while spacing >= floor and small < 2:
        levels += 1
        start = resample_polyline(best, spacing)  # even spacing lets points slide along the path
        if not world.path_free(start):
            start = densify(best, spacing)
        cand = _relax(world, start, model, objective, iterations, spacing)
        if objective == "length":
            cand = key_waypoints(cand, world)
        cost = path_cost(problem, spec, cand)["total"]
        gain = (best_cost - cost) / max(abs(best_cost), 1e-12)
        if cost < best_cost and world.path_free(cand):
            best, best_cost = cand, cost
        small = small + 1 if gain < tol else 0
        spacing *= 0.5
    return best, best_cost, levels


def path_cost(problem: PlanningProblem, spec: PlannerSpec, path: ArrayLike) -> dict[str, float]:
    """Cost terms of a polyline under the planner's cost function, as in :class:`PlanResult.cost_terms`.

    Segments no longer than 1/``spec.samples`` of the path, vertices kept.

    Parameters
    ----------
    problem : PlanningProblem
        World and vehicle figures.
    spec : PlannerSpec
        Cost settings and samples per path.
    path : array_like
        Vertices ``(N, 3)`` (m).

    Returns
    -------
    dict of str to float
        ``total`` and the terms of :func:`~auvplan.planners.swarm_problem.plan_terms`.
    """
    path = np.asarray(path, dtype=float)
    spacing = max(float(polyline_length(path)) / spec.samples, 1e-9)
    terms = evaluate_paths(problem.world, densify(path, spacing)[None], cost_model_for(problem, spec), exact=True)
    row = terms.row(0)
    return {"total": row["total"], **plan_terms(row, spec)}


def _failure(status: Status, message: str, t0: float) -> PlanResult:
    return PlanResult(status, np.empty((0, 3)), float("inf"), {}, 0, 0, time.perf_counter() - t0, np.empty(0),
                      "grid", None, message)


def plan_grid(problem: PlanningProblem, spec: PlannerSpec, reference: GridReference | None = None) -> PlanResult:
    """Plan on the lattice (see the module notes).

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        ``spec.grid`` settings and the cost function.
    reference : GridReference, optional
        A cost-to-go field built for the same goal, world and cost function, re-used.

    Returns
    -------
    PlanResult
        The plan; ``evaluations`` counts lattice edges (the work of the search), ``iterations`` is 1.
    """
    t0 = time.perf_counter()
    bad = check_endpoints(problem)
    if bad is not None:
        return _failure(bad[0], bad[1], t0)
    params = spec.grid
    model = cost_model_for(problem, spec)
    if reference is None:
        lower, upper = search_box(problem)
        try:
            reference = GridReference(problem.world, problem.goal, model, lower, upper, params)
        except ValueError as exc:
            return _failure(Status.INFEASIBLE, str(exc), t0)
    raw = reference.query(problem.start)
    if raw.shape[0] == 0:
        msg = (f"the goal cannot be reached from the start: no free path on the {reference.shape} lattice "
               f"at {reference.cell:g} m x {reference.cell_z:g} m cells ({int(reference.free.sum())} of "
               f"{reference.nodes} nodes free); the goal may be enclosed by the seabed or obstacles, "
               "or a smaller [planner.grid] cell may find a passage")
        return _failure(Status.INFEASIBLE, msg, t0)
    w = problem.world
    length_only = params.objective == "length"
    path = key_waypoints(raw, w) if length_only else raw
    path = _refine(w, path, model, params.objective, reference.cell, params.relax_iterations)
    if length_only:
        path = key_waypoints(path, w)
    levels = 0
    if params.converge:
        path, _, levels = _converge(problem, spec, path, model, reference.cell, params.relax_iterations,
                                    params.converge_tol)
    terms = path_cost(problem, spec, path)
    straight = np.stack([problem.start, problem.goal])
    if path.shape[0] > 2 and w.path_free(straight):
        sterms = path_cost(problem, spec, straight)
        if sterms["total"] <= terms["total"]:
            path, terms = straight, sterms
    ctrl = None
    if params.smooth and path.shape[0] >= 4:
        smooth = sample_population(path[None], spec.samples)[0]
        if w.path_free(smooth):
            sterms = path_cost(problem, spec, smooth)
            if sterms["total"] < terms["total"]:
                path, terms, ctrl = smooth, sterms, path
    total = terms.pop("total")
    free = w.path_free(path)
    status = Status.EXACT if free else Status.INFEASIBLE
    message = "" if free else "the shortened lattice path failed the exact segment test"
    if free:
        message = (f"reference: lattice {reference.shape} at {reference.cell:g} m x {reference.cell_z:g} m, "
                   + (f"refined to convergence ({levels} levels, tol {params.converge_tol:g})" if params.converge
                      else "elastic band only (lattice-bound reference)"))
    return PlanResult(
        status=status,
        path=path,
        cost=total,
        cost_terms=terms,
        evaluations=reference.edges,
        iterations=1,
        wall_time_s=time.perf_counter() - t0,
        history=np.array([total]),
        planner="grid",
        control_points=ctrl,
        message=message,
    )


def on_cost_function(result: PlanResult, problem: PlanningProblem, spec: PlannerSpec) -> PlanResult:
    """``result`` with its cost and cost terms on the planner's cost function of ``spec``.

    Swarm and lattice plans are costed on it already; a streamline (length only) or a timed plan
    is re-costed, so that tables and sweeps compare every planner like with like.

    Parameters
    ----------
    result : PlanResult
        Any planner's result.
    problem : PlanningProblem
        World and vehicle figures.
    spec : PlannerSpec
        The cost function's weights and sampling.

    Returns
    -------
    PlanResult
        ``result`` itself for swarm and lattice plans and empty paths, else a copy re-costed.
    """
    if result.planner in SWARM or result.planner == "grid" or result.path.shape[0] < 2:
        return result
    terms = path_cost(problem, spec, result.path)
    total = terms.pop("total")
    return replace(result, cost=float(total), cost_terms={**result.cost_terms, **terms})


def with_reference(result: PlanResult, problem: PlanningProblem, spec: PlannerSpec,
                   reference: PlanResult) -> PlanResult:
    """``result`` on the planner's cost function (:func:`on_cost_function`) with the reference's cost.

    Parameters
    ----------
    result : PlanResult
        Any planner's result.
    problem : PlanningProblem
        World and vehicle figures.
    spec : PlannerSpec
        The cost function.
    reference : PlanResult
        The grid reference plan.

    Returns
    -------
    PlanResult
        A copy with ``reference_cost`` set (``inf``/its cost as is when the reference failed).
    """
    if not reference.status.ok or result.path.shape[0] < 2:
        return replace(result, reference_cost=reference.cost)
    return replace(on_cost_function(result, problem, spec), reference_cost=float(reference.cost))
