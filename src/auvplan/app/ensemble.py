"""``auvplan plan`` with ``[currents] members`` (issue 39): the plan flown and scored in every member, and the
robust plan of ``[planner] robust``."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._types import Status
from ..planners.core.base import PlanResult
from ..runtime.parallel import Runner
from ..sim import Mission
from ..world import CurrentField, World

__all__ = ["ensemble_plan"]

def ensemble_plan(members: tuple[tuple[str, CurrentField], ...], world: World, mission: Mission,
                  seed: int, runner: Runner | None = None) -> tuple[PlanResult, dict[str, Any]]:
    """The plan to report and its ensemble fields for ``plan --json``.

    With ``[planner] robust = "none"`` the nominal plan is kept; otherwise the robust plan
    (:func:`auvplan.sim.ensemble.robust.plan_robust`).  Either is flown in every member.

    Parameters
    ----------
    members : tuple of (str, CurrentField)
        The ensemble (:func:`auvplan.io.scenario.inputs.members.scenario_members`).
    world : World
        Its world.
    mission : Mission
        Its mission, with the planner settings in force (command-line overrides applied).
    seed : int
        The planner's seed.
    runner : Runner, optional
        Where the robust candidates are planned (:class:`auvplan.runtime.parallel.Runner`; this process by default).

    Returns
    -------
    plan : PlanResult
        The plan to report.
    fields : dict
        ``robust``, ``robust_candidate``, ``arrival_p50_s``, ``arrival_p90_s``, ``success_probability``,
        ``members`` (each ``name``, ``arrival_s``, ``status``, ``success``, ``energy_wh``, ``heading_deg``)
        and ``nominal`` (the nominal plan's P50, P90 and success probability).
    """
    from ..sim.ensemble.robust import plan_robust

    robust = plan_robust(world, mission, members, mission.planner.robust, seed, runner)
    chosen = robust.chosen
    fields: dict[str, Any] = {"robust": mission.planner.robust, "robust_candidate": chosen.label}
    if chosen.score is not None:
        fields.update(chosen.score.as_dict())
    else:  # no route: the plan failed, nothing arrives
        fields.update({"arrival_p50_s": None, "arrival_p90_s": None, "success_probability": 0.0,
                       "members": [{"name": n, "arrival_s": None, "status": "INFEASIBLE", "success": False}
                                   for n, _ in members]})
    if robust.nominal.score is not None:
        n = robust.nominal.score
        fields["nominal"] = {"arrival_p50_s": n.arrival_p50_s, "arrival_p90_s": n.arrival_p90_s,
                             "success_probability": n.success_probability}
    plan = chosen.plan
    if plan is None:  # a fixed [mission] route: no planner ran
        route = chosen.route if chosen.route is not None else np.asarray(mission.route, dtype=float)
        plan = PlanResult(Status.EXACT, route, 0.0, {}, 0, 0, 0.0, np.empty(0), "route")
    return plan, fields
