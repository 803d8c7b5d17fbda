"""The lattice and its cost-to-go field to one goal (the grid planner's steps 1–3).

:func:`auto_cell` sizes the cells; :class:`GridReference` builds the lattice (free nodes, free edges,
node currents), searches it once from the goal (reversed Dijkstra / A*, optionally with any-angle links)
and answers the cheapest lattice path from any start.  Used by :mod:`auvplan.planners.grid.planner`
and :mod:`auvplan.planners.grid.ladder`.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...cost import CostModel, energy_mode, propulsion_power
from ...world import World
from ..core.params import GridParams
from .band import edge_cost
from .lattice import down32, edge_bits, node_fields, search

__all__ = ["GridReference", "auto_cell"]


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
    start : array_like, shape (3,), optional
        The one start that will be queried: the search becomes A* towards it and stops when its
        cheapest path is known (:func:`auvplan.planners.grid.lattice.search`).  Other starts are then
        answered by real but not necessarily cheapest lattice paths.
    keep : bool, default False
        Keep the node fields and the free-edge bits as :attr:`fields` (for another search of the
        same lattice; set it to None when done, they are most of the lattice's memory).
    fields : tuple, optional
        :attr:`fields` of a lattice of the same world, box, cells and objective: re-used instead of
        computed (only the search differs, e.g. its any-angle links).

    Attributes
    ----------
    axes : tuple of ndarray
        Node coordinates along x, y and z.
    free : ndarray of bool, shape (nx, ny, nz)
        Free nodes.
    cost_to_go : ndarray, shape (nx, ny, nz)
        Cost from each node to the goal (``inf`` where unreachable or not free; with ``start``,
        exact on the settled nodes and an upper bound on the others).
    edges : int
        Directed edges in the graph.
    settled : int
        Nodes the search settled.
    search_cpu_s : float
        CPU time of the search alone (the field over the built lattice), s.
    fields : tuple or None
        With ``keep``: free nodes, altitudes, obstacle clearances, currents and free-edge bits.
    """

    def __init__(self, world: World, goal: ArrayLike, model: CostModel, lower: ArrayLike, upper: ArrayLike,
                 params: GridParams, start: ArrayLike | None = None, keep: bool = False,
                 fields: tuple[Any, ...] | None = None) -> None:
        self.world, self.model, self.params = world, model, params
        self.goal = np.asarray(goal, dtype=float).reshape(3)
        lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
        cell, cell_z = auto_cell(world, lower, upper, params)
        steps = np.array([cell, cell, cell_z])
        n = np.floor((upper - lower) / steps + 1e-9).astype(int) + 1
        if np.prod(n) > params.max_nodes:
            raise ValueError(f"a lattice of {n.tolist()} nodes at {cell:g} m x {cell_z:g} m cells exceeds "
                             f"max_nodes = {params.max_nodes}; raise [planner.grid] cell")
        origin = lower + 0.5 * ((upper - lower) - (n - 1) * steps)
        self.cell, self.cell_z, self.shape = cell, cell_z, tuple(int(v) for v in n)
        self.axes = tuple(origin[d] + steps[d] * np.arange(n[d]) for d in range(3))
        use_cost = params.objective == "cost"
        if fields is None:
            self.free, alt, obs, current = node_fields(world, self.axes, use_cost)
            bits = edge_bits(world, self.free, alt, obs, steps, self._coords)
        else:  # another kind of link on the same lattice (the search reads them only)
            self.free, alt, obs, current, bits = fields
        self.fields = (self.free, alt, obs, current, bits) if keep else None
        links = self._links(alt, obs) if params.any_angle > 0 else None
        del alt, obs
        near, w_goal = self._connect(self.goal, towards=True)
        keep = np.isfinite(w_goal)
        near, w_goal = near[keep], np.maximum(w_goal[keep], 1e-12)
        self.edges = int(np.bitwise_count(bits).sum()) + int(near.size)
        self._goal_id = self.nodes
        cost = (model.w_length, model.w_energy * model.scale, model.speed, propulsion_power(model),
                energy_mode(model)) if use_cost else None
        start_near, c_min = None, 0.0
        if start is not None:
            start = np.asarray(start, dtype=float).reshape(3)
            ids, w = self._connect(start, towards=False)
            ids, w = ids[np.isfinite(w)], w[np.isfinite(w)]
            start_near, c_min = (ids, w), self._cost_per_metre(current)
            span = np.linalg.norm(self._coords(ids) - start, axis=1)  # the start's links obey the bound too
            if np.any(span > 0):
                c_min = min(c_min, float(np.min(w[span > 0] / span[span > 0])))
        t0 = time.process_time()
        self._dist, self._next, self.settled = search(self.shape, bits, steps, origin, current, cost, (near, w_goal),
                                                      start_near, start, c_min, links)
        self.search_cpu_s = time.process_time() - t0
        self.cost_to_go = self._dist[:self._goal_id].reshape(self.shape)

    def _links(self, alt: np.ndarray, obs: np.ndarray) -> tuple[int, np.ndarray, np.ndarray, np.ndarray, bool, bool,
                                                                 float, float, np.ndarray]:
        """The any-angle links' settings for :func:`~auvplan.planners.grid.lattice.search`: the node
        fields, the land's signed distance per column (rounded down) and the seabed's slope."""
        w = self.world
        land = np.zeros((1, 1), np.float32)
        if w.land is not None:
            columns = np.stack(np.meshgrid(self.axes[0], self.axes[1], indexing="ij"), axis=-1)
            land = down32(np.asarray(w.land.signed_distance(columns), dtype=float))
        slope = float(w.terrain.max_slope) if w.terrain is not None else 0.0
        return (int(self.params.any_angle), alt, obs, land, w.terrain is not None, w.land is not None, slope,
                float(w.margins.min_altitude), self.goal)

    def _cost_per_metre(self, current: np.ndarray) -> float:
        """A lower bound of any lattice edge's cost per metre (A*'s heuristic): 1 for the length;
        the length weight plus the energy at the ground speed of the still-water speed plus the
        strongest node current (an edge takes the mean of its two nodes' currents) for the
        physical energy model; the length weight alone for either document reading (which can be
        near zero)."""
        m = self.model
        if self.params.objective == "length":
            return 1.0
        if m.energy != "physical" or current.shape[0] == 0:
            return float(m.w_length)
        c2 = max((float(np.einsum("ij,ij->i", c, c).max()) for c in np.array_split(current, 16) if c.size),
                 default=0.0)
        vmax = m.speed + math.sqrt(c2)
        return float(m.w_length + m.w_energy * m.scale * propulsion_power(m) / vmax)

    # ------------------------------------------------------------------ lattice
    def _coords(self, ids: np.ndarray) -> np.ndarray:
        i, j, k = np.unravel_index(np.asarray(ids), self.shape)
        return np.stack([self.axes[0][i], self.axes[1][j], self.axes[2][k]], axis=-1)

    def _connect(self, point: np.ndarray, towards: bool) -> tuple[np.ndarray, np.ndarray]:
        """Free nodes within two cells of ``point`` joined to it by a free segment, and the
        cost of that segment (node -> point when ``towards``, else point -> node)."""
        lo = [max(0, int(np.searchsorted(ax, point[d] - 2.01 * s))) for d, (ax, s) in
              enumerate(zip(self.axes, (self.cell, self.cell, self.cell_z)))]
        hi = [int(np.searchsorted(ax, point[d] + 2.01 * s)) for d, (ax, s) in
              enumerate(zip(self.axes, (self.cell, self.cell, self.cell_z)))]
        box = np.s_[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]]
        ijk = np.nonzero(self.free[box])
        ids = np.ravel_multi_index(tuple(v + lo[d] for d, v in enumerate(ijk)), self.shape)
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
