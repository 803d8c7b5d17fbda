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

from dataclasses import replace

import numpy as np

from ..core.base import PlannerSpec, PlanningProblem, PlanResult
from ..core.common import cost_model_for, path_cost
from ..core.registry import has
from .band import _converge, edge_cost, resample_free
from .ladder import plan_ladder, plan_lattice
from .reference import GridReference, auto_cell

__all__ = ["GridReference", "plan_grid", "refine_plan", "auto_cell", "edge_cost", "on_cost_function",
           "resample_free", "with_reference"]


def plan_grid(problem: PlanningProblem, spec: PlannerSpec, reference: GridReference | None = None) -> PlanResult:
    """Plan on the lattice (see the module notes); ``reference`` re-uses a cost-to-go field
    built for the same goal, world and cost function.

    With ``converge`` (the default) :func:`~auvplan.planners.grid.ladder.plan_ladder`: with ``ladder``
    (the default) the lattices 2, 4, … times coarser, up to the first at least 1/25 of the search
    box's narrower side, are planned too, coarse to fine, each with the 26 directions and with
    any-angle links (``also_any_angle``), and the cheapest refined plan wins: the candidates of a
    cell include those of the cell twice as coarse, so halving the cell never gives a worse
    reference.  The ladder also runs when the finest lattice finds no path or is refused over
    ``max_nodes`` (a coarser one may find one); when none does, the finest lattice's failure is
    returned with the cells tried named.  Without ``converge``: one lattice, elastic band only
    (:func:`~auvplan.planners.grid.ladder.plan_lattice`).

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
    if spec.grid.converge:
        return plan_ladder(problem, spec, reference)
    return plan_lattice(problem, spec, reference)


def refine_plan(problem: PlanningProblem, spec: PlannerSpec, result: PlanResult, finest: float = 2048.0,
                target: float | None = None) -> PlanResult:
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
    target : float, optional
        A cost the refined path is of no use above: the refinement gives up when it cannot reach below
        it (:func:`~auvplan.planners.grid.band.gives_up`).

    Returns
    -------
    PlanResult
        The refined polyline (no control points) with its cost terms, or ``result``.
    """
    if not result.status.ok or result.path.shape[0] < 2:
        return result
    params = spec.grid
    path, cost, levels = _converge(problem, spec, np.asarray(result.path, dtype=float), cost_model_for(problem, spec),
                                   params.relax_iterations, params.converge_tol, finest=finest, target=target)
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
    if has(result.planner, "path_cost") or result.path.shape[0] < 2:
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
