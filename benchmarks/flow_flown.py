"""Flights of the default flow pipeline from seeded near-surface starts in document 000's Figs. 7-8 scenes.

    .venv/bin/python benchmarks/flow_flown.py --starts 100 --out results/bench-flow-flown

The built-in ``flow-fig8`` (0.5 m margin, goal (28, 28, 0), the 10 m-turn vehicle, its default follower
and avoidance) with its obstacles replaced by each scene of ``benchmarks/flow_fig78.py`` (document reading:
the ellipsoid at yaw 45°; axis-aligned: unturned; Fig. 7 alone, Fig. 8 with the two spheres).  Starts: the
same seeded near-surface starts as flow_fig78.py (0.5-5 m from a real surface, equal numbers per obstacle).
Each start runs the whole default pipeline (:func:`auvplan.sim.pipeline.run_mission`: flyable flow plan ->
mission waypoints -> turn fit -> key waypoints -> closed-loop simulation).

Columns: planned = plans the planner returned OK (the rest are INFEASIBLE: unflyable starts); arrived = of
the flown; least distance = the least exact distance from any recorded position to a *real* obstacle
surface (``Shape.distance``, independent of the simulator's contact flag); contacts = flights with a
recorded position at distance <= 0, and (sim) the simulator's own collision count; CPU = process time per
start.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners.flow.field import FlowField
from auvplan.planners.params import FlowParams
from auvplan.sim.pipeline import run_mission

sys.path.insert(0, str(Path(__file__).resolve().parent))
from flow_fig78 import GOAL, MARGIN, near_surface_starts, scenes  # noqa: E402


def fly_scene(obstacles, n, seed=0):
    """Fly the default pipeline from ``n`` seeded near-surface starts; one dict per start."""
    world, mission = sc.build(sc.load("flow-fig8"))
    world = replace(world, obstacles=tuple(obstacles))
    field = FlowField(obstacles, GOAL, FlowParams(), MARGIN)
    out = []
    for p in near_surface_starts(obstacles, field, n, seed):
        t0 = time.process_time()
        rec = run_mission(world, replace(mission, start=tuple(float(v) for v in p)))
        cpu = time.process_time() - t0
        row = {"start": p, "planned": bool(rec.plan is not None and rec.plan.status.ok and rec.sim is not None),
               "cpu": cpu, "arrived": False, "least": np.inf, "contact": False, "sim_contacts": 0}
        if rec.sim is not None:
            d = np.min([ob.distance(rec.sim.position) for ob in obstacles], axis=0)
            row.update(arrived=bool(rec.sim.arrived), least=float(d.min()), contact=bool(d.min() <= 0.0),
                       sim_contacts=int(rec.sim.metrics["collisions"]))
        out.append(row)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="results/bench-flow-flown")
    ap.add_argument("--figure", default="docs/figures/flow-flown.md")
    a = ap.parse_args(argv)
    lines = [f"Default flow pipeline flown (built-in flow-fig8 vehicle and follower; {a.starts} seeded starts per "
             f"scene, seed {a.seed}, 0.5-5 m from a real surface; `benchmarks/flow_flown.py --starts {a.starts}`; "
             f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)", "",
             "| scene | starts | planned | arrived | least distance to a real surface (m) | contacts (exact; sim) | "
             "CPU per start (s, median / max) |", "|---|---|---|---|---|---|---|"]
    worst = []
    for name, obstacles in scenes():
        rows = fly_scene(obstacles, a.starts, a.seed)
        flown = [r for r in rows if r["planned"]]
        least = min((r["least"] for r in flown), default=np.inf)
        cpu = np.array([r["cpu"] for r in rows])
        lines.append(f"| {name} | {len(rows)} | {len(flown)} | {sum(r['arrived'] for r in flown)} | {least:.3f} | "
                     f"{sum(r['contact'] for r in flown)}; {sum(r['sim_contacts'] > 0 for r in flown)} | "
                     f"{np.median(cpu):.2f} / {cpu.max():.2f} |")
        worst += [(r["least"], name, r["start"]) for r in flown if r["least"] < 0.5 or not r["arrived"]]
        print(lines[-1], flush=True)
    if worst:
        lines += ["", "Flights closer than the 0.5 m margin or not arriving (least distance, scene, start):", ""]
        lines += [f"- {d:.3f} m, {s}, start ({', '.join(f'{v:.3f}' for v in p)})" for d, s, p in sorted(worst)[:20]]
    text = "\n".join(lines) + "\n"
    Path(a.out).mkdir(parents=True, exist_ok=True)
    (Path(a.out) / "flow-flown.md").write_text(text)
    if a.figure:
        Path(a.figure).parent.mkdir(parents=True, exist_ok=True)
        Path(a.figure).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
