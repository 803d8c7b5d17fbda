"""Monte Carlo of local avoidance on ``dynamic-terrain`` (or another scenario) with randomised obstacle tracks.

    .venv/bin/python benchmarks/montecarlo.py --seeds 1000 --workers 2 --out results/bench-mc
    .venv/bin/python benchmarks/montecarlo.py --seeds 1000 --scheduler tcp://host:8786   # a cluster
    .venv/bin/python benchmarks/montecarlo.py --scenario avoidance-gauntlet --avoidance predictive apf --seeds 12

Each avoidance variant (``--avoidance``, default the scenario's own) flies the same seeds in the
same run, so their decision-step times are measured under the same machine load (``uptime`` is
recorded in the summary).

The global plan is made once (seed of the scenario); each seed then re-draws every moving
obstacle's track (start shifted ±150 m along and across its motion, speed ×[0.6, 1.2], new
random-walk seeds; all stay slower than the vehicle) and flies the mission with the APF.
Reported: arrival rate, terrain collisions, obstacle collisions not flagged UNAVOIDABLE,
escapes, path-length overhead over the global path, mean compute time of one APF decision step,
and — for the "re-plan the remaining path" strategy the document argues against — the time one
re-plan takes (the swarm planner from the vehicle's position at its first encounter to the goal,
with the obstacles frozen as static spheres), i.e. the reaction time of each strategy.

The seeds run on dask.distributed (``--workers N``, ``--scheduler ADDR``, ``--retries N``: the Runner of
``auvplan bench``, ``benchmarks/parallel_runs.py``); rows reach ``rows.jsonl`` as they finish, the summary takes
them in seed order, and all but the timing fields are the same on 1 and N workers.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.app.bench.sweep import perturb_moving
from auvplan.guidance.avoidance.local import key_waypoints
from auvplan.io.scenario import loader as sc
from auvplan.planners import PlanningProblem, plan
from auvplan.sim import mission_route, planning_problem, simulate
from auvplan.world import Sphere

sys.path.insert(0, str(Path(__file__).resolve().parent))
from parallel_runs import add_arguments, run_all, where  # noqa: E402


def one(args) -> dict:
    seed, route, keys, path_length, scenario, avoidance = args
    world, mission = sc.build(sc.load(scenario))
    w = perturb_moving(world, seed)
    r = simulate(w, mission, route=route, rng=seed, avoidance=avoidance, keys=keys)
    kinds = [e[1] for e in r.events]
    terrain_hit = any(k == "collision" and "seabed" in e[2] for k, e in zip(kinds, r.events))
    obstacle_hit = any(k == "collision" and "obstacle" in e[2] for k, e in zip(kinds, r.events))
    # reaction time of the re-plan strategy at the first encounter
    replan_s = None
    near = np.flatnonzero((r.obstacle_distance[:, len(w.obstacles):] <= mission.avoidance.radius).any(axis=1))
    if near.size:
        i = int(near[0])
        t = float(r.t[i])
        frozen = tuple(Sphere(tuple(o.center(t)), o.shape.bounding_radius) for o in w.moving if o.active(t))
        static = replace(w, moving=(), obstacles=w.obstacles + frozen)
        prob = PlanningProblem(static, r.position[i], np.asarray(mission.goal), mission.vehicle.speed,
                               mission.vehicle.hotel_power, mission.vehicle.drag_k)
        t0 = time.perf_counter()
        plan(prob, mission.planner, rng=seed)
        replan_s = time.perf_counter() - t0
    return {
        "avoidance": avoidance, "seed": seed, "status": r.status.value, "arrived": r.arrived,
        "terrain_collision": terrain_hit,
        "obstacle_collision_unflagged": obstacle_hit, "unavoidable": "unavoidable" in kinds,
        "escapes": r.escapes, "overhead": r.metrics["distance_m"] / path_length - 1.0,
        "decisions": r.decision_steps, "decision_time_s": r.decision_time_s, "replan_s": replan_s,
        "min_obstacle_distance_m": r.metrics["min_obstacle_distance_m"], "wall_s": r.wall_time_s,
    }


def _summary(rows: list[dict], args, avoidance: str, wall: float) -> str:
    n = len(rows)
    dec = sum(r["decisions"] for r in rows)
    dec_t = sum(r["decision_time_s"] for r in rows)
    replans = [r["replan_s"] for r in rows if r["replan_s"] is not None]
    replan = f"median {np.median(replans):.3f} s ({len(replans)} encounters)" if replans else "no encounter"
    return (
        f"# {args.scenario} Monte Carlo, {avoidance}: {n} seeds, {where(args)}, {wall:.0f} s wall\n\n"
        f"- arrival: {sum(r['arrived'] for r in rows)}/{n} ({100 * np.mean([r['arrived'] for r in rows]):.1f} %)\n"
        f"- terrain collisions: {sum(r['terrain_collision'] for r in rows)}\n"
        f"- obstacle collisions not flagged UNAVOIDABLE: {sum(r['obstacle_collision_unflagged'] for r in rows)}\n"
        f"- flagged UNAVOIDABLE: {sum(r['unavoidable'] for r in rows)}\n"
        f"- deadlocks: {sum(r['status'] == 'DEADLOCK' for r in rows)}\n"
        f"- escapes: {sum(r['escapes'] for r in rows)} in total\n"
        f"- smallest obstacle distance: {min(r['min_obstacle_distance_m'] for r in rows):.2f} m\n"
        f"- path-length overhead over the global path: median {100 * np.median([r['overhead'] for r in rows]):.2f} %, "
        f"max {100 * max(r['overhead'] for r in rows):.2f} %\n"
        f"- decision step: {1e6 * dec_t / max(dec, 1):.1f} µs mean over {dec} steps\n"
        f"- re-plan strategy, one re-plan of the remaining path: {replan}\n"
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=1000)
    ap.add_argument("--out", default="results/bench-mc")
    ap.add_argument("--scenario", default="dynamic-terrain")
    ap.add_argument("--avoidance", nargs="+", default=None, help="variants (default: the scenario's own)")
    add_arguments(ap, workers=2)
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    world, mission = sc.build(sc.load(args.scenario))
    variants = args.avoidance or [mission.avoidance.name]
    planned = plan(planning_problem(world, mission), mission.planner, rng=mission.seed)
    length = float(np.linalg.norm(np.diff(planned.path, axis=0), axis=1).sum())
    route = mission_route(world, mission, planned.path)
    keys = key_waypoints(route, world)
    load = os.getloadavg()
    texts = []
    with open(out / "rows.jsonl", "w") as fh:

        def arrived(row: dict) -> None:
            fh.write(json.dumps(row) + "\n")
            fh.flush()

        for avoidance in variants:
            t0 = time.perf_counter()
            tasks = [(s, route, keys, length, args.scenario, avoidance) for s in range(args.seeds)]
            rows = run_all(args, one, tasks, arrived)
            texts.append(_summary(rows, args, avoidance, time.perf_counter() - t0))
    text = "\n".join(texts) + "\nmachine load (1, 5, 15 min) at the start: " + ", ".join(f"{v:.1f}" for v in load)
    text += "\n"
    (out / "summary.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
