"""Global planners: swarm optimisers over B-splines (document 002) and streamlines (document 000)."""

from .base import PLANNERS, SWARM, GridParams, PlannerSpec, PlanningProblem, PlanResult
from .flow import plan_flow
from .grid import GridReference, plan_grid, with_reference
from .swarm import plan_swarm
from .timeplan import plan_timeopt

__all__ = ["PLANNERS", "SWARM", "GridParams", "GridReference", "PlanResult", "PlannerSpec", "PlanningProblem", "plan",
           "plan_flow", "plan_grid", "plan_swarm", "plan_timeopt", "reference", "with_reference"]


def plan(problem: PlanningProblem, spec: PlannerSpec, rng=None, progress=None) -> PlanResult:
    """Plan with the planner named by ``spec.name`` (see ``PLANNERS``)."""
    if spec.name == "flow":
        return plan_flow(problem, spec.flow)
    if spec.name == "grid":
        return plan_grid(problem, spec)
    if spec.name == "timeopt":
        return plan_timeopt(problem, spec)
    return plan_swarm(problem, spec, rng, progress)


def reference(problem: PlanningProblem, spec: PlannerSpec) -> PlanResult:
    """The grid reference plan of ``problem`` on the cost function of ``spec``."""
    return plan_grid(problem, spec)
