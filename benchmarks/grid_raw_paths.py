"""Why a finer any-angle lattice can return a dearer raw path: each cell's lattice path costed on every
cell's own lattice model (docs/lattice.md, wave 7).

For each cell, the raw any-angle lattice path (no refinement) is costed (a) exactly, on the planner's cost
function (:func:`auvplan.planners.core.common.path_cost`), and (b) in the lattice model of every cell of
the study: the segment cut into pieces of at most half a cell along its longest axis, each piece costed in
the current of its nearest node (:func:`auvplan.planners.grid.anyangle._piece_cost`, the any-angle links'
own model).  Its length, its summed climb ``Σ|dz|`` and its least clearance are printed too.  If a finer
lattice's model prices a coarser cell's path below the path the finer search returned, the search (not the
model, the terrain or a vertical zig-zag) missed it.

    nice -n 5 .venv/bin/python benchmarks/grid_raw_paths.py marcus-wake --cells 4000 2000 1000 500
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace

import numpy as np


def main(argv: list[str] | None = None) -> int:
    from auvplan.cost import energy_mode, propulsion_power
    from auvplan.io.scenario import loader as sc
    from auvplan.planners import GridReference
    from auvplan.planners.core.common import cost_model_for, path_cost, search_box
    from auvplan.planners.grid.anyangle import _piece_cost
    from auvplan.planners.grid.lattice import node_fields
    from auvplan.sim import planning_problem

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenario")
    ap.add_argument("--cells", type=float, nargs="+", default=[4000.0, 2000.0, 1000.0, 500.0])
    ap.add_argument("--links", type=int, default=16)
    args = ap.parse_args(argv)
    world, mission = sc.build(sc.load(args.scenario))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="grid")
    lo, hi = search_box(prob)
    model = cost_model_for(prob, spec)
    refs, paths = {}, {}
    for cell in args.cells:
        g = replace(spec.grid, cell=cell, any_angle=args.links, max_nodes=16_000_000)
        refs[cell] = GridReference(world, prob.goal, model, lo, hi, g, prob.start)
        paths[cell] = refs[cell].query(prob.start)

    def on_lattice(ref: GridReference, path: np.ndarray) -> float:
        current = node_fields(world, ref.axes, True)[3].reshape(*ref.shape, 3)
        steps = np.array([ref.cell, ref.cell, ref.cell_z])
        origin = np.array([ax[0] for ax in ref.axes])
        total = 0.0
        for a, b in zip(path[:-1], path[1:]):
            n = max(1, int(np.ceil(2.0 * np.max(np.abs(b - a) / steps))))
            for t in range(n):
                p, q = a + (b - a) * t / n, a + (b - a) * (t + 1) / n
                ijk = np.clip(np.rint((0.5 * (p + q) - origin) / steps).astype(int), 0, np.array(ref.shape) - 1)
                c, e = current[tuple(ijk)], q - p
                total += _piece_cost(e[0], e[1], e[2], c[0], c[1], c[2], True, model.w_length,
                                     model.w_energy * model.scale, model.speed, propulsion_power(model),
                                     energy_mode(model))
        return total

    for cell, path in paths.items():
        terms = path_cost(prob, spec, path)
        models = ", ".join(f"{c:g} m: {on_lattice(refs[c], path):,.1f}" for c in args.cells)
        print(f"{args.scenario} {cell:g} m path: {path.shape[0]} vertices, exact cost {terms['total']:,.1f}, "
              f"length {terms['length_m']:,.0f} m, sum|dz| {np.abs(np.diff(path[:, 2])).sum():,.0f} m, "
              f"least clearance {terms['min_clearance_m']:,.0f} m; in the lattice models of {models}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
