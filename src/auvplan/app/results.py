"""The one writer of a results folder, for ``run``/``demo``, ``plan --out`` and the planning page's save:
the run files, what makes the folder self-contained (the scenario's source, its terrain), the energy files,
every mission export and ``report.html``; and a folder written before, read back for ``report``/``export``.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import AuvplanError
from ..io.files.safeio import atomic_write, prepare_out, save_figure

if TYPE_CHECKING:
    from ..endurance import Endurance
    from ..io.missions.readback.mission_storage import BoardStorage
    from ..io.scenario.specs import Scenario
    from ..nav import NavPlan
    from ..planners import PlanResult
    from ..sim import Mission, RunRecord
    from ..world import World

__all__ = ["FIGURES", "scenario_text", "save_context", "save_plan", "write_results", "write_report",
           "planned_speeds", "load_results"]


def scenario_text(sc: Scenario, world: World | None = None) -> str:
    """The text of the scenario file, with the ``[origin]`` and ``[bounds]`` the build derived from ``world``
    written in (issue 51, :func:`auvplan.io.scenario.saved.with_derived_frame`).

    Parameters
    ----------
    sc : Scenario
        The scenario.
    world : World, optional
        The world built from it (None: the text as it is).

    Returns
    -------
    str
        The file's text (empty where it cannot be read).
    """
    from ..io.scenario.saved import with_derived_frame

    try:
        text = Path(sc.source).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return ""
    return with_derived_frame(text, world) if world is not None else text


def save_context(out: Path, source: str, world: World) -> None:
    """What makes a results folder self-contained: the scenario file's path and the terrain it used.

    Parameters
    ----------
    out : pathlib.Path
        The folder.
    source : str
        The scenario file's path.
    world : World
        The world (its terrain is saved).
    """
    from ..io.files.jsonfile import scenario_origin
    from ..io.results import folder as results
    from ..io.results import records

    # the original scenario, followed now: a results folder's scenario.toml run again into its own folder
    # (--force) recorded itself, and its relative data paths were lost ('zones.geojson': not found)
    origin = scenario_origin(Path(source).resolve()).resolve()
    records.write_json(out / "source.json", {"scenario_source": str(origin)})
    results.save_terrain(out, world.terrain)


def save_plan(out: Path, sc: Scenario, world: World, result: PlanResult, seed: int,
              ensemble: dict[str, Any] | None = None) -> None:
    """``plan --out``: the plan files plus a run record without a flight, so report/export work on it.

    Parameters
    ----------
    out : pathlib.Path
        The folder, prepared by the caller.
    sc : Scenario
        The scenario.
    world : World
        Its world.
    result : PlanResult
        The plan.
    seed : int
        Its seed.
    ensemble : dict, optional
        The ensemble fields of the plan (``ensemble.json``).
    """
    from ..io.results import records
    from ..io.results.ensemble import write_ensemble
    from ..sim import RunRecord

    text = scenario_text(sc, world)
    empty = result.path[:0].reshape(0, 3)
    records.write_run(out, RunRecord(sc.name, seed, result, empty, empty, None), text, origin=world.origin)
    save_context(out, sc.source, world)
    write_ensemble(out, ensemble or {})


def write_results(out: Path, world: World, mission: Mission, record: RunRecord, text: str, source: str, *,
                  full: bool = False, endurance: Endurance | None = None,
                  ensemble: dict[str, Any] | None = None, board: BoardStorage | None = None) -> list[str]:
    """Write a flown (or planned) mission's results folder: ``ensemble.json`` (when ``ensemble`` is given),
    the run files, ``source.json`` and the terrain, the energy files, every mission export and the report.

    Parameters
    ----------
    out : pathlib.Path
        The folder, prepared by the caller (:func:`auvplan.io.files.safeio.prepare_out`).
    world, mission : World, Mission
        What was flown.
    record : RunRecord
        The run.
    text : str
        The scenario file's text (``scenario.toml`` of the folder).
    source : str
        The scenario file's path (``source.json``: where relative data paths were resolved).
    full : bool
        Full-rate time series and exports instead of decimated ones.
    endurance : Endurance, optional
        The mission's energy assessment; computed here when not given.
    ensemble : dict, optional
        The ensemble fields of the route (:func:`auvplan.app.run.run_scenario`'s scoring in every member).
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a ``.plan`` it cannot hold is left out (:func:`write_report`).

    Returns
    -------
    list of str
        Notes on the exports (a format that would fly a tail-first leg nose-first), for the caller to show.
    """
    from ..io.data.geo import LocalFrame
    from ..io.missions.energy import mission_endurance, write_energy
    from ..io.results import records
    from ..io.scenario.saved import with_derived_frame

    text = with_derived_frame(text, world)  # issue 51: the derived [origin] and [bounds] kept with the results
    if ensemble is not None:
        from ..io.results.ensemble import write_ensemble

        write_ensemble(out, ensemble)
    records.write_run(out, record, text, full, world.origin)
    save_context(out, source, world)
    if endurance is None:
        endurance = mission_endurance(world, mission, record)
    if endurance is not None:
        frame = LocalFrame(*world.origin) if world.origin is not None else None
        write_energy(out, endurance, frame.inverse if frame else None)
    return write_report(out, world, mission, record, text, full=full, endurance=endurance, board=board)[1]


def write_report(out: Path, world: World, mission: Mission, record: RunRecord, text: str, figures: bool = False,
                 full: bool = False, endurance: Endurance | None = None,
                 board: BoardStorage | None = None) -> tuple[Path, list[str]]:
    """The report, ``report.html`` (and the exports, and with ``figures`` the static PNG/SVG figures) into ``out``.

    Parameters
    ----------
    out : pathlib.Path
        The results folder.
    world, mission : World, Mission
        What was flown.
    record : RunRecord
        The run.
    text : str
        The scenario file's text.
    figures : bool
        Also the static figures (``figures/``).
    full : bool
        Full-rate exports.
    endurance : Endurance, optional
        The energy assessment; computed here when not given.
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a ``.plan`` it cannot hold is left out, said in the notes.

    Returns
    -------
    path : pathlib.Path
        The report.
    notes : list of str
        Notes on the exports, for the caller to show.
    """
    from ..io.data.geo import LocalFrame
    from ..io.missions import export
    from ..io.missions.energy import mission_endurance
    from ..io.results import records
    from ..io.results.ensemble import read_ensemble
    from ..viz.report import build_report

    frame = LocalFrame(*world.origin) if world.origin is not None else None
    formats, notes = export.exportable(record, [f for f in export.EXPORT_FORMATS
                                                if frame is not None or f not in export.GEOGRAPHIC])
    speeds = planned_speeds(out, record, mission)
    deploy = export.deploy_for(world, mission, record, speeds, export.survey_payload(out, record))
    notes = [*notes, *export.write_mission_files(out, record, world.origin, speeds, formats, full, deploy, board)]
    if endurance is None:
        endurance = mission_endurance(world, mission, record)
    metrics = records.summary_metrics(record)
    if world.terrain is not None and world.terrain.fit is not None:
        metrics.update(records.fit_metrics(world.terrain.fit))
    page = build_report(world, record, text, metrics, frame.inverse if frame else None, endurance, read_ensemble(out))
    path = atomic_write(out / "report.html", page)
    if figures:
        from ..viz import plots

        plots.write_mission_figures(out / "figures", world, record, save=save_figure,
                                    to_lonlat=frame.inverse if frame else None)
    return path, list(notes)


def planned_speeds(out: Path, record: RunRecord, mission: Mission) -> float | np.ndarray:
    """The speed of each leg of the mission.

    Parameters
    ----------
    out : pathlib.Path
        The results folder (its ``legs.csv``).
    record : RunRecord
        The run.
    mission : Mission
        The mission (its vehicle's speed; a plan folder's leg speeds, :func:`load_results`).

    Returns
    -------
    float or numpy.ndarray
        The planned speed of each leg, else the vehicle's speed.
    """
    from ..io.missions.energy import read_leg_speeds

    speeds = read_leg_speeds(out, max(record.route.shape[0] - 1, 0))
    if speeds is None and len(mission.leg_speeds) == record.route.shape[0] - 1 > 0:  # a plan folder's (load_results)
        return np.asarray(mission.leg_speeds, dtype=float)
    return mission.vehicle.speed if speeds is None else speeds


FIGURES = tuple(f"figures/{n}.{f}" for n in ("plan_view", "profiles", "convergence") for f in ("png", "svg"))
"""Files of ``report --figures``."""


def load_results(folder: str | Path, names: list[str], force: bool = False
                 ) -> tuple[Path, RunRecord, str, World, Mission]:
    """A results folder written before: its record, scenario text and the World and Mission rebuilt.

    Parameters
    ----------
    folder : str or pathlib.Path
        The results folder.
    names : list of str
        The files the caller will write into it (checked first: no user file or link in the way).
    force : bool
        Replace those files when they exist.

    Returns
    -------
    tuple
        The folder, the run record (a plan without a flight gets its executable mission as route, with the
        position fixes ``[navigation]`` plans, as ``run`` flies it), the scenario text, the World and the Mission.
    """
    from ..io.results import folder as results
    from ..io.results import records
    from ..io.results.readback import check_scenario
    from ..io.scenario import loader as scenario_io
    from ..sim import mission_route
    from ..sim.pipeline import with_leg_speeds

    out = Path(folder)
    if not out.is_dir():
        raise AuvplanError(f"{out}: no such results folder")
    prepare_out(out, names, force=force)
    record, text = records.read_run(out)
    if not text:
        raise AuvplanError(f"{out}/scenario.toml: missing — the report needs the scenario to rebuild the world")
    check_scenario(out)  # the scenario the run saved, not one put there after it
    sc = scenario_io.loads(text, str(out / "scenario.toml"), base_dir=results.scenario_base(out))
    world, mission = scenario_io.build(sc, terrain=results.load_terrain(out))
    flown = bool(record.route.size)
    if not flown and record.plan is not None and record.plan.path.size:
        # a plan without a flight: export the executable mission, not the raw planned curve
        record = replace(record, route=mission_route(world, mission, record.plan.path))
    if mission.navigation is not None and record.nav is None and record.route.shape[0] >= 2:
        nav = _navigation(out, world, mission, record.route, flown)
        # a plan's mission carries its fixes, as run's does: the surfacings (depth 0) and USBL fix waypoints, so that
        # its exports surface, wait surface_s there (.plan param 1, MOOS station keep) and pass their check
        record = replace(record, nav=nav, route=record.route if flown or nav is None else nav.points)
    if not flown and record.route.shape[0] >= 2:  # the speeds [endurance] chooses for its legs, as run flies them
        mission = with_leg_speeds(world, mission, record.route)
    return out, record, text, world, mission


def _navigation(out: Path, world: World, mission: Mission, route: np.ndarray, flown: bool) -> NavPlan | None:
    """A results folder's navigation read back (issue 52): the fixes in its route (surface waypoints, and the
    USBL fixes of its ``fixes.csv``) with their budget; a plan without a flight gets its fixes planned."""
    from ..io.missions.energy import read_leg_speeds
    from ..io.missions.readback.fixes import fix_kinds
    from ..nav import navigation_of
    from ..sim.navigation import navigation_plan, timed_navigation

    nav = mission.navigation
    assert nav is not None
    if not flown:
        return navigation_plan(world, mission, route)
    kinds, _ = fix_kinds(route, out / "mission.csv", world.origin)
    speeds = read_leg_speeds(out, route.shape[0] - 1)  # the fixes' times as run timed them
    timed = mission if speeds is None else replace(mission, leg_speeds=tuple(float(v) for v in speeds))
    return timed_navigation(world, timed, navigation_of(world, route, kinds, nav, mission.vehicle.speed, nav.usbl_xy))
