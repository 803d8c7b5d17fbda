"""``auvplan plan`` with ``[currents] members`` (issue 39): the plan flown and scored in every member, and the
robust plan of ``[planner] robust``."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from .._types import Status
from ..io.data.geo import LocalFrame
from ..io.scenario.members import member_fields
from ..io.scenario.specs import Scenario
from ..parallel import Runner
from ..planners.base import PlanResult
from ..sim import Mission
from ..world import CurrentField, World

__all__ = ["scenario_members", "ensemble_plan", "route_fields", "write_ensemble", "read_ensemble", "ENSEMBLE_FILE"]

ENSEMBLE_FILE = "ensemble.json"
"""The results folder's ensemble fields (``plan --out``, ``run --out``), read by ``report``."""


def scenario_members(sc: Scenario, world: World) -> tuple[tuple[str, CurrentField], ...]:
    """The scenario's ensemble members, read and checked against the world's bounds.

    Parameters
    ----------
    sc : Scenario
        The scenario (its ``[currents] members``).
    world : World
        Its world (bounds and nominal current).

    Returns
    -------
    tuple of (str, CurrentField)
        Name and field of each member; empty without members.
    """
    if not sc.currents.members:
        return ()
    b = world.bounds
    frame = LocalFrame(sc.origin.lat, sc.origin.lon) if sc.origin else None
    return member_fields(sc.currents.members, world.currents, frame, (b.xmin, b.xmax, b.ymin, b.ymax),
                         source=sc.source, base_dir=sc.base_dir, start_time=sc.mission.start_time)


def ensemble_plan(members: tuple[tuple[str, CurrentField], ...], world: World, mission: Mission,
                  seed: int, runner: Runner | None = None) -> tuple[PlanResult, dict[str, Any]]:
    """The plan to report and its ensemble fields for ``plan --json``.

    With ``[planner] robust = "none"`` the nominal plan is kept; otherwise the robust plan
    (:func:`auvplan.ensemble.plan_robust`).  Either is flown in every member.

    Parameters
    ----------
    members : tuple of (str, CurrentField)
        The ensemble (:func:`scenario_members`).
    world : World
        Its world.
    mission : Mission
        Its mission, with the planner settings in force (command-line overrides applied).
    seed : int
        The planner's seed.
    runner : Runner, optional
        Where the robust candidates are planned (:class:`auvplan.parallel.Runner`; this process by default).

    Returns
    -------
    plan : PlanResult
        The plan to report.
    fields : dict
        ``robust``, ``robust_candidate``, ``arrival_p50_s``, ``arrival_p90_s``, ``success_probability``,
        ``members`` (each ``name``, ``arrival_s``, ``status``, ``success``, ``energy_wh``, ``heading_deg``)
        and ``nominal`` (the nominal plan's P50, P90 and success probability).
    """
    from ..ensemble import plan_robust

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


def route_fields(members: tuple[tuple[str, CurrentField], ...], world: World, mission: Mission,
                 route: Any) -> dict[str, Any]:
    """A flown mission's route scored in every member: the ``plan --json`` ensemble fields.

    Parameters
    ----------
    members : tuple of (str, CurrentField)
        The ensemble (:func:`scenario_members`).
    world : World
        Its world.
    mission : Mission
        Its mission (the vehicle).
    route : array_like
        ``(N, 3)`` mission waypoints (m).

    Returns
    -------
    dict
        ``arrival_p50_s``, ``arrival_p90_s``, ``success_probability``, ``members``; empty without
        members or a route.
    """
    from ..ensemble import score_route

    p = np.asarray(route, dtype=float).reshape(-1, 3)
    if not members or p.shape[0] < 2:
        return {}
    return score_route(world, members, p, mission.vehicle).as_dict()


def write_ensemble(out: Path, fields: dict[str, Any]) -> None:
    """Write the ensemble fields into ``out/ensemble.json`` (infinite times as null); remove a stale one
    when there are none.

    Parameters
    ----------
    out : pathlib.Path
        The results folder (prepared by the command: the name is one of its files).
    fields : dict
        The ``plan --json`` ensemble fields, or empty.
    """
    from ..io.safeio import atomic_write

    path = Path(out) / ENSEMBLE_FILE
    if not fields:
        if path.is_file() and not path.is_symlink():
            path.unlink()
        return

    def clean(v: Any) -> Any:
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        if isinstance(v, list | tuple):
            return [clean(x) for x in v]
        if isinstance(v, float) and not math.isfinite(v):
            return None
        return v

    atomic_write(path, json.dumps(clean(fields), indent=1) + "\n")


def read_ensemble(out: Path) -> dict[str, Any] | None:
    """The ensemble fields of a results folder (``ensemble.json``), if it has them.

    Parameters
    ----------
    out : pathlib.Path
        The results folder.

    Returns
    -------
    dict or None
        The fields; None without the file (or when it is not a JSON object).
    """
    path = Path(out) / ENSEMBLE_FILE
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None
