"""Missions and their closed-loop simulation, one vehicle (formations: :mod:`auvplan.sim.formation`).

Each idea has its module; every public name is importable from :mod:`auvplan.sim` itself:

* :mod:`~auvplan.sim.mission`: what to fly (:class:`Mission`, :class:`SimParams`);
* :mod:`~auvplan.sim.events`: the event rules of one step (contact, arrival, progress, deadlock);
* :mod:`~auvplan.sim.loop`: the fixed-step closed loop (:func:`simulate`, :func:`make_guidance`);
* :mod:`~auvplan.sim.result`: what a run produced (:class:`SimResult`, :class:`SimMetrics`,
  :class:`RunRecord`, :func:`decimate`);
* :mod:`~auvplan.sim.pipeline`: plan → mission route → key waypoints → simulation (:func:`run_mission`);
* :mod:`~auvplan.sim.navigation`: the navigation budget as flown (``[navigation]``: its fixes and each leg's drift
  through the water);
* :mod:`~auvplan.sim.band`: a terrain-following run's altitude against its band (``metrics.json``);
* :mod:`~auvplan.sim.problem`: a mission's planning problem (:func:`planning_problem`).

The loop's and the pipeline's names are imported at their first access (``plan`` needs neither).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..runtime.lazy import lazy_attributes
from .mission import Mission, SimParams, SimSettings
from .result import RunRecord, SimMetrics, SimResult, decimate

if TYPE_CHECKING:  # pragma: no cover - for type checkers only
    from .loop import make_guidance, simulate
    from .pipeline import (
        mission_route,
        planned_route,
        record_tail,
        route_from_path,
        run_mission,
        with_leg_speeds,
    )
    from .problem import planning_problem

__all__ = [
    "SimParams",
    "SimSettings",
    "Mission",
    "SimResult",
    "SimMetrics",
    "RunRecord",
    "planning_problem",
    "make_guidance",
    "simulate",
    "run_mission",
    "route_from_path",
    "mission_route",
    "planned_route",
    "decimate",
    "with_leg_speeds",
    "record_tail",
]

_LAZY = {name: "auvplan.sim.loop" for name in ("make_guidance", "simulate")} | {
    name: "auvplan.sim.pipeline" for name in ("mission_route", "planned_route", "record_tail",
                                                "route_from_path", "run_mission", "with_leg_speeds")} | {
    "planning_problem": "auvplan.sim.problem"}
"""Loaded on first access: a plan builds a :class:`Mission` and flies nothing (issue 56: guidance, vehicles'
dynamics and the pipeline are not imported for ``plan``)."""


__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, __all__)
