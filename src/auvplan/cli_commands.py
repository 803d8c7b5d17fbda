"""The commands of the command line (DESIGN.md §4): each reads its arguments, calls the library and
writes the results; :mod:`auvplan.cli` declares the arguments and maps errors to exit codes.

The handlers :mod:`auvplan.cli` names are all found here (``_cmd_<command>``); the larger commands live in
their topic's module: :mod:`auvplan.cli_plan` (``plan``, ``simulate``), :mod:`auvplan.cli_sweep` (the
departure sweep), :mod:`auvplan.cli_run` (``run``, ``demo``), :mod:`auvplan.cli_results` (``report``,
``export``), on what they share in :mod:`auvplan.cli_output`.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path

import numpy as np

from . import cli_plan, cli_results, cli_run
from .io.safeio import atomic_write, prepare_out, save_figure, write_new

__all__ = ["DEMO_SCENARIO"]

DEMO_SCENARIO = cli_run.DEMO_SCENARIO
"""The built-in default scenario: a real seamount flank, two eddies and twelve fast moving obstacles."""

# the handlers of the topic modules, under the names cli.py dispatches to
_cmd_plan, _cmd_simulate = cli_plan.cmd_plan, cli_plan.cmd_simulate
_cmd_run, _cmd_demo = cli_run.cmd_run, cli_run.cmd_demo
_cmd_report, _cmd_export = cli_results.cmd_report, cli_results.cmd_export

log = logging.getLogger("auvplan")


def _cmd_scenarios(args: argparse.Namespace) -> int:
    from .io.scenario.builtins import builtin_scenarios

    for name, desc in builtin_scenarios().items():
        print(f"{name:18s} {desc}")
    return 0


def _cmd_data_inspect(args: argparse.Namespace) -> int:
    from .io.data.inspect import inspect_file

    print(inspect_file(args.file))
    return 0


def _cmd_validate(args: argparse.Namespace) -> int:
    from .io.scenario import loader as scenario_io
    from .sim import planning_problem

    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)  # every check `plan` and `run` make before their work
    planning_problem(world, mission)
    from .cli_ensemble import scenario_members

    members = scenario_members(sc, world)  # [currents] members: every one read and checked
    survey = None
    if sc.survey is not None:  # every check `survey` makes before planning, before saying OK
        from .io.results.survey import survey_params

        survey = survey_params(sc.survey, world, mission.vehicle, sc.base_dir, f"{sc.source}: [survey]")
    b = world.bounds
    print(f"{sc.source}: OK — {sc.name}")
    print(f"  bounds x [{b.xmin:.0f}, {b.xmax:.0f}] y [{b.ymin:.0f}, {b.ymax:.0f}] z [{b.zmin:.0f}, {b.zmax:.0f}] m")
    if world.terrain is not None:
        t = world.terrain
        print(f"  terrain {t.name}: {t.x.size} x {t.y.size} nodes, cell {t.dx:.0f} m, "
              f"seabed {t.z.min():.0f} .. {t.z.max():.0f} m")
        if t.fit is not None:
            print(f"  {t.fit.describe()}")
    print(f"  start {list(mission.start)} goal {list(mission.goal)}; "
          f"{len(world.obstacles)} static and {len(world.moving)} moving obstacles")
    if members:
        print(f"  {len(members)} current members: {', '.join(n for n, _ in members[:8])}"
              + (" ..." if len(members) > 8 else "") + f"; [planner] robust = {mission.planner.robust!r}")
    if sc.mission.confidence:
        print(f"  seabed: the worst case at {100 * sc.mission.confidence:g} % ([terrain] uncertainty)")
    if sc.survey is not None and survey is not None:
        kind = "corridor" if sc.survey.corridor else "survey"
        print(f"  {kind} of {survey.area.area / 1e6:.3g} km² with a {sc.survey.sensor} ({sc.survey.mounting} mounting)"
              + (f", {sc.survey.tie_lines} tie lines" if sc.survey.tie_lines else ""))
    return 0


def _cmd_scenario_new(args: argparse.Namespace) -> int:
    from .io.scenario.schema import template

    text = template(Path(args.file).stem if args.file else "my-mission")
    if not args.file:
        sys.stdout.write(text)
        return 0
    path = write_new(Path(args.file), text, force=args.force)
    print(f"wrote {path}; check it with: auvplan validate {path}", file=sys.stderr)
    return 0


def _cmd_scenario_schema(args: argparse.Namespace) -> int:
    from .io.scenario.schema import scenario_schema

    sys.stdout.write(json.dumps(scenario_schema(), indent=2) + "\n")
    return 0


def _cmd_mission_check(args: argparse.Namespace) -> int:
    from .flyable import check_limits
    from .io.missions.energy import mission_file_energy
    from .io.missions.formats import check_mission_file, read_mission
    from .io.results import records
    from .io.scenario import loader as scenario_io
    from .sim.pipeline import vehicle_limits

    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    worst = 0
    checks = []
    for name in args.files:
        check, fmt = check_mission_file(Path(name), world, args.pitch)
        points = read_mission(Path(name), world.origin)[0]
        # a QGC plan starts from its home on the surface: the launch, not a leg of the mission
        vlimits = check_limits(points[1:] if fmt == "qgc" else points, vehicle_limits(mission.vehicle))
        energy, energy_ok, energy_line = mission_file_energy(world, mission, Path(name))
        rec = {"file": name, "format": fmt, **check.as_dict(), "vehicle": vlimits.as_dict(), "energy": energy}
        if sc.mission.confidence:  # issue 39: checked against the worst-case seabed at that confidence
            rec["clearance_confidence"] = sc.mission.confidence
        checks.append(rec)
        worst = max(worst, 0 if check.ok and vlimits.ok and energy_ok else 1)
        if not args.json:
            held = (f"; flown at {check.pitch_deg:g}° pitch: least altitude {check.executor_min_altitude_m:.2f} m"
                    if check.semantics == "held" else "")
            obstacles = (f"least obstacle distance {check.min_obstacle_distance_m:.2f} m (margin "
                         f"{check.obstacle_margin_m:g} m), {check.obstacle_hits} legs meet an obstacle"
                         if np.isfinite(check.min_obstacle_distance_m) else "no static obstacle in the scenario")
            limits = "".join(f"{r}; " for r in (check.limits.reasons() if check.limits is not None else []))
            print(f"{name} ({fmt}, depth {check.semantics}): {'OK' if check.ok else 'FAIL'} — {limits}least altitude "
                  f"{check.min_altitude_m:.2f} m (required {check.required_altitude_m:g} m, leg "
                  f"{check.min_altitude_leg}), {obstacles}{held}")
            print(f"{name} vehicle: {'OK' if vlimits.ok else 'FAIL'} — {vlimits.summary}"
                  + (f"; {len(vlimits.violations)} violations: {vlimits.message}" if not vlimits.ok else ""))
            print(f"{name}: {energy_line}")
            if sc.mission.confidence:
                print(f"{name}: clearance {check.min_altitude_m:.2f} m at {100 * sc.mission.confidence:g} % "
                      f"(above the worst-case seabed, [terrain] uncertainty; required {check.required_altitude_m:g} m)")
    if args.json:
        print(json.dumps(records.jsonable(checks[0] if len(checks) == 1 else checks)))
    return worst


_BENCH_NAMES = ("summary.csv", "summary.md", "bench.html", "bench.png")
"""Files of ``bench --out`` besides rows.csv and histories.jsonl (which ``--resume`` appends to)."""


def _cmd_bench(args: argparse.Namespace) -> int:
    from .bench import SweepSpec, summarise, sweep

    spec = SweepSpec(tuple(args.scenarios), tuple(args.planners), tuple(args.guidance), args.seeds, args.budget,
                     args.reference, args.randomise, args.plan_once, args.chunk, tuple(args.avoidance),
                     tuple(args.members), tuple(args.member_seeds))
    out = prepare_out(args.out, ("rows.csv", "histories.jsonl", *_BENCH_NAMES), force=args.force)  # no link in the way
    rows = sweep(spec, out, workers=args.workers, scheduler=args.scheduler, resume=args.resume)
    table = summarise(rows)
    cols = list(table[0]) if table else []
    atomic_write(out / "summary.csv", "".join(",".join(str(v) for v in r) + "\n"
                                              for r in [cols] + [[r[c] for c in cols] for r in table]))
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(f"{r[c]:.6g}" if isinstance(r[c], float) else str(r[c]) for c in cols) + " |"
              for r in table]
    text = "\n".join(lines)
    atomic_write(out / "summary.md", f"# auvplan bench: {len(rows)} runs\n\n{text}\n")
    from .bench import read_histories
    from .viz.plots import bench_figures
    from .viz.report import build_bench_report

    bench_figures(rows, out, save=save_figure)
    page = build_bench_report(rows, table, read_histories(out / "histories.jsonl"))
    atomic_write(out / "bench.html", page)
    print(text)
    print(f"rows in {out / 'rows.csv'}, summary in {out / 'summary.md'}, report {out / 'bench.html'}")
    return 0


def _cmd_survey(args: argparse.Namespace) -> int:
    from .cli_survey import cmd_survey

    return cmd_survey(args)


def _cmd_serve(args: argparse.Namespace) -> int:
    from .cli_serve import cmd_serve

    return cmd_serve(args)
