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
relative difference of the best cost, of the plan (path and control points) and of the convergence trace;
it exits 1 when a best cost or a plan differs by more than ``--rtol`` (0 by default: bit-identical).
``--figure-md NAME`` also writes the table to ``docs/figures/NAME.md``.  Clock fields (CPU and wall times)
are not dumped.
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


def agreement(a: Path, b: Path) -> dict[str, dict[str, float]]:
    """Per problem: seeds, seeds bit-identical in every array, and the largest relative difference of the
    best cost, of the plan (path and control points), of its exact cost terms, of the convergence trace and of
    any array."""
    da, db = np.load(a), np.load(b)
    per: dict[str, dict[str, float]] = {}
    seeds: dict[str, dict[str, float]] = {}
    for k in sorted(set(da.files) | set(db.files)):
        name, seed, field = k.split("/", 2)
        r = _rel(da[k], db[k]) if k in da.files and k in db.files else np.inf
        row = per.setdefault(name, {"cost": 0.0, "plan": 0.0, "terms": 0.0, "trace": 0.0, "any": 0.0})
        part = "plan" if field in ("path", "control_points") else field if field in ("cost", "trace") else \
            "terms" if field.startswith("terms/") else "any"
        row[part] = max(row[part], r)
        row["any"] = max(row["any"], r)
        by_seed = seeds.setdefault(name, {})
        by_seed[seed] = max(by_seed.get(seed, 0.0), r)
    for name, row in per.items():
        row["seeds"] = float(len(seeds[name]))
        row["identical"] = float(sum(v == 0.0 for v in seeds[name].values()))
    return per


def compare(a: Path, b: Path, rtol: float = 0.0, figure: str | None = None) -> int:
    """Print the per-problem agreement of two dumps (and write it as ``docs/figures/<figure>.md``);
    1 if the best cost or the plan of any seed differs by more than ``rtol`` (relative)."""
    per = agreement(a, b)
    lines = [f"`benchmarks/hard_identity.py --compare {a.name} {b.name}` (the default plan at the scenario's "
             "budget, per problem and seed; relative differences, 0 = bit-identical)", "",
             "| scenario | seeds bit-identical in every array | best cost | plan (path, control points) "
             "| exact cost terms | convergence trace |", "|---|---|---|---|---|---|"]
    for name, row in per.items():
        trace = "different length" if row["trace"] == np.inf else f"{row['trace']:.2g}"
        lines.append(f"| {name} | {row['identical']:.0f}/{row['seeds']:.0f} | {row['cost']:.2g} | {row['plan']:.2g} "
                     f"| {row['terms']:.2g} | {trace} |")
    print("\n".join(lines))
    worst = max(max(row["cost"], row["plan"]) for row in per.values())
    print(f"largest relative difference of a best cost or a plan: {worst:.3g} (tolerance {rtol:g})")
    if figure:
        path = Path(__file__).resolve().parents[1] / "docs" / "figures" / f"{figure}.md"
        path.write_text("\n".join(lines) + "\n")
        print(f"wrote {path}")
    return 0 if worst <= rtol else 1


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path)
    ap.add_argument("--compare", nargs=2, type=Path)
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--budget", type=int, default=10_000)
    ap.add_argument("--only", nargs="+", choices=SCENARIOS)
    ap.add_argument("--rtol", type=float, default=0.0)
    ap.add_argument("--figure-md", help="with --compare: write the table to docs/figures/NAME.md")
    args = ap.parse_args(argv)
    if args.compare:
        return compare(*args.compare, rtol=args.rtol, figure=args.figure_md)
    if args.out is None:
        ap.error("--out or --compare is needed")
    np.savez_compressed(args.out, **collect(args.seeds, args.budget, args.only))
    return 0


if __name__ == "__main__":
    sys.exit(main())
