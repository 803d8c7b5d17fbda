"""The ladder of lattices behind the grid planner and ``--reference`` (issue 35.2).

A *rung* is one cell size.  Each rung's lattice is searched twice, with the 26 lattice directions
and with any-angle links (``[planner.grid] also_any_angle``, lazy Theta*), and both lattice paths go
through one cheap *screening* refinement (:data:`SCREEN`: one cycle of elastic-band levels down to
1/64 of the path).  The cheaper of the two is refined to convergence (the
:func:`~auvplan.planners.grid.band._converge` of every reference), unless its screened cost is more
than :data:`MARGIN` above the screened cost of the best plan of the coarser rungs, which it would not beat.

The rungs run from the coarsest (the first cell at least 1/25 of the search box's narrower side) to
the finest, and the plan of the ladder is the cheapest rung's.  The rungs of a cell are the rungs of
the cell twice as coarse plus one, run in the same order from the same state, so halving the cell
never gives a worse reference (by construction, whatever the screening decides).

Why both kinds of link: with the 26 directions alone a lattice path is metricated (up to 8 % long
whatever the cell) and its refinement lands in a local optimum that does not improve as the cell
halves (new-england-seamounts: 429 958, 428 254, 428 254, 428 123 from 4 000 to 500 m); with
any-angle links alone it improves there (432 069 → 424 344) but not on every scene (ninetyeast-ridge
settles 0.02 % higher; the sphere scene of ``tests/oracles/test_grid.py`` 0.2 % higher).  The better of the
two on every rung keeps both (``docs/lattice.md``).
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np

from ..._types import FloatArray, Status
from ...cost import CostModel
from ...guidance.avoidance.local import key_waypoints
from ...path import sample_population
from ..core.base import PlannerSpec, PlanningProblem, PlanResult
from ..core.common import check_endpoints, cost_model_for, path_cost, search_box
from ..core.params import GridParams
from .band import _converge, _refine
from .reference import GridReference, auto_cell

__all__ = ["MARGIN", "SCREEN", "SWEEPS", "plan_ladder", "plan_lattice"]

SCREEN = 64.0
"""The screening refinement's finest level, as a fraction of the path's length (one cycle of levels
1/8 … 1/``SCREEN``); the chosen lattice path is then refined to convergence from the start, exactly as
the reference refined every lattice path before (so a rung's plan is the same as before whenever the
screening picks the kind that converges cheaper).  Measured on
ninetyeast-ridge and new-england-seamounts, 500–16 000 m cells, both kinds of link: it ranks the two
lattice paths of every rung (11 of 11) as their converged refinements do, at 0.03–0.16 s CPU against
0.2–0.6 s for a convergence."""

SWEEPS = 30
"""Most elastic-band sweeps per level of the screening refinement (the convergence's are
``relax_iterations``, 200): the same screened costs to 10⁻⁴ on the measurements above but one (the
26-direction 500 m path of ninetyeast-ridge, +0.12 %, still ranked right), 1.0–3.5× faster."""

MARGIN = 2e-4
"""A rung's screened path is refined to convergence only when its screened cost is at most this much
(relative) above the screened cost of the path whose convergence is the best plan so far: screened
against screened, both a similar 0.02–0.13 % above their converged costs on the measurements above.
(A screened path above that line would have to gain more from the convergence than the best one
did; skipping it saves a convergence, 0.15–0.6 s, where a finer rung does not find a better path.)"""


def _failure(status: Status, message: str, t0: float) -> PlanResult:
    return PlanResult.failure(status, message, "grid", time.perf_counter() - t0)


def _lattice(problem: PlanningProblem, model: CostModel, params: GridParams, reference: GridReference | None,
             keep: bool = False, fields: tuple[Any, ...] | None = None) -> tuple[GridReference | None, FloatArray, str]:
    """The lattice of ``params`` (or ``reference``) and its path from the start; the message says
    why when there is no path (the path is then empty).  ``keep`` / ``fields``: see :class:`GridReference`."""
    if reference is None:
        lower, upper = search_box(problem)
        try:
            reference = GridReference(problem.world, problem.goal, model, lower, upper, params, problem.start,
                                      keep=keep, fields=fields)
        except ValueError as exc:
            return None, np.empty((0, 3)), str(exc)
    raw = reference.query(problem.start)
    if raw.shape[0] == 0:
        return reference, raw, (
            f"the goal cannot be reached from the start: no free path on the {reference.shape} lattice "
            f"at {reference.cell:g} m x {reference.cell_z:g} m cells ({int(reference.free.sum())} of "
            f"{reference.nodes} nodes free); the goal may be enclosed by the seabed or obstacles, "
            "or a smaller [planner.grid] cell may find a passage")
    return reference, raw, ""


def _finish(problem: PlanningProblem, spec: PlannerSpec, path: FloatArray, reference: GridReference,
            levels: int, t0: float) -> PlanResult:
    """The refined ``path`` as a plan: the straight segment when free and cheaper, the B-spline over
    it when free and cheaper (``smooth``), the status by the exact segment test."""
    w, params = problem.world, spec.grid
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
    message = "" if free else "the shortened lattice path failed the exact segment test"
    if free:
        message = (f"reference: lattice {reference.shape} at {reference.cell:g} m x {reference.cell_z:g} m, "
                   + (f"refined to convergence ({levels} levels, tol {params.converge_tol:g})" if params.converge
                      else "elastic band only (lattice-bound reference)"))
    return PlanResult(status=Status.EXACT if free else Status.INFEASIBLE, path=path, cost=total, cost_terms=terms,
                      evaluations=reference.edges, iterations=1, wall_time_s=time.perf_counter() - t0,
                      history=np.array([total]), planner="grid", control_points=ctrl, message=message)


def plan_lattice(problem: PlanningProblem, spec: PlannerSpec, reference: GridReference | None = None) -> PlanResult:
    """One lattice of ``spec.grid``'s links, its path shortened and relaxed by the elastic band only
    (the lattice-bound reference, ``converge = false``).

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        The cost function and the lattice settings.
    reference : GridReference, optional
        A cost-to-go field to re-use.

    Returns
    -------
    PlanResult
        The plan, or a failure status with a message.
    """
    t0 = time.perf_counter()
    bad = check_endpoints(problem)
    if bad is not None:
        return _failure(bad[0], bad[1], t0)
    params, w = spec.grid, problem.world
    reference, raw, why = _lattice(problem, cost_model_for(problem, spec), params, reference)
    if reference is None or raw.shape[0] == 0:
        return _failure(Status.INFEASIBLE, why, t0)
    path = _refine(w, key_waypoints(raw, w) if params.objective == "length" else raw, cost_model_for(problem, spec),
                   params.objective, reference.cell, params.relax_iterations)
    if params.objective == "length":
        path = key_waypoints(path, w)
    return _finish(problem, spec, path, reference, 0, t0)


def _cells(problem: PlanningProblem, params: GridParams, reference: GridReference | None) -> list[float]:
    """The rungs' horizontal cells, finest first."""
    lower, upper = search_box(problem)
    cells = [reference.cell if reference is not None else auto_cell(problem.world, lower, upper, params)[0]]
    top = float(np.min(upper[:2] - lower[:2])) / 25.0
    while params.ladder and cells[-1] < top:
        cells.append(2.0 * cells[-1])
    return cells


