"""Missions and their closed-loop simulation, one vehicle (formations: :mod:`auvplan.sim.formation`).

Each idea has its module; every public name is importable from :mod:`auvplan.sim` itself:

* :mod:`~auvplan.sim.mission`: what to fly (:class:`Mission`, :class:`SimParams`);
* :mod:`~auvplan.sim.events`: the event rules of one step (contact, arrival, progress, deadlock);
* :mod:`~auvplan.sim.loop`: the fixed-step closed loop (:func:`simulate`, :func:`make_guidance`);
* :mod:`~auvplan.sim.result`: what a run produced (:class:`SimResult`, :class:`SimMetrics`,
  :class:`RunRecord`, :func:`decimate`);
* :mod:`~auvplan.sim.pipeline`: plan → mission route → key waypoints → simulation (:func:`run_mission`);
* :mod:`~auvplan.sim.band`: a terrain-following run's altitude against its band (``metrics.json``).
"""

from __future__ import annotations

from .loop import make_guidance, simulate
from .mission import Mission, SimParams, SimSettings
from .pipeline import (
    mission_route,
    planned_route,
    planning_problem,
    record_tail,
    route_from_path,
    run_mission,
    with_leg_speeds,
)
from .result import RunRecord, SimMetrics, SimResult, decimate

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
