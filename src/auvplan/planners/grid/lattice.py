"""The lean 3D lattice of the reference planner: node fields, free edges and the compiled search.

Memory grows with the nodes, not with the 26 edges of each node, and no array the size of the
lattice is held twice:

* **Node fields** (:func:`node_fields`) are evaluated one slab of x at a time: the World's
  constraints on the slab's points, the seabed and the land (horizontal fields) once per column.
  What the edge test needs is kept in single precision rounded towards the safe side (altitude and
  obstacle clearance rounded down), the current in single precision.
* **Free edges** (:func:`edge_bits`) are one bit per lattice direction and node.  One compiled
  pass per direction clears most edges from the node values alone (the seabed's Lipschitz bound,
  the obstacles' 1-Lipschitz distance); the few others go through the World's exact segment test.
* **The search** (:func:`search`) is Dijkstra from the goal over the reversed lattice with an
  indexed binary heap (``int32`` indices), edges and their costs generated on the fly.  Given a
  start it becomes A*: the heuristic ``c_min |x - start|`` with ``c_min`` the cheapest cost per
  metre any edge can have (length weight, plus the energy of travelling at the vehicle's speed
  plus the strongest current), which is consistent, so the first settled value of every node is
  its cost-to-go and the search stops as soon as no unsettled node can lead to a cheaper start.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from ..._types import ArrayLike, FloatArray, IntArray
from ...cost import energy_kernel
from ...runtime.jit import kernel
from ...world import World
from .anyangle import link_exact, link_guess
from .heap import pop as _pop
from .heap import push as _push
from .slopes import column_slopes

__all__ = ["HALF", "OFFSETS", "node_fields", "edge_bits", "edge_states", "lattice_slopes", "search", "down32"]

HALF = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)
                 if (i, j, k) > (0, 0, 0)], dtype=np.int64)
"""The 13 lattice offsets with a positive first non-zero component (the other 13 are their reverses)."""

OFFSETS = np.concatenate([HALF, -HALF]).astype(np.int64)
"""The 26 lattice directions; bit ``s`` of a node's edge mask is the edge along ``OFFSETS[s]``."""

_SLAB = 100_000
"""Points per slab of the node-field evaluation (bounds the temporaries to a few tens of MB)."""


def down32(a: FloatArray) -> Any:
    """``a`` in single precision, rounded down (never above the double value: a safe clearance).

    Parameters
    ----------
    a : ndarray
        Double-precision values.

    Returns
    -------
    ndarray of float32
        The largest single-precision values not above ``a``.
    """
    b = a.astype(np.float32)
    return np.where(b > a, np.nextafter(b, np.float32(-np.inf)), b)


