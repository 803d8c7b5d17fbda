"""``run`` and ``demo``: plan, key waypoints and the closed-loop flight of one vehicle (or a formation),
the results folder and the summary lines."""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from .cli_output import Progress, emit
from .cli_results import save_context, scenario_text, write_report
from .errors import AuvplanError
from .io.safeio import RESULT_NAMES, atomic_write, prepare_out

if TYPE_CHECKING:
    from .endurance import Endurance
    from .io.scenario.specs import Scenario
    from .nav import NavPlan
    from .sim import Mission, RunRecord
    from .world import World

__all__: list[str] = ["DEMO_SCENARIO"]  # handlers: CLI internals, not library API


DEMO_SCENARIO = "showcase"
"""The built-in default scenario: a real seamount flank, two eddies and twelve fast moving obstacles."""


def run_scenario(scenario: str, out: str | None, guidance: str | None, avoidance: str | None, seed: int | None,
                 full: bool = False, force: bool = False, quiet: bool = False,
                 planner: str | None = None) -> tuple[Scenario, RunRecord, Endurance | None]:
    """Plan and fly one scenario (``run``, ``demo``); with ``out``, its results folder, report and exports."""
    from .io.data.geo import LocalFrame
    from .io.missions.energy import mission_endurance
    from .io.results import records
    from .io.scenario import loader as scenario_io
    from .sim import run_mission

    if out:
        prepare_out(out, RESULT_NAMES, force=force)
    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    if planner:
        mission = replace(mission, planner=replace(mission.planner, name=planner))
    seed = sc.seed if seed is None else seed
    bar = Progress(mission.planner, sc.name, quiet)
    try:
        record = run_mission(world, mission, seed, bar, guidance=guidance, avoidance=avoidance, flight=bar.flight)
    finally:
        bar.close()
    endurance = mission_endurance(world, mission, record)
    if out:
        bar.stage(f"writing results, report and exports into {out}")
        from .cli_ensemble import route_fields, scenario_members, write_ensemble

        write_ensemble(Path(out), route_fields(scenario_members(sc, world), world, mission, record.route))
        text = scenario_text(sc)
        records.write_run(Path(out), record, text, full, world.origin)
        save_context(Path(out), sc, world)
        if endurance is not None:
            from .io.missions.energy import write_energy

            frame = LocalFrame(*world.origin) if world.origin is not None else None
            write_energy(Path(out), endurance, frame.inverse if frame else None)
        write_report(Path(out), world, mission, record, text, full=full, endurance=endurance)
    return sc, record, endurance


def describe_run(name: str, record: RunRecord, endurance: Endurance | None = None) -> str:
    """The human summary of a run: its plan, flight and energy."""
    status = record.status if endurance is None or not record.status.ok else endurance.status
    lines = [f"{name}: {status.value}"]
    if record.plan is not None:
        p = record.plan
        lines.append(f"  plan   {p.planner}: {p.status.value}, length {p.cost_terms.get('length_m', 0):.0f} m, "
                     f"{p.evaluations} evaluations, {p.wall_time_s:.2f} s" + (f" — {p.message}" if p.message else ""))
    if record.sim is not None:
        m = record.sim.metrics
        kind = f"{record.sim.guidance}+{record.sim.avoidance}"
        lines.append(f"  flight {kind}: {m['status']} after {m['duration_s']:.0f} s, "
                     f"{m['distance_m']:.0f} m flown, min altitude {m['min_altitude_m']:.1f} m, "
                     f"min obstacle distance {m['min_obstacle_distance_m']:.1f} m, {m['escapes']} escapes; "
                     f"{len(record.keys)} key waypoints")
    if endurance is not None:
        flown = f"; flown {endurance.flown.energy.energy_wh:.1f} Wh" if endurance.flown is not None else ""
        lines.append(f"  energy {endurance.budget.message}{flown}")
        lines.append(f"  point of no return: {endurance.pnr.message}")
    if record.nav is not None:
        lines.extend(describe_navigation(record.nav))
    return "\n".join(lines)


def describe_navigation(nav: NavPlan) -> list[str]:
    """The navigation lines of a run's summary: where to surface, and whether the mission is safe under its error."""
    m, b = nav.metrics(), nav.check.budget
    if not nav.ok:
        return [f"  navigation: NOT SAFE — {nav.message}"]
    head = (f"  navigation: {m['fixes']} fixes, predicted error at most {m['nav_error_max_m']:.1f} m, every leg "
            f"clear of the seabed within it (least {float(nav.check.leg_uncertain_altitude_m.min()):.1f} m)")
    if m["fixes_fixed_period"] is not None:
        head += f"; a fix every {m['fixed_period_s']:.0f} s would need {m['fixes_fixed_period']}"
    idx = [i for i, k in enumerate(nav.kinds) if k]
    fixes = [f"{nav.kinds[i]} at x {nav.points[i, 0]:.0f} y {nav.points[i, 1]:.0f} m, t {t / 3600:.2f} h "
             f"(error before {b.leg_error_m[i - 1]:.0f} m)" for i, t in zip(idx, nav.times_s, strict=True)]
    return [head] + [f"    fix {n + 1}: {f}" for n, f in enumerate(fixes)]


