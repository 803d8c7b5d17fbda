"""Command-line front end (DESIGN.md §4): argument parsing and output only, no logic.

Exit codes: 0 success, 1 the plan/simulation failed (status not EXACT or
APPROXIMATE), 2 bad input.  ``--json`` prints exactly one JSON object on
stdout; progress and messages go to stderr.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
from dataclasses import replace
from pathlib import Path

from . import __version__
from .errors import AuvplanError
from .io import export
from .io import scenario as scenario_io
from .io.geo import LocalFrame
from .planners import PLANNERS, SWARM, plan, reference, with_reference
from .sim import planning_problem, run_mission, simulate

__all__ = ["main", "main_entry"]

log = logging.getLogger("auvplan")

DEMO_SCENARIO = "dynamic-terrain"
"""The built-in default scenario: real Marcus-Wake seamount terrain with moving obstacles."""


class _Progress:
    """A tqdm bar on stderr for iterative work (silent when stderr is not a terminal and quiet)."""

    def __init__(self, spec, scenario: str, quiet: bool) -> None:
        from tqdm import tqdm

        # only the swarm optimisers iterate; the grid and flow planners would show a bar stuck at 0
        self.bar = tqdm(total=spec.iterations, desc=f"{spec.name} on {scenario}", file=sys.stderr,
                        disable=quiet or spec.name not in SWARM, leave=False, mininterval=0.5)

    def __call__(self, iteration: int, best: float) -> None:
        self.bar.update(iteration - self.bar.n)
        self.bar.set_postfix_str(f"best {best:.6g}", refresh=False)

    def close(self) -> None:
        self.bar.close()


def _emit(record: dict, as_json: bool, human: str) -> None:
    if as_json:
        sys.stdout.write(json.dumps(export.jsonable(record)) + "\n")
    else:
        print(human)


def _cmd_scenarios(args) -> int:
    for name, desc in scenario_io.builtin_scenarios().items():
        print(f"{name:18s} {desc}")
    return 0


def _cmd_data_inspect(args) -> int:
    from .io.inspect import inspect_file

    print(inspect_file(args.file))
    return 0


def _cmd_validate(args) -> int:
    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    b = world.bounds
    print(f"{sc.source}: OK — {sc.name}")
    print(f"  bounds x [{b.xmin:.0f}, {b.xmax:.0f}] y [{b.ymin:.0f}, {b.ymax:.0f}] z [{b.zmin:.0f}, {b.zmax:.0f}] m")
    if world.terrain is not None:
        t = world.terrain
        print(f"  terrain {t.name}: {t.x.size} x {t.y.size} nodes, cell {t.dx:.0f} m, "
              f"seabed {t.z.min():.0f} .. {t.z.max():.0f} m")
    print(f"  start {list(mission.start)} goal {list(mission.goal)}; "
          f"{len(world.obstacles)} static and {len(world.moving)} moving obstacles")
    return 0


def _plan(args, quiet: bool):
    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    spec = mission.planner
    if args.planner:
        spec = replace(spec, name=args.planner)
    if args.budget is not None:
        spec = replace(spec, budget=args.budget)
    seed = sc.seed if args.seed is None else args.seed
    bar = _Progress(spec, sc.name, quiet)
    problem = planning_problem(world, mission)
    try:
        result = plan(problem, spec, seed, bar)
    finally:
        bar.close()
    if getattr(args, "reference", False):
        result = with_reference(result, problem, spec, reference(problem, spec))
    return sc, result, seed


def _cmd_plan(args) -> int:
    sc, result, seed = _plan(args, quiet=False)
    record = export.plan_record(result, sc.name, seed)
    if args.reference:
        record["reference_cost"] = result.reference_cost
        record["gap_pct"] = result.gap_pct
    if args.out:
        export.write_plan(Path(args.out), result, sc.name, seed, Path(sc.source).read_text(encoding="utf-8"))
    human = (f"{sc.name}: {result.planner} seed {seed} → {result.status.value}  cost {result.cost:.6g}  "
             f"length {record['length_m'] or 0:.0f} m  evaluations {result.evaluations}  "
             f"{result.wall_time_s:.2f} s" + (f"\n  {result.message}" if result.message else "")
             + (f"\n  grid reference cost {result.reference_cost:.6g}, gap {result.gap_pct:+.2f} %"
                if args.reference else ""))
    _emit(record, args.json, human)
    return 0 if result.status.ok else 1


def _cmd_simulate(args) -> int:
    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    seed = sc.seed if args.seed is None else args.seed
    route = mission.route
    if not route:
        bar = _Progress(mission.planner, sc.name, False)
        try:
            planned = plan(planning_problem(world, mission), mission.planner, seed, bar)
        finally:
            bar.close()
        if not planned.status.ok:
            print(f"auvplan: the global plan failed ({planned.status.value}): {planned.message}", file=sys.stderr)
            return 1
        route = planned.path[:: max(len(planned.path) // 40, 1)].tolist() + [planned.path[-1].tolist()]
    result = simulate(world, mission, route=route, guidance=args.guidance, rng=seed)
    record = export.sim_record(result, sc.name, seed)
    if args.out:
        export.write_sim(Path(args.out), result, sc.name, seed)
    m = result.metrics
    human = (f"{sc.name}: {result.guidance} seed {seed} → {result.status.value} after {m['duration_s']:.0f} s; "
             f"cross-track RMS {m['cross_track_rms_m']:.2f} m, max {m['cross_track_max_m']:.2f} m; "
             f"min obstacle distance {m['min_obstacle_distance_m']:.2f} m")
    _emit(record, args.json, human)
    return 0 if result.status.ok else 1


def _run(scenario: str, out: str | None, guidance: str | None, avoidance: str | None, seed: int | None):
    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    seed = sc.seed if seed is None else seed
    bar = _Progress(mission.planner, sc.name, False)
    try:
        record = run_mission(world, mission, seed, bar, guidance=guidance, avoidance=avoidance)
    finally:
        bar.close()
    if out:
        export.write_run(Path(out), record, Path(sc.source).read_text(encoding="utf-8"))
        export.write_json(Path(out) / "source.json", {"scenario_source": str(Path(sc.source).resolve())})
        _write_report(Path(out), world, mission, record, Path(sc.source).read_text(encoding="utf-8"))
    return sc, record


def _write_report(out: Path, world, mission, record, text: str, figures: bool = False) -> Path:
    """report.html (and the exports, and with ``figures`` the static PNG/SVG figures) into ``out``."""
    from .viz.report import build_report

    frame = LocalFrame(*world.origin) if world.origin is not None else None
    formats = export.EXPORT_FORMATS if frame is not None else ("csv", "moos")
    export.write_exports(out, record, world.origin, mission.vehicle.speed, formats)
    page = build_report(world, record, text, export.summary_metrics(record), frame.inverse if frame else None)
    path = out / "report.html"
    path.write_text(page, encoding="utf-8")
    if figures:
        from .viz import plots

        plots.write_mission_figures(out / "figures", world, record)
    return path


def _load_results(directory: str):
    out = Path(directory)
    record, text = export.read_run(out)
    if not text:
        raise AuvplanError(f"{out}/scenario.toml: missing — the report needs the scenario to rebuild the world")
    src = out / "source.json"
    base = Path(json.loads(src.read_text())["scenario_source"]).parent if src.is_file() else out
    sc = scenario_io.loads(text, str(out / "scenario.toml"), base_dir=base)
    world, mission = scenario_io.build(sc)
    return out, record, text, world, mission


def _cmd_report(args) -> int:
    out, record, text, world, mission = _load_results(args.dir)
    path = _write_report(out, world, mission, record, text, figures=args.figures)
    print(f"report: {path} ({path.stat().st_size / 1e6:.1f} MB)")
    return 0


def _cmd_export(args) -> int:
    out, record, _, world, mission = _load_results(args.dir)
    for p in export.write_exports(out, record, world.origin, mission.vehicle.speed, args.format):
        print(p)
    return 0


def _describe_run(name: str, record) -> str:
    lines = [f"{name}: {record.status.value}"]
    if record.plan is not None:
        p = record.plan
        lines.append(f"  plan   {p.planner}: {p.status.value}, length {p.cost_terms.get('length_m', 0):.0f} m, "
                     f"{p.evaluations} evaluations, {p.wall_time_s:.2f} s" + (f" — {p.message}" if p.message else ""))
    if record.sim is not None:
        m = record.sim.metrics
        kind = f"{record.sim.guidance}+{record.sim.avoidance}"
        lines.append(f"  flight {kind}: {m['status']} after {m['duration_s']:.0f} s, "
                     f"{m['distance_m']:.0f} m flown, min altitude {m['min_clearance_m']:.1f} m, "
                     f"min obstacle distance {m['min_obstacle_distance_m']:.1f} m, {m['escapes']} escapes; "
                     f"{len(record.keys)} key waypoints")
    return "\n".join(lines)


def _cmd_run(args) -> int:
    sc, record = _run(args.scenario, args.out, args.guidance, args.avoidance, args.seed)
    _emit(export.run_record(record), args.json, _describe_run(sc.name, record))
    if args.out and not args.json:
        print(f"results in {args.out}/")
    return 0 if record.status.ok else 1


def _cmd_demo(args) -> int:
    sc, record = _run(DEMO_SCENARIO, args.out, None, None, None)
    print(_describe_run(sc.name, record))
    print(f"results in {args.out}/")
    return 0 if record.status.ok else 1


def _cmd_bench(args) -> int:
    from .bench import SweepSpec, summarise, sweep

    spec = SweepSpec(tuple(args.scenarios), tuple(args.planners), tuple(args.guidance), args.seeds, args.budget,
                     args.reference, args.randomise, args.plan_once, args.chunk)
    out = Path(args.out)
    rows = sweep(spec, out, workers=args.workers, scheduler=args.scheduler, resume=args.resume)
    table = summarise(rows)
    cols = list(table[0]) if table else []
    with (out / "summary.csv").open("w") as fh:
        fh.write(",".join(cols) + "\n")
        fh.writelines(",".join(str(r[c]) for c in cols) + "\n" for r in table)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(f"{r[c]:.6g}" if isinstance(r[c], float) else str(r[c]) for c in cols) + " |"
              for r in table]
    text = "\n".join(lines)
    (out / "summary.md").write_text(f"# auvplan bench: {len(rows)} runs\n\n{text}\n")
    from .bench import read_histories
    from .viz.plots import bench_figures
    from .viz.report import build_bench_report

    bench_figures(rows, out)
    page = build_bench_report(rows, table, read_histories(out / "histories.jsonl"))
    (out / "bench.html").write_text(page, encoding="utf-8")
    print(text)
    print(f"rows in {out / 'rows.csv'}, summary in {out / 'summary.md'}, report {out / 'bench.html'}")
    return 0


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="auvplan", description="Plan, check and simulate 3D AUV missions.")
    p.add_argument("--version", action="version", version=f"auvplan {__version__}")
    p.add_argument("-v", "--verbose", action="store_true", help="log progress details to stderr")
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("scenarios", help="list the built-in scenarios")
    s.set_defaults(func=_cmd_scenarios)

    s = sub.add_parser("validate", help="check a scenario file (exit 2 with clear messages)")
    s.add_argument("scenario", help="TOML file or built-in scenario name")
    s.set_defaults(func=_cmd_validate)

    s = sub.add_parser("data", help="inspect bathymetry and current files (NetCDF, GeoTIFF)")
    dsub = s.add_subparsers(dest="data_command", required=True)
    d = dsub.add_parser("inspect", help="print the layout, variables, units and axes auvplan detects in FILE")
    d.add_argument("file", help="NetCDF or GeoTIFF file")
    d.set_defaults(func=_cmd_data_inspect)

    s = sub.add_parser("plan", help="plan a global path")
    s.add_argument("scenario", help="TOML file or built-in scenario name")
    s.add_argument("--planner", choices=PLANNERS, help="override the scenario's planner")
    s.add_argument("--seed", type=int, help="random seed (default: the scenario's)")
    s.add_argument("--budget", type=int, help="objective evaluations (equal budgets for comparisons)")
    s.add_argument("--reference", action="store_true",
                   help="also plan the grid reference and report reference_cost and gap_pct")
    s.add_argument("--out", help="write metrics.json, path.csv and the scenario here")
    s.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    s.set_defaults(func=_cmd_plan)

    s = sub.add_parser("simulate", help="simulate the vehicle following the route (or the planned path)")
    s.add_argument("scenario", help="TOML file or built-in scenario name")
    s.add_argument("--guidance", choices=("hybrid", "los", "ilos"), help="override the scenario's guidance")
    s.add_argument("--seed", type=int, help="random seed (default: the scenario's)")
    s.add_argument("--out", help="write sim_metrics.json and track.csv here")
    s.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    s.set_defaults(func=_cmd_simulate)

    s = sub.add_parser("run", help="plan + key waypoints + closed-loop simulation with moving obstacles")
    s.add_argument("scenario", help="TOML file or built-in scenario name")
    s.add_argument("--guidance", choices=("hybrid", "los", "ilos"), help="override the scenario's guidance")
    s.add_argument("--avoidance", choices=("apf", "none"), help="override the scenario's avoidance")
    s.add_argument("--seed", type=int, help="random seed (default: the scenario's)")
    s.add_argument("--out", help="write every result file here")
    s.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    s.set_defaults(func=_cmd_run)

    s = sub.add_parser("report", help="write report.html (and the exports) for a results directory of `run --out`")
    s.add_argument("dir", help="results directory written by `auvplan run --out` or `demo`")
    s.add_argument("--figures", action="store_true", help="also write static PNG/SVG figures into DIR/figures")
    s.set_defaults(func=_cmd_report)

    s = sub.add_parser("export", help="write mission exports (GeoJSON, KML, CSV, MOOS-IvP) for a results directory")
    s.add_argument("dir", help="results directory written by `auvplan run --out` or `demo`")
    s.add_argument("--format", nargs="+", default=list(export.EXPORT_FORMATS), choices=export.EXPORT_FORMATS)
    s.set_defaults(func=_cmd_export)

    s = sub.add_parser("bench", help="sweep scenarios x planners x guidance x seeds on dask (rows.csv + summary)")
    s.add_argument("--scenarios", nargs="+", default=["dynamic-terrain"], help="built-in names or TOML files")
    s.add_argument("--planners", nargs="+", default=["scenario"], help="planner names, or 'scenario'")
    s.add_argument("--guidance", nargs="+", default=["scenario"], help="hybrid, los, ilos, or 'scenario'")
    s.add_argument("--seeds", type=int, default=10, help="seeds 0..N-1 per cell")
    s.add_argument("--budget", type=int, default=0, help="objective evaluations per plan (0: the scenario's)")
    s.add_argument("--reference", action="store_true", help="add the gap to the grid reference to every row")
    s.add_argument("--randomise", action="store_true", help="re-draw the moving obstacles' tracks per seed")
    s.add_argument("--plan-once", action="store_true", help="plan once per cell, fly it in every seed")
    s.add_argument("--chunk", type=int, default=10, help="seeds per dask task")
    g = s.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, default=2, help="local worker processes (a LocalCluster)")
    g.add_argument("--scheduler", help="address of an existing dask scheduler, e.g. tcp://host:8786")
    s.add_argument("--resume", action="store_true", help="complete an interrupted sweep in --out")
    s.add_argument("--out", default="results/bench", help="folder of rows.csv, summary.csv/md and figures")
    s.set_defaults(func=_cmd_bench)

    s = sub.add_parser("demo", help="run the built-in default scenario (dynamic-terrain) end to end")
    s.add_argument("--out", default="auvplan-demo", help="results directory (default: auvplan-demo)")
    s.set_defaults(func=_cmd_demo)
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse exits 2 on bad usage, 0 on --help
        return int(exc.code or 0)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, stream=sys.stderr,
                        format="%(levelname)s %(name)s: %(message)s")
    try:
        return args.func(args)
    except AuvplanError as exc:
        print(f"auvplan: error: {exc}", file=sys.stderr)
        return 2


def main_entry() -> None:
    """Console-script entry point."""
    sys.exit(main())


if __name__ == "__main__":  # pragma: no cover
    main_entry()
