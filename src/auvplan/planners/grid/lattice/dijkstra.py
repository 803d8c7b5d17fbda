"""The lattice search: edge weights, the A* heuristic and the compiled reversed Dijkstra / A* with links.

Dijkstra from the goal over the reversed lattice with an indexed binary heap (``int32`` indices), edges and
their costs generated on the fly; given a start, A* (:mod:`auvplan.planners.grid.lattice`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from ...._types import ArrayLike, FloatArray, IntArray
from ....cost import energy_kernel
from ....runtime.jit import kernel
from ..anyangle import link_exact, link_guess
from ..heap import pop as _pop
from ..heap import push as _push
from .nodes import OFFSETS

__all__ = ["search"]


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
    dist, nxt = _goal_rooted(n)
    astar = start is not None and start_near is not None and c_min > 0.0
    vec = OFFSETS * np.asarray(steps, dtype=float)
    sn, ws, box = _astar_target(shape, start_near if astar else None)
    w = cost if cost is not None else (1.0, 0.0, 1.0, 0.0, False)
    link, l_alt, l_obs, l_land, has_t, has_l, lip, min_alt, gf = _link_fields(links, origin, steps)
    settled = _search(np.array(shape, dtype=np.int64), bits, OFFSETS, vec, current, cost is not None, float(w[0]),
                      float(w[1]), float(w[2]), float(w[3]), int(w[4]), np.asarray(goal_near[0], dtype=np.int64),
                      np.asarray(goal_near[1], dtype=float), n, dist, nxt, np.empty(n), np.asarray(origin, dtype=float),
                      np.asarray(steps, dtype=float), np.zeros(3) if start is None else np.asarray(start, float),
                      float(c_min) if astar else 0.0, np.asarray(sn, dtype=np.int64), np.asarray(ws, dtype=float), box,
                      np.empty(n, dtype=np.int32), np.full(n, -1, dtype=np.int32),  # heap; pos: -1 unqueued, -2 settled
                      int(link), l_alt, l_obs, l_land, np.array([has_t, has_l]), float(lip), float(min_alt), gf)
    return dist, nxt, int(settled)


def _goal_rooted(n: int) -> tuple[FloatArray, npt.NDArray[np.int32]]:
    """The cost-to-go and next node of ``n`` nodes and the goal (node ``n``): only the goal reached, at 0."""
    dist: FloatArray = np.full(n + 1, np.inf)
    nxt = np.full(n + 1, -1, dtype=np.int32)
    dist[n] = 0.0
    return dist, nxt


def _astar_target(shape: tuple[int, ...], start_near: tuple[Any, Any] | None) -> tuple[Any, Any, IntArray]:
    """A*'s target: the nodes joined to the start, their segments' costs and the box of their indices (none,
    and a zero box, for plain Dijkstra)."""
    sn, ws = start_near if start_near is not None else (np.zeros(0, np.int64), np.zeros(0))
    box = np.zeros(6, dtype=np.int64)
    if start_near is not None and sn.size:
        ijk = np.stack(np.unravel_index(sn, shape))
        box = np.stack([ijk.min(axis=1), ijk.max(axis=1)], axis=1).reshape(-1)
    return sn, ws, box


def _link_fields(links: tuple[int, Any, Any, Any, bool, bool, float, float, Any] | None, origin: ArrayLike,
                 steps: ArrayLike) -> tuple[int, Any, Any, Any, bool, bool, float, float, FloatArray]:
    """The any-angle links' fields as the kernel takes them (placeholders without links), the goal in cells."""
    empty3, empty2 = np.zeros((1, 1, 1), np.float32), np.zeros((1, 1), np.float32)
    link, l_alt, l_obs, l_land, has_t, has_l, lip, min_alt, goal_point = links if links is not None else \
        (0, empty3, empty3, empty2, False, False, 0.0, 0.0, np.zeros(3))
    gf = (np.asarray(goal_point, dtype=float) - np.asarray(origin, dtype=float)) / np.asarray(steps, dtype=float)
    return link, l_alt, l_obs, l_land, has_t, has_l, lip, min_alt, gf
