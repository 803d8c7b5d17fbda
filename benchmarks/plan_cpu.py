"""CPU time of the default plan on the hard scenarios, beside scipy's differential evolution.

For each hard built-in scenario, ``--repeats`` plans with the default planner (seeded IABC,
10 000 evaluations) interleaved with as many runs of scipy's vectorised
``differential_evolution`` alone on the same cost and budget (``de``, document pipeline), so
that both see the same machine load; reports the median CPU seconds of each, their ratio and the
load average (``os.getloadavg``) before and after.  The machine this was written on is shared:
read the ratio, not the seconds alone.

    nice -n 5 .venv/bin/python benchmarks/plan_cpu.py --repeats 10
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import replace

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.sim import planning_problem

SCENARIOS = ("ninetyeast-ridge", "new-england-seamounts", "chagos-banks", "marcus-wake-deep")


def _cpu(prob, spec, seed: int) -> float:
    c0 = time.process_time()
    plan(prob, spec, rng=seed)
    return time.process_time() - c0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--budget", type=int, default=10_000)
    args = ap.parse_args()
    before = os.getloadavg()
    print(f"load average before {before[0]:.1f} / {before[1]:.1f} / {before[2]:.1f} on {os.cpu_count()} cores")
    print("| scenario | default plan CPU s (median) | scipy DE alone CPU s (median) | ratio |")
    print("|---|---|---|---|")
    ratios = []
    for name in SCENARIOS:
        world, mission = sc.build(sc.load(name))
        prob = planning_problem(world, mission)
        ours = replace(mission.planner, budget=args.budget)
        peer = replace(ours, name="de", pipeline="document")
        _cpu(prob, ours, 99), _cpu(prob, peer, 99)  # compile and warm the caches
        a, b = [], []
        for seed in range(args.repeats):
            a.append(_cpu(prob, ours, seed))
            b.append(_cpu(prob, peer, seed))
        ratios.append(np.median(a) / np.median(b))
        print(f"| {name} | {np.median(a):.3f} | {np.median(b):.3f} | {ratios[-1]:.2f} |", flush=True)
    after = os.getloadavg()
    print(f"load average after {after[0]:.1f} / {after[1]:.1f} / {after[2]:.1f}")


if __name__ == "__main__":
    main()
