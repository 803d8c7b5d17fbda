"""auvplan — plan, check and simulate 3D missions for autonomous underwater vehicles.

The public API (imported lazily, so ``import auvplan`` stays cheap)::

    import auvplan

    world, mission = auvplan.load_scenario("marcus-wake")
    result = auvplan.plan(auvplan.planning_problem(world, mission), mission.planner, rng=1)
    record = auvplan.run_mission(world, mission)          # plan → key waypoints → closed loop
    print(result.status, record.status is auvplan.Status.EXACT)

Layers (each imports only from those below; checked by import-linter):
``cli`` → ``bench | io | viz`` → ``sim`` → ``planners | guidance | vehicles`` →
``cost | metrics`` → ``world | path | optim`` → ``errors | geometry | _types | _jit``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ._version import __version__
from .runtime.lazy import lazy_attributes

_LAZY = {
    "Status": "auvplan._types",
    "AuvplanError": "auvplan.errors",
    "ScenarioError": "auvplan.errors",
    "DataError": "auvplan.errors",
    "World": "auvplan.world",
    "Bounds": "auvplan.world",
    "Margins": "auvplan.world",
    "Terrain": "auvplan.world",
    "PlanningProblem": "auvplan.planners",
    "PlannerSpec": "auvplan.planners",
    "PlanResult": "auvplan.planners",
    "plan": "auvplan.planners",
    "Mission": "auvplan.sim",
    "SimResult": "auvplan.sim",
    "RunRecord": "auvplan.sim",
    "planning_problem": "auvplan.sim",
    "simulate": "auvplan.sim",
    "run_mission": "auvplan.sim",
}

__all__ = [
    "__version__",
    "load_scenario",
    "Status",
    "AuvplanError",
    "ScenarioError",
    "DataError",
    "World",
    "Bounds",
    "Margins",
    "Terrain",
    "PlanningProblem",
    "PlannerSpec",
    "PlanResult",
    "plan",
    "Mission",
    "SimResult",
    "RunRecord",
    "planning_problem",
    "simulate",
    "run_mission",
]

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs only
    from ._types import Status
    from .errors import AuvplanError, DataError, ScenarioError
    from .planners import PlannerSpec, PlanningProblem, PlanResult, plan
    from .sim import Mission, RunRecord, SimResult, planning_problem, run_mission, simulate
    from .world import Bounds, Margins, Terrain, World


__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, __all__)


def load_scenario(scenario: str) -> tuple[World, Mission]:
    """Read a scenario (a TOML file or a built-in name) and build its World and Mission.

    Parameters
    ----------
    scenario : str or path
        Path of a scenario TOML file, or the name of a built-in scenario
        (``auvplan scenarios`` lists them).

    Returns
    -------
    world : World
        Seabed, currents, static and moving obstacles, margins.
    mission : Mission
        End points, route and the settings of every component.

    Raises
    ------
    ScenarioError
        The file is malformed (the message names the file, key and value).
    DataError
        Gridded input data referenced by the scenario is unusable.
    """
    from .io.scenario import loader as _scenario

    return _scenario.build(_scenario.load(scenario))
