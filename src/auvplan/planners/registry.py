"""One interface and a registry for every global planner (after OMPL's planner factory and
robotics-toolbox's planner classes).

A planner is a function ``run(problem, spec, rng, progress) -> PlanResult``: the
:class:`~auvplan.planners.base.PlanningProblem` (world, end points, vehicle figures) as one
object, the :class:`~auvplan.planners.base.PlannerSpec` (its settings), a seed or generator and
an optional ``progress(iteration, best_cost)``.  :func:`register` adds one under a name;
:func:`auvplan.planners.plan` dispatches by ``spec.name``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from .._types import RngLike
from .base import PLANNERS, PlannerSpec, PlanningProblem, PlanResult, Progress
from .flow.planner import plan_flow
from .grid.planner import plan_grid
from .swarm.planner import plan_swarm
from .timeopt.planner import plan_timeopt

__all__ = ["PlannerEntry", "REGISTRY", "register", "get"]

PlannerFn = Callable[[PlanningProblem, PlannerSpec, RngLike, "Progress | None"], PlanResult]


@dataclass(frozen=True)
class PlannerEntry:
    """A registered planner: its function, whether it iterates (reports progress) and a description.

    Parameters
    ----------
    name : str
        Registered name (``spec.name``).
    run : callable
        ``run(problem, spec, rng, progress) -> PlanResult``.
    iterative : bool
        Whether it iterates and calls ``progress``.
    description : str
        One line for ``auvplan planners`` and the docs.
    """

    name: str
    run: PlannerFn
    iterative: bool
    description: str


REGISTRY: dict[str, PlannerEntry] = {}


def register(name: str, *, iterative: bool, description: str) -> Callable[[PlannerFn], PlannerFn]:
    """Decorator: register ``run(problem, spec, rng, progress)`` as planner ``name``.

    Parameters
    ----------
    name : str
        Planner name (must be new).
    iterative : bool
        Whether the planner iterates and calls ``progress``.
    description : str
        One line describing it.

    Returns
    -------
    callable
        The decorator; it returns the function unchanged.

    Raises
    ------
    ValueError
        If ``name`` is already registered (when the decorator is applied).
    """

    def add(run: PlannerFn) -> PlannerFn:
        if name in REGISTRY:
            raise ValueError(f"planner {name!r} is already registered")
        REGISTRY[name] = PlannerEntry(name, run, iterative, description)
        return run

    return add


def get(name: str) -> PlannerEntry:
    """The planner registered as ``name``.

    Parameters
    ----------
    name : str
        Planner name.

    Returns
    -------
    PlannerEntry
        Its registry entry.

    Raises
    ------
    ValueError
        If no planner has that name.
    """
    try:
        return REGISTRY[name]
    except KeyError:
        raise ValueError(f"unknown planner {name!r}; choose one of {', '.join(REGISTRY)}") from None


_SWARM_TEXT = {
    "iabc": "improved artificial bee colony over B-splines (document 002)",
    "abc": "artificial bee colony (Karaboga 2005) over B-splines",
    "ga": "real-coded genetic algorithm (SBX, polynomial mutation) over B-splines",
    "pso": "particle swarm (Clerc-Kennedy constants) over B-splines",
    "de": "scipy's differential evolution (vectorised) over B-splines",
}
for _name, _text in _SWARM_TEXT.items():
    register(_name, iterative=True, description=_text)(plan_swarm)


@register("flow", iterative=False, description="potential-flow streamline from the start (document 000)")
def _flow(problem: PlanningProblem, spec: PlannerSpec, rng: RngLike = None,
          progress: Progress | None = None) -> PlanResult:
    return plan_flow(problem, spec.flow)


@register("grid", iterative=False, description="lattice reference: Dijkstra cost-to-go, elastic band, B-spline")
def _grid(problem: PlanningProblem, spec: PlannerSpec, rng: RngLike = None,
          progress: Progress | None = None) -> PlanResult:
    return plan_grid(problem, spec)


@register("timeopt", iterative=False, description="time-optimal path in tidal currents, departure time given")
def _timeopt(problem: PlanningProblem, spec: PlannerSpec, rng: RngLike = None,
             progress: Progress | None = None) -> PlanResult:
    return plan_timeopt(problem, spec)


if tuple(REGISTRY) != PLANNERS:  # pragma: no cover - a programming error
    raise RuntimeError(f"registry {tuple(REGISTRY)} does not match PLANNERS {PLANNERS}")
