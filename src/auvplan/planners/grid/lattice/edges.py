"""The lattice's free edges: the compiled node-value test, the exact fallback, one bit per direction and node.

One compiled pass per direction clears most edges from the node values alone (the seabed's Lipschitz
bound, the obstacles' 1-Lipschitz distance); the few others go through the World's exact segment test
(:mod:`auvplan.planners.grid.lattice`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from ...._types import ArrayLike, FloatArray, IntArray
from ....runtime.jit import kernel
from ....world import World
from ..slopes import column_slopes
from .nodes import HALF

__all__ = ["edge_states", "lattice_slopes", "edge_bits", "free_edges"]


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
        tests = _zones_first(world, unsure, delta, coords, free, altitude, obstacle, args, state)
    for w, ids in tests:
        for c0 in range(0, ids.size, 200_000):
            u = ids[c0:c0 + 200_000]
            seg = np.stack([coords(u), coords(u + delta)], axis=1)
            state[u] = w.segments_free(seg, moving=False, ends_free=True)
    return state


def _zones_first(world: World, unsure: Any, delta: int, coords: Callable[[Any], FloatArray], free: Any,
                 altitude: Any, obstacle: Any, args: tuple[IntArray, float, float, float, Any, float, bool],
                 state: Any) -> list[tuple[World, Any]]:
    """The unsure edges that enter a zone set to 0 (one clip per column's trace), those the seabed alone clears set
    to 1 without obstacles; the exact tests left: each world (without its zones, or its obstacles alone) and its
    edges."""
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
    return tests


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
