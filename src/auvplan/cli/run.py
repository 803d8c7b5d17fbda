"""``run`` and ``demo``: their arguments to the jobs of :mod:`auvplan.app.run` (one vehicle, a formation) and
:mod:`auvplan.app.survey`, and the summary lines."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Mapping
from typing import TYPE_CHECKING

from ..errors import AuvplanError
from .output import emit, finish, reporter

if TYPE_CHECKING:
    from ..endurance import Endurance
    from ..io.scenario.specs import Scenario
    from ..nav import NavPlan
    from ..sim import Mission, RunRecord
    from ..world import World

__all__: list[str] = []  # handlers: CLI internals, not library API


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
        alt = f"min altitude {m['min_altitude_m']:.1f} m" if math.isfinite(m["min_altitude_m"]) else "no seabed"
        d = m["min_obstacle_distance_m"]
        obst = f"min obstacle distance {d:.1f} m" if math.isfinite(d) else "no obstacle"
        lines.append(f"  flight {kind}: {m['status']} after {m['duration_s']:.0f} s, "
                     f"{m['distance_m']:.0f} m flown, {alt}, "
                     f"{obst}, {m['escapes']} escapes; "
                     f"{len(record.keys)} key waypoints")
    if record.altitude is not None:
        lines.append(describe_altitude(record.altitude))
    if endurance is not None:
        flown = f"; flown {endurance.flown.energy.energy_wh:.1f} Wh" if endurance.flown is not None else ""
        lines.append(f"  energy {endurance.budget.message}{flown}")
        lines.append(f"  point of no return: {endurance.pnr.message}")
    if record.nav is not None:
        lines.extend(describe_navigation(record.nav))
    return "\n".join(lines)


def describe_altitude(a: Mapping[str, float | int]) -> str:
    """The altitude line of a terrain-following run: the mission's and the flight's altitude against the band."""
    line = (f"  altitude {a['altitude_target_m']:g} ± {a['altitude_band_m']:g} m: mission {a['altitude_min_m']:.1f}"
            f"-{a['altitude_max_m']:.1f} m, RMS off target {a['altitude_rms_m']:.2f} m, within the band on "
            f"{100.0 * a['altitude_band_held_fraction']:.1f} % ({a['altitude_band_legs']} "
            f"leg{'' if a['altitude_band_legs'] == 1 else 's'} out where the pitch limit forces it)")
    if "flown_altitude_rms_m" in a:
        line += (f"; flown {a['flown_altitude_min_m']:.1f}-{a['flown_altitude_max_m']:.1f} m, RMS off target "
                 f"{a['flown_altitude_rms_m']:.2f} m where the mission is in the band")
    return line


def describe_navigation(nav: NavPlan) -> list[str]:
    """The navigation lines of a run's summary: where to surface, and whether the mission is safe under its error."""
    m, b = nav.metrics(), nav.check.budget
    if not nav.ok:
        return [f"  navigation: NOT SAFE — {nav.message}"]
    least = float(nav.check.leg_uncertain_altitude_m.min())
    head = (f"  navigation: {m['fixes']} fixes, predicted error at most {m['nav_error_max_m']:.1f} m, every leg "
            f"clear of the seabed, obstacles and no-go zones within it (least altitude {least:.1f} m)")
    if m["fixes_fixed_period"] is not None:
        head += f"; a fix every {m['fixed_period_s']:.0f} s would need {m['fixes_fixed_period']}"
    idx = [i for i, k in enumerate(nav.kinds) if k]
    fixes = [f"{nav.kinds[i]} at x {nav.points[i, 0]:.0f} y {nav.points[i, 1]:.0f} m, t {t / 3600:.2f} h "
             f"(error before {b.leg_error_m[i - 1]:.0f} m)" for i, t in zip(idx, nav.times_s, strict=True)]
    return [head] + [f"    fix {n + 1}: {f}" for n, f in enumerate(fixes)]


def _settled(v: float | None) -> str:
    """The fleet's settled largest formation error for the summary line (None: a vehicle never settled)."""
    return "n/a" if v is None else f"{v:.2f} m"


def _notes(notes: list[str]) -> None:
    finish()  # the live progress line, before the result (issue 56)
    for line in notes:  # a format that would fly a tail-first leg nose-first
        print(f"auvplan: {line}", file=sys.stderr)


def cmd_formation(args: argparse.Namespace, sc: Scenario, world: World, mission: Mission) -> int:
    """``run`` of a scenario with ``[[vehicles]]``: the fleet's summary line (or JSON record)."""
    from ..app.run import run_formation_scenario

    if args.guidance or args.avoidance:
        raise AuvplanError(f"{sc.source}: --guidance/--avoidance do not apply to a formation (each vehicle flies "
                           "the formation field of [formation])")
    record, rec = run_formation_scenario(sc, world, mission, args.out, args.seed, args.full, args.force,
                                         args.planner, reporter(args.quiet or args.json), args.board_storage)
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
    from ..app.run import run_scenario
    from ..io.results import records
    from ..io.scenario import loader as scenario_io

    sc = scenario_io.load(args.scenario)
    if sc.survey is not None:
        from .survey import cmd_survey

        return cmd_survey(args)
    if sc.vehicle.type == "glider":
        from .glider import cmd_glider

        return cmd_glider(args)
    if sc.formation is not None:
        world, mission = scenario_io.build(sc)
        return cmd_formation(args, sc, world, mission)
    sc, record, endurance, notes = run_scenario(args.scenario, args.out, args.guidance, args.avoidance, args.seed,
                                                full=args.full, force=args.force, planner=args.planner,
                                                reporter=reporter(args.quiet or args.json),
                                                board=args.board_storage)
    said = [n for n in notes if n.startswith("currents:")]  # issue 51: the rules the run applied to its inputs
    if not args.json:  # --json: stderr stays empty on success, the notes go into the JSON object
        _notes([n for n in notes if n not in said])
    rec = records.run_record(record)
    if endurance is not None:
        from ..io.missions.energy import energy_record
        from ..io.scenario.defaults import energy_defaults

        rec["energy"] = records.jsonable(energy_record(endurance))
        if record.status.ok and not endurance.status.ok:
            rec["status"] = endurance.status.value
        said += energy_defaults(sc)
    if notes or said:
        rec["notes"] = said + [n for n in notes if n not in said]
    emit(rec, args.json, describe_run(sc.name, record, endurance) + "".join(f"\n  note: {n}" for n in said))
    if args.out and not args.json:
        print(f"results in {args.out}/")
    return 0 if record.status.ok and (endurance is None or endurance.status.ok) else 1


def cmd_demo(args: argparse.Namespace) -> int:
    """``demo``: ``run`` of the built-in default scenario into ``--out``."""
    from ..app.run import DEMO_SCENARIO, run_scenario

    sc, record, endurance, notes = run_scenario(DEMO_SCENARIO, args.out, None, None, None, force=args.force,
                                                reporter=reporter(args.quiet))
    _notes(notes)
    print(describe_run(sc.name, record, endurance))
    print(f"results in {args.out}/")
    return 0 if record.status.ok and (endurance is None or endurance.status.ok) else 1
