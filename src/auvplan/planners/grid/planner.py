"""Deterministic reference planner on a 3D lattice: the yardstick of every other planner.

1. A lattice over the search box (the World's bounds and depth band); a node is free
   when :meth:`World.is_free` holds there (static constraints only).
2. 26-connected edges between free nodes whose straight segment passes the World's
   exact segment test; each edge is weighted by the planner's own cost function
   (``w_L`` length + ``w_E`` energy in the current field, :func:`auvplan.cost.segment_energy`)
   in its own direction, or by length alone.
3. One Dijkstra search from the goal on the reversed graph gives the cost-to-go of every node
   (with ``[planner.grid] any_angle``, lazy Theta*'s straight links past the 26 directions,
   :mod:`auvplan.planners.grid.anyangle`);
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

import numpy as np

from ..._types import ArrayLike, FloatArray, Status
from ...cost import CostModel, energy_mode, propulsion_power
from ...guidance.local import key_waypoints
from ...path import sample_population
from ...world import World
from ..base import SWARM, PlannerSpec, PlanningProblem, PlanResult
from ..common import check_endpoints, cost_model_for, search_box
from ..params import GridParams
from .band import _converge, _refine, edge_cost, path_cost, resample_free
from .lattice import down32, edge_bits, node_fields, search

__all__ = ["GridReference", "plan_grid", "refine_plan", "auto_cell", "edge_cost", "on_cost_function",
           "path_cost", "resample_free", "with_reference"]

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
    """

    def __init__(self, world: World, goal: ArrayLike, model: CostModel, lower: ArrayLike, upper: ArrayLike,
                 params: GridParams, start: ArrayLike | None = None) -> None:
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
        self.free, alt, obs, current = node_fields(world, self.axes, use_cost)
        bits = edge_bits(world, self.free, alt, obs, steps, self._coords)
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


def _failure(status: Status, message: str, t0: float) -> PlanResult:
    return PlanResult(status, np.empty((0, 3)), float("inf"), {}, 0, 0, time.perf_counter() - t0, np.empty(0),
                      "grid", None, message)


def plan_grid(problem: PlanningProblem, spec: PlannerSpec, reference: GridReference | None = None) -> PlanResult:
    """Plan on the lattice (see the module notes); ``reference`` re-uses a cost-to-go field
    built for the same goal, world and cost function.

    With ``converge`` and ``ladder`` (the defaults) the lattices 2, 4, … times coarser, up to
    the first at least 1/25 of the search box's narrower side, are planned and refined the same
    way and the cheapest plan wins: the candidates of a cell include those of the cell twice as
    coarse, so halving the cell never gives a worse reference.  The ladder also runs when the finest
    lattice finds no path or is refused over ``max_nodes`` (a coarser one may find one); when none
    does, the finest lattice's failure is returned with the cells tried named.

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        The cost function and ``spec.grid``'s lattice and refinement settings.
    reference : GridReference, optional
        A cost-to-go field to re-use for the finest lattice.

    Returns
    -------
    PlanResult
        ``evaluations`` counts lattice edges (the work of the searches); ``iterations`` is 1; the
        message says what the reference is (lattice, convergence, which lattice of the ladder won).
    """
    t0 = time.perf_counter()
    best, cell = _plan_lattice(problem, spec, reference)
    params = spec.grid
    if not (params.converge and params.ladder) or best.status in (Status.INVALID_START, Status.INVALID_GOAL):
        return best
    lower, upper = search_box(problem)
    if cell <= 0:  # the finest lattice was refused (over max_nodes): the ladder starts from its cell
        cell = auto_cell(problem.world, lower, upper, params)[0]
    top = float(np.min(upper[:2] - lower[:2])) / 25.0
    cells, won, edges, coarse = [cell], cell, best.evaluations, cell
    while coarse < top:
        coarse *= 2.0
        run, _ = _plan_lattice(problem, replace(spec, grid=replace(params, cell=coarse)))
        cells.append(coarse)
        edges += run.evaluations
        if run.status.ok and (not best.status.ok or run.cost < best.cost):
            best, won = run, coarse
    if not best.status.ok:  # no lattice of the ladder found a path: the finest one's failure, tried cells named
        return replace(best, evaluations=edges, wall_time_s=time.perf_counter() - t0,
                       message=f"{best.message}; no path on the coarser lattices either "
                       f"({', '.join(f'{c:g}' for c in cells[1:])} m)" if len(cells) > 1 else best.message)
    return replace(best, evaluations=edges, wall_time_s=time.perf_counter() - t0,
                   message=f"{best.message}; best of the lattices at {', '.join(f'{c:g}' for c in cells)} m: "
                   f"{won:g} m")


def _plan_lattice(problem: PlanningProblem, spec: PlannerSpec,
                  reference: GridReference | None = None) -> tuple[PlanResult, float]:
    """:func:`plan_grid` on one lattice; also returns its horizontal cell."""
    t0 = time.perf_counter()
    bad = check_endpoints(problem)
    if bad is not None:
        return _failure(bad[0], bad[1], t0), 0.0
    params = spec.grid
    model = cost_model_for(problem, spec)
    if reference is None:
        lower, upper = search_box(problem)
        try:
            reference = GridReference(problem.world, problem.goal, model, lower, upper, params, problem.start)
        except ValueError as exc:
            return _failure(Status.INFEASIBLE, str(exc), t0), 0.0
    raw = reference.query(problem.start)
    if raw.shape[0] == 0:
        msg = (f"the goal cannot be reached from the start: no free path on the {reference.shape} lattice "
               f"at {reference.cell:g} m x {reference.cell_z:g} m cells ({int(reference.free.sum())} of "
               f"{reference.nodes} nodes free); the goal may be enclosed by the seabed or obstacles, "
               "or a smaller [planner.grid] cell may find a passage")
        return _failure(Status.INFEASIBLE, msg, t0), reference.cell
    w = problem.world
    length_only = params.objective == "length"
    path = key_waypoints(raw, w) if length_only else raw
    levels = 0
    if params.converge:
        path, _, levels = _converge(problem, spec, path, model, params.relax_iterations, params.converge_tol)
    else:
        path = _refine(w, path, model, params.objective, reference.cell, params.relax_iterations)
        if length_only:
            path = key_waypoints(path, w)
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
    ), reference.cell


def refine_plan(problem: PlanningProblem, spec: PlannerSpec, result: PlanResult, finest: float = 2048.0) -> PlanResult:
    """``result`` with its path refined to convergence on the planner's cost function (the lattice
    reference's own refinement) when that is cheaper and free, else ``result`` unchanged.

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        The cost function and the refinement settings (``spec.grid``).
    result : PlanResult
        A plan of any planner.
    finest : float, default 2048
        The finest level's spacing as a fraction of the length (1/``finest``).

    Returns
    -------
    PlanResult
        The refined polyline (no control points) with its cost terms, or ``result``.
    """
    if not result.status.ok or result.path.shape[0] < 2:
        return result
    params = spec.grid
    path, cost, levels = _converge(problem, spec, np.asarray(result.path, dtype=float), cost_model_for(problem, spec),
                                   params.relax_iterations, params.converge_tol, finest=finest)
    if not cost < result.cost or not problem.world.path_free(path):
        return result
    terms = path_cost(problem, spec, path)
    total = float(terms.pop("total"))
    return replace(result, path=path, cost=total, cost_terms={**result.cost_terms, **terms}, control_points=None,
                   message=f"{result.message}; refined to convergence ({levels} levels)".lstrip("; "))


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
