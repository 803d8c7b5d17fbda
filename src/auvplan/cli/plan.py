"""``plan`` and ``simulate``: the global plan of a scenario (with ``--reference``, against the lattice and the
seeded optimisers), its record and files; the flight of the same pipeline."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..app.results import save_plan
from ..errors import AuvplanError
from .output import Progress, check_out, emit
from .sweep import cmd_sweep

if TYPE_CHECKING:
    from ..io.scenario.specs import Scenario
    from ..planners import PlanResult
    from ..world import World

__all__: list[str] = []  # handlers: CLI internals, not library API


def plan_scenario(args: argparse.Namespace, quiet: bool) -> tuple[Scenario, PlanResult, int, World, dict[str, Any]]:
    """Load, build and plan the scenario of ``plan`` (with its members, or against the reference)."""
    from ..io.scenario import loader as scenario_io
    from ..planners import plan, reference, with_reference
    from ..sim import planning_problem

    check_out(args)
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
    from ..app.ensemble import scenario_members

    members = scenario_members(sc, world)  # issue 39: [currents] members, read (and checked) before planning
    bar = Progress(spec, sc.name, quiet or args.quiet)
    problem = planning_problem(world, mission)
    ensemble: dict[str, Any] = {}
    try:
        if members:  # the plan flown in every member, or the robust plan
            from ..app.ensemble import ensemble_plan

            result, ensemble = ensemble_plan(members, world, replace(mission, planner=spec), seed)
        else:
            result = plan(problem, spec, seed, bar)
    finally:
        bar.close()
    if getattr(args, "reference", False):
        bar.stage("reference: the converged lattice plan and the seeded iabc, pso, de at twice the budget")
        result = with_reference(result, problem, spec, reference(problem, spec))
    return sc, result, seed, world, ensemble


def cmd_plan(args: argparse.Namespace) -> int:
    """``plan``: one global plan, its record on stdout and with ``--out`` its files (or the departure sweep)."""
    from ..io.results import records

    if args.depart_between:
        return cmd_sweep(args)
    if args.objective:
        raise AuvplanError("--objective applies to the departure sweep (--depart-between); set "
                           "[planner.timeopt] objective in the scenario for one plan")
    sc, result, seed, world, ensemble = plan_scenario(args, quiet=False)
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
             + (f"\n  grid reference cost {result.reference_cost:.6g}, gap {result.gap_pct:+.2f} %"
                if args.reference else ""))
    emit(record, args.json, human)
    return 0 if result.status.ok else 1


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
    from ..io.results import records
    from ..io.scenario import loader as scenario_io
    from ..sim import run_mission

    check_out(args)
    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    seed = sc.seed if args.seed is None else args.seed
    bar = Progress(mission.planner, sc.name, args.quiet or args.json)
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
    emit(record, args.json, human)
    return 0 if result.status.ok else 1
