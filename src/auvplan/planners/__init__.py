"""Global planners: swarm optimisers over B-splines (document 002), streamlines (document 000) and
the lattice reference, behind one interface (:mod:`auvplan.planners.registry`)."""

from dataclasses import replace

from .._types import RngLike
from .base import PIPELINES, PLANNERS, SWARM, GridParams, PlannerSpec, PlanningProblem, PlanResult, Progress
from .flow import plan_flow
from .grid import GridReference, plan_grid, refine_plan, with_reference
from .registry import REGISTRY, PlannerEntry, get, register
from .swarm import plan_swarm
from .timeplan import plan_timeopt
from .vehicle_limits import enforce_limits

__all__ = ["PIPELINES", "PLANNERS", "REGISTRY", "SWARM", "GridParams", "GridReference", "PlanResult", "PlannerEntry",
           "enforce_limits",
           "PlannerSpec", "PlanningProblem", "get", "plan", "plan_flow", "plan_grid", "plan_swarm", "plan_timeopt",
           "REFERENCE_SWARMS", "reference", "register", "with_reference"]


def plan(problem: PlanningProblem, spec: PlannerSpec, rng: RngLike = None,
         progress: Progress | None = None) -> PlanResult:
    """Plan with the planner registered as ``spec.name`` (see ``REGISTRY``).

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        Planner name and settings (the scenario's ``[planner]`` table).
    rng : Generator, int or None
        Seed of the swarm planners (the flow and grid planners are deterministic).
    progress : callable, optional
        ``progress(iteration, best)`` after each iteration of a swarm planner.

    Returns
    -------
    PlanResult
        Status, path, cost terms and history; a failure is a status, never an exception.  With
        ``problem.limits`` the result is held to the vehicle's limits
        (:func:`~auvplan.planners.vehicle_limits.enforce_limits`: pitch repaired, else ``INFEASIBLE``).
    """
    return enforce_limits(problem, spec, get(spec.name).run(problem, spec, rng, progress))


REFERENCE_SWARMS = ("iabc", "pso", "de")
"""The seeded planners whose best plan, at twice the budget, joins the reference (best of N)."""


def reference(problem: PlanningProblem, spec: PlannerSpec, swarms: tuple[str, ...] = REFERENCE_SWARMS,
              seed: int = 2**31 - 1) -> PlanResult:
    """The best known plan of ``problem`` on the cost function of ``spec``: the lattice plan
    refined to convergence (:func:`plan_grid`) and the seeded pipeline of each planner in
    ``swarms`` at twice ``spec``'s evaluation budget (seed ``seed``, apart from the seeds users
    run), each of those then refined to convergence as a polyline by the lattice plan's own
    refinement (:func:`auvplan.planners.grid.refine_plan`), the cheapest feasible one; its
    ``message`` says which (best of N).

    Parameters
    ----------
    problem : PlanningProblem
        World, start, goal and vehicle figures.
    spec : PlannerSpec
        The cost function and the budget the compared planners spend.
    swarms : tuple of str
        Planners that join the lattice plan (empty: the lattice plan alone).
    seed : int
        Seed of their runs.

    Returns
    -------
    PlanResult
        Named ``grid`` whichever plan won, with that plan's path and cost.
    """
    grid = plan_grid(problem, spec)
    if not grid.status.ok or not swarms:
        return grid
    best, label = grid, "the refined lattice plan"
    for name in swarms:
        run = refine_plan(problem, spec, plan(problem, replace(spec, name=name, pipeline="seeded",
                                                               budget=2 * spec.evaluations), seed))
        if run.status.ok and run.cost < best.cost:
            best, label = run, f"{name} (seeded, {2 * spec.evaluations} evaluations, refined)"
    return replace(best, planner="grid", message=f"{grid.message}; best of {1 + len(swarms)} (lattice, "
                   f"{', '.join(swarms)} at twice the budget, each refined): {label}")
