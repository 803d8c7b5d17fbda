"""What the page asks the planners for, as data in, data out: a survey of an area, a new plan, a flight.

Each goes through the code the command line runs: the ``[survey]`` table is validated by the scenario
loader and planned by :func:`auvplan.survey.mission.plan_survey` (``auvplan survey``), a plan is
:func:`auvplan.sim.planned_route` (``auvplan run``'s global plan and executable mission), a flight
:func:`auvplan.sim.simulate` with the key waypoints and leg speeds ``run`` gives it.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...errors import AuvplanError
from ...io.scenario import loader as scenario_io
from ...io.scenario.specs import Scenario
from ...planners import PlanResult
from ...sim import Mission, SimResult, planned_route, with_leg_speeds
from ...world import World
from .paths import Roots
from .tomlout import dumps

__all__ = ["PlannedSurvey", "as_points", "survey_table", "plan_area", "replanned", "flown", "nearest_leg"]

_F64 = NDArray[np.float64]


def as_points(value: Any, what: str) -> _F64:
    """Numbers sent by the page as an array, all finite.

    Parameters
    ----------
    value : object
        A number or nested lists of numbers.
    what : str
        What they are, for the message.

    Returns
    -------
    numpy.ndarray
        The numbers.
    """
    try:
        p = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise AuvplanError(f"{what}: not a list of numbers") from None
    if not np.isfinite(p).all():
        raise AuvplanError(f"{what}: every coordinate must be a finite number")
    return p


@dataclass(frozen=True, eq=False)
class PlannedSurvey:
    """A survey planned from a scenario document.

    Attributes
    ----------
    doc, text, scenario : dict, str, Scenario
        The document with its ``[survey]``, as TOML, validated.
    area : list of [x, y]
        The area's outline in the local frame (m).
    route : numpy.ndarray
        ``(N, 3)`` the survey mission: transit out, lines and turns, transit home (m).
    label : str
        One line: how many lines, how long.
    """

    doc: dict[str, Any]
    text: str
    scenario: Scenario
    area: list[list[float]]
    route: _F64
    label: str


def survey_table(doc: dict[str, Any], polygon_xy: Any = None, file: Path | None = None) -> dict[str, Any]:
    """``doc`` with its ``[survey]`` area replaced by a polygon in the local frame or a vector file.

    Parameters
    ----------
    doc : dict
        The scenario document (not changed).
    polygon_xy : array_like, optional
        ``(K, 2)`` polygon (m), K >= 3.
    file : pathlib.Path, optional
        GeoJSON or KML file (its largest polygon).

    Returns
    -------
    dict
        The new document; the other ``[survey]`` keys (sensor, overlap, heading...) are kept.
    """
    out = copy.deepcopy(doc)
    table = {k: v for k, v in out.get("survey", {}).items() if k not in ("polygon", "polygon_xy", "file", "layer")}
    if file is not None:
        table["file"] = str(file)
    else:
        p = as_points(polygon_xy, "survey polygon").reshape(-1, 2)
        if p.shape[0] < 3:
            raise AuvplanError(f"survey polygon: {p.shape[0]} points; an area needs at least 3")
        table["polygon_xy"] = [[float(a), float(b)] for a, b in p]
    out["survey"] = table
    return out


def plan_area(world: World, mission: Mission, doc: dict[str, Any], source: str,
              base_dir: Path | None, roots: Roots | None = None) -> PlannedSurvey:
    """Validate ``doc`` and plan its ``[survey]`` (``auvplan survey``'s plan, without the flight).

    Parameters
    ----------
    world, mission : World, Mission
        The scenario's.
    doc : dict
        The document with a ``[survey]`` table.
    source : str
        The scenario's file, for messages.
    base_dir : pathlib.Path or None
        Folder relative paths resolve against.
    roots : Roots, optional
        The served folders: every file the document names must lie inside.

    Returns
    -------
    PlannedSurvey
        The survey; a plan that fails is an error naming why.
    """
    from ...io.results.survey import survey_params
    from ...survey.mission import plan_survey

    text = dumps(doc)
    if roots is not None:  # the survey file the loader reads (to derive the bounds), before it does
        roots.confine_text(text, source, base_dir)
    sc = scenario_io.loads(text, source, base_dir=base_dir)
    if roots is not None:
        roots.confine(sc)
    if sc.survey is None:
        raise AuvplanError(f"{source}: no [survey] table")
    params = survey_params(sc.survey, world, mission.vehicle, base_dir, f"{source}: [survey]")
    plan = plan_survey(world, mission, params, sc.seed)
    if not plan.status.ok:
        raise AuvplanError(f"{source}: [survey] {plan.status.value}: {plan.message}")
    area = [list(map(float, c)) for c in params.area.exterior.coords]
    return PlannedSurvey(doc, text, sc, area, plan.route,
                         f"{len(plan.lines.lines)} lines, {plan.length_m / 1e3:.1f} km")


def replanned(world: World, mission: Mission, planner: str, seed: Any,
              progress: Callable[[int, float], None] | None = None) -> tuple[PlanResult | None, _F64]:
    """Plan the mission from its start to its goal again, and build its executable mission.

    Parameters
    ----------
    world, mission : World, Mission
        The scenario's (a fixed ``[mission] route`` is ignored).
    planner : str
        A registered planner.
    seed : int
        Seed >= 0.
    progress : callable, optional
        ``progress(iteration, best)`` of a swarm planner (the page's stop raises from it).

    Returns
    -------
    tuple
        The plan and the mission ``(N, 3)`` (m).
    """
    from ...planners.core.registry import names

    if planner not in names():
        raise AuvplanError(f"--planner {planner!r}: choose one of {', '.join(names())}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise AuvplanError(f"--seed {seed!r}: must be an integer >= 0")
    m = replace(mission, planner=replace(mission.planner, name=planner), route=())
    plan, route = planned_route(world, m, seed, progress)
    if route is None:
        status = plan.status.value if plan is not None else "INFEASIBLE"
        raise AuvplanError(f"plan with {planner} seed {seed}: {status} — {plan.message if plan else ''}")
    return plan, route


def flown(world: World, mission: Mission, waypoints: _F64, seed: int,
          progress: Callable[[float, float], object] | None = None) -> SimResult:
    """Fly ``waypoints`` in the closed loop as ``auvplan run`` flies its mission.

    Parameters
    ----------
    world, mission : World, Mission
        Currents, obstacles, vehicle, guidance and avoidance.
    waypoints : numpy.ndarray
        ``(N, 3)`` the mission (m).
    seed : int
        Seed of the simulation.
    progress : callable, optional
        ``progress(t, expected)`` every simulated minute (the page's stop raises from it).

    Returns
    -------
    SimResult
        The flight.
    """
    from ...guidance.avoidance.local import key_waypoints
    from ...sim import simulate

    keys = key_waypoints(waypoints, world, mission.avoidance.collision_check)
    return simulate(world, with_leg_speeds(world, mission, waypoints), route=waypoints, rng=seed, keys=keys,
                    progress=progress)


def nearest_leg(w: _F64, p: _F64) -> tuple[int, float]:
    """The leg of ``w`` nearest to the horizontal point ``p`` and the fraction along it.

    Parameters
    ----------
    w : numpy.ndarray
        ``(N, 3)`` waypoints (m).
    p : numpy.ndarray
        ``(2,)`` point (m).

    Returns
    -------
    tuple of (int, float)
        Leg index and the fraction in [0, 1] of its nearest point.
    """
    a, b = w[:-1, :2], w[1:, :2]
    d = b - a
    den = np.maximum((d * d).sum(-1), 1e-12)
    f = np.clip(((p - a) * d).sum(-1) / den, 0.0, 1.0)
    dist = np.hypot(*(a + f[:, None] * d - p).T)
    k = int(np.argmin(dist))
    return k, float(f[k]) if math.isfinite(f[k]) else 0.5
