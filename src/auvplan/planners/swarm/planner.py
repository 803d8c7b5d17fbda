"""Global planning with population optimisers over B-spline control points (document 002).

The problem (:mod:`auvplan.planners.swarm.problem`): the ``K`` interior control points of a
clamped cubic B-spline from the start to the goal, costed by :func:`auvplan.cost.evaluate_paths`.
The optimiser is IABC (document 002's improvement), ABC, GA, PSO or scipy's differential
evolution.  Three pipelines (``PlannerSpec.pipeline``):

* ``"seeded"`` (default): a coarse lattice path (:mod:`auvplan.planners.swarm.seeding`) gives candidate
  control points (least-squares fits, control points repeated at the corners of its taut
  polygon); the best of them, screened by the objective (evaluations counted), seed
  ``seed_fraction`` of the first population; the optimiser spends
  ``(1 - refine_fraction)`` of the budget; a pattern search (:func:`auvplan.optim.pattern_search`)
  spends the rest refining the best plan, accepting only paths that pass the exact test when the
  optimiser's plan did (so the refined plan is never worse and never less safe); when the
  optimiser found no feasible path, the lattice path (shortened and relaxed by the grid planner)
  is returned instead, so that a plan is INFEASIBLE only when the lattice found none either;
  last, the plan is polished as a polyline by the lattice's band (:mod:`auvplan.planners.swarm.polish`,
  ``spec.polish`` sweeps per level), kept only when cheaper and free.  The lattice seeding and the
  polish are not objective evaluations of the optimiser's problem: they are outside the budget,
  and reported beside it in ``PlanResult.work`` (``seeding_lattice_nodes``, ``seeding_cpu_s``,
  ``polish_cpu_s``), so that a comparison at equal budgets is equal in the evaluations of the swarm,
  with the seeding and the polish counted apart.  IABC at its default budget (``budget = 0``) stops
  early when its swarm has not improved in :data:`~auvplan.planners.swarm.convergence.STALL_ITERATIONS`
  iterations and the seeding lattice's corridor, polished, is more than
  :data:`~auvplan.planners.swarm.convergence.CORRIDOR_MARGIN` below its best
  (:func:`~auvplan.planners.swarm.convergence.stalled_behind`): neither the rest of its budget nor the
  refinement is spent, the corridor's polish is kept for the final polish, and the plan says so
  (``message``, ``work["swarm_stopped_at_evaluations"]``).  In a dense field of no-go zones the swarm
  stalls at its seeds from the start while the corridor wins the final polish anyway (docs/zones.md);
  an explicit budget is always spent exactly;
* ``"document"``: the algorithm alone, as in document 002 (IterMax iterations when no budget is
  given);
* ``"progressive"``: the algorithm alone, coarse to fine (:mod:`auvplan.planners.swarm.progressive`):
  ``coarse_fraction`` of the budget with ``⌈K/2⌉`` control points, then the rest with ``K``,
  seeded by the first stage's best paths refitted with the control points crowded at the bends.

``--budget N`` (``PlannerSpec.budget``) makes every optimiser, and the seeded pipeline as a whole,
spend exactly N objective evaluations (the last batch truncated).

Status: ``EXACT`` when the returned path passes every exact constraint test, ``INFEASIBLE``
when even the best path violates one (the path is still returned, with the number of
violating segments in the message), ``INVALID_START`` / ``INVALID_GOAL`` when an end point is
not free.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from functools import partial

import numpy as np

from ..._types import FloatArray, RngLike, Status, as_rng
from ...cost import evaluate_paths
from ...optim import (
    ABC,
    GA,
    IABC,
    PSO,
    Optimizer,
    OptimizeResult,
    Problem,
    Termination,
    differential_evolution,
    minimize,
    pattern_search,
)
from ...path import sample_population
from ..core.base import PlannerSpec, PlanningProblem, PlanResult, Progress
from ..core.common import (
    check_endpoints,
    cost_model_for,
    plan_terms,
    search_box,
)
from ..grid.planner import GridReference, plan_grid
from .convergence import CORRIDOR_MARGIN, STALL_ITERATIONS, assess, stalled_behind
from .polish import LatticeCorridor, polish_polyline
from .problem import (
    control_polygon,
    spline_problem,
)
from .progressive import coarse_count, coarse_stage
from .seeding import coarse_reference, lattice_seeds, seed_candidates

__all__ = ["plan_swarm", "make_optimizer", "run_optimizer"]


def make_optimizer(spec: PlannerSpec, lower: FloatArray, upper: FloatArray, rng: np.random.Generator) -> Optimizer:
    """The ask/tell optimiser named by ``spec.name`` over a box.

    Parameters
    ----------
    spec : PlannerSpec
        Optimiser name (``iabc``, ``abc``, ``ga`` or ``pso``), population and settings.
    lower, upper : numpy.ndarray
        Search box ``(D,)``.
    rng : numpy.random.Generator
        The run's generator.

    Returns
    -------
    Optimizer
        A fresh optimiser.

    Raises
    ------
    ValueError
        For any other name.
    """
    if spec.name == "iabc":
        params = replace(spec.iabc, max_iterations=spec.iterations)
        return IABC(lower, upper, spec.population, params, rng)
    if spec.name == "abc":
        return ABC(lower, upper, spec.population, spec.abc, rng)
    if spec.name == "ga":
        return GA(lower, upper, spec.population, spec.ga, rng)
    if spec.name == "pso":
        return PSO(lower, upper, spec.population, spec.pso, rng)
    raise ValueError(f"unknown swarm planner {spec.name!r}")


def run_optimizer(spec: PlannerSpec, problem: Problem, rng: np.random.Generator,
                  progress: Progress | None = None, on_stall: Callable[[float], bool] | None = None) -> OptimizeResult:
    """Run the optimiser of ``spec`` on ``problem`` until its budget is spent.

    Without a budget, for ``spec.iterations`` iterations.

    Parameters
    ----------
    spec : PlannerSpec
        Optimiser name, population, settings and iteration cap.
    problem : Problem
        Objective, box, seeds and budget.
    rng : numpy.random.Generator
        The run's generator.
    progress : callable, optional
        ``progress(iteration, best_cost)`` after each iteration.
    on_stall : callable, optional
        ``on_stall(best_cost) -> bool`` after :data:`~auvplan.planners.swarm.convergence.STALL_ITERATIONS`
        iterations without an improvement: True stops the run early (``reason`` ``"stall"``).  Not asked of
        scipy's differential evolution.

    Returns
    -------
    OptimizeResult
        The optimiser's best decision vector and its record.
    """
    if spec.name == "de":
        return differential_evolution(problem, spec.population, spec.de, rng, progress)
    optimizer = make_optimizer(spec, problem.lower, problem.upper, rng)
    termination = (Termination(max_iterations=spec.iterations) if problem.budget is None
                   else Termination(max_iterations=None, max_evaluations=problem.budget))
    if on_stall is not None:
        termination = replace(termination, stall_iterations=STALL_ITERATIONS, on_stall=on_stall)
    return minimize(problem, optimizer, termination, progress)


def _budgets(spec: PlannerSpec) -> tuple[int | None, int]:
    """Evaluations of the optimiser (None: iteration cap only) and of the refinement."""
    if spec.pipeline == "document":
        return (spec.budget or (spec.evaluations if spec.name == "de" else None)), 0
    if spec.pipeline == "progressive":
        return spec.evaluations, 0
    total = spec.evaluations
    refine = int(round(spec.refine_fraction * total)) if total > 2 * 3 * spec.control_points else 0
    return total - refine, refine


def plan_swarm(
    problem: PlanningProblem,
    spec: PlannerSpec,
    rng: RngLike = None,
    progress: Progress | None = None,
) -> PlanResult:
    """Plan with the population optimiser named by ``spec.name`` (see the module notes).

    Parameters
    ----------
    problem : PlanningProblem
        World, end points, vehicle energy figures.
    spec : PlannerSpec
        Optimiser, pipeline, population, evaluation budget, cost settings.
    rng : Generator, int or None
        Seed of the run (same seed → same result).
    progress : callable, optional
        ``progress(iteration, best_cost)`` after each iteration.

    Returns
    -------
    PlanResult
        Status, path, control points, cost terms and history; a failure is a status.
    """
    t0 = time.perf_counter()
    bad = check_endpoints(problem)
    if bad is not None:
        return PlanResult.failure(bad[0], bad[1], spec.name)
    gen = as_rng(rng)
    budget, refine = _budgets(spec)
    ref, lattice, x0, count = None, None, None, 0
    work: dict[str, float] = {}
    if spec.pipeline == "seeded":
        ref, lattice, x0, count, work = _seeded(problem, spec, gen)
    corridor = (LatticeCorridor(problem, spec, lattice) if spec.pipeline == "seeded" and spec.name == "iabc"
                and spec.budget == 0 and spec.polish > 0 and lattice is not None and lattice.shape[0] >= 2 else None)
    coarse = None
    if spec.pipeline == "progressive" and budget is not None and budget >= 2 and coarse_count(spec.control_points) < \
            spec.control_points:
        first = max(1, int(round(spec.coarse_fraction * budget)))
        x0, coarse = coarse_stage(problem, spec, first, lambda s, t, g: run_optimizer(s, t, g, progress), gen)
        budget -= coarse.evaluations
    task = spline_problem(problem, spec, budget, x0)
    if x0 is not None and x0.shape[0] > count and spec.pipeline == "seeded":  # screen the candidates (counted)
        task.x0 = x0[np.argsort(task.evaluate(x0), kind="stable")[:count]]
    opt = run_optimizer(spec, task, gen, progress, None if corridor is None else partial(stalled_behind, corridor))
    x, f, evals = opt.x, opt.f, task.evaluations  # the screening included
    if opt.reason == "stall":
        work = {**work, "swarm_stopped_at_evaluations": float(evals)}
    history, trace = opt.history, np.asarray(task.trace, dtype=float).reshape(-1, 2)
    if coarse is not None:  # the coarse stage's record first
        history = np.r_[coarse.history, history]
        trace = np.vstack([coarse.trace, trace + np.array([coarse.evaluations, 0.0])])
        trace[:, 1] = np.minimum.accumulate(trace[:, 1])
        evals += coarse.evaluations
    if refine > 0 and opt.reason != "stall":
        x, f, history, trace, evals = _refine(problem, spec, refine, gen, (x, f, history, trace, evals))
    iterations = opt.iterations + (coarse.iterations if coarse is not None else 0)
    result = replace(_result(problem, spec, x, f, evals, iterations, history, trace), work=work)
    if opt.reason == "stall":
        result = replace(result, message="; ".join(m for m in (result.message, _stopped_note(spec, evals)) if m))
    fell_back = not result.status.ok
    if fell_back and spec.pipeline == "seeded" and lattice is not None and lattice.shape[0] >= 2:
        result = replace(_fallback(problem, spec, ref, result), work=work)
    if spec.pipeline == "seeded":
        result = polish_polyline(problem, spec, result, lattice, corridor)
        converged, why = assess(result, work["seeding_lattice_nodes"], lattice is not None and lattice.shape[0] >= 2,
                                fell_back)
        result = replace(result, converged=converged, convergence=why)
    return replace(result, wall_time_s=time.perf_counter() - t0)


_Record = tuple[FloatArray, float, FloatArray, FloatArray, int]


def _refine(problem: PlanningProblem, spec: PlannerSpec, refine: int, gen: np.random.Generator,
            record: _Record) -> _Record:
    """The pattern search's refinement of the optimiser's best with ``refine`` evaluations: the record
    ``(x, f, history, trace, evaluations)`` after it (strict when the best is feasible: never less safe)."""
    x, f, history, trace, evals = record
    feasible = _feasible(problem, spec, x)
    polished = pattern_search(spline_problem(problem, spec, refine, strict=feasible), x, f, spec.refine, gen)
    if polished.f <= f:
        x, f = polished.x, polished.f
    trace = np.vstack([trace, polished.trace + np.array([evals, 0.0])])
    trace[:, 1] = np.minimum.accumulate(trace[:, 1])  # the polls' best against the incumbent
    return x, f, np.r_[history, f], trace, evals + polished.evaluations


def _seeded(problem: PlanningProblem, spec: PlannerSpec, gen: np.random.Generator
            ) -> tuple[GridReference | None, FloatArray, FloatArray | None, int, dict[str, float]]:
    """The seeded pipeline's coarse lattice: its reference, its path, the candidate seeds, how many of
    them seed the population, and the work done (outside the budget)."""
    c0 = time.process_time()
    ref, lattice = coarse_reference(problem, spec)
    x0, count = None, 0
    if lattice.shape[0] >= 2 and spec.seed_fraction > 0:
        lo3, hi3 = search_box(problem)
        k = spec.control_points
        count = max(1, int(round(spec.seed_fraction * spec.population)))
        bases = lattice_seeds(lattice, problem.world, k, spec.samples)
        x0 = seed_candidates(bases, max(count, len(bases)), np.tile(lo3, k), np.tile(hi3, k), gen)
    work = {"seeding_lattice_nodes": float(ref.nodes if ref is not None else 0),
            "seeding_cpu_s": time.process_time() - c0}
    return ref, lattice, x0, count, work


def _stopped_note(spec: PlannerSpec, evaluations: int) -> str:
    """The plan's note when the swarm stopped early, stalled behind the seeding lattice's corridor."""
    return (f"the {spec.name} swarm stopped after {evaluations} of {spec.evaluations} evaluations: no better "
            f"in {STALL_ITERATIONS} iterations, and the seeding lattice's corridor, polished, more than "
            f"{100 * CORRIDOR_MARGIN:.1f} % below its best")


def _feasible(problem: PlanningProblem, spec: PlannerSpec, x: FloatArray) -> bool:
    """Whether decision vector ``x`` passes every constraint (a check of the optimiser's answer,
    not a search step: it does not count against the budget)."""
    path = sample_population(control_polygon(problem, x), spec.samples)
    return bool(evaluate_paths(problem.world, path, cost_model_for(problem, spec)).feasible[0])


def _result(problem: PlanningProblem, spec: PlannerSpec, x: FloatArray, f: float, evals: int, iterations: int,
            history: FloatArray, trace: FloatArray) -> PlanResult:
    """The plan of decision vector ``x`` with its exact status."""
    ctrl = control_polygon(problem, x)[0]
    path = sample_population(ctrl, spec.samples)
    terms = evaluate_paths(problem.world, path[None], cost_model_for(problem, spec), exact=True)
    row = terms.row(0)
    free = problem.world.path_free(path, moving=False)
    status = Status.EXACT if (free and row["violations"] == 0) else Status.INFEASIBLE
    message = "" if status is Status.EXACT else (
        f"the best path found still violates {row['violations']} segment constraint(s) "
        f"(deepest violation {-row['min_clearance_m']:.1f} m); raise the budget or relax the margins"
    )
    return PlanResult(status=status, path=path, cost=float(f), cost_terms=plan_terms(row, spec), evaluations=evals,
                      iterations=iterations, wall_time_s=0.0, history=history, planner=spec.name, control_points=ctrl,
                      message=message, trace=trace)


def _fallback(problem: PlanningProblem, spec: PlannerSpec, ref: GridReference | None,
              failed: PlanResult) -> PlanResult:
    """The coarse lattice path (shortened and relaxed by the grid planner) in place of a failed plan."""
    grid = plan_grid(problem, spec, reference=ref)
    if not grid.status.ok:
        return failed
    note = (f"the {spec.name} optimiser found no feasible path ({failed.message}); returned the lattice path "
            f"of the seeding lattice instead")
    return replace(grid, planner=spec.name, evaluations=failed.evaluations, iterations=failed.iterations,
                   history=np.r_[failed.history, grid.cost], trace=failed.trace, message=note)
