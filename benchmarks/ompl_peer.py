"""Peer: OMPL's Informed RRT* on the same World, against the grid reference and IABC.

OMPL checks states with auvplan's own ``World.is_free`` (static constraints) and motions by its
default discrete sampling; the returned path is then put through auvplan's exact segment test
and costed with the same cost function as every auvplan planner.  OMPL is installed only for
this benchmark:

    python3 -m venv .venv-peers && .venv-peers/bin/pip install -e . ompl
    .venv-peers/bin/python benchmarks/ompl_peer.py --times 1 5 --out results/bench-ompl
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners import GridParams, plan
from auvplan.planners.core.common import path_cost, search_box
from auvplan.sim import planning_problem


def informed_rrt_star(world, prob, seconds: float) -> tuple[np.ndarray, int]:
    """OMPL Informed RRT* (path-length objective) for ``seconds``; the path and the state checks."""
    from ompl import base as ob
    from ompl import geometric as og
    from ompl import util as ou

    ou.setLogLevel(ou.LOG_WARN)
    lo, hi = search_box(prob)
    space = ob.RealVectorStateSpace(3)
    bounds = ob.RealVectorBounds(3)
    for i in range(3):
        bounds.setLow(i, float(lo[i]))
        bounds.setHigh(i, float(hi[i]))
    space.setBounds(bounds)
    ss = og.SimpleSetup(space)
    calls = [0]

    def valid(s) -> bool:
        calls[0] += 1
        return bool(world.is_free(np.array([s[0], s[1], s[2]]), moving=False))

    ss.setStateValidityChecker(valid)
    start, goal = space.allocState(), space.allocState()
    for i in range(3):
        start[i], goal[i] = float(prob.start[i]), float(prob.goal[i])
    ss.setStartAndGoalStates(start, goal)
    si = ss.getSpaceInformation()
    ss.setPlanner(og.InformedRRTstar(si))
    ss.getProblemDefinition().setOptimizationObjective(ob.PathLengthOptimizationObjective(si))
    if not ss.solve(seconds):
        return np.empty((0, 3)), calls[0]
    return np.array([[s[0], s[1], s[2]] for s in ss.getSolutionPath().getStates()]), calls[0]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", nargs="+", default=["marcus-wake", "salish-shelf"])
    ap.add_argument("--times", type=float, nargs="+", default=[1.0, 5.0])
    ap.add_argument("--out", default="results/bench-ompl")
    args = ap.parse_args(argv)
    rows = []
    for name in args.scenarios:
        world, mission = sc.build(sc.load(name))
        prob = planning_problem(world, mission)
        spec = mission.planner
        t0 = time.perf_counter()
        ref = plan(prob, replace(spec, name="grid", grid=GridParams(objective="length")))
        rows.append({"scenario": name, "planner": "grid reference (length)", "wall_s": time.perf_counter() - t0,
                     "length_m": ref.cost_terms["length_m"], "cost": path_cost(prob, spec, ref.path)["total"],
                     "exact_free": world.path_free(ref.path)})
        t0 = time.perf_counter()
        iabc = plan(prob, spec, rng=0)
        rows.append({"scenario": name, "planner": "iabc (seed 0)", "wall_s": time.perf_counter() - t0,
                     "length_m": iabc.cost_terms["length_m"], "cost": iabc.cost,
                     "exact_free": world.path_free(iabc.path)})
        for seconds in args.times:
            t0 = time.perf_counter()
            path, calls = informed_rrt_star(world, prob, seconds)
            row = {"scenario": name, "planner": f"OMPL InformedRRT* {seconds:g} s", "wall_s": time.perf_counter() - t0,
                   "state_checks": calls}
            if path.shape[0]:
                terms = path_cost(prob, spec, path)
                row.update(length_m=terms["length_m"], cost=terms["total"], exact_free=world.path_free(path))
            rows.append(row)
    lines = ["| scenario | planner | wall (s) | length (m) | cost (same function) | passes the exact test |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scenario']} | {r['planner']} | {r['wall_s']:.2f} | "
                     f"{r.get('length_m', float('nan')):.0f} | {r.get('cost', float('nan')):.0f} | "
                     f"{r.get('exact_free', '-')} |")
    text = "\n".join(lines)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "ompl.json").write_text(json.dumps(rows, indent=2, default=str) + "\n")
    (out / "summary.md").write_text(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
