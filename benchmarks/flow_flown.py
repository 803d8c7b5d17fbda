"""Flights of the default flow pipeline from seeded near-surface starts in document 000's Figs. 7-8 scenes.

    .venv/bin/python benchmarks/flow_flown.py --starts 100 --out results/bench-flow-flown [--followers los]

The built-in ``flow-fig8`` (0.5 m margin, goal (28, 28, 0), the 10 m-turn vehicle, its avoidance; every
follower: hybrid, los, ilos) with its obstacles replaced by each scene of ``benchmarks/flow_fig78.py``
(document reading: the ellipsoid at yaw 45°; axis-aligned: unturned; Fig. 7 alone, Fig. 8 with the two
spheres). Starts: the same seeded near-surface starts as flow_fig78.py (0.5-5 m from a real surface, equal
numbers per obstacle). Each start runs the whole default pipeline (:func:`auvplan.sim.pipeline.run_mission`:
flyable flow plan -> mission waypoints -> turn fit -> the clearance contract of
:func:`auvplan.sim.pipeline.kept_fit` -> key waypoints -> closed-loop simulation).

Columns: flown = plans the planner returned OK under the contract; refused = the rest, by reason (those the
contract refused are marked ``contract:``; every one with its message in ``refused.csv``); arrived = of the
flown; flown off the route = the largest 3-D distance of a flight from its route and how far that lies inside
the contract's bound (``tracking_bound_m``); least distance = the least exact distance from any recorded
position to a *real* obstacle surface (``Shape.distance``, independent of the simulator's contact flag);
contacts = flights with a recorded position at distance <= 0, and (sim) the simulator's own collision count;
CPU = process time per start.
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners.core.params import FlowParams
from auvplan.planners.flow.field import FlowField
from auvplan.sim.pipeline import run_mission
from auvplan.sim.tracking import route_deviation

sys.path.insert(0, str(Path(__file__).resolve().parent))
from flow_fig78 import GOAL, MARGIN, near_surface_starts, scenes  # noqa: E402

FOLLOWERS = ("hybrid", "los", "ilos")

REASONS = (("is not free", "start or goal inside the margin"), ("cannot follow it", "flow path not flyable at 1/R"),
           ("cannot fly the mission", "mission's turns or envelope not flyable"),
           ("did not keep it", "re-plans with a raised margin did not keep it"),
           ("streamline ended", "streamline did not arrive"), ("arrives but its leg", "streamline leg in a margin"),
           ("exceed max_pitch_deg", "plan steeper than max_pitch_deg"),
           ("no room to raise", "start within the margin + bound: no room to raise it"))


def reason(plan):
    """A refused plan's reason in a few words (the contract's refusals are marked so)."""
    if plan is None:
        return "no plan"
    msg = plan.message
    tag = "contract: " if msg.startswith("clearance contract") else ""
    core = msg.split(" m: ", 1)[1] if tag and " m: " in msg else msg
    for key, text in REASONS:
        if key in core:
            return f"{tag}{text} ({plan.status.name})"
    return f"{tag}{core[:60]} ({plan.status.name})"


def fly_scene(obstacles, n, seed=0, followers=FOLLOWERS):
    """Fly the default pipeline from ``n`` seeded near-surface starts under each follower; one dict per flight."""
    world, mission = sc.build(sc.load("flow-fig8"))
    world = replace(world, obstacles=tuple(obstacles))
    field = FlowField(obstacles, GOAL, FlowParams(), MARGIN)
    out = []
    for p in near_surface_starts(obstacles, field, n, seed):
        m = replace(mission, start=tuple(float(v) for v in p))
        for g in followers:
            t0 = time.process_time()
            rec = run_mission(world, m, guidance=g)
            cpu = time.process_time() - t0
            ok = bool(rec.plan is not None and rec.plan.status.ok and rec.sim is not None)
            row = {"start": p, "follower": g, "planned": ok, "cpu": cpu, "arrived": False, "least": np.inf,
                   "contact": False, "sim_contacts": 0, "reason": "" if ok else reason(rec.plan),
                   "message": "" if ok or rec.plan is None else rec.plan.message, "deviation": np.nan,
                   "bound": np.nan}
            if rec.sim is not None:
                d = np.min([ob.distance(rec.sim.position) for ob in obstacles], axis=0)
                dev, _ = route_deviation(rec.sim.position, rec.route)
                row.update(arrived=bool(rec.sim.arrived), least=float(d.min()), contact=bool(d.min() <= 0.0),
                           sim_contacts=int(rec.sim.metrics["collisions"]), deviation=float(dev.max()),
                           bound=float(rec.plan.cost_terms.get("tracking_bound_m", np.nan)))
            out.append(row)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--followers", nargs="+", default=list(FOLLOWERS))
    ap.add_argument("--out", default="results/bench-flow-flown")
    ap.add_argument("--figure", default="docs/figures/flow-flown.md")
    a = ap.parse_args(argv)
    lines = [f"Default flow pipeline flown under the clearance contract (built-in flow-fig8 vehicle, its predictive "
             f"avoidance, each follower; {a.starts} seeded starts per scene, seed {a.seed}, 0.5-5 m from a real "
             f"surface; `benchmarks/flow_flown.py --starts {a.starts}`; load average {os.getloadavg()[0]:.1f} on "
             f"{os.cpu_count()} cores)", "",
             "| scene | follower | starts | flown | arrived | contacts (exact; sim) | least distance to a real surface "
             "(m) | flown off the route, max / its bound (m) | refused | CPU per start (s, median / max) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    refused, worst = [], []
    for name, obstacles in scenes():
        rows = fly_scene(obstacles, a.starts, a.seed, a.followers)
        for g in a.followers:
            mine = [r for r in rows if r["follower"] == g]
            flown = [r for r in mine if r["planned"]]
            least = min((r["least"] for r in flown), default=np.inf)
            cpu = np.array([r["cpu"] for r in mine])
            over = max((r["deviation"] - r["bound"] for r in flown), default=np.nan)
            dev = max((r["deviation"] for r in flown), default=np.nan)
            lines.append(f"| {name} | {g} | {len(mine)} | {len(flown)} | {sum(r['arrived'] for r in flown)} | "
                         f"{sum(r['contact'] for r in flown)}; {sum(r['sim_contacts'] > 0 for r in flown)} | "
                         f"{least:.3f} | {dev:.2f} / deviation - bound ≤ {over:.2f} | {len(mine) - len(flown)} | "
                         f"{np.median(cpu):.2f} / {cpu.max():.2f} |")
            print(lines[-1], flush=True)
            reasons = {}
            for r in mine:
                if not r["planned"]:
                    reasons[r["reason"]] = reasons.get(r["reason"], 0) + 1
                    refused.append((name, g, r["start"], r["reason"], r["message"]))
            refused_line = "; ".join(f"{k}: {v}" for k, v in sorted(reasons.items(), key=lambda kv: -kv[1]))
            worst.append(f"- {name}, {g}: {refused_line or 'none'}")
    lines += ["", "Refused starts by reason (scene, follower: reason: count; every start with its message in "
              "`results/bench-flow-flown/refused.csv`):", ""] + worst
    text = "\n".join(lines) + "\n"
    Path(a.out).mkdir(parents=True, exist_ok=True)
    (Path(a.out) / "flow-flown.md").write_text(text)
    with open(Path(a.out) / "refused.csv", "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["scene", "follower", "x", "y", "z", "reason", "message"])
        for name, g, p, why, msg in refused:
            wr.writerow([name, g, *(f"{v:.3f}" for v in p), why, msg])
    if a.figure:
        Path(a.figure).parent.mkdir(parents=True, exist_ok=True)
        Path(a.figure).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
