"""``run`` and ``demo`` as jobs: plan, key waypoints and the closed-loop flight of one vehicle (or a formation),
and their results folder.  Progress goes to the caller's reporter (:class:`auvplan.app.Reporter`); nothing
is printed."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..io.files.safeio import RESULT_NAMES, atomic_write, prepare_out
from . import ReporterFor, silent
from .results import save_context, scenario_text, write_results

if TYPE_CHECKING:
    from ..endurance import Endurance
    from ..io.missions.readback.mission_storage import BoardStorage
    from ..io.scenario.specs import Scenario
    from ..sim import Mission, RunRecord
    from ..world import CurrentField, World

__all__ = ["DEMO_SCENARIO", "run_scenario", "run_formation_scenario"]

DEMO_SCENARIO = "showcase"
"""The built-in default scenario: a real seamount flank, two eddies and twelve fast moving obstacles."""


def run_scenario(scenario: str, out: str | None, guidance: str | None, avoidance: str | None, seed: int | None,
                 full: bool = False, force: bool = False, planner: str | None = None,
                 reporter: ReporterFor = silent,
                 board: BoardStorage | None = None) -> tuple[Scenario, RunRecord, Endurance | None, list[str]]:
    """Plan and fly one scenario (``run``, ``demo``); with ``out``, its results folder, report and exports.

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file.
    out : str, optional
        The results folder (checked before any work).
    guidance, avoidance : str, optional
        Override the scenario's.
    seed : int, optional
        Override the scenario's.
    full, force : bool
        Full-rate files; replace the folder's result files.
    planner : str, optional
        Override the scenario's planner.
    reporter : callable
        Builds the progress reporter from the planner's settings and the scenario's name.
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a ``mission.plan`` it cannot hold is left out (a note).

    Returns
    -------
    tuple
        The scenario, the run record, its energy assessment (or None) and the notes: the rule applied to currents
        past the file (``currents: …``, issue 51), then those on the exports.
    """
    from ..io.missions.energy import mission_endurance
    from ..io.scenario import loader as scenario_io
    from ..io.scenario.inputs.members import scenario_members
    from ..sim import run_mission

    if out:
        prepare_out(out, RESULT_NAMES, force=force, job="run", inputs=(scenario,))
    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    if planner:
        mission = replace(mission, planner=replace(mission.planner, name=planner))
    seed = sc.seed if seed is None else seed
    bar = reporter(mission.planner, sc.name)
    try:
        record = run_mission(world, mission, seed, bar, guidance=guidance, avoidance=avoidance, flight=bar.flight)
    finally:
        bar.close()
    from ..io.scenario.inputs.currentspan import run_note

    note = run_note(sc.source, sc.currents.beyond, world, record)  # issue 51: currents past the file refused or said
    endurance = mission_endurance(world, mission, record)
    notes: list[str] = []
    if out:
        bar.stage(f"writing results, report and exports into {out}")
        ensemble = _route_fields(scenario_members(sc, world), world, mission, record.route)
        notes = write_results(Path(out), world, mission, record, scenario_text(sc), sc.source, full=full,
                              endurance=endurance, ensemble=ensemble, board=board)
    return sc, record, endurance, ([note] if note else []) + notes


def _formation_names(mission: Mission) -> list[str]:
    """The files a formation's results folder holds (the fleet's, and each vehicle's run files)."""
    from ..io.missions.formation import FORMATION_NAMES

    assert mission.formation is not None
    return [*FORMATION_NAMES, *(f"{v.name}/{f}" for v in mission.formation.vehicles for f in RESULT_NAMES)]


def run_formation_scenario(sc: Scenario, world: World, mission: Mission, out: str | None, seed: int | None,
                           full: bool = False, force: bool = False, planner: str | None = None,
                           reporter: ReporterFor = silent,
                           board: BoardStorage | None = None) -> tuple[Any, dict[str, Any]]:
    """``run`` of a scenario with ``[[vehicles]]``: the formation pipeline, and with ``out`` its files and report.

    Parameters
    ----------
    sc : Scenario
        The scenario.
    world, mission : World, Mission
        Built from it.
    out : str, optional
        The results folder, checked before any work.
    seed : int, optional
        Override the scenario's.
    full, force : bool
        Full-rate files; replace the folder's result files.
    planner : str, optional
        Override the scenario's planner.
    reporter : callable
        Builds the progress reporter.
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a vehicle's ``.plan`` it cannot hold is refused (exit 2).

    Returns
    -------
    record : FormationRecord
        The fleet's run.
    summary : dict
        Its JSON record (:func:`auvplan.io.missions.formation.formation_record`).
    """
    from ..io.data.geo import LocalFrame
    from ..io.missions.formation import formation_record, vehicle_records, write_formation
    from ..sim.formation import run_formation

    assert mission.formation is not None  # called only for a scenario with [[vehicles]]
    if out:
        prepare_out(out, _formation_names(mission), force=force, job="run formation")
    if planner:
        mission = replace(mission, planner=replace(mission.planner, name=planner))
    seed = sc.seed if seed is None else seed
    bar = reporter(mission.planner, sc.name)
    try:
        record = run_formation(world, mission, seed, bar, flight=bar.flight)
    finally:
        bar.close()
    if out:
        from ..viz.formation import build_formation_report

        bar.stage(f"writing results, report and exports into {out}")
        folder, text = Path(out), scenario_text(sc)
        write_formation(folder, world, mission, record, text, full, board)
        save_context(folder, sc.source, world)
        frame = LocalFrame(*world.origin) if world.origin is not None else None
        page = build_formation_report(world, record, [r for _, r in vehicle_records(world, mission, record)], text,
                                      frame.inverse if frame else None)
        atomic_write(folder / "report.html", page)
    return record, formation_record(record)


def _route_fields(members: tuple[tuple[str, CurrentField], ...], world: World, mission: Mission,
                  route: Any) -> dict[str, Any]:
    """A flown mission's route scored in every member: the ``plan --json`` ensemble fields.

    Parameters
    ----------
    members : tuple of (str, CurrentField)
        The ensemble (:func:`auvplan.io.scenario.inputs.members.scenario_members`).
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
    import numpy as np

    from ..sim.ensemble.score import score_route

    p = np.asarray(route, dtype=float).reshape(-1, 3)
    if not members or p.shape[0] < 2:
        return {}
    return score_route(world, members, p, mission.vehicle).as_dict()
