"""Global planners: swarm optimisers over B-splines (document 002)."""

from .base import PLANNERS, PlannerSpec, PlanningProblem, PlanResult
from .swarm import plan_swarm

__all__ = ["PLANNERS", "PlanResult", "PlannerSpec", "PlanningProblem", "plan", "plan_swarm"]


def plan(problem: PlanningProblem, spec: PlannerSpec, rng=None, progress=None) -> PlanResult:
    """Plan with the planner named by ``spec.name`` (see ``PLANNERS``)."""
    return plan_swarm(problem, spec, rng, progress)