def _settled(v: float | None) -> str:
    """The fleet's settled largest formation error for the summary line (None: a vehicle never settled)."""
    return "n/a" if v is None else f"{v:.2f} m"


def run_formation_scenario(args: argparse.Namespace, sc: Scenario, world: World, mission: Mission) -> int:
    """``run`` of a scenario with ``[[vehicles]]``: the formation pipeline, its files and report."""
    from .io.data.geo import LocalFrame
    from .io.missions.formation import FORMATION_NAMES, formation_record, vehicle_records, write_formation
    from .sim.formation import run_formation

    assert mission.formation is not None  # cmd_run calls this only for a scenario with [[vehicles]]
    if args.guidance or args.avoidance:
        raise AuvplanError(f"{sc.source}: --guidance/--avoidance do not apply to a formation (each vehicle flies "
                           "the formation field of [formation])")
    if args.out:
        names = [*FORMATION_NAMES, *(f"{v.name}/{f}" for v in mission.formation.vehicles for f in RESULT_NAMES)]
        prepare_out(args.out, names, force=args.force)
    if args.planner:
        mission = replace(mission, planner=replace(mission.planner, name=args.planner))
    seed = sc.seed if args.seed is None else args.seed
    bar = Progress(mission.planner, sc.name, args.quiet or args.json)
    try:
        record = run_formation(world, mission, seed, bar, flight=bar.flight)
    finally:
        bar.close()
    if args.out:
        from .viz.formation import build_formation_report

        bar.stage(f"writing results, report and exports into {args.out}")
        out, text = Path(args.out), scenario_text(sc)
        write_formation(out, world, mission, record, text, args.full)
        save_context(out, sc, world)
        frame = LocalFrame(*world.origin) if world.origin is not None else None
        page = build_formation_report(world, record, [r for _, r in vehicle_records(world, mission, record)], text,
                                      frame.inverse if frame else None)
        atomic_write(out / "report.html", page)
    rec = formation_record(record)
    m = rec["metrics"] or {}
    human = f"{sc.name}: {record.status.value}" + (
        f" — {m['arrivals']}/{m['vehicles']} vehicles arrived, {m['collisions']} collisions, least vehicle "
        f"distance {m['min_vehicle_distance_m']:.1f} m, formation error RMS {m['formation_error_rms_m']:.2f} m "
        f"(max {m['formation_error_max_m']:.2f} m, settled {_settled(m.get('settled_error_max_m'))}); shapes: "
        + " → ".join(f"{s} from {b:.0f} m" for b, s in record.formation.breaks) if m and record.formation else "")
    emit(rec, args.json, human)
    if args.out and not args.json:
        print(f"results in {args.out}/ (one folder per vehicle)")
    return 0 if record.status.ok else 1


def cmd_run(args: argparse.Namespace) -> int:
    """``run``: one vehicle, a formation (``[[vehicles]]``) or a survey (``[survey]``), planned and flown."""
    from .io.results import records
    from .io.scenario import loader as scenario_io

    sc = scenario_io.load(args.scenario)
    if sc.survey is not None:
        from .cli_survey import cmd_survey

        return cmd_survey(args)
    if sc.formation is not None:
        world, mission = scenario_io.build(sc)
        return run_formation_scenario(args, sc, world, mission)
    sc, record, endurance = run_scenario(args.scenario, args.out, args.guidance, args.avoidance, args.seed,
                                         full=args.full, force=args.force, quiet=args.quiet or args.json,
                                         planner=args.planner)
    rec = records.run_record(record)
    if endurance is not None:
        from .io.missions.energy import energy_record

        rec["energy"] = records.jsonable(energy_record(endurance))
        if record.status.ok and not endurance.status.ok:
            rec["status"] = endurance.status.value
    emit(rec, args.json, describe_run(sc.name, record, endurance))
    if args.out and not args.json:
        print(f"results in {args.out}/")
    return 0 if record.status.ok and (endurance is None or endurance.status.ok) else 1


def cmd_demo(args: argparse.Namespace) -> int:
    """``demo``: ``run`` of the built-in default scenario into ``--out``."""
    sc, record, endurance = run_scenario(DEMO_SCENARIO, args.out, None, None, None, force=args.force, quiet=args.quiet)
    print(describe_run(sc.name, record, endurance))
    print(f"results in {args.out}/")
    return 0 if record.status.ok and (endurance is None or endurance.status.ok) else 1
