"""``survey`` (and ``run`` of a scenario with ``[survey]``) as a job: plan the depth-adaptive lines, fly the
whole mission in the closed loop, measure the coverage; with ``out``, write ``lines.csv``, ``coverage.json``,
``gaps.geojson``, ``coverage.png``, ``report.html``, the run files and every mission export."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import ScenarioError
from ..io.files.safeio import RESULT_NAMES, prepare_out, save_figure
from ..io.missions import export
from ..io.missions.readback.mission_storage import BoardStorage
from ..io.results import records
from ..io.results.survey import SURVEY_NAMES, coverage_record, survey_params, write_survey
from ..io.scenario import loader as scenario_io
from ..runtime.parallel import Runner
from ..sim import Mission
from ..survey.run import SurveyRun, run_survey
from ..world import World
from .results import save_context

if TYPE_CHECKING:
    from ..io.scenario.specs import Scenario
    from ..survey.mission import SurveyParams

__all__ = ["survey_scenario"]


def survey_scenario(scenario: str, out: str | None = None, force: bool = False, seed: int | None = None,
                    guidance: str | None = None, full: bool = False,
                    say: Callable[[str], None] = lambda text: None,
                    runner: Runner | None = None, board: BoardStorage | None = None) -> tuple[Any, dict[str, Any]]:
    """Plan, fly and measure the ``[survey]`` of a scenario.

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file (with a ``[survey]`` table).
    out : str, optional
        The results folder, checked before any work.
    force : bool
        Replace the folder's result files.
    seed, guidance : optional
        Override the scenario's.
    full : bool
        Full-rate run files and exports.
    say : callable
        Receives a line at each stage.
    runner : Runner, optional
        Where the independent transits are planned (:class:`auvplan.runtime.parallel.Runner`; this process by default).
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a ``.plan`` it cannot hold is refused.

    Returns
    -------
    scenario : Scenario
        The scenario.
    record : dict
        The coverage record (:func:`auvplan.io.results.survey.coverage_record`).
    """
    if out:
        prepare_out(out, (*RESULT_NAMES, *SURVEY_NAMES), force=force, job="survey", inputs=(scenario,))
    sc = scenario_io.load(scenario)
    if sc.survey is None:
        raise ScenarioError(f"{sc.source}: no [survey] table (polygon, sensor, opening_deg, mounting, overlap)")
    world, mission = scenario_io.build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, sc.base_dir, f"{sc.source}: [survey]")
    seed = sc.seed if seed is None else seed
    say(f"planning and flying the survey of {sc.name}")
    run = run_survey(world, mission, params, seed, guidance=guidance, runner=runner)
    from ..io.scenario.inputs.currentspan import run_note

    note = run_note(sc.source, sc.currents.beyond, world, run.record)  # issue 51: refused, or said
    rec = coverage_record(run, params)
    if note:
        rec["notes"] = [note]
    if out:
        _write_folder(Path(out), sc, world, mission, run, params, rec, full, say, board)
    return sc, rec



def _write_folder(folder: Path, sc: Scenario, world: World, mission: Mission, run: SurveyRun, params: SurveyParams,
                  rec: dict[str, Any], full: bool, say: Callable[[str], None], board: BoardStorage | None) -> None:
    """The results folder of a survey: its lines and coverage, the run files, the scenario's context, the mission
    exports (as run's: a ``.plan`` ``board`` cannot hold left out, said in ``rec["notes"]``), the coverage map and
    the report."""
    say(f"writing the survey, the run files and the mission exports into {folder}")
    write_survey(folder, run, params, world.origin)
    from ..io.missions.deploy import payload_from_labels
    from ..io.scenario.saved import with_derived_frame

    text = Path(sc.source).read_text(encoding="utf-8") if Path(sc.source).is_file() else ""
    records.write_run(folder, run.record, with_derived_frame(text, world), full)  # issue 51: derived frame
    # the scenario file's path and the terrain, as `run --out` keeps them: the folder's scenario.toml names its
    # data files relative to the scenario's own folder (`mission check --scenario DIR/scenario.toml`, `export`)
    save_context(folder, sc.source, world)
    formats = [f for f in export.EXPORT_FORMATS if world.origin is not None or f not in export.GEOGRAPHIC]
    deploy = export.deploy_for(world, mission, run.record, mission.vehicle.speed,
                               payload_from_labels(run.plan.labels))  # issue 51: envelope, payload
    left = export.write_mission_files(folder, run.record, world.origin, mission.vehicle.speed, formats, full, deploy,
                                      board)
    if left:
        rec["notes"] = [*rec.get("notes", []), *left]
    from ..viz.survey import coverage_map

    save_figure(folder / "coverage.png",  # atomically, and into the manifest (a re-run adopts it)
                coverage_map(world, run, params.area, (params.lines.overlap_min, params.lines.overlap_max)),
                dpi=110)
    _report(folder, world, run, rec, text, mission)


def _report(out: Path, world: World, run: SurveyRun, rec: dict[str, Any], text: str, mission: Mission) -> None:
    """``report.html``: the run's report with the survey's coverage map, headline figures and line table (and
    under ``[navigation]`` the error band along the survey and the error against time)."""
    from ..io.data.geo import LocalFrame
    from ..io.files.safeio import atomic_write
    from ..viz.report import build_report
    from ..viz.survey import line_table, survey_section

    frame = LocalFrame(*world.origin) if world.origin is not None else None
    keys = ("status", "lines", "coverage_pct", "overlap_min_pct", "overlap_max_pct", "measured_on",
            "survey_length_m", "mission_length_m", "survey_time_s")
    summary = {k: rec[k] for k in keys} | {"tie_lines": len(run.plan.tie_waypoints()),
                                           "overlap_margin_pct": 100 * run.plan.overlap_margin,
                                           "least_turn_radius_m": run.plan.min_turn_radius_m}
    if rec.get("nav_spacing"):  # issue 52: the spacing under the relative navigation error, stated
        summary["navigation"] = rec["nav_spacing"]["text"]
    section = survey_section((out / "coverage.png").read_bytes(), line_table(run, world.seabed), summary)
    record = run.record
    nav = mission.navigation
    if nav is not None and record.route.shape[0] >= 2:  # issue 52: the survey's own error budget drawn
        from ..nav import navigation_of, surface_kinds
        from ..sim.navigation import timed_navigation  # flown through the current: its drift over the water

        record = replace(record, nav=timed_navigation(world, mission, navigation_of(
            world, record.route, surface_kinds(record.route), nav, mission.vehicle.speed, nav.usbl_xy)))
    page = build_report(world, record, text, records.summary_metrics(record),
                        frame.inverse if frame else None, sections=[("Survey", section)])
    atomic_write(out / "report.html", page)
