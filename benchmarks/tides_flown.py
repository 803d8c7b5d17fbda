"""Planned against flown durations of ``juan-de-fuca-tides`` over the departure sweep (issue 36, point 5).

    .venv/bin/python benchmarks/tides_flown.py [--hours 25] [--step 30] [--out results/tides]
        [--scenario juan-de-fuca-tides] [--figure NAME]

For every departure of the sweep of ``benchmarks/tides.py`` (``--hours`` every ``--step`` minutes from
the scenario's start time), the departure sweep's timed plan (:func:`departure_sweep`, its duration
flown through the World's current, :mod:`auvplan.planners.timeopt.timing`) is built into the
executable mission (:func:`auvplan.sim.mission_route` with the plan's times: floors, Douglas–Peucker
with a tolerance small enough to keep the plan's duration within 0.2 %, fly-by turns) and
flown by the closed loop (:func:`auvplan.sim.simulate`: the scenario's guidance, vehicle and
``[sim]`` settings, seed 1) in the same tidal current with its epoch moved to the departure (what
``[mission] start_time`` = the departure does).  The deadlock watch is lengthened to 6 h so that
a plan which drifts back with the tide is flown, not stopped (no plan of the sweep drifts: see the
``drift_back_m`` column).  Writes ``tides_flown.json`` with one row per departure and the worst, and
with ``--figure NAME`` the summary as ``docs/figures/NAME.md`` (quoted in docs/timeopt.md).
``--scenario rotary-tide``: the same for the rotary current stronger than the vehicle (issue 36).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import time
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from auvplan.io.scenario import loader as scenario
from auvplan.planners import plan
from auvplan.planners.timeopt.planner import departure_sweep
from auvplan.planners.timeopt.timing import fly_times
from auvplan.sim import mission_route, planning_problem, simulate
from auvplan.sim.pipeline import route_tail


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--hours", type=float, default=25.0)
    ap.add_argument("--step", type=float, default=30.0, help="minutes")
    ap.add_argument("--out", default="results/tides")
    ap.add_argument("--scenario", default="juan-de-fuca-tides")
    ap.add_argument("--figure", default="", help="write docs/figures/NAME.md")
    ap.add_argument("--tail-first", action="store_true", help="plan each departure with tail_first = true "
                    "(plan(), not the sweep) and fly its tail-first legs tail-first")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print("load:", load, "cpus", os.cpu_count())
    world, mission = scenario.build(scenario.load(args.scenario))
    mission = replace(mission, sim=replace(mission.sim, deadlock_time=6 * 3600.0))
    problem = planning_problem(world, mission)
    departs = np.arange(0.0, args.hours * 3600.0 + 1.0, args.step * 60.0)
    paths: list = []
    c0 = time.process_time()
    tails: list = []
    if args.tail_first:
        rows = []
        for d in departs:
            res = plan(problem, replace(mission.planner, name="timeopt", timeopt=replace(
                mission.planner.timeopt, depart_s=float(d), tail_first=True)))
            ok = res.status.value == "EXACT"
            rows.append(SimpleNamespace(depart_s=float(d), duration_s=float(res.cost) if ok else math.inf))
            paths.append((res.path, float(res.cost_terms["speed_m_s"])) if ok else None)
            tails.append(res.tail if ok else None)
    else:
        rows, _ = departure_sweep(problem, replace(mission.planner, name="timeopt"), departs, paths=paths)
        tails = [None] * len(rows)
    sweep_cpu = time.process_time() - c0
    print(f"sweep: {len(rows)} departures, {sweep_cpu:.1f} s CPU")
    out_rows = []
    for row, plan_, tail in zip(rows, paths, tails, strict=True):
        if plan_ is None:
            out_rows.append({"depart_h": row.depart_s / 3600.0, "planned_s": None, "flown_s": None,
                             "status": "no plan"})
            continue
        shifted = replace(world, currents=replace(world.currents, epoch=world.currents.epoch + row.depart_s))
        times, back = fly_times(world.currents, plan_[0], row.depart_s, plan_[1], 62.5, row.depart_s + 2 * 86400.0,
                                tail)
        route = mission_route(shifted, mission, plan_[0], times - row.depart_s, plan_[1], tail)
        w0 = time.perf_counter()
        sim = simulate(shifted, mission, route=route, rng=mission.seed, tail=route_tail(route, plan_[0], tail))
        flown = float(sim.t[-1])
        r = {"depart_h": row.depart_s / 3600.0, "planned_s": row.duration_s, "flown_s": flown,
             "error_pct": 100.0 * (flown - row.duration_s) / row.duration_s, "status": sim.status.value,
             "waypoints": int(route.shape[0]), "drift_back_m": float(back.max()), "wall_s": time.perf_counter() - w0,
             "tail_first_legs": int(np.sum(tail)) if tail is not None else 0}
        out_rows.append(r)
        print(json.dumps(r), flush=True)
    errs = [r for r in out_rows if r.get("error_pct") is not None]
    worst = max(errs, key=lambda r: abs(r["error_pct"])) if errs else None
    doc = {"departures": len(rows), "arrived": sum(r["status"] == "EXACT" for r in out_rows),
           "worst": worst, "mean_abs_error_pct": float(np.mean([abs(r["error_pct"]) for r in errs])) if errs else None,
           "rows": out_rows}
    (out / "tides_flown.json").write_text(json.dumps(doc, indent=1))
    print("worst:", json.dumps(worst), "arrived", doc["arrived"], "of", doc["departures"])
    if args.figure and worst is not None:
        planned = sum(r.get("planned_s") is not None for r in out_rows)
        text = (f"`{args.scenario}`, departures every {args.step:g} min over {args.hours:g} h: {planned}/{len(rows)} "
                f"planned, {doc['arrived']} flown to the goal, {sum(abs(r['error_pct']) <= 1.0 for r in errs)} within "
                f"1 % of the plan; planned vs flown worst {worst['error_pct']:+.3f} % "
                f"(+{worst['depart_h']:g} h: planned {worst['planned_s']:.1f} s, flown {worst['flown_s']:.1f} s), "
                f"mean |error| {doc['mean_abs_error_pct']:.3f} %, largest drift back "
                f"{max(r.get('drift_back_m', 0.0) for r in out_rows):.0f} m; sweep {sweep_cpu:.0f} s CPU; "
                f"{mission.guidance} guidance, seed {mission.seed}; load average "
                f"{load.split('load average:')[-1].strip()} on {os.cpu_count()} "
                f"cores (`benchmarks/tides_flown.py --scenario {args.scenario} --hours {args.hours:g} "
                f"--step {args.step:g}{' --tail-first' if args.tail_first else ''}`)"
                + (f"; tail-first legs in {sum(r.get('tail_first_legs', 0) > 0 for r in out_rows)} plans, flown "
                   "tail-first" if args.tail_first else "") + "\n")
        Path(__file__).resolve().parents[1].joinpath("docs", "figures", f"{args.figure}.md").write_text(text)


if __name__ == "__main__":
    main()
