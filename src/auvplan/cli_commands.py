"""The commands of the command line (DESIGN.md §4): each reads its arguments, calls the library and
writes the results; :mod:`auvplan.cli` declares the arguments and maps errors to exit codes.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import logging
import sys
from collections.abc import Iterable
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .errors import AuvplanError
from .io.safeio import RESULT_NAMES, atomic_write, prepare_out, save_figure, write_new

if TYPE_CHECKING:
    from .endurance import Endurance
    from .io.scenario.specs import Scenario
    from .planners import PlannerSpec, PlanResult
    from .sim import Mission, RunRecord
    from .world import World

__all__ = ["DEMO_SCENARIO"]

log = logging.getLogger("auvplan")

DEMO_SCENARIO = "showcase"
"""The built-in default scenario: a real seamount flank, two eddies and twelve fast moving obstacles."""


class _Progress:
    """Progress of the long stages on stderr: a tqdm bar for the swarm planners' iterations and one
    for the flight (simulated time against the route's expected duration), a line for the other
    stages; all silent with ``quiet`` (``-q`` or ``--json``)."""

    def __init__(self, spec: PlannerSpec, scenario: str, quiet: bool) -> None:
        from tqdm import tqdm

        from .planners import get as get_planner

        self._tqdm, self.quiet, self.scenario = tqdm, quiet, scenario
        self.flight_bar: Any = None
        # only the iterating planners (the swarm optimisers) report progress; the others get a line, not a
        # bar stuck at 0
        iterative = get_planner(spec.name).iterative
        self.bar = tqdm(total=spec.iterations, desc=f"{spec.name} on {scenario}", file=sys.stderr,
                        disable=quiet or not iterative, leave=False, mininterval=0.5)
        if not iterative:
            self.stage(f"planning with {spec.name}")

    def __call__(self, iteration: int, best: float) -> None:
        self.bar.update(iteration - self.bar.n)
        self.bar.set_postfix_str(f"best {best:.6g}", refresh=False)

    def flight(self, t: float, expected: float) -> None:
        """The simulation's callback: simulated seconds flown of about ``expected``."""
        if self.flight_bar is None:
            self.bar.close()
            self.flight_bar = self._tqdm(total=max(1, round(expected)), desc=f"flight on {self.scenario}", unit="s",
                                         file=sys.stderr, disable=self.quiet, leave=False, mininterval=0.5)
        self.flight_bar.update(min(round(t), self.flight_bar.total) - self.flight_bar.n)

    def stage(self, text: str) -> None:
        """One line on stderr for a stage without a bar (the report, a lattice plan)."""
        if not self.quiet:
            self._tqdm.write(f"auvplan: {text} …", file=sys.stderr)

    def close(self) -> None:
        self.bar.close()
        if self.flight_bar is not None:
            self.flight_bar.close()


def _out(args: argparse.Namespace, names: Iterable[str] = RESULT_NAMES) -> Path | None:
    """Check ``--out`` before any work (creatable, writable, no user file or link in the way)."""
    if getattr(args, "out", None) is None:
        return None
    return prepare_out(args.out, names, force=getattr(args, "force", False))


def _emit(record: dict[str, Any], as_json: bool, human: str) -> None:
    from .io.results import records

    if as_json:
        sys.stdout.write(json.dumps(records.jsonable(record)) + "\n")
    else:
        print(human)


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
    if sc.survey is not None:
        from .io.results.survey import survey_params

        area = survey_params(sc.survey, world, mission.vehicle, sc.base_dir, f"{sc.source}: [survey]").area
        print(f"  survey of {area.area / 1e6:.3g} km² with a {sc.survey.sensor} ({sc.survey.mounting} mounting)")
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


def _plan(args: argparse.Namespace, quiet: bool) -> tuple[Scenario, PlanResult, int, World, dict[str, Any]]:
    from .io.scenario import loader as scenario_io
    from .planners import plan, reference, with_reference
    from .sim import planning_problem

    _out(args)
    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    spec = mission.planner
    if args.planner:
        spec = replace(spec, name=args.planner)
    if args.budget is not None:
        spec = replace(spec, budget=args.budget)
    if getattr(args, "pipeline", None):
        spec = replace(spec, pipeline=args.pipeline)
    seed = sc.seed if args.seed is None else args.seed
    from .cli_ensemble import scenario_members

    members = scenario_members(sc, world)  # issue 39: [currents] members, read (and checked) before planning
    bar = _Progress(spec, sc.name, quiet or args.quiet)
    problem = planning_problem(world, mission)
    ensemble: dict[str, Any] = {}
    try:
        if members:  # the plan flown in every member, or the robust plan
            from .cli_ensemble import ensemble_plan

            result, ensemble = ensemble_plan(members, world, replace(mission, planner=spec), seed)
        else:
            result = plan(problem, spec, seed, bar)
    finally:
        bar.close()
    if getattr(args, "reference", False):
        bar.stage("reference: the converged lattice plan and the seeded iabc, pso, de at twice the budget")
        result = with_reference(result, problem, spec, reference(problem, spec))
    return sc, result, seed, world, ensemble


def _duration(text: str, what: str) -> float:
    """Seconds of '15min', '900s', '2h', '1.5h' or a bare number of seconds."""
    units = {"s": 1.0, "sec": 1.0, "min": 60.0, "m": 60.0, "h": 3600.0, "d": 86400.0}
    t = text.strip().lower().lstrip("+")
    for unit in sorted(units, key=len, reverse=True):
        if t.endswith(unit):
            t, scale = t[: -len(unit)], units[unit]
            break
    else:
        scale = 1.0
    try:
        return float(t) * scale
    except ValueError:
        raise AuvplanError(f"{what} {text!r}: not a duration (e.g. 15min, 900s, 2h)") from None


def _is_offset(text: str) -> bool:
    """Whether a departure is an offset after start_time ('+6h', '900') rather than a date-time."""
    return text.startswith("+") or text[:1].isdigit() and not any(c in text for c in "-:T")


def _instant(text: str, start_time: str, what: str) -> float:
    """Seconds after the mission's start_time of an ISO 8601 time or a '+6h' offset."""
    from .io.data.tides import parse_start_time

    if _is_offset(text):
        return _duration(text, what)
    if not start_time:
        raise AuvplanError(f"{what} {text!r}: a date-time needs [mission] start_time (or give an offset: +6h)")
    try:
        return parse_start_time(text) - parse_start_time(start_time)
    except ValueError as exc:
        raise AuvplanError(f"{what} {exc}") from None


def _cmd_sweep(args: argparse.Namespace) -> int:
    from .io.missions.energy import sweep_energy
    from .io.results import records
    from .io.scenario import loader as scenario_io
    from .planners.timeopt.planner import departure_sweep, sweep_summary
    from .sim import planning_problem

    _out(args, ("sweep.csv", "sweep_summary.json", "sweep.png"))
    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    spec = replace(mission.planner, name="timeopt")
    if args.objective:
        spec = replace(spec, timeopt=replace(spec.timeopt, objective=args.objective))
    t0, t1 = (_instant(v, sc.mission.start_time, "--depart-between") for v in args.depart_between)
    step = _duration(args.step, "--step")
    if not (t1 >= t0 and step > 0 and (t1 - t0) / step <= 500):
        raise AuvplanError(f"--depart-between {args.depart_between} --step {args.step}: need T1 >= T0 and at most "
                           "500 departures")
    from .io.scenario.build import check_plan_sizes

    b = world.bounds
    check_plan_sizes(sc, (b.xmax - b.xmin, b.ymax - b.ymin), t1 - t0, timeopt=True)  # the table: sweep + horizon
    departs = np.arange(t0, t1 + 0.5 * step, step)
    plans: list[Any] = []
    from tqdm import tqdm

    # departures done / total and an ETA on stderr; silent with -q or --json
    with tqdm(total=len(departs), desc=f"departures of {sc.name}", unit="dep", file=sys.stderr,
              disable=args.quiet or args.json, mininterval=0.5) as bar:
        rows, _ = departure_sweep(planning_problem(world, mission), spec, departs, paths=plans,
                                  progress=lambda done, total: bar.update(done - bar.n))
    energy = sweep_energy(world, mission, plans, departs)
    summary = sweep_summary(rows, energy=spec.timeopt.objective == "energy")
    if sc.mission.start_time and summary.get("feasible_departures"):
        from .io.data.tides import parse_start_time, utc_iso

        summary["best_depart_utc"] = utc_iso(parse_start_time(sc.mission.start_time) + summary["best_depart_s"])
    table = [{**dataclasses.asdict(r), **e} for r, e in zip(rows, energy)]
    if args.out:
        out = Path(args.out)
        atomic_write(out / "sweep.csv", ",".join(table[0]) + "\n"
                     + "".join(",".join(f"{v:.6g}" for v in row.values()) + "\n" for row in table))
        records.write_json(out / "sweep_summary.json", summary)
        from .viz.timeplots import sweep_figure

        save_figure(out / "sweep.png", sweep_figure(rows, f"{sc.name}: departure sweep"), dpi=120)
    lines = [f"{sc.name}: {len(rows)} departures every {step / 60:.0f} min from {t0 / 3600:+.2f} h "
             f"(after {sc.mission.start_time or 't = 0'})",
             f"{'depart h':>9} {'timed h':>8} {'steady h':>9} {'straight h':>10} {'timed MJ':>9} {'energy Wh':>9} "
             f"{'margin Wh':>9} {'PNR h':>6} {'PNR km':>6}"]
    lines += [f"{r.depart_s / 3600:9.2f} {r.duration_s / 3600:8.2f} {r.steady_duration_s / 3600:9.2f} "
              f"{r.straight_duration_s / 3600:10.2f} {r.energy_j / 1e6:9.3f} {e['energy_wh']:9.1f} "
              f"{e['margin_wh']:9.1f} {e['pnr_t_s'] / 3600:6.2f} {e['pnr_s_m'] / 1000:6.1f}"
              + (" (whole mission)" if e["pnr_whole_mission"] == 1 else "")
              + ("" if np.isfinite(e["energy_wh"]) or not np.isfinite(r.duration_s) else
                 " (a cross current beats the vehicle on the plan's track: PNR up to there)")
              for r, e in zip(rows, energy)]
    if summary.get("feasible_departures"):
        lines.append(f"best departure {summary['best_depart_s'] / 3600:+.2f} h: "
                     f"{summary['best_duration_s'] / 3600:.2f} h, saves {summary['saved_vs_worst_pct']:.1f} % "
                     "against the worst departure, "
                     f"{summary['saved_vs_steady_pct']:.1f} % against the steady-current plan and "
                     f"{summary['saved_vs_straight_pct']:.1f} % against the straight line"
                     + (f"\n  fly it: [mission] start_time = \"{summary['best_depart_utc']}\""
                        if "best_depart_utc" in summary else ""))
    _emit({"scenario": sc.name, "summary": summary, "rows": table}, args.json, "\n".join(lines))
    return 0 if summary.get("feasible_departures") else 1


def _cmd_plan(args: argparse.Namespace) -> int:
    from .io.results import records

    if args.depart_between:
        return _cmd_sweep(args)
    if args.objective:
        raise AuvplanError("--objective applies to the departure sweep (--depart-between); set "
                           "[planner.timeopt] objective in the scenario for one plan")
    sc, result, seed, world, ensemble = _plan(args, quiet=False)
    record = records.plan_record(result, sc.name, seed)
    record.update(ensemble)
    if world.terrain is not None and world.terrain.fit is not None:
        record.update(records.fit_metrics(world.terrain.fit))
    if args.reference:
        record["reference_cost"] = result.reference_cost
        record["gap_pct"] = result.gap_pct
    if args.out:
        _save_plan(Path(args.out), sc, world, result, seed, ensemble)
    human = (f"{sc.name}: {result.planner} seed {seed} → {result.status.value}  cost {result.cost:.6g}  "
             f"length {record['length_m'] or 0:.0f} m  evaluations {result.evaluations}  "
             f"{result.wall_time_s:.2f} s" + _work_note(result.work)
             + (f"\n  {result.message}" if result.message else "")
             + (f"\n  grid reference cost {result.reference_cost:.6g}, gap {result.gap_pct:+.2f} %"
                if args.reference else ""))
    _emit(record, args.json, human)
    return 0 if result.status.ok else 1


def _work_note(work: dict[str, float]) -> str:
    """The seeded pipeline's work outside the evaluation budget, for the human line of ``plan``."""
    if not work:
        return ""
    parts = []
    if "seeding_cpu_s" in work:
        parts.append(f"seeding lattice {work['seeding_lattice_nodes']:.0f} nodes {work['seeding_cpu_s']:.3f} s CPU")
    if "polish_cpu_s" in work:
        parts.append(f"polish {work['polish_cpu_s']:.3f} s CPU")
    return f"  (outside the budget: {', '.join(parts)})"


def _cmd_simulate(args: argparse.Namespace) -> int:
    from .io.results import records
    from .io.scenario import loader as scenario_io
    from .sim import run_mission

    _out(args)
    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    seed = sc.seed if args.seed is None else args.seed
    bar = _Progress(mission.planner, sc.name, args.quiet or args.json)
    try:  # the same pipeline as `run`: the same plan, mission and seed fly the same track
        run = run_mission(world, mission, seed, bar, guidance=args.guidance, avoidance=args.avoidance,
                          flight=bar.flight)
    finally:
        bar.close()
    if run.sim is None:
        assert run.plan is not None  # no flight without a route: the plan failed
        print(f"auvplan: the global plan failed ({run.plan.status.value}): {run.plan.message}", file=sys.stderr)
        return 1
    result = run.sim
    record = records.sim_record(result, sc.name, seed, result.avoidance)
    if args.out:
        records.write_sim(Path(args.out), result, sc.name, seed, result.avoidance, args.full, world.origin)
    m = result.metrics
    human = (f"{sc.name}: {result.guidance} seed {seed} → {result.status.value} after {m['duration_s']:.0f} s; "
             f"cross-track RMS {m['cross_track_rms_m']:.2f} m, max {m['cross_track_max_m']:.2f} m; "
             f"min obstacle distance {m['min_obstacle_distance_m']:.2f} m")
    _emit(record, args.json, human)
    return 0 if result.status.ok else 1


def _run(scenario: str, out: str | None, guidance: str | None, avoidance: str | None, seed: int | None,
         full: bool = False, force: bool = False, quiet: bool = False,
         planner: str | None = None) -> tuple[Scenario, RunRecord, Endurance | None]:
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
    bar = _Progress(mission.planner, sc.name, quiet)
    try:
        record = run_mission(world, mission, seed, bar, guidance=guidance, avoidance=avoidance, flight=bar.flight)
    finally:
        bar.close()
    endurance = mission_endurance(world, mission, record)
    if out:
        bar.stage(f"writing results, report and exports into {out}")
        from .cli_ensemble import route_fields, scenario_members, write_ensemble

        write_ensemble(Path(out), route_fields(scenario_members(sc, world), world, mission, record.route))
        text = _scenario_text(sc)
        records.write_run(Path(out), record, text, full, world.origin)
        _save_context(Path(out), sc, world)
        if endurance is not None:
            from .io.missions.energy import write_energy

            frame = LocalFrame(*world.origin) if world.origin is not None else None
            write_energy(Path(out), endurance, frame.inverse if frame else None)
        _write_report(Path(out), world, mission, record, text, full=full, endurance=endurance)
    return sc, record, endurance


def _scenario_text(sc: Scenario) -> str:
    try:
        return Path(sc.source).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return ""


def _save_context(out: Path, sc: Scenario, world: World) -> None:
    """What makes a results folder self-contained: the scenario's origin and the terrain it used."""
    from .io.results import folder as results
    from .io.results import records

    records.write_json(out / "source.json", {"scenario_source": str(Path(sc.source).resolve())})
    results.save_terrain(out, world.terrain)


def _save_plan(out: Path, sc: Scenario, world: World, result: PlanResult, seed: int,
               ensemble: dict[str, Any] | None = None) -> None:
    """``plan --out``: the plan files plus a run record without a flight, so report/export work on it."""
    from .io.results import records
    from .sim import RunRecord

    text = _scenario_text(sc)
    empty = result.path[:0].reshape(0, 3)
    records.write_run(out, RunRecord(sc.name, seed, result, empty, empty, None), text, origin=world.origin)
    _save_context(out, sc, world)
    from .cli_ensemble import write_ensemble

    write_ensemble(out, ensemble or {})


def _write_report(out: Path, world: World, mission: Mission, record: RunRecord, text: str, figures: bool = False,
                  full: bool = False, endurance: Endurance | None = None) -> Path:
    """report.html (and the exports, and with ``figures`` the static PNG/SVG figures) into ``out``."""
    from .io.data.geo import LocalFrame
    from .io.missions import export
    from .io.results import records
    from .viz.report import build_report

    frame = LocalFrame(*world.origin) if world.origin is not None else None
    formats = [f for f in export.EXPORT_FORMATS if frame is not None or f not in export.GEOGRAPHIC]
    from .io.missions.energy import mission_endurance

    export.write_exports(out, record, world.origin, _planned_speeds(out, record, mission), formats, full)
    if endurance is None:
        endurance = mission_endurance(world, mission, record)
    metrics = records.summary_metrics(record)
    if world.terrain is not None and world.terrain.fit is not None:
        metrics.update(records.fit_metrics(world.terrain.fit))
    from .cli_ensemble import read_ensemble

    page = build_report(world, record, text, metrics, frame.inverse if frame else None, endurance, read_ensemble(out))
    path = atomic_write(out / "report.html", page)
    if figures:
        from .viz import plots

        plots.write_mission_figures(out / "figures", world, record, save=save_figure,
                                    to_lonlat=frame.inverse if frame else None)
    return path


def _planned_speeds(out: Path, record: RunRecord, mission: Mission) -> float | np.ndarray:
    """The speed of each leg of the mission (``legs.csv`` of the folder), else the vehicle's speed."""
    from .io.missions.energy import read_leg_speeds

    speeds = read_leg_speeds(out, max(record.route.shape[0] - 1, 0))
    return mission.vehicle.speed if speeds is None else speeds


_FIGURES = tuple(f"figures/{n}.{f}" for n in ("plan_view", "profiles", "convergence") for f in ("png", "svg"))
"""Files of ``report --figures``."""


def _load_results(args: argparse.Namespace) -> tuple[Path, RunRecord, str, World, Mission]:
    from .io.results import folder as results
    from .io.results import records
    from .io.scenario import loader as scenario_io
    from .sim import mission_route

    out = Path(args.dir)
    if not out.is_dir():
        raise AuvplanError(f"{out}: no such results folder")
    names = [*RESULT_NAMES, *(_FIGURES if getattr(args, "figures", False) else ())] if args.command == "report" \
        else [f"mission.{f}" for f in args.format]
    prepare_out(out, names, force=args.force)
    record, text = records.read_run(out)
    if not text:
        raise AuvplanError(f"{out}/scenario.toml: missing — the report needs the scenario to rebuild the world")
    sc = scenario_io.loads(text, str(out / "scenario.toml"), base_dir=results.scenario_base(out))
    world, mission = scenario_io.build(sc, terrain=results.load_terrain(out))
    if not record.route.size and record.plan is not None and record.plan.path.size:
        # a plan without a flight: export the executable mission, not the raw planned curve
        record = replace(record, route=mission_route(world, mission, record.plan.path))
    return out, record, text, world, mission


def _cmd_report(args: argparse.Namespace) -> int:
    out, record, text, world, mission = _load_results(args)
    path = _write_report(out, world, mission, record, text, figures=args.figures)
    print(f"report: {path} ({path.stat().st_size / 1e6:.1f} MB)")
    return 0


def _cmd_export(args: argparse.Namespace) -> int:
    from .io.missions import export

    out, record, _, world, mission = _load_results(args)
    for p in export.write_exports(out, record, world.origin, _planned_speeds(out, record, mission), args.format,
                                  args.full):
        print(p)
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


def _describe_run(name: str, record: RunRecord, endurance: Endurance | None = None) -> str:
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
    return "\n".join(lines)


def _run_formation(args: argparse.Namespace, sc: Scenario, world: World, mission: Mission) -> int:
    """``run`` of a scenario with ``[[vehicles]]``: the formation pipeline, its files and report."""
    from .io.data.geo import LocalFrame
    from .io.missions.formation import FORMATION_NAMES, formation_record, vehicle_records, write_formation
    from .sim.formation import run_formation

    assert mission.formation is not None  # _cmd_run calls this only for a scenario with [[vehicles]]
    if args.guidance or args.avoidance:
        raise AuvplanError(f"{sc.source}: --guidance/--avoidance do not apply to a formation (each vehicle flies "
                           "the formation field of [formation])")
    if args.out:
        names = [*FORMATION_NAMES, *(f"{v.name}/{f}" for v in mission.formation.vehicles for f in RESULT_NAMES)]
        prepare_out(args.out, names, force=args.force)
    if args.planner:
        mission = replace(mission, planner=replace(mission.planner, name=args.planner))
    seed = sc.seed if args.seed is None else args.seed
    bar = _Progress(mission.planner, sc.name, args.quiet or args.json)
    try:
        record = run_formation(world, mission, seed, bar, flight=bar.flight)
    finally:
        bar.close()
    if args.out:
        from .viz.formation import build_formation_report

        bar.stage(f"writing results, report and exports into {args.out}")
        out, text = Path(args.out), _scenario_text(sc)
        write_formation(out, world, mission, record, text, args.full)
        _save_context(out, sc, world)
        frame = LocalFrame(*world.origin) if world.origin is not None else None
        page = build_formation_report(world, record, [r for _, r in vehicle_records(world, mission, record)], text,
                                      frame.inverse if frame else None)
        atomic_write(out / "report.html", page)
    rec = formation_record(record)
    m = rec["metrics"] or {}
    human = f"{sc.name}: {record.status.value}" + (
        f" — {m['arrivals']}/{m['vehicles']} vehicles arrived, {m['collisions']} collisions, least vehicle "
        f"distance {m['min_vehicle_distance_m']:.1f} m, formation error RMS {m['formation_error_rms_m']:.2f} m "
        f"(max {m['formation_error_max_m']:.2f} m); shapes: "
        + " → ".join(f"{s} from {b:.0f} m" for b, s in record.formation.breaks) if m and record.formation else "")
    _emit(rec, args.json, human)
    if args.out and not args.json:
        print(f"results in {args.out}/ (one folder per vehicle)")
    return 0 if record.status.ok else 1


def _cmd_run(args: argparse.Namespace) -> int:
    from .io.results import records
    from .io.scenario import loader as scenario_io

    sc = scenario_io.load(args.scenario)
    if sc.survey is not None:
        from .cli_survey import cmd_survey

        return cmd_survey(args)
    if sc.formation is not None:
        world, mission = scenario_io.build(sc)
        return _run_formation(args, sc, world, mission)
    sc, record, endurance = _run(args.scenario, args.out, args.guidance, args.avoidance, args.seed, full=args.full,
                                 force=args.force, quiet=args.quiet or args.json, planner=args.planner)
    rec = records.run_record(record)
    if endurance is not None:
        from .io.missions.energy import energy_record

        rec["energy"] = records.jsonable(energy_record(endurance))
        if record.status.ok and not endurance.status.ok:
            rec["status"] = endurance.status.value
    _emit(rec, args.json, _describe_run(sc.name, record, endurance))
    if args.out and not args.json:
        print(f"results in {args.out}/")
    return 0 if record.status.ok and (endurance is None or endurance.status.ok) else 1


def _cmd_demo(args: argparse.Namespace) -> int:
    sc, record, endurance = _run(DEMO_SCENARIO, args.out, None, None, None, force=args.force, quiet=args.quiet)
    print(_describe_run(sc.name, record, endurance))
    print(f"results in {args.out}/")
    return 0 if record.status.ok and (endurance is None or endurance.status.ok) else 1


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