def node_fields(world: World, axes: tuple[FloatArray, ...], currents: bool) -> tuple[Any, Any, Any, Any]:
    """Free nodes, altitudes, obstacle clearances and currents of the lattice ``axes``.

    Parameters
    ----------
    world : World
        Static constraints only are applied.
    axes : tuple of ndarray
        Node coordinates along x, y and z.
    currents : bool
        Evaluate the current at the nodes (else an empty ``(0, 3)`` array).

    Returns
    -------
    free : ndarray of bool, shape (nx, ny, nz)
        Where every static constraint of :meth:`World.clearances` holds.
    altitude : ndarray of float32, shape (nx, ny, nz)
        Height above the seabed (``inf`` without terrain), rounded down.
    obstacle : ndarray of float32, shape (nx, ny, nz)
        Static-obstacle slack (distance minus margin), rounded down.
    current : ndarray of float32, shape (N, 3) or (0, 3)
        Current at the nodes in flat C order (m/s).
    """
    ax, ay, az = (np.asarray(a, dtype=float) for a in axes)
    shape = (ax.size, ay.size, az.size)
    columns = np.stack(np.meshgrid(ax, ay, indexing="ij"), axis=-1)
    seabed = world.terrain.elevation(columns[..., 0], columns[..., 1]) if world.terrain is not None else None
    land = world.land.signed_distance(columns) if world.land is not None else None
    body = replace(world, terrain=None, land=None)  # the 3D constraints; seabed and land per column
    free = np.empty(shape, dtype=bool)
    alt = np.full(shape, np.inf, dtype=np.float32)
    obs = np.empty(shape, dtype=np.float32)
    cur = np.empty((int(np.prod(shape)) if currents else 0, 3), dtype=np.float32)
    step = max(1, _SLAB // (shape[1] * shape[2]))
    for i0 in range(0, shape[0], step):
        i1 = min(shape[0], i0 + step)
        pts = np.empty((i1 - i0, shape[1], shape[2], 3))
        pts[..., 0] = ax[i0:i1, None, None]
        pts[..., 1] = ay[None, :, None]
        pts[..., 2] = az[None, None, :]
        slack = body.clearances(pts, moving=False)
        least = np.minimum.reduce(list(slack.values()))
        if seabed is not None:
            height = pts[..., 2] - seabed[i0:i1, :, None]
            least = np.minimum(least, height - world.margins.min_altitude)
            alt[i0:i1] = down32(height)
        if land is not None:
            least = np.minimum(least, land[i0:i1, :, None])
        free[i0:i1] = least >= 0.0
        obs[i0:i1] = down32(np.minimum(slack["obstacles"], slack["zones"]))  # both lower-bound a distance
        if currents:
            n = shape[1] * shape[2]
            cur[i0 * n:i1 * n] = world.currents.velocity(pts).reshape(-1, 3)
    return free, alt, obs, cur


@kernel
def _offset_states(free: Any, alt: Any, obs: Any, off: IntArray, half_length: float, dz: float, lh: float,
                   slope: Any, min_alt: float, has_terrain: bool, state: Any) -> None:
    """``state[u]`` for the edge ``u -> u + off`` of each node (flat C order): 0 no edge (an end
    outside the lattice or not free), 1 free by the node values alone, 2 to be tested exactly;
    ``slope[i, j]`` bounds the seabed's slope round ``u``'s column (:mod:`.slopes`)."""
    nx, ny, nz = free.shape
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                u = (i * ny + j) * nz + k
                vi, vj, vk = i + off[0], j + off[1], k + off[2]
                if (vi < 0 or vi >= nx or vj < 0 or vj >= ny or vk < 0 or vk >= nz
                        or not free[i, j, k] or not free[vi, vj, vk]):
                    state[u] = 0
                    continue
                sure = min(obs[i, j, k], obs[vi, vj, vk]) >= half_length
                if sure and has_terrain:
                    ga, gb = alt[i, j, k], alt[vi, vj, vk]
                    lb = min(ga, gb, 0.5 * (ga + gb - abs(dz) - slope[i, j] * lh))
                    sure = lb >= min_alt
                state[u] = 1 if sure else 2


def edge_states(world: World, free: Any, altitude: Any, obstacle: Any, steps: ArrayLike, off: ArrayLike,
                coords: Callable[[Any], FloatArray], slope: Any = None) -> Any:
    """Which edges ``u -> u + off`` are free.

    Most edges are cleared by the node values in one compiled pass (the seabed's Lipschitz bound
    on the end altitudes, the obstacles' 1-Lipschitz distance); the rest go through
    :meth:`World.segments_free`.

    Parameters
    ----------
    world : World
        Static constraints.
    free : ndarray of bool, shape (nx, ny, nz)
        Free nodes.
    altitude, obstacle : ndarray, shape (nx, ny, nz)
        Node heights above the seabed and static-obstacle slack (:func:`node_fields`), never above
        the true values.
    steps : array_like, shape (3,)
        Cell sizes (m).
    off : array_like of int, shape (3,)
        The lattice offset of the edges.
    coords : callable
        ``coords(ids)`` gives the coordinates ``(n, 3)`` of flat node ids.
    slope : ndarray, shape (nx, ny), optional
        The seabed's local slope within one cell of each column (:func:`lattice_slopes`); computed
        when not given or when ``off`` reaches further along x or y.

    Returns
    -------
    ndarray of int8, shape (N,)
        Over the source nodes (flat C order): 1 where the edge is free, 0 where it is not (an end
        outside the lattice or not free, or the segment fails the exact test).
    """
    off = np.asarray(off, dtype=np.int64)
    d = off * np.asarray(steps, dtype=float)
    state = np.empty(free.size, dtype=np.int8)
    has_terrain = world.terrain is not None
    reach = max(1, int(abs(off[0])), int(abs(off[1])))
    if slope is None or reach > 1:  # a given slope field is for the one-cell rectangles of the 26 directions
        slope = lattice_slopes(world, free.shape, steps, coords, reach)
    args = (off, 0.5 * float(np.linalg.norm(d)), float(d[2]), float(np.hypot(d[0], d[1])), slope,
            world.margins.min_altitude, has_terrain)
    _offset_states(free, altitude, obstacle, *args, state)
    delta = int((off[0] * free.shape[1] + off[1]) * free.shape[2] + off[2])
    unsure = np.flatnonzero(state == 2)
    tests = [(world, unsure)]
    if world.zones and unsure.size:  # the zones first, one clip per column's trace; then the rest without them
        entered = _zone_entries(world, unsure, delta, free.shape[2], coords)
        state[unsure[entered]] = 0
        unsure = unsure[~entered]
        seabed_state = np.empty_like(state)
        _offset_states(free, altitude, np.full_like(obstacle, np.inf), *args, seabed_state)
        sure = seabed_state[unsure] == 1  # the seabed clears these: the static obstacles alone are left
        rest = replace(world, zones=None)
        tests = [(rest, unsure[~sure])]
        if world.obstacles:
            tests.append((replace(rest, terrain=None, land=None), unsure[sure]))
        else:
            state[unsure[sure]] = 1
    for w, ids in tests:
        for c0 in range(0, ids.size, 200_000):
            u = ids[c0:c0 + 200_000]
            seg = np.stack([coords(u), coords(u + delta)], axis=1)
            state[u] = w.segments_free(seg, moving=False, ends_free=True)
    return state


def _zone_entries(world: World, u: Any, delta: int, nz: int, coords: Callable[[Any], FloatArray]) -> Any:
    """Which edges ``u -> u + delta`` enter a zone (:meth:`Zones.traces_enter`): a node's x and y are its
    column's (``u // nz``), so the edges from one column share one horizontal trace."""
    assert world.zones is not None
    column = u // nz  # sorted, as u is
    new = np.r_[True, column[1:] != column[:-1]]
    rep = u[new]
    traces = np.stack([coords(rep)[:, :2], coords(rep + delta)[:, :2]], axis=1)
    level = coords(np.arange(nz))[:, 2]  # the levels of column 0: every column's
    return world.zones.traces_enter(traces, np.cumsum(new) - 1, level[u % nz], level[(u + delta) % nz])


def lattice_slopes(world: World, shape: tuple[int, ...], steps: ArrayLike,
                   coords: Callable[[Any], FloatArray], reach: int = 1) -> Any:
    """The seabed's steepest slope within one cell of each lattice column (:func:`.slopes.column_slopes`).

    Parameters
    ----------
    world : World
        Its terrain (none: zeros).
    shape : tuple of int
        Lattice shape ``(nx, ny, nz)``.
    steps : array_like, shape (3,)
        Cell sizes (m).
    coords : callable
        ``coords(ids)`` gives the coordinates ``(n, 3)`` of flat node ids.
    reach : int, default 1
        Half-width of each column's rectangle in cells (an edge reaching ``reach`` cells along x
        or y stays inside it).

    Returns
    -------
    ndarray of float64, shape (nx, ny)
        A Lipschitz constant of the seabed round each column (0 without terrain).
    """
    if world.terrain is None:
        return np.zeros(tuple(shape[:2]))
    nx, ny, nz = shape
    ax = coords(np.arange(nx, dtype=np.int64) * ny * nz)[:, 0]
    ay = coords(np.arange(ny, dtype=np.int64) * nz)[:, 1]
    st = np.asarray(steps, dtype=float)
    return column_slopes(world.terrain, ax, ay, reach * float(st[0]), reach * float(st[1]))


@kernel
def _set_bits(state: Any, delta: int, bits: Any, fwd: Any, rev: Any) -> None:
    for u in range(state.size):
        if state[u] == 1:
            bits[u] |= fwd
            bits[u + delta] |= rev


def edge_bits(world: World, free: Any, altitude: Any, obstacle: Any, steps: ArrayLike,
              coords: Callable[[Any], FloatArray]) -> Any:
    """Free edges as one bit per lattice direction and node, from :func:`edge_states`.

    Parameters
    ----------
    world : World
        Static constraints.
    free : ndarray of bool, shape (nx, ny, nz)
        Free nodes.
    altitude, obstacle : ndarray, shape (nx, ny, nz)
        Node heights above the seabed and static-obstacle slack (:func:`node_fields`).
    steps : array_like, shape (3,)
        Cell sizes (m).
    coords : callable
        ``coords(ids)`` gives the coordinates ``(n, 3)`` of flat node ids.

    Returns
    -------
    ndarray of uint32, shape (N,)
        Bit ``s`` of node ``u`` is set when the edge ``u -> u + OFFSETS[s]`` is free.
    """
    shape = free.shape
    bits = np.zeros(free.size, dtype=np.uint32)
    slope = lattice_slopes(world, shape, steps, coords)
    for slot, off in enumerate(HALF):
        state = edge_states(world, free, altitude, obstacle, steps, off, coords, slope)
        delta = int((off[0] * shape[1] + off[1]) * shape[2] + off[2])
        _set_bits(state, delta, bits, np.uint32(1 << slot), np.uint32(1 << (13 + slot)))
    return bits


@kernel
def _edge_weight(u: int, v: int, s: int, vec: FloatArray, current: Any, use_cost: bool, w_length: float,
                 w_energy: float, speed: float, power: float, document: int) -> float:
    """Cost of the lattice edge ``u -> v`` along direction ``s``: its length, or ``w_L`` length +
    ``w_E`` energy with the current at the midpoint taken as the mean of the two nodes'
    (:func:`auvplan.cost.segment_energy`'s model); ``inf`` where the current beats the vehicle."""
    ex, ey, ez = vec[s, 0], vec[s, 1], vec[s, 2]
    ds = math.sqrt(ex * ex + ey * ey + ez * ez)
    if not use_cost:
        return ds
    # np.float64, not float(): numba's float() keeps a float32 scalar in single precision (the mean was
    # then rounded to float32, ~1e-5 relative error in the cost of an edge the current nearly blocks)
    cx = 0.5 * (np.float64(current[u, 0]) + np.float64(current[v, 0]))
    cy = 0.5 * (np.float64(current[u, 1]) + np.float64(current[v, 1]))
    cz = 0.5 * (np.float64(current[u, 2]) + np.float64(current[v, 2]))
    units, _, _, blocked = energy_kernel(ex, ey, ez, ds, cx, cy, cz, speed, power, document)
    if blocked:
        return np.inf
    return max(w_length * ds + w_energy * units, 1e-12)


@kernel
def _heuristic(u: int, ny: int, nz: int, origin: FloatArray, steps: FloatArray, start: FloatArray,
               c_min: float) -> float:
    if c_min <= 0.0:
        return 0.0
    k = u % nz
    j = (u // nz) % ny
    i = u // (nz * ny)
    dx = origin[0] + i * steps[0] - start[0]
    dy = origin[1] + j * steps[1] - start[1]
    dz = origin[2] + k * steps[2] - start[2]
    return c_min * math.sqrt(dx * dx + dy * dy + dz * dz)


@kernel
def _settle_link(v: int, shape: IntArray, bits: Any, offsets: IntArray, vec: FloatArray, current: Any,
                 use_cost: bool, w_length: float, w_energy: float, speed: float, power: float, document: int,
                 dist: FloatArray, nxt: Any, pos: Any, steps: FloatArray, alt: Any, obs: Any, land: Any,
                 flags: Any, lipschitz: float, min_alt: float, goal: int, gf: FloatArray, pf: FloatArray) -> None:
    """Lazy Theta*'s check of a node being settled: its tentative straight link, or the cheapest
    lattice edge to a settled neighbour (:mod:`auvplan.planners.grid.anyangle`)."""
    nx, ny, nz = shape[0], shape[1], shape[2]
    p = nxt[v]
    vk, vj, vi = v % nz, (v // nz) % ny, v // (nz * ny)
    pk, pj, pi = p % nz, (p // nz) % ny, p // (nz * ny)
    if p == goal:
        pf[0], pf[1], pf[2] = gf[0], gf[1], gf[2]
    else:
        pf[0], pf[1], pf[2] = pi, pj, pk
    if p != goal and max(abs(pi - vi), abs(pj - vj), abs(pk - vk)) <= 1:
        for s in range(26):  # a lattice neighbour: the link is the lattice edge, if free
            if vi + offsets[s, 0] == pi and vj + offsets[s, 1] == pj and vk + offsets[s, 2] == pk:
                if (bits[v] >> s) & 1:
                    dist[v] = dist[p] + _edge_weight(v, p, s, vec, current, use_cost, w_length, w_energy, speed,
                                                     power, document)
                    return
    guess = dist[v]
    best = dist[p] + link_exact(v, pf, ny, nz, steps, alt, obs, land, flags[0], flags[1], lipschitz, min_alt,
                                current, use_cost, w_length, w_energy, speed, power, document)
    to = p
    if not best <= guess * (1.0 + 1e-12):
        for s in range(26):
            wi, wj, wk = vi + offsets[s, 0], vj + offsets[s, 1], vk + offsets[s, 2]
            if wi < 0 or wi >= nx or wj < 0 or wj >= ny or wk < 0 or wk >= nz or not (bits[v] >> s) & 1:
                continue
            w = (wi * ny + wj) * nz + wk
            if pos[w] != -2:
                continue
            cand = dist[w] + _edge_weight(v, w, s, vec, current, use_cost, w_length, w_energy, speed, power, document)
            if cand < best:
                best, to = cand, w
    dist[v] = best
    nxt[v] = to


@kernel
def _search(shape: IntArray, bits: Any, offsets: IntArray, vec: FloatArray, current: Any, use_cost: bool,
            w_length: float, w_energy: float, speed: float, power: float, document: int, near: IntArray,
            w_goal: FloatArray, goal: int, dist: FloatArray, nxt: Any, hkey: FloatArray, origin: FloatArray,
            steps: FloatArray, start: FloatArray, c_min: float, start_near: IntArray, w_start: FloatArray,
            box: IntArray, heap: Any, pos: Any, link: int, alt: Any, obs: Any, land: Any, flags: Any,
            lipschitz: float, min_alt: float, gf: FloatArray) -> int:
    """Dijkstra (``c_min = 0``) or A* towards ``start`` from the goal over the reversed lattice,
    with any-angle links of up to ``link`` cells (0: the 26 directions only); see :func:`search`.
    Returns the nodes settled."""
    ny, nz = shape[1], shape[2]
    pf = np.empty(3)  # the far end of a link, in cells
    delta = np.empty(26, dtype=np.int64)  # each direction's step in flat node ids
    lens = np.empty(26)  # each direction's edge length
    for s in range(26):
        delta[s] = (offsets[s, 0] * ny + offsets[s, 1]) * nz + offsets[s, 2]
        lens[s] = math.sqrt(vec[s, 0] * vec[s, 0] + vec[s, 1] * vec[s, 1] + vec[s, 2] * vec[s, 2])
    size = 0
    for k in range(near.size):
        u = near[k]
        if w_goal[k] < dist[u]:
            dist[u] = w_goal[k]
            nxt[u] = goal
            size = _push(heap, hkey, pos, size, u, dist[u] + _heuristic(u, ny, nz, origin, steps, start, c_min))
    best = np.inf
    settled = 0
    while size > 0:
        v = heap[0]
        if hkey[0] >= best:
            break  # A*: no unsettled node leads to a cheaper start
        size = _pop(heap, hkey, pos, size, -2)
        settled += 1
        if link > 0 and (nxt[v] != goal or max(abs(v // (nz * ny) - gf[0]), abs((v // nz) % ny - gf[1]),
                                               abs(v % nz - gf[2])) > 2.01):  # a goal link of its own is exact
            _settle_link(v, shape, bits, offsets, vec, current, use_cost, w_length, w_energy, speed, power, document,
                         dist, nxt, pos, steps, alt, obs, land, flags, lipschitz, min_alt, goal, gf, pf)
        k = v % nz
        j = (v // nz) % ny
        i = v // (nz * ny)
        if c_min > 0.0 and box[0] <= i <= box[1] and box[2] <= j <= box[3] and box[4] <= k <= box[5]:
            for m in range(start_near.size):
                if start_near[m] == v:
                    best = min(best, dist[v] + w_start[m])
        mask = bits[v]
        for s in range(26):
            # the edge u -> v along direction s starts at u = v - offsets[s]; it is free when v's edge back
            # along the reverse direction is (one edge, both bits set): no bounds test, no load of bits[u]
            if not (mask >> (s + 13 if s < 13 else s - 13)) & 1:
                continue
            u = v - delta[s]
            if pos[u] == -2:
                continue
            if use_cost:
                via = dist[v] + _edge_weight(u, v, s, vec, current, use_cost, w_length, w_energy, speed, power,
                                             document)
            else:
                via = dist[v] + lens[s]  # the length objective: the edge's length, computed once per direction
            to = v
            if link > 0:  # Theta*: straight on to v's next node (or the goal), checked when u is settled
                p = nxt[v]
                ui, uj, uk = i - offsets[s, 0], j - offsets[s, 1], k - offsets[s, 2]
                if p == goal:
                    pf[0], pf[1], pf[2] = gf[0], gf[1], gf[2]
                else:
                    pf[0], pf[1], pf[2] = p // (nz * ny), (p // nz) % ny, p % nz
                reach = max(abs(pf[0] - ui), abs(pf[1] - uj), abs(pf[2] - uk))
                if reach <= link and (p != goal or reach > 2.01):  # within two cells the goal links are exact
                    guess = dist[p] + link_guess(u, p if p != goal else -1, pf, ny, nz, steps, current, use_cost,
                                                 w_length, w_energy, speed, power, document)
                    if guess < via:
                        via, to = guess, p
            if via < dist[u]:
                dist[u] = via
                nxt[u] = to
                size = _push(heap, hkey, pos, size, u, via + _heuristic(u, ny, nz, origin, steps, start, c_min))
    return settled


def search(shape: tuple[int, ...], bits: Any, steps: ArrayLike, origin: ArrayLike, current: Any,
           cost: tuple[float, float, float, float, int] | None, goal_near: tuple[Any, Any],
           start_near: tuple[Any, Any] | None = None, start: ArrayLike | None = None,
           c_min: float = 0.0, links: tuple[int, Any, Any, Any, bool, bool, float, float, Any] | None = None
           ) -> tuple[FloatArray, Any, int]:
    """Cost-to-go from every node to the goal over the lattice (reversed Dijkstra), or A* for one start.

    Parameters
    ----------
    shape : tuple of int
        Lattice shape ``(nx, ny, nz)``.
    bits : ndarray of uint32, shape (N,)
        Free edges (:func:`edge_bits`), undirected: the edge ``u -> v`` is read from ``v``'s bit of the
        reverse direction, so both bits of an edge must be set or neither (as :func:`edge_bits` does).
    steps, origin : ndarray, shape (3,)
        Cell sizes and the first node's coordinates.
    current : ndarray, shape (N, 3) or (0, 3)
        Node currents (used with a cost objective).
    cost : tuple or None
        ``(w_length, w_energy, speed, power, document)`` of the cost function; ``None``: length.
    goal_near : tuple of ndarray
        Nodes joined to the goal and the cost of their segment to it.
    start_near : tuple of ndarray, optional
        Nodes joined to the start and the cost of the segment from it; with ``start`` and
        ``c_min > 0`` the search is A* and stops once the start's best link is settled.
    start : ndarray, shape (3,), optional
        The start point (A*'s target).
    c_min : float
        Lower bound of any edge's cost per metre (0: plain Dijkstra over the whole lattice).
    links : tuple, optional
        Any-angle links (:mod:`~auvplan.planners.grid.anyangle`): ``(link, altitude, obstacle,
        land, has_terrain, has_land, lipschitz, min_altitude, goal)`` with ``link`` the longest link
        in cells, the node fields of :func:`node_fields`, the land's signed distance per column and
        the goal point (links to it are tried beyond the two cells of its own links);
        ``None``: the 26 lattice directions only.

    Returns
    -------
    dist : ndarray, shape (N + 1,)
        Cost-to-go (the goal is node ``N``): exact on settled nodes, an upper bound reached by a
        real path on the other reached nodes, ``inf`` on the unreached.
    nxt : ndarray of int32, shape (N + 1,)
        Next node towards the goal.
    settled : int
        Nodes settled.
    """
    n = int(np.prod(shape))
    dist = np.full(n + 1, np.inf)
    nxt = np.full(n + 1, -1, dtype=np.int32)
    dist[n] = 0.0
    astar = start is not None and start_near is not None and c_min > 0.0
    vec = OFFSETS * np.asarray(steps, dtype=float)
    sn, ws = start_near if astar and start_near is not None else (np.zeros(0, np.int64), np.zeros(0))
    box = np.zeros(6, dtype=np.int64)
    if astar and sn.size:
        ijk = np.stack(np.unravel_index(sn, shape))
        box = np.stack([ijk.min(axis=1), ijk.max(axis=1)], axis=1).reshape(-1)
    w = cost if cost is not None else (1.0, 0.0, 1.0, 0.0, False)
    empty3, empty2 = np.zeros((1, 1, 1), np.float32), np.zeros((1, 1), np.float32)
    link, l_alt, l_obs, l_land, has_t, has_l, lip, min_alt, goal_point = links if links is not None else \
        (0, empty3, empty3, empty2, False, False, 0.0, 0.0, np.zeros(3))
    gf = (np.asarray(goal_point, dtype=float) - np.asarray(origin, dtype=float)) / np.asarray(steps, dtype=float)
    settled = _search(np.array(shape, dtype=np.int64), bits, OFFSETS, vec, current, cost is not None, float(w[0]),
                      float(w[1]), float(w[2]), float(w[3]), int(w[4]), np.asarray(goal_near[0], dtype=np.int64),
                      np.asarray(goal_near[1], dtype=float), n, dist, nxt, np.empty(n), np.asarray(origin, dtype=float),
                      np.asarray(steps, dtype=float), np.zeros(3) if start is None else np.asarray(start, float),
                      float(c_min) if astar else 0.0, np.asarray(sn, dtype=np.int64),
                      np.asarray(ws, dtype=float), box, np.empty(n, dtype=np.int32),
                      np.full(n, -1, dtype=np.int32),  # heap; pos: -1 never queued, -2 settled
                      int(link), l_alt, l_obs, l_land, np.array([has_t, has_l]), float(lip), float(min_alt),
                      gf)
    return dist, nxt, int(settled)


def free_edges(world: World, free: Any, altitude: Any, obstacle: Any, steps: ArrayLike, off: ArrayLike,
               coords: Callable[[Any], FloatArray]) -> tuple[IntArray, IntArray]:
    """The free lattice edges ``src -> src + off`` between free nodes.

    The seabed's Lipschitz bound (``altitude``: node altitudes above the seabed) and the
    obstacles' 1-Lipschitz distance (``obstacle``: slack beyond the margin) clear most edges from
    the node values alone in one compiled pass; only the others go through the World's exact
    segment test (:func:`auvplan.planners.grid.lattice.edge_states`).

    Parameters
    ----------
    world : World
        Static constraints.
    free : numpy.ndarray
        Free nodes, the lattice's shape ``(nx, ny, nz)``.
    altitude, obstacle : numpy.ndarray
        Node heights above the seabed and static-obstacle slack (m), the lattice's shape.
    steps : array_like
        Cell sizes ``(3,)`` (m).
    off : array_like
        The lattice offset ``(3,)`` of the edges.
    coords : callable
        ``coords(ids)`` gives the coordinates ``(n, 3)`` of flat node ids.

    Returns
    -------
    tuple of numpy.ndarray
        Flat node ids ``(src, dst)`` of the free edges.
    """
    off = np.asarray(off, dtype=np.int64)
    src = np.flatnonzero(edge_states(world, free, altitude, obstacle, steps, off, coords))
    return src, src + int((off[0] * free.shape[1] + off[1]) * free.shape[2] + off[2])
