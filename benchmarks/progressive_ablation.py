"""What each part of the progressive pipeline does, for IABC alone at an equal budget.

Variants (each IABC alone, no lattice, no refinement, exactly ``--budget`` evaluations):

* ``document`` — one run with K control points (the document pipeline);
* ``refit only`` — a first stage at K control points (not coarser), its best paths refitted to K
  with the bend-weighted fit: what the re-arrangement of the control points does alone;
* ``coarse, plain fit`` — ⌈K/2⌉ control points first, refitted at uniform arc length (``bend = 0``);
* ``coarse, bend 0.5 / 1 (default) / 2`` — the weight of the bends in the refit;
* ``coarse share 0.1 / 0.3`` — the budget of the coarse stage (default 0.2).

Reports, per hard scenario, the median and worst gap over seeds to the best known cost (``--best``
defaults to the costs of docs/bench_hard.md, the refined lattice reference) and the seeds ending
INFEASIBLE.

    .venv/bin/python benchmarks/progressive_ablation.py --seeds 20 --budget 10000
"""

from __future__ import annotations

import argparse
import os
from dataclasses import replace
from unittest import mock

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.planners.swarm import progressive
from auvplan.sim import planning_problem

BEST = {"ninetyeast-ridge": 581_937.0, "new-england-seamounts": 423_442.0, "chagos-banks": 491_967.0,
        "marcus-wake-deep": 251_458.0}
"""Best known costs (docs/bench_hard.md, 10 000 evaluations: the refined lattice reference)."""

VARIANTS = (
    ("document", {"pipeline": "document"}, False),
    ("refit only (K, bend 1)", {}, True),
    ("coarse, plain fit (bend 0)", {"bend": 0.0}, False),
    ("coarse, bend 0.5", {"bend": 0.5}, False),
    ("coarse, bend 1 (default)", {}, False),
    ("coarse, bend 2", {"bend": 2.0}, False),
    ("coarse share 0.1", {"coarse_fraction": 0.1}, False),
    ("coarse share 0.3", {"coarse_fraction": 0.3}, False),
)
"""(label, PlannerSpec overrides on the progressive pipeline, first stage at K instead of ⌈K/2⌉)."""


def run(name: str, seeds: int, budget: int) -> dict[str, list[tuple[float, bool]]]:
    world, mission = sc.build(sc.load(name))
    prob = planning_problem(world, mission)
    base = replace(mission.planner, name="iabc", pipeline="progressive", budget=budget)
    out: dict[str, list[tuple[float, bool]]] = {}
    for label, over, same_k in VARIANTS:
        spec = replace(base, **over)
        with mock.patch.object(progressive, "coarse_count", (lambda k: k) if same_k else progressive.coarse_count):
            out[label] = [(r.cost, r.status.ok) for r in (plan(prob, spec, rng=s) for s in range(seeds))]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--budget", type=int, default=10_000)
    ap.add_argument("--scenarios", nargs="+", default=list(BEST))
    args = ap.parse_args()
    load = os.getloadavg()
    print(f"load average at start {load[0]:.1f} on {os.cpu_count()} cores; {args.seeds} seeds, "
          f"{args.budget} evaluations")
    results = {name: run(name, args.seeds, args.budget) for name in args.scenarios}
    print("\n| variant | " + " | ".join(args.scenarios) + " |")
    print("|---|" + "---|" * len(args.scenarios))
    for label, _, _ in VARIANTS:
        cells = []
        for name in args.scenarios:
            cost = np.array([c for c, _ in results[name][label]])
            bad = sum(not ok for _, ok in results[name][label])
            gap = 100 * (cost / BEST[name] - 1)
            cells.append(f"{np.median(gap):+.2f} / {gap.max():+.2f} % ({bad})")
        print(f"| {label} | " + " | ".join(cells) + " |")
    load = os.getloadavg()
    print(f"\nload average at end {load[0]:.1f}")


if __name__ == "__main__":
    main()
