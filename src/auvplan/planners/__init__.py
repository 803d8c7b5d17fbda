"""Global planners: swarm optimisers over B-splines (document 002), streamlines (document 000), the
lattice reference and the time-optimal planner, one package each, behind one interface and one registry
(:mod:`auvplan.planners.core.registry`, the plug-in point).

The planners themselves are imported when first used (``plan_flow`` … below are loaded on access), so
naming, checking or registering a planner imports none of them.
"""

from dataclasses import replace
from typing import TYPE_CHECKING

from .._types import RngLike
from ..runtime.lazy import lazy_attributes
from .core.base import PlannerSpec, PlanningProblem, PlanResult, Progress
from .core.params import GridParams
from .core.registry import CAPABILITIES, PIPELINES, PLANNERS, REGISTRY, SWARM, PlannerEntry, get, has, register

if TYPE_CHECKING:  # pragma: no cover - for type checkers only
    from .flow.planner import plan_flow
    from .grid.planner import GridReference, plan_grid, refine_plan, with_reference
    from .swarm.planner import plan_swarm
    from .timeopt.planner import plan_timeopt

__all__ = ["CAPABILITIES", "has", "PIPELINES", "PLANNERS", "REGISTRY", "SWARM", "GridParams", "GridReference",
           "PlanResult", "PlannerEntry", "enforce_limits",
           "PlannerSpec", "PlanningProblem", "get", "plan", "plan_flow", "plan_grid", "plan_swarm", "plan_timeopt",
           "REFERENCE_SWARMS", "reference", "register", "refine_plan", "with_reference"]

_LAZY = {
    "plan_flow": "auvplan.planners.flow.planner",
    "plan_grid": "auvplan.planners.grid.planner",
    "GridReference": "auvplan.planners.grid.planner",
    "refine_plan": "auvplan.planners.grid.planner",
    "with_reference": "auvplan.planners.grid.planner",
    "plan_swarm": "auvplan.planners.swarm.planner",
    "plan_timeopt": "auvplan.planners.timeopt.planner",
    "enforce_limits": "auvplan.planners.core.vehicle_limits",
}


__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, __all__)


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
        (:func:`~auvplan.planners.core.vehicle_limits.enforce_limits`: pitch repaired, else ``INFEASIBLE``).
        A plan whose path enters one of the world's ``[[zones]]`` is ``INFEASIBLE``, naming the zone and
        the leg (:func:`~auvplan.planners.core.zone_check.hold_to_zones`).

    Raises
    ------
    ScenarioError
        If the world has zones and the planner cannot keep out of them (``flow``).
    """
    from .core.vehicle_limits import enforce_limits
    from .core.zone_check import hold_to_zones, refuse_unless_zones

    entry = get(spec.name)
    refuse_unless_zones(problem, entry)
    result = entry.run(problem, spec, rng, progress)
    if not isinstance(result, PlanResult):  # a planner registered from outside that breaks the interface
        raise TypeError(f"planner {spec.name!r} returned {type(result).__name__}, not a PlanResult")
    return hold_to_zones(problem, enforce_limits(problem, spec, result))


REFERENCE_SWARMS = ("iabc", "pso", "de")
"""The seeded planners whose best plan, at twice the budget, joins the reference (best of N)."""


def reference(problem: PlanningProblem, spec: PlannerSpec, swarms: tuple[str, ...] = REFERENCE_SWARMS,
              seed: int = 2**31 - 1) -> PlanResult:
    """The best known plan of ``problem`` on the cost function of ``spec``: the lattice plan
    refined to convergence (:func:`plan_grid`) and the seeded pipeline of each planner in
    ``swarms`` at twice ``spec``'s evaluation budget (seed ``seed``, apart from the seeds users
    run), each of those then refined to convergence as a polyline by the lattice plan's own
    refinement (:func:`auvplan.planners.grid.planner.refine_plan`), the cheapest feasible one; its
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
    from .grid.planner import plan_grid, refine_plan

    grid = plan_grid(problem, spec)
    if not grid.status.ok or not swarms:
        return grid
    best, label = grid, "the refined lattice plan"
    for name in swarms:
        run = refine_plan(problem, spec, plan(problem, replace(spec, name=name, pipeline="seeded",
                                                               budget=2 * spec.evaluations), seed))
        if run.status.ok and run.cost < best.cost:
            best, label = run, f"{name} (seeded, {2 * spec.evaluations} evaluations, refined)"
    from .core.zone_check import hold_to_zones

    message = (f"{grid.message}; best of {1 + len(swarms)} (lattice, {', '.join(swarms)} at twice the budget, "
               f"each refined): {label}")
    return hold_to_zones(problem, replace(best, planner="grid", message=message))
