"""The hard built-ins on the conservative seabed against the previous default (cubic): issue 30.

For each scenario and terrain method: how the seabed sits against its data (largest depth below it,
largest and mean height above it), the lattice plan's cost (``grid``: deterministic), and the default
planner (``iabc``, seeded pipeline) over ``--seeds`` seeds at the scenario's budget: median cost and the
seeds ending INFEASIBLE.  Every cost is on the seabed of that row's method.

    .venv/bin/python benchmarks/seabed.py --seeds 3 --out results/bench-seabed.json
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.sim import planning_problem

SCENARIOS = ("ninetyeast-ridge", "new-england-seamounts", "chagos-banks", "marcus-wake-deep")


def measure(name: str, method: str, seeds: int) -> dict:
    s = sc.load(name)
    s = replace(s, terrain=replace(s.terrain, method=method))
    world, mission = sc.build(s)
    prob = planning_problem(world, mission)
    fit = world.terrain.fit
    t0 = time.process_time()
    grid = plan(prob, replace(mission.planner, name="grid"), rng=0)
    costs, infeasible = [], 0
    for seed in range(1, seeds + 1):
        r = plan(prob, replace(mission.planner, name="iabc", pipeline="seeded"), rng=seed)
        if r.status.ok:
            costs.append(r.cost)
        else:
            infeasible += 1
    return {"scenario": name, "method": method, "below_data_max_m": fit.deficit_max_m,
            "excess_max_m": fit.excess_max_m, "excess_mean_m": fit.excess_mean_m,
            "grid_status": grid.status.value, "grid_cost": grid.cost,
            "iabc_median_cost": float(np.median(costs)) if costs else None, "iabc_infeasible": infeasible,
            "cpu_s": time.process_time() - t0}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--scenarios", nargs="*", default=list(SCENARIOS))
    ap.add_argument("--out", default="")
    args = ap.parse_args()
    rows = []
    for name in args.scenarios:
        for method in ("cubic", "conservative"):
            rows.append(measure(name, method, args.seeds))
            r = rows[-1]
            print(f"{name:24s} {method:12s} below {r['below_data_max_m']:7.1f} m  above max {r['excess_max_m']:6.1f} "
                  f"mean {r['excess_mean_m']:5.2f} m  grid {r['grid_cost']:.6g} ({r['grid_status']})  iabc median "
                  f"{r['iabc_median_cost']}  infeasible {r['iabc_infeasible']}/{args.seeds}  {r['cpu_s']:.0f} s",
                  flush=True)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
