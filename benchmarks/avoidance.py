"""Avoidance without deadlocks (issue #36 point 4): fast-mover Monte Carlo and ``avoidance-gauntlet`` over seeds.

    nice -n 10 .venv/bin/python benchmarks/avoidance.py --seeds 100 --workers 2 --out results/bench-avoidance \
        --figure docs/figures/avoidance-monte-carlo.md && .venv/bin/python tools/docs_figures.py sync

Three sets of missions, each seed flown once per avoidance variant (``--avoidance``, default
``predictive``):

``fast-movers``
    The held-out kind of case: ``avoidance-gauntlet``'s real seamount flank (ETOPO1, 100 m) and
    global plan (scenario seed), and per seed (:func:`auvplan.app.bench.sweep.fast_movers`) six spheres of
    15–30 m radius at 1.8–3.0 m/s (1.2–2× the vehicle's 1.5 m/s), each timed to meet the vehicle on
    the route at a random 10–90 % of its length (±40 s): straight runs at any angle to the route,
    shuttles 300 m across or along it, orbits of 60–100 m radius about it.
``gauntlet``
    ``avoidance-gauntlet`` as shipped: ``run_mission`` with the seed (the global plan, the escapes'
    random sub-goals); the obstacles' tracks are the file's.
``gauntlet-randomised``
    The README's kind: the scenario's plan (its seed), each seed re-drawing every moving
    obstacle's track (:func:`auvplan.app.bench.sweep.perturb_moving`).
``avoidance-net``
    The built-in where document 004's escape is needed (a towed trawl net the vehicle steers into),
    the first ``NET_SEEDS`` seeds: the escapes must fire and the runs arrive.

**Design criterion** (fast movers, :mod:`auvplan.guidance.avoidance.oracle`): every encounter of every seed must
be avoidable with margin — from the state of a vehicle flying the route at cruise speed when the mover
first comes within the sensor range (200 m of its surface), at least one constant heading/pitch/speed
manoeuvre flown with the vehicle's model keeps ``ORACLE_MARGIN`` m from that mover's true track for
``ORACLE_HORIZON`` s.  Each encounter is judged on its own: held for 150 s, one constant manoeuvre
may run into *another* mover of the seed although a vehicle that re-plans would not (seed 36: −7.5 m
with all six movers, ≥ 146 m for each alone); overlapping encounters are judged by the runs.  Each row
carries that margin (``oracle_margin_m``, the smallest over the seed's
encounters of the best manoeuvre's clearance); the summary states the smallest over the seeds.  Every run
that does not arrive gets the same oracle from its own state when the mover it hit was first sensed
(``avoidable``): a contact is never explained away by its label.

Per set: arrivals, contacts (obstacle or seabed, UNAVOIDABLE included), deadlocks, timeouts,
runs where an escape fired (``escapes`` > 0: document 004's random sub-goal, fired by its
local-minimum count or by the stalled route progress, :meth:`auvplan.guidance.avoidance.local.LocalAvoidance.stalled`)
and of those the runs that arrived, the smallest obstacle distance.  The runs go to dask.distributed
(``--workers N``, default 2; ``--scheduler ADDR``; ``--retries N``: ``benchmarks/parallel_runs.py``), rows reach
``rows.jsonl`` as they finish (``--resume`` runs only the missing ones) and come back in task order: the same
on 1 and N workers but for the timing fields.  Writes ``rows.jsonl`` and ``summary.md`` to ``--out`` and, with
``--figure``, the
same summary as a figure file (``docs/figures/avoidance-monte-carlo.md``, quoted in docs/avoidance.md by
its ``<!-- figure: avoidance-monte-carlo -->`` marker; ``tools/docs_figures.py sync`` copies it).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.app.bench.sweep import fast_movers, perturb_moving
from auvplan.guidance.avoidance.local import key_waypoints
from auvplan.guidance.avoidance.oracle import best_constant_manoeuvre
from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.sim import mission_route, planning_problem, run_mission, simulate
from auvplan.vehicles import VehicleState

sys.path.insert(0, str(Path(__file__).resolve().parent))
from parallel_runs import add_arguments, run_all, where  # noqa: E402

SCENARIO = "avoidance-gauntlet"
SETS = ("fast-movers", "gauntlet", "gauntlet-randomised", "avoidance-net")
NET_SEEDS = 6
"""Seeds of the ``avoidance-net`` set (the first ``NET_SEEDS`` of the requested ones)."""
ORACLE_MARGIN = 10.0
"""Clearance (m) the design criterion asks of the best constant manoeuvre (the avoidance's own margin)."""
ORACLE_HORIZON = 150.0
"""Duration (s) over which the manoeuvre must stay clear."""


def _row(kind: str, seed: int, avoidance: str, r) -> dict:
    kinds = [e[1] for e in r.events]
    return {"set": kind, "seed": seed, "avoidance": avoidance, "status": r.status.value, "arrived": r.arrived,
            "contact": any(k in ("collision", "unavoidable") for k in kinds), "escapes": r.escapes,
            "min_obstacle_m": float(r.metrics["min_obstacle_distance_m"]), "duration_s": r.metrics["duration_s"],
            "wall_s": r.wall_time_s, "events": [e[2] for e in r.events if e[1] != "arrival"]}


def design_margin(world, mission, route) -> float:
    """The design criterion's margin of one seed: over its movers, the smallest best-manoeuvre clearance from
    the nominal vehicle (on ``route`` at cruise speed) when the mover first comes within sensor range."""
    speed, sensor = mission.vehicle.speed, mission.avoidance.sensor_range
    cum = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(route, axis=0), axis=1))]
    t = np.arange(0.0, cum[-1] / speed, 1.0)
    pos = np.stack([np.interp(speed * t, cum, route[:, k]) for k in range(3)], axis=1)
    ahead = np.stack([np.interp(speed * t + 1.0, cum, route[:, k]) for k in range(3)], axis=1) - pos
    worst = math.inf
    for o in world.moving:
        d = np.linalg.norm(np.asarray(o.motion.position(t)) - pos, axis=1) - o.shape.bounding_radius
        seen = np.flatnonzero(d <= sensor)
        if seen.size == 0:
            continue
        k = int(seen[0])
        s0 = VehicleState(*pos[k], math.atan2(ahead[k, 0], ahead[k, 1]) % (2 * math.pi), speed)
        alone = replace(world, moving=(o,))  # each encounter on its own (see the module notes)
        worst = min(worst, best_constant_manoeuvre(alone, mission.vehicle, s0, float(t[k]),
                                                   horizon=ORACLE_HORIZON).clearance)
    return worst


