"""An optimum independent of the lattice: scipy's L-BFGS-B over the interior vertices of a polyline.

The polyline starts on the straight line from start to goal (no lattice, no elastic band) and its
``K`` interior vertices move freely to minimise the planner's cost (:func:`auvplan.planners.core.
common.path_cost`, the same cost the lattice reference reports); the result is checked free.  As
``K`` doubles its cost falls towards the continuous optimum, which tells whether a reference that
does not improve with a finer lattice is flat because it is already optimal (docs/performance.md,
"The lattice: cost against cell size").  Only meaningful where the straight line's neighbourhood is
free of terrain (marcus-wake); the optimiser knows no obstacles.

    nice -n 5 .venv/bin/python benchmarks/grid_optimum.py marcus-wake --segments 21 41 81
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace

import numpy as np
from scipy.optimize import minimize


def optimum(scenario: str, segments: int) -> tuple[float, bool, float]:
    """Cost, whether the path is free, and CPU seconds of the L-BFGS-B polyline of ``segments`` segments."""
    from auvplan.io.scenario import loader as sc
    from auvplan.planners.core.common import path_cost
    from auvplan.sim import planning_problem

    world, mission = sc.build(sc.load(scenario))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="grid")
    a, b = prob.start, prob.goal
    scale = np.array([1000.0, 1000.0, 100.0])  # km horizontally, 100 m vertically: a balanced problem
    x0 = (a + np.linspace(0.0, 1.0, segments + 1)[1:-1, None] * (b - a)) / scale

    def cost(x: np.ndarray) -> float:
        return float(path_cost(prob, spec, np.vstack([a, x.reshape(-1, 3) * scale, b]))["total"])

    c0 = time.process_time()
    r = minimize(cost, x0.ravel(), method="L-BFGS-B",
                 options=dict(maxiter=3000, maxfun=10**6, ftol=1e-14, gtol=1e-9))
    path = np.vstack([a, r.x.reshape(-1, 3) * scale, b])
    return float(r.fun), bool(world.path_free(path)), time.process_time() - c0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenario")
    ap.add_argument("--segments", type=int, nargs="+", default=[21, 41])
    args = ap.parse_args(argv)
    for k in args.segments:
        c, free, cpu = optimum(args.scenario, k)
        print(f"{args.scenario}: {k} segments, cost {c:.2f}, {'free' if free else 'NOT FREE'}, {cpu:.1f} s CPU",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
