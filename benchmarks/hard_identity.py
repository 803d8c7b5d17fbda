"""Dump the default plan of every hard problem and seed, to show a speed-up leaves the results unchanged.

For each of the six hard problems of :mod:`benchmarks.hard` and each seed, the default plan at the
scenario's budget (``--budget``, 10 000 by default as in ``benchmarks/hard.py``): its status, best cost,
evaluations, cost terms, control points, path and convergence trace are written to one ``.npz``.  Run it
before and after a change of a kernel, then compare::

    .venv/bin/python benchmarks/hard_identity.py --seeds 5 --out results/before.npz
    ... speed up ...
    .venv/bin/python benchmarks/hard_identity.py --seeds 5 --out results/after.npz
    .venv/bin/python benchmarks/hard_identity.py --compare results/before.npz results/after.npz

The comparison prints, per problem, how many seeds are bit-identical in every array and the largest
relative difference of the best cost and of any array; it exits 1 when a difference exceeds ``--rtol``
(0 by default: bit-identical).  Clock fields (CPU and wall times) are left out.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.sim import planning_problem

try:
    from hard import SCENARIOS
except ImportError:  # imported as benchmarks.hard_identity
    from benchmarks.hard import SCENARIOS


def collect(seeds: int, budget: int, only: list[str] | None = None) -> dict[str, np.ndarray]:
    """Arrays of the default plans, keyed ``scenario/seed/field``."""
    out: dict[str, np.ndarray] = {}
    for name in only or SCENARIOS:
        world, mission = sc.build(sc.load(name))
        prob = planning_problem(world, mission)
        spec = replace(mission.planner, budget=budget)
        for seed in range(seeds):
            r = plan(prob, spec, rng=seed)
            key = f"{name}/{seed}"
            out[f"{key}/status"] = np.asarray(r.status.value)
            out[f"{key}/cost"] = np.asarray(r.cost)
            out[f"{key}/evaluations"] = np.asarray(r.evaluations)
            out[f"{key}/path"] = np.asarray(r.path)
            out[f"{key}/trace"] = np.asarray(r.trace)
            if r.control_points is not None:
                out[f"{key}/control_points"] = np.asarray(r.control_points)
            for k, v in sorted(r.cost_terms.items()):
                out[f"{key}/terms/{k}"] = np.asarray(v)
            print(f"{name} seed {seed}: {r.status.value} cost {r.cost!r}", flush=True)
    return out


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    if a.dtype.kind not in "fiu" or b.dtype.kind not in "fiu":
        return 0.0 if np.array_equal(a, b) else np.inf
    if a.shape != b.shape:
        return np.inf
    a, b = a.astype(float), b.astype(float)
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    if same.all():
        return 0.0
    scale = np.maximum(np.abs(a), np.abs(b))
    return float(np.max(np.where(same, 0.0, np.abs(a - b) / np.where(scale > 0, scale, 1.0))))


def compare(a: Path, b: Path, rtol: float = 0.0) -> int:
    """Print the per-problem agreement of two dumps; 1 if any difference exceeds ``rtol``."""
    da, db = np.load(a), np.load(b)
    keys = sorted(set(da.files) | set(db.files))
    worst = 0.0
    per: dict[str, dict[str, float]] = {}
    for k in keys:
        name, seed, field = k.split("/", 2)
        r = _rel(da[k], db[k]) if k in da.files and k in db.files else np.inf
        row = per.setdefault(name, {})
        row[seed] = max(row.get(seed, 0.0), r)
        if field == "cost":
            row["cost"] = max(row.get("cost", 0.0), r)
        worst = max(worst, r)
    for name, row in per.items():
        seeds = [s for s in row if s != "cost"]
        same = sum(row[s] == 0.0 for s in seeds)
        print(f"{name}: {same}/{len(seeds)} seeds bit-identical; largest relative difference: "
              f"cost {row.get('cost', 0.0):.3g}, any array {max(row[s] for s in seeds):.3g}")
    print(f"largest relative difference overall: {worst:.3g} (tolerance {rtol:g})")
    return 0 if worst <= rtol else 1


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path)
    ap.add_argument("--compare", nargs=2, type=Path)
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--budget", type=int, default=10_000)
    ap.add_argument("--only", nargs="+", choices=SCENARIOS)
    ap.add_argument("--rtol", type=float, default=0.0)
    args = ap.parse_args(argv)
    if args.compare:
        return compare(*args.compare, rtol=args.rtol)
    if args.out is None:
        ap.error("--out or --compare is needed")
    np.savez_compressed(args.out, **collect(args.seeds, args.budget, args.only))
    return 0


if __name__ == "__main__":
    sys.exit(main())
