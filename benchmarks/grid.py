"""Resolution study of the lattice reference: time, peak memory and cost versus cell size, beside
scikit-fmm on the same lattice, on marcus-wake and the hard built-in scenarios.

Each (scenario, cell) runs in a fresh process.  The process first builds the scenario and compiles
the kernels on a coarse lattice (its resident memory then is the *baseline*), then computes the
converged lattice reference alone (:func:`auvplan.planners.plan_grid`: node fields, free edges,
A* towards the start, elastic band, convergence) and records its wall time, the process's peak
resident memory (``ru_maxrss``) and the peak of numpy's buffers (tracemalloc).  Only then, in the
same process, come the peers and the extras (their memory does not count in the peak above):

* scikit-fmm (ordered-upwind eikonal solver, first order) solves |∇T| = 1 on the same free-node
  mask from the goal node over the whole lattice; beside it the reference's full cost-to-go field
  on the same lattice with the length objective (Dijkstra, no start: like for like).  The ratio
  ``field_s / skfmm_s`` compares the two field computations, ``plan_s / skfmm_s`` the whole
  converged plan (currents, path, refinement) with the peer's bare distance field.
* the lattice-bound cost (elastic band only, no convergence).

    .venv/bin/pip install scikit-fmm          # the peer, installed only for this benchmark
    nice -n 5 .venv/bin/python benchmarks/grid.py --cells 1000 500 350 250 \\
        --scenarios marcus-wake ninetyeast-ridge new-england-seamounts chagos-banks marcus-wake-deep \\
        --out results/bench-grid
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
import tracemalloc
from dataclasses import replace
from pathlib import Path

import numpy as np

HARD = ("ninetyeast-ridge", "new-england-seamounts", "chagos-banks", "marcus-wake-deep")


def _rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def measure(cell: float, scenario: str) -> dict:
    """One cell size on one scenario (see the module notes)."""
    from auvplan.io.scenario import loader as sc
    from auvplan.planners import GridParams, GridReference, plan_grid
    from auvplan.planners.common import cost_model_for, search_box
    from auvplan.planners.grid.lattice import node_fields
    from auvplan.sim import planning_problem

    world, mission = sc.build(sc.load(scenario))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="grid", grid=GridParams(cell=cell, max_nodes=16_000_000))
    plan_grid(prob, replace(spec, grid=GridParams(cell=8 * cell)))  # compile and load the kernels
    row: dict = {"scenario": scenario, "cell_m": cell, "baseline_rss_mib": _rss_mib()}
    t0, c0 = time.perf_counter(), time.process_time()
    r = plan_grid(prob, spec)  # timed without tracemalloc (it slows every numpy allocation)
    row["plan_s"], row["plan_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
    tracemalloc.start()
    plan_grid(prob, spec)  # the same plan again for numpy's peak (the peak RSS is the same work's)
    row["numpy_peak_mib"] = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    row["peak_rss_mib"] = _rss_mib()
    row.update(status=r.status.value, cost=r.cost, length_m=r.cost_terms.get("length_m"), edges=r.evaluations,
               reference=r.message)
    row["cost_lattice_bound"] = plan_grid(prob, replace(spec, grid=replace(spec.grid, converge=False))).cost
    row["cost_single_lattice"] = plan_grid(prob, replace(spec, grid=replace(spec.grid, ladder=False))).cost
    lspec = replace(spec, grid=replace(spec.grid, objective="length"))
    lo, hi = search_box(prob)
    t0, c0 = time.perf_counter(), time.process_time()
    ref = GridReference(world, prob.goal, cost_model_for(prob, lspec), lo, hi, lspec.grid)
    row["field_s"], row["field_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
    row["nodes"], row["free_nodes"], row["shape"] = ref.nodes, int(ref.free.sum()), list(ref.shape)
    try:
        import skfmm
    except ImportError:
        row["skfmm"] = "not installed"
        return row
    free = node_fields(world, ref.axes, currents=False)[0]
    def nearest_free(p):  # the free node nearest to p (the node nearest to a seabed-hugging end may be in the seabed)
        ids = np.flatnonzero(free)
        xyz = np.stack([ref.axes[d][i] for d, i in enumerate(np.unravel_index(ids, ref.shape))], axis=1)
        return np.unravel_index(ids[int(np.argmin(np.linalg.norm(xyz - p, axis=1)))], ref.shape)

    gi = nearest_free(prob.goal)
    phi = np.ones(ref.shape)
    phi[gi] = -1.0
    t0, c0 = time.perf_counter(), time.process_time()
    tt = skfmm.distance(np.ma.MaskedArray(phi, ~free), dx=[ref.cell, ref.cell, ref.cell_z])
    row["skfmm_s"], row["skfmm_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
    si = nearest_free(prob.start)
    row["skfmm_distance_m"] = float(tt[si])
    row["dijkstra_distance_m"] = float(ref.cost_to_go[si])
    return row


def _print(r: dict) -> None:
    print(f"{r['scenario']:22s} {r['cell_m']:6.0f} m  nodes {r['nodes']:>9d}  plan {r['plan_s']:6.2f} s "
          f"(cpu {r['plan_cpu_s']:6.2f} s)  "
          f"peak RSS {r['peak_rss_mib']:6.0f} MiB (baseline {r['baseline_rss_mib']:4.0f}, "
          f"numpy {r['numpy_peak_mib']:5.0f})"
          f"  cost {r['cost']:.7g} (this lattice alone {r['cost_single_lattice']:.7g}, lattice-bound "
          f"{r['cost_lattice_bound']:.7g})  field cpu {r['field_cpu_s']:5.2f} s  "
          f"skfmm cpu {r.get('skfmm_cpu_s', float('nan')):5.2f} s", flush=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cells", type=float, nargs="+", default=[1000, 500, 350, 250])
    ap.add_argument("--scenarios", nargs="+", default=["marcus-wake", *HARD])
    ap.add_argument("--out", default="results/bench-grid")
    ap.add_argument("--one", type=float, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(measure(args.one, args.scenarios[0])))
        return 0
    rows: list[dict] = []
    Path(args.out).mkdir(parents=True, exist_ok=True)
    for cell, scenario in ((c, s) for c in args.cells for s in args.scenarios):  # coarse cells first
        load = os.getloadavg()[0]
        out = subprocess.run([sys.executable, __file__, "--one", str(cell), "--scenarios", scenario],
                             capture_output=True, text=True)
        if out.returncode:
            print(f"{scenario} {cell:g} m failed: {out.stderr.strip().splitlines()[-1]}", flush=True)
            continue
        rows.append({**json.loads(out.stdout.strip().splitlines()[-1]), "load_1min": load})
        _print(rows[-1])
        (Path(args.out) / "grid.json").write_text(json.dumps(rows, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