def _screened(problem: PlanningProblem, spec: PlannerSpec, model: CostModel, params: GridParams,
              reference: GridReference | None) -> tuple[list[tuple[float, int, FloatArray, GridReference]], int, str]:
    """One rung: each kind of link's lattice path with its cost after the screening refinement, as
    ``(cost, links, path, lattice)``; also the lattices' edges and the first failure's message."""
    kinds = list(dict.fromkeys([params.any_angle] + ([params.also_any_angle] if params.also_any_angle else [])))
    out, edges, why, shared = [], 0, "", None
    for n, links in enumerate(kinds):
        given = reference if reference is not None and reference.params.any_angle == links else None
        p = replace(params, any_angle=links)
        if reference is not None and given is None:  # the other kind on the given lattice's cells
            p = replace(p, cell=reference.cell, cell_z=reference.cell_z)
        ref, raw, msg = _lattice(problem, model, p, given, keep=n + 1 < len(kinds), fields=shared)
        if ref is not None:  # the next kind searches the same lattice: its node fields and edges re-used
            shared, ref.fields = ref.fields, None
        edges += ref.edges if ref is not None else 0
        if ref is None or raw.shape[0] == 0:
            why = why or msg
            continue
        path = key_waypoints(raw, problem.world) if params.objective == "length" else raw
        cost = _converge(problem, spec, path, model, min(params.relax_iterations, SWEEPS), params.converge_tol,
                         cycles=1, finest=SCREEN)[1]
        out.append((float(cost), links, path, ref))
    return out, edges, why


