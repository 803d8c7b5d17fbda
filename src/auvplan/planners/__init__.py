"""Global planners: swarm optimisers over B-splines (document 002), streamlines (document 000) and
the lattice reference, behind one interface (:mod:`auvplan.planners.registry`)."""

from .base import PIPELINES, PLANNERS, SWARM, GridParams, PlannerSpec, PlanningProblem, PlanResult
from .flow import plan_flow
from .grid import GridReference, plan_grid, with_reference
from .registry import REGISTRY, PlannerEntry, get, register
from .swarm import plan_swarm
from .timeplan import plan_timeopt

__all__ = ["PIPELINES", "PLANNERS", "REGISTRY", "SWARM", "GridParams", "GridReference", "PlanResult", "PlannerEntry",
           "PlannerSpec", "PlanningProblem", "get", "plan", "plan_flow", "plan_grid", "plan_swarm", "plan_timeopt",
           "reference", "register", "with_reference"]


def plan(problem: PlanningProblem, spec: PlannerSpec, rng=None, progress=None) -> PlanResult:
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
        Status, path, cost terms and history; a failure is a status, never an exception.
    """
    return get(spec.name).run(problem, spec, rng, progress)


def reference(problem: PlanningProblem, spec: PlannerSpec) -> PlanResult:
    """The grid reference plan of ``problem`` on the cost function of ``spec``."""
    return plan_grid(problem, spec)
