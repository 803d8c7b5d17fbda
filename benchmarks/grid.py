"""The lattice reference planner on marcus-wake: plan time and peak memory from 1 km to 250 m
cells, and scikit-fmm's travel-time field on the same lattice in the same run.

Each cell size runs in a fresh process so that its peak resident memory is its own.  The
scikit-fmm peer (an ordered-upwind eikonal solver, first order) solves |∇T| = 1 on the same
free-node mask from the goal node; its distance at the start is set beside the reference's
length-objective cost-to-go (Dijkstra on the 26-connected lattice) and the shortened path.

    .venv/bin/pip install scikit-fmm          # the peer, installed only for this benchmark
    .venv/bin/python benchmarks/grid.py --cells 1000 750 500 350 250 --out results/bench-grid
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np


def measure(cell: float, repeats: int, scenario: str = "marcus-wake") -> dict:
    """Plan ``scenario`` on ``cell`` m cells (cost objective, then length) and run scikit-fmm."""
    from auvplan.io import scenario as sc
    from auvplan.planners import GridParams, GridReference, plan_grid
    from auvplan.planners.swarm import cost_model_for, search_box
    from auvplan.sim import planning_problem

    world, mission = sc.build(sc.load(scenario))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="grid", grid=GridParams(cell=cell, max_nodes=8_000_000))
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = plan_grid(prob, spec)
        times.append(time.perf_counter() - t0)
    row = {"scenario": scenario, "cell_m": cell, "plan_s": float(np.median(times)), "plan_s_all": times,
           "status": r.status.value, "cost": r.cost, "length_m": r.cost_terms.get("length_m"), "edges": r.evaluations,
           "reference": r.message}
    lattice_only = plan_grid(prob, replace(spec, grid=replace(spec.grid, converge=False)))
    row["cost_lattice_bound"] = lattice_only.cost
    # length objective: the lattice distance, the shortened path, and the peer on the same lattice
    lspec = replace(spec, grid=GridParams(cell=cell, objective="length", max_nodes=8_000_000))
    lo, hi = search_box(prob)
    t0 = time.perf_counter()
    ref = GridReference(world, prob.goal, cost_model_for(prob, lspec), lo, hi, lspec.grid)
    row["dijkstra_field_s"] = time.perf_counter() - t0
    row["nodes"], row["free_nodes"] = ref.nodes, int(ref.free.sum())
    near = ref._connect(prob.start, towards=False)
    row["lattice_distance_m"] = float((near[1] + ref._dist[near[0]]).min())
    row["shortened_length_m"] = plan_grid(prob, lspec, reference=ref).cost_terms["length_m"]
    try:
        import skfmm
    except ImportError:
        row["skfmm"] = "not installed"
    else:
        gi = [int(np.argmin(np.abs(ax - g))) for ax, g in zip(ref.axes, prob.goal)]
        phi = np.ones(ref.shape)
        phi[tuple(gi)] = -1.0
        phi = np.ma.MaskedArray(phi, ~ref.free)
        t0 = time.perf_counter()
        tt = skfmm.distance(phi, dx=[ref.cell, ref.cell, ref.cell_z])
        row["skfmm_s"] = time.perf_counter() - t0
        si = tuple(int(np.argmin(np.abs(ax - s))) for ax, s in zip(ref.axes, prob.start))
        row["skfmm_distance_m"] = float(tt[si])
        row["dijkstra_distance_same_node_m"] = float(ref.cost_to_go[si])
    row["peak_rss_mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cells", type=float, nargs="+", default=[1000, 750, 500, 350, 250])
    ap.add_argument("--scenarios", nargs="+", default=["marcus-wake"])
    ap.add_argument("--repeats", type=int, default=3, help="plans per cell size (median reported)")
    ap.add_argument("--out", default="results/bench-grid")
    ap.add_argument("--one", type=float, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(measure(args.one, args.repeats, args.scenarios[0])))
        return 0
    rows = []
    for scenario, cell in ((s, c) for s in args.scenarios for c in args.cells):
        reps = args.repeats if cell >= 400 else 1
        out = subprocess.run([sys.executable, __file__, "--one", str(cell), "--repeats", str(reps),
                              "--scenarios", scenario], capture_output=True, text=True, check=True)
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
        r = rows[-1]
        print(f"{scenario} {cell:6.0f} m  cost lattice-bound {r['cost_lattice_bound']:.6g} → "
              f"converged {r['cost']:.6g}  "
              f"nodes {r['nodes']:>9d}  edges {r['edges']:>10d}  plan {r['plan_s']:6.2f} s  "
              f"peak {r['peak_rss_mib']:6.0f} MiB  cost {r['cost']:.6g}  "
              f"skfmm {r.get('skfmm_s', float('nan')):.2f} s  "
              f"dist at start: dijkstra {r.get('dijkstra_distance_same_node_m', float('nan')):.0f} m, "
              f"fmm {r.get('skfmm_distance_m', float('nan')):.0f} m, shortened {r['shortened_length_m']:.0f} m",
              flush=True)
    Path(args.out).mkdir(parents=True, exist_ok=True)
    (Path(args.out) / "grid.json").write_text(json.dumps(rows, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