def plan_ladder(problem: PlanningProblem, spec: PlannerSpec, reference: GridReference | None = None) -> PlanResult:
    """The converged lattice reference over the ladder of cells (see the module notes).

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        The cost function and ``spec.grid`` (``ladder = false``: the finest rung alone).
    reference : GridReference, optional
        The finest rung's lattice of its own kind of link, re-used.

    Returns
    -------
    PlanResult
        The cheapest rung's plan; ``evaluations`` counts the edges of every lattice built; ``history``
        is the ladder's cost after each rung, coarsest first (its last entry the plan's cost; ``inf``
        while no rung has a plan), i.e. the reference of each cell; the message names the rungs, the
        winner's cell and links, and how many paths were refined to convergence.  When no rung finds a
        path, the finest rung's failure with the cells tried named.
    """
    t0 = time.perf_counter()
    bad = check_endpoints(problem)
    if bad is not None:
        return _failure(bad[0], bad[1], t0)
    params = spec.grid
    model = cost_model_for(problem, spec)
    cells = _cells(problem, params, reference)
    best: PlanResult | None = None
    failed: PlanResult | None = None
    edges, screened, refined, won, why = 0, 0, 0, (cells[0], 0), ""
    history: list[float] = []  # the ladder's cost after each rung, coarse to fine
    best_screened = float("inf")
    for cell in reversed(cells):  # coarse to fine: a finer ladder re-runs the same rungs first
        finest = cell == cells[0]
        rung = params if finest else replace(params, cell=cell)
        cands, e, msg = _screened(problem, spec, model, rung, reference if finest else None)
        edges += e
        why = msg if finest else why
        history.append(best.cost if best is not None else float("inf"))
        if not cands:
            continue
        screened += len(cands)
        cost, links, raw, ref = min(cands, key=lambda c: c[0])
        if best is not None and cost - best_screened > MARGIN * abs(best_screened):
            continue
        path, _, levels = _converge(problem, spec, raw, model, params.relax_iterations, params.converge_tol)
        refined += 1
        run = _finish(problem, spec, path, ref, levels, t0)
        if not run.status.ok:
            failed = failed or run
        elif best is None or run.cost < best.cost:
            best, won, best_screened = run, (cell, links), cost
            history[-1] = best.cost
    done = time.perf_counter() - t0
    if best is None:
        return _no_rung(failed, edges, done, why, cells, t0)
    return replace(best, evaluations=edges, wall_time_s=done, history=np.array(history),
                   message=_ladder_message(best.message, cells, won, screened, refined))


def _ladder_message(message: str, cells: list[float], won: tuple[float, int], screened: int, refined: int) -> str:
    """The winner's message with the rungs, its cell and links, and the paths screened and refined."""
    kinds = "26 directions" if won[1] == 0 else f"any-angle links of {won[1]} cells"
    return (f"{message}; best of the lattices at {', '.join(f'{c:g}' for c in cells)} m: "
            f"{won[0]:g} m, {kinds} ({screened} lattice paths screened, {refined} refined to convergence)")


def _no_rung(failed: PlanResult | None, edges: int, done: float, why: str, cells: list[float],
             t0: float) -> PlanResult:
    """No rung's plan: the first refined path that failed, else the finest rung's failure with the cells tried."""
    if failed is not None:
        return replace(failed, evaluations=edges, wall_time_s=done)
    tried = f"; no path on the coarser lattices either ({', '.join(f'{c:g}' for c in cells[1:])} m)"
    return replace(_failure(Status.INFEASIBLE, why, t0), message=why + (tried if len(cells) > 1 else ""))
