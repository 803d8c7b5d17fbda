"""The lattice reference's cost-to-go: any-angle links against the 26 directions and scikit-fmm.

    nice -n 5 .venv/bin/python benchmarks/lattice_fmm.py --out results/bench-lattice

For each scenario and cell (``[planner.grid] cell``), with the 26 lattice directions only
(``any_angle = 0``) and with any-angle links (the default, 16 cells):

* the lattice path's cost (the cost-to-go field's answer for the start, re-costed exactly on the
  planner's cost function) and its length, against the refined reference plan of the same cell
  (``converge``, no ladder): a finer cell must lower the lattice cost, and the any-angle lattice
  path's length must be within 1 % of the refined path's;
* the field's time against scikit-fmm's distance field on the same lattice (same free nodes, same
  cells; length objective, whole lattice, no A* stop, goal links as the seed), in the same run.

scikit-fmm is an optional peer, installed for this benchmark only (``pip install scikit-fmm``):
without it the comparison is skipped and said so.
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.path import polyline_length
from auvplan.planners import GridParams, GridReference, plan_grid
from auvplan.planners.core.common import cost_model_for, path_cost, search_box
from auvplan.planners.grid.lattice import edge_bits, node_fields, search
from auvplan.sim import planning_problem

SCENARIOS = ("marcus-wake", "new-england-seamounts")
CELLS = (4000.0, 2000.0, 1000.0, 500.0)


def lattice_row(prob, spec, cell: float, links: int) -> dict:
    """The lattice path (A* for the start) and the refined plan of one cell."""
    grid = replace(spec.grid, cell=cell, any_angle=links, ladder=False)
    s = replace(spec, name="grid", grid=grid)
    lo, hi = search_box(prob)
    t0 = time.process_time()
    ref = GridReference(prob.world, prob.goal, cost_model_for(prob, s), lo, hi, grid, prob.start)
    build = time.process_time() - t0
    raw = ref.query(prob.start)
    refined = plan_grid(prob, s)
    return {"cell": cell, "links": links, "nodes": ref.nodes, "build_s": build,
            "lattice_cost": float(path_cost(prob, s, raw)["total"]), "lattice_len": float(polyline_length(raw)),
            "refined_cost": float(refined.cost), "refined_len": float(polyline_length(refined.path))}


def field_times(prob, spec, cell: float, repeats: int = 3) -> tuple[float, float, float, int]:
    """Best CPU of the any-angle and the 26-direction distance fields over the whole lattice, and
    of scikit-fmm's (nan without it), on the same lattice; the node count."""
    grid = replace(spec.grid, cell=cell, objective="length")
    s = replace(spec, name="grid", grid=grid)
    lo, hi = search_box(prob)
    full = GridReference(prob.world, prob.goal, cost_model_for(prob, s), lo, hi, grid)  # its lattice and goal links
    steps = np.array([full.cell, full.cell, full.cell_z])
    origin = np.array([ax[0] for ax in full.axes])
    free, alt, obs, cur = node_fields(prob.world, full.axes, False)
    bits = edge_bits(prob.world, free, alt, obs, steps, full._coords)
    near, w = full._connect(full.goal, towards=True)
    keep = np.isfinite(w)
    goal_near = (near[keep], np.maximum(w[keep], 1e-12))
    links = full._links(alt, obs)
    times = []
    for lk in (links, None):
        best = np.inf
        for _ in range(repeats):
            t0 = time.process_time()
            search(full.shape, bits, steps, origin, cur, None, goal_near, links=lk)
            best = min(best, time.process_time() - t0)
        times.append(best)
    try:
        import skfmm
    except ImportError:
        return times[0], times[1], float("nan"), full.nodes
    phi = np.ones(full.shape)
    gi = np.unravel_index(goal_near[0], full.shape)
    phi[gi] = -1.0  # the goal's linked nodes: the zero level set between them and the rest
    phi_m = np.ma.MaskedArray(phi, mask=~free)
    best = np.inf
    for _ in range(repeats):
        t0 = time.process_time()
        skfmm.distance(phi_m, dx=list(steps))
        best = min(best, time.process_time() - t0)
    return times[0], times[1], best, full.nodes


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--scenarios", nargs="+", default=list(SCENARIOS))
    ap.add_argument("--cells", nargs="+", type=float, default=list(CELLS))
    ap.add_argument("--out", default="results/bench-lattice")
    args = ap.parse_args(argv)
    load0 = os.getloadavg()[0]
    lines = ["# Lattice cost-to-go: any-angle links, 26 directions, scikit-fmm\n",
             f"load average {load0:.1f} at the start (2 shared cores).\n",
             "| scenario | cell (m) | nodes | links | lattice cost | lattice length (m) | refined cost "
             "| refined length (m) | lattice / refined length | build CPU (s) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for name in args.scenarios:
        world, mission = sc.build(sc.load(name))
        prob, spec = planning_problem(world, mission), replace(mission.planner, grid=GridParams())
        lattice_row(prob, spec, max(args.cells), 0)  # compiled code loaded
        for links in (16, 0):
            for cell in sorted(args.cells, reverse=True):
                r = lattice_row(prob, spec, cell, links)
                lines.append(f"| {name} | {cell:g} | {r['nodes']:,} | {links or '26 dirs'} | {r['lattice_cost']:.2f} | "
                             f"{r['lattice_len']:.1f} | {r['refined_cost']:.2f} | {r['refined_len']:.1f} | "
                             f"{r['lattice_len'] / r['refined_len']:.4f} | {r['build_s']:.2f} |")
                print(lines[-1], flush=True)
    lines += ["", "| scenario | cell (m) | nodes | any-angle field CPU (s) | 26-direction field CPU (s) | "
              "scikit-fmm distance CPU (s) | any-angle / scikit-fmm |", "|---|---|---|---|---|---|---|"]
    for name in args.scenarios:
        world, mission = sc.build(sc.load(name))
        prob, spec = planning_problem(world, mission), replace(mission.planner, grid=GridParams())
        for cell in (1000.0, 500.0):
            ours, d26, fmm, nodes = field_times(prob, spec, cell)
            ratio = "scikit-fmm not installed" if not np.isfinite(fmm) else f"{ours / fmm:.2f}"
            lines.append(f"| {name} | {cell:g} | {nodes:,} | {ours:.3f} | {d26:.3f} | {fmm:.3f} | {ratio} |")
            print(lines[-1], flush=True)
    lines.append(f"\nload average {os.getloadavg()[0]:.1f} at the end.")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
