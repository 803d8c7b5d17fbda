"""Avoidance without deadlocks (issue #36 point 4): fast-mover Monte Carlo and ``avoidance-gauntlet`` over seeds.

    nice -n 10 .venv/bin/python benchmarks/avoidance.py --seeds 100 --workers 2 --out results/bench-avoidance \
        --doc docs/avoidance.md

Three sets of missions, each seed flown once per avoidance variant (``--avoidance``, default
``predictive``):

``fast-movers``
    The held-out kind of case: ``avoidance-gauntlet``'s real seamount flank (ETOPO1, 100 m) and
    global plan (scenario seed), and per seed (:func:`auvplan.bench.fast_movers`) six spheres of
    15–30 m radius at 1.8–3.0 m/s (1.2–2× the vehicle's 1.5 m/s), each timed to meet the vehicle on
    the route at a random 10–90 % of its length (±40 s): straight runs at any angle to the route,
    shuttles 300 m across or along it, orbits of 60–100 m radius about it.
``gauntlet``
    ``avoidance-gauntlet`` as shipped: ``run_mission`` with the seed (the global plan, the escapes'
    random sub-goals); the obstacles' tracks are the file's.
``gauntlet-randomised``
    The README's kind: the scenario's plan (its seed), each seed re-drawing every moving
    obstacle's track (:func:`auvplan.bench.perturb_moving`).

Per set: arrivals, contacts (obstacle or seabed, UNAVOIDABLE included), deadlocks, timeouts,
runs where an escape fired (``escapes`` > 0: document 004's random sub-goal, or the sweep
replan / wait of :mod:`auvplan.guidance.escape`) and of those the runs that arrived, the smallest
obstacle distance.  Writes ``rows.jsonl`` and ``summary.md`` to ``--out`` and, with ``--doc``, the
same summary into that markdown file between the ``<!-- bench:avoidance -->`` markers.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from auvplan.bench import fast_movers, perturb_moving
from auvplan.guidance.local import key_waypoints
from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.sim import mission_route, planning_problem, run_mission, simulate

SCENARIO = "avoidance-gauntlet"
SETS = ("fast-movers", "gauntlet", "gauntlet-randomised")
MARK = "<!-- bench:avoidance -->"


def _row(kind: str, seed: int, avoidance: str, r) -> dict:
    kinds = [e[1] for e in r.events]
    return {"set": kind, "seed": seed, "avoidance": avoidance, "status": r.status.value, "arrived": r.arrived,
            "contact": any(k in ("collision", "unavoidable") for k in kinds), "escapes": r.escapes,
            "min_obstacle_m": float(r.metrics["min_obstacle_distance_m"]), "duration_s": r.metrics["duration_s"],
            "wall_s": r.wall_time_s, "events": [e[2] for e in r.events if e[1] != "arrival"]}


def one(args) -> dict:
    kind, seed, avoidance, route, keys = args
    world, mission = sc.build(sc.load(SCENARIO))
    if kind == "gauntlet":
        record = run_mission(world, mission, seed, avoidance=avoidance)
        return _row(kind, seed, avoidance, record.sim)
    w = fast_movers(world, route, mission.vehicle.speed, seed) if kind == "fast-movers" else perturb_moving(world, seed)
    return _row(kind, seed, avoidance, simulate(w, mission, route=route, rng=seed, avoidance=avoidance, keys=keys))


def summary(rows: list[dict]) -> str:
    """The markdown table of the rows, one line per (set, avoidance)."""
    lines = ["| set | avoidance | seeds | arrivals | contacts | deadlocks | timeouts | runs with an escape "
             "(arrived) | smallest obstacle distance (m) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for kind in SETS:
        for av in sorted({r["avoidance"] for r in rows}):
            rs = [r for r in rows if r["set"] == kind and r["avoidance"] == av]
            if not rs:
                continue
            n = len(rs)
            arr = sum(r["arrived"] for r in rs)
            esc = [r for r in rs if r["escapes"] > 0]
            seeds = f"{min(r['seed'] for r in rs)}–{max(r['seed'] for r in rs)}"
            lines.append(f"| {kind} | {av} | {n} ({seeds}) | {arr}/{n} ({100 * arr / n:.1f} %) | "
                         f"{sum(r['contact'] for r in rs)} | {sum(r['status'] == 'DEADLOCK' for r in rs)} | "
                         f"{sum(r['status'] == 'TIMEOUT' for r in rs)} | "
                         f"{len(esc)} ({sum(r['arrived'] for r in esc)}) | "
                         f"{min(r['min_obstacle_m'] for r in rs):.2f} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--first", type=int, default=0, help="first seed")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--sets", nargs="+", default=list(SETS), choices=SETS)
    ap.add_argument("--avoidance", nargs="+", default=["predictive"])
    ap.add_argument("--out", default="results/bench-avoidance")
    ap.add_argument("--doc", default=None, help="markdown file whose bench:avoidance block is replaced")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    world, mission = sc.build(sc.load(SCENARIO))
    planned = plan(planning_problem(world, mission), mission.planner, rng=mission.seed)
    route = mission_route(world, mission, planned.path)
    keys = key_waypoints(route, world)
    load = os.getloadavg()
    t0 = time.perf_counter()
    tasks = [(k, s, a, route, keys) for k in args.sets for a in args.avoidance
             for s in range(args.first, args.first + args.seeds)]
    rows = []
    with ProcessPoolExecutor(args.workers) as pool, open(out / "rows.jsonl", "w") as fh:
        for row in pool.map(one, tasks, chunksize=2):
            rows.append(row)
            fh.write(json.dumps(row) + "\n")
            fh.flush()
    wall = time.perf_counter() - t0
    text = summary(rows)
    text += (f"\n`{' '.join(['benchmarks/avoidance.py', '--seeds', str(args.seeds), '--first', str(args.first)])}`: "
             f"{len(rows)} runs in {wall:.0f} s wall on {args.workers} workers, machine load (1, 5, 15 min) at the "
             f"start {', '.join(f'{v:.1f}' for v in load)}.\n")
    bad = [r for r in rows if not r["arrived"]]
    if bad:
        text += "\nRuns that did not arrive:\n\n" + "".join(
            f"- {r['set']} {r['avoidance']} seed {r['seed']}: {r['status']}, {r['escapes']} escapes; "
            f"{'; '.join(r['events'])}\n" for r in bad)
    (out / "summary.md").write_text(text)
    print(text)
    if args.doc:
        doc = Path(args.doc)
        body = doc.read_text()
        head, _, rest = body.partition(MARK)
        _, _, tail = rest.partition(MARK)
        doc.write_text(head + MARK + "\n" + text + MARK + tail)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
