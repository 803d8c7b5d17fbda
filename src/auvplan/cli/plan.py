"""``plan`` and ``simulate``: their arguments to the jobs of :mod:`auvplan.app.plan`, and their output (a
human line, or one JSON object)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import AuvplanError
from .output import emit, finish, reporter, runner_of

__all__: list[str] = []  # handlers: CLI internals, not library API


def cmd_plan(args: argparse.Namespace) -> int:
    """``plan``: one global plan, its record on stdout and with ``--out`` its files (or the departure sweep)."""
    from ..app.plan import plan_scenario
    from ..app.results import save_plan
    from ..io.results import records
    from ..io.scenario import loader as scenario_io

    if scenario_io.load(args.scenario).vehicle.type == "glider":  # issue 58: planned in dive cycles, and flown
        if args.depart_between:
            raise AuvplanError(f"{args.scenario}: --depart-between does not sweep a glider's departures yet; set "
                               "[planner.timeopt] depart_s for one departure")
        from .glider import cmd_glider

        return cmd_glider(args)
    if args.depart_between:
        from .sweep import cmd_sweep

        return cmd_sweep(args)
    if args.objective:
        raise AuvplanError("--objective applies to the departure sweep (--depart-between); set "
                           "[planner.timeopt] objective in the scenario for one plan")
    sc, result, seed, world, ensemble = plan_scenario(
        args.scenario, args.out, getattr(args, "force", False), args.planner, args.budget,
        getattr(args, "pipeline", None), args.seed, getattr(args, "reference", False),
        reporter(args.quiet or args.json), runner_of(args))  # issue 51: --json leaves stderr empty
    record = records.plan_record(result, sc.name, seed)
    record.update(ensemble)
    if world.terrain is not None and world.terrain.fit is not None:
        record.update(records.fit_metrics(world.terrain.fit))
    if args.reference:
        record["reference_cost"] = result.reference_cost
        record["gap_pct"] = result.gap_pct
    if args.out:
        save_plan(Path(args.out), sc, world, result, seed, ensemble)
    human = (f"{sc.name}: {result.planner} seed {seed} → {result.status.value}  cost {result.cost:.6g}  "
             f"length {record['length_m'] or 0:.0f} m  evaluations {result.evaluations}  "
             f"{result.wall_time_s:.2f} s" + work_note(result.work)
             + (f"\n  {result.message}" if result.message else "")
             + (f"\n  not converged ({result.convergence})" if result.converged is False else "")
             + (f"\n  grid reference cost {result.reference_cost:.6g}, gap {result.gap_pct:+.2f} %"
                if args.reference else "") + route_note(len(sc.mission.route)))
    emit(record, args.json, human)
    return 0 if result.status.ok else 1


def route_note(waypoints: int) -> str:
    """The line of ``plan`` for a scenario with a fixed ``[mission] route``: ``run`` flies it, ``plan`` does not.

    Parameters
    ----------
    waypoints : int
        How many waypoints the scenario's ``[mission] route`` holds (0: none, no line).

    Returns
    -------
    str
        ``""``, or a line (with its leading newline) saying that this plan goes from start to goal, and that the
        route ``run`` flies and exports is the scenario's.
    """
    if not waypoints:
        return ""
    return (f"\n  note: the scenario's [mission] route ({waypoints} waypoint{'' if waypoints == 1 else 's'}) is what "
            "`run` flies and exports; this plan goes from start to goal without it")


def work_note(work: dict[str, float]) -> str:
    """The seeded pipeline's work outside the evaluation budget, for the human line of ``plan``."""
    if not work:
        return ""
    parts = []
    if "seeding_cpu_s" in work:
        parts.append(f"seeding lattice {work['seeding_lattice_nodes']:.0f} nodes {work['seeding_cpu_s']:.3f} s CPU")
    if "polish_cpu_s" in work:
        parts.append(f"polish {work['polish_cpu_s']:.3f} s CPU")
    return f"  (outside the budget: {', '.join(parts)})"


def cmd_simulate(args: argparse.Namespace) -> int:
    """``simulate``: the pipeline of ``run``, its flight's record and files."""
    from ..app.plan import simulate_scenario
    from ..io.results import records

    sc, run, seed = simulate_scenario(args.scenario, args.out, getattr(args, "force", False), args.guidance,
                                      args.avoidance, args.seed, args.full, reporter(args.quiet or args.json))
    if run.sim is None:
        assert run.plan is not None  # no flight without a route: the plan failed
        finish()  # the live line, before the verdict
        print(f"auvplan: the global plan failed ({run.plan.status.value}): {run.plan.message}", file=sys.stderr)
        return 1
    result = run.sim
    record = records.sim_record(result, sc.name, seed, result.avoidance)
    m = result.metrics
    human = (f"{sc.name}: {result.guidance} seed {seed} → {result.status.value} after {m['duration_s']:.0f} s; "
             f"cross-track RMS {m['cross_track_rms_m']:.2f} m, max {m['cross_track_max_m']:.2f} m; "
             f"min obstacle distance {m['min_obstacle_distance_m']:.2f} m")
    emit(record, args.json, human)
    return 0 if result.status.ok else 1