def avoidable(world, mission, r) -> str:
    """The oracle on a run that did not arrive: from its own state when the obstacle it hit was first sensed."""
    last = r.events[-1][2]
    if "obstacle " not in last:
        return "no obstacle contact"
    i = int(last.split("obstacle ")[1].split()[0]) - len(world.obstacles)
    o = world.moving[i]
    d = np.linalg.norm(r.position - np.asarray(o.motion.position(r.t)), axis=1) - o.shape.bounding_radius
    k = len(d) - 1
    while k > 0 and d[k - 1] <= mission.avoidance.sensor_range:
        k -= 1
    s0 = VehicleState(*r.position[k], float(r.heading[k]), mission.vehicle.speed)
    best = best_constant_manoeuvre(world, mission.vehicle, s0, float(r.t[k]), horizon=ORACLE_HORIZON)
    verdict = "avoidable" if best.safe else "no constant manoeuvre avoids it"
    return (f"{verdict}: from t = {r.t[k]:.0f} s (first sensed) {best.safe}/{best.candidates} constant manoeuvres "
            f"stay clear, best {best.clearance:.1f} m")


def one(args) -> dict:
    kind, seed, avoidance, route, keys = args
    if kind == "avoidance-net":
        world, mission = sc.build(sc.load("avoidance-net"))
        r = simulate(world, mission, rng=seed, avoidance=avoidance)
        row = _row(kind, seed, avoidance, r)
        row["minimum_escapes"] = r.minimum_escapes
        return row
    world, mission = sc.build(sc.load(SCENARIO))
    if kind == "gauntlet":
        record = run_mission(world, mission, seed, avoidance=avoidance)
        return _row(kind, seed, avoidance, record.sim)
    w = fast_movers(world, route, mission.vehicle.speed, seed) if kind == "fast-movers" else perturb_moving(world, seed)
    r = simulate(w, mission, route=route, rng=seed, avoidance=avoidance, keys=keys)
    row = _row(kind, seed, avoidance, r)
    if kind == "fast-movers":
        row["oracle_margin_m"] = design_margin(w, mission, route)
        if not r.arrived:
            row["events"].append(avoidable(w, mission, r))
    return row


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
    margins = [r["oracle_margin_m"] for r in rows if "oracle_margin_m" in r]
    text = "\n".join(lines) + "\n"
    if margins:
        text += (f"\nDesign criterion (fast-movers): every encounter avoidable on its own by a constant manoeuvre "
                 f"from the nominal state at the mover's detection with ≥ {ORACLE_MARGIN:g} m over "
                 f"{ORACLE_HORIZON:g} s: smallest best clearance {min(margins):.1f} m over {len(margins)} seeds; "
                 f"{sum(m < ORACLE_MARGIN for m in margins)} seeds below it.\n")
    return text


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--first", type=int, default=0, help="first seed")
    ap.add_argument("--sets", nargs="+", default=list(SETS), choices=SETS)
    ap.add_argument("--avoidance", nargs="+", default=["predictive"])
    ap.add_argument("--out", default="results/bench-avoidance")
    ap.add_argument("--resume", action="store_true", help="keep the rows already in --out's rows.jsonl and run "
                    "only the missing (set, seed, avoidance) tasks; the summary covers all rows")
    ap.add_argument("--figure", default=None, help="figure file to write the summary to "
                    "(docs/figures/avoidance-monte-carlo.md)")
    add_arguments(ap, workers=2)
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    world, mission = sc.build(sc.load(SCENARIO))
    planned = plan(planning_problem(world, mission), mission.planner, rng=mission.seed)
    route = mission_route(world, mission, planned.path)
    keys = key_waypoints(route, world)
    load = os.getloadavg()
    t0 = time.perf_counter()
    rows = []
    if args.resume and (out / "rows.jsonl").exists():
        rows = [json.loads(line) for line in (out / "rows.jsonl").read_text().splitlines() if line.strip()]
    done = {(r["set"], r["seed"], r["avoidance"]) for r in rows}
    resumed = len(rows)
    n_seeds = {k: min(args.seeds, NET_SEEDS) if k == "avoidance-net" else args.seeds for k in args.sets}
    tasks = [(k, s, a, route, keys) for k in args.sets for a in args.avoidance
             for s in range(args.first, args.first + n_seeds[k]) if (k, s, a) not in done]
    with open(out / "rows.jsonl", "a" if resumed else "w") as fh:  # the checkpoint: --resume runs the rest

        def arrived(row: dict) -> None:
            fh.write(json.dumps(row) + "\n")
            fh.flush()

        rows += run_all(args, one, tasks, arrived)
    wall = time.perf_counter() - t0
    text = summary(rows)
    end = os.getloadavg()
    text += (f"\n`{' '.join(['benchmarks/avoidance.py', '--seeds', str(args.seeds), '--first', str(args.first)])}` "
             f"(avoidance {', '.join(args.avoidance)}, fast movers seeded 20000 + seed, gauntlet planned with the "
             f"seed): {len(rows) - resumed} runs in {wall:.0f} s wall on {where(args)}"
             f"{f' (and {resumed} rows of earlier runs resumed)' if resumed else ''}, machine load (1, 5, 15 min) "
             f"{', '.join(f'{v:.1f}' for v in load)} at the start, {', '.join(f'{v:.1f}' for v in end)} at the end.\n")
    bad = [r for r in rows if not r["arrived"]]
    if bad:
        text += "\nRuns that did not arrive:\n\n" + "".join(
            f"- {r['set']} {r['avoidance']} seed {r['seed']}: {r['status']}, {r['escapes']} escapes; "
            f"{'; '.join(r['events'])}\n" for r in bad)
    (out / "summary.md").write_text(text)
    print(text)
    if args.figure:
        Path(args.figure).write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
