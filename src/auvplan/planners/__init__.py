"""Global planners: swarm optimisers over B-splines (document 002) and streamlines (document 000)."""

from .base import PLANNERS, PlannerSpec, PlanningProblem, PlanResult
from .flow import plan_flow
from .swarm import plan_swarm

__all__ = ["PLANNERS", "PlanResult", "PlannerSpec", "PlanningProblem", "plan", "plan_flow", "plan_swarm"]


def plan(problem: PlanningProblem, spec: PlannerSpec, rng=None, progress=None) -> PlanResult:
    """Plan with the planner named by ``spec.name`` (see ``PLANNERS``)."""
    if spec.name == "flow":
        return plan_flow(problem, spec.flow)
    return plan_swarm(problem, spec, rng, progress)
