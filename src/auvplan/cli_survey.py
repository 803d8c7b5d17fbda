"""``auvplan survey SCENARIO --out DIR`` (and ``run`` of a scenario with ``[survey]``): plan the
depth-adaptive lines, fly the whole mission in the closed loop, measure the coverage, write ``lines.csv``,
``coverage.json``, ``gaps.geojson``, ``coverage.png``, ``report.html``, the run files and every mission export."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

from .errors import ScenarioError
from .io.missions import export
from .io.results import records
from .io.results.survey import SURVEY_NAMES, coverage_record, survey_params, write_survey
from .io.safeio import RESULT_NAMES, prepare_out
from .io.scenario import loader as scenario_io
from .survey.run import SurveyRun, run_survey
from .world import World

__all__ = ["cmd_survey"]


def _say(args: argparse.Namespace, text: str) -> None:
    if not (getattr(args, "quiet", False) or getattr(args, "json", False)):
        print(f"auvplan: {text} …", file=sys.stderr)


def cmd_survey(args: argparse.Namespace) -> int:
    """Run the survey command.

    Parameters
    ----------
    args : argparse.Namespace
        ``scenario``, ``out``, ``seed``, ``guidance``, ``full``, ``force``, ``json``, ``quiet``.

    Returns
    -------
    int
        0 when the survey was planned and flown, 1 when a check, a transit or the flight failed.
    """
    if args.out:
        prepare_out(args.out, (*RESULT_NAMES, *SURVEY_NAMES), force=args.force)
    sc = scenario_io.load(args.scenario)
    if sc.survey is None:
        raise ScenarioError(f"{sc.source}: no [survey] table (polygon, sensor, opening_deg, mounting, overlap)")
    world, mission = scenario_io.build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, sc.base_dir, f"{sc.source}: [survey]")
    seed = sc.seed if args.seed is None else args.seed
    _say(args, f"planning and flying the survey of {sc.name}")
    run = run_survey(world, mission, params, seed, guidance=getattr(args, "guidance", None))
    rec = coverage_record(run, params)
    if args.out:
        out = Path(args.out)
        _say(args, f"writing the survey, the run files and the mission exports into {out}")
        write_survey(out, run, params, world.origin)
        text = Path(sc.source).read_text(encoding="utf-8") if Path(sc.source).is_file() else ""
        records.write_run(out, run.record, text, args.full)
        formats = [f for f in export.EXPORT_FORMATS if world.origin is not None or f not in export.GEOGRAPHIC]
        export.write_exports(out, run.record, world.origin, mission.vehicle.speed, formats, args.full)
        from .viz.survey import coverage_map

        coverage_map(world, run, params.area, (params.lines.overlap_min, params.lines.overlap_max)).savefig(
            out / "coverage.png", dpi=110)
        _report(out, world, run, rec, text)
    m = rec["lawnmower"]
    human = (f"{sc.name}: {rec['status']} — {rec['lines']} lines at {rec['heading_deg']:.0f}°, "
             f"planned coverage {rec['planned']['coverage_pct']:.2f} % (overlap {rec['planned']['overlap_min_pct']:.1f}"
             f"–{rec['planned']['overlap_max_pct']:.1f} %)"
             + (f", flown {rec['coverage_pct']:.2f} % (overlap {rec['overlap_min_pct']:.1f}–"
                f"{rec['overlap_max_pct']:.1f} %, {rec['flown']['gaps']} gaps)" if rec["flown"] else "")
             + f"\n  survey {rec['survey_length_m'] / 1e3:.1f} km"
             + (f" in {rec['survey_time_s'] / 3600:.2f} h" if math.isfinite(rec["survey_time_s"]) else "")
             + f"; fixed lawnmower for {m['shallowest_m']:.0f} m: {m['lines']} lines, "
               f"{m['lines_saved']} lines and {m['line_length_saved_m'] / 1e3:.1f} km of line saved"
             + (f"\n  {rec['message']}" if rec["message"] else ""))
    if args.json:
        print(_json(rec))
    else:
        print(human)
        if args.out:
            print(f"results in {args.out}/")
    return 0 if rec["status"] in ("EXACT", "APPROXIMATE") else 1


def _report(out: Path, world: World, run: SurveyRun, rec: dict[str, Any], text: str) -> None:
    """``report.html``: the run's report with the survey's coverage map, headline figures and line table."""
    from .io.data.geo import LocalFrame
    from .io.safeio import atomic_write
    from .viz.report import build_report
    from .viz.survey import line_table, survey_section

    frame = LocalFrame(*world.origin) if world.origin is not None else None
    keys = ("status", "lines", "coverage_pct", "overlap_min_pct", "overlap_max_pct", "measured_on",
            "survey_length_m", "mission_length_m", "survey_time_s")
    summary = {k: rec[k] for k in keys} | {"tie_lines": len(run.plan.tie_waypoints()),
                                           "overlap_margin_pct": 100 * run.plan.overlap_margin,
                                           "least_turn_radius_m": run.plan.min_turn_radius_m}
    section = survey_section((out / "coverage.png").read_bytes(), line_table(run, world.seabed), summary)
    page = build_report(world, run.record, text, records.summary_metrics(run.record),
                        frame.inverse if frame else None, sections=[("Survey", section)])
    atomic_write(out / "report.html", page)


def _json(rec: dict[str, object]) -> str:
    import json

    return json.dumps(records.jsonable(rec))
