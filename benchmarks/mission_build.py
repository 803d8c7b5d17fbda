"""Mission building from dense paths: the breadth-first, array Douglas-Peucker of
:func:`auvplan.guidance.mission.waypoints.build_waypoints` against the recursive one it replaced, in one run.

    .venv/bin/python benchmarks/mission_build.py --starts 30

Paths: the plans of the built-ins whose planner is deterministic and quick (flow, grid, timeopt), and the
default flyable flow paths from seeded near-surface starts of the axis-aligned Fig. 8 scene
(benchmarks/flow_fig78.py; dense: one point per 0.5 m).  Each path is built by both; the missions must be
identical (bit for bit) and the table gives the process time of each.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path
from unittest import mock

import numpy as np

from auvplan.guidance.mission import waypoints as gm
from auvplan.io.scenario import loader as sc
from auvplan.io.scenario.builtins import builtin_scenarios
from auvplan.planners import plan
from auvplan.sim import planning_problem

sys.path.insert(0, str(Path(__file__).resolve().parent))
from flow_fig78 import ALIGNED, GOAL, MARGIN, SPHERES, near_surface_starts  # noqa: E402


def recursive_douglas_peucker(world, p, tolerance):
    """The previous implementation: depth first, one chord (one envelope test) at a time."""
    keep = np.zeros(len(p), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(p) - 1)]
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        dev, k = gm._deviation(p, i, j)
        if dev <= tolerance and gm.envelopes_free(world, p[i][None], p[j][None])[0]:
            continue
        k = k if dev > 0.0 else (i + j) // 2
        keep[k] = True
        stack += [(i, k), (k, j)]
    return np.flatnonzero(keep)


def paths(starts):
    """(name, world, path) of the quick built-ins' plans and of dense flyable flow paths."""
    for name in sorted(builtin_scenarios()):
        spec = sc.load(name)
        if spec.planner.name not in ("flow", "grid", "timeopt"):
            continue
        world, mission = sc.build(spec)
        res = plan(planning_problem(world, mission), mission.planner, mission.seed)
        if res.status.ok:
            yield name, world, res.path
    world, mission = sc.build(sc.load("flow-fig8"))
    obstacles = (ALIGNED,) + SPHERES
    world = replace(world, obstacles=obstacles)
    from auvplan.planners.core.params import FlowParams
    from auvplan.planners.flow.field import FlowField
    field = FlowField(obstacles, GOAL, FlowParams(), MARGIN)
    for k, p in enumerate(near_surface_starts(obstacles, field, starts, 1)):
        res = plan(planning_problem(world, replace(mission, start=tuple(p))), mission.planner, 0)
        if res.status.ok:
            yield f"flow path {k}", world, res.path


def timed(path, world):
    t0 = time.process_time()
    w = gm.build_waypoints(path, world)
    return w, time.process_time() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=30)
    a = ap.parse_args(argv)
    rows, same, t_old, t_new = [], 0, 0.0, 0.0
    for name, world, path in paths(a.starts):
        new, tn = timed(path, world)
        with mock.patch.object(gm, "_douglas_peucker", recursive_douglas_peucker):
            old, to = timed(path, world)
        ok = old.shape == new.shape and bool(np.array_equal(old, new))
        same += ok
        t_old += to
        t_new += tn
        rows.append(f"| {name} | {len(path)} | {len(new)} | {'yes' if ok else 'NO'} | {to:.3f} | {tn:.3f} |")
    print(f"build_waypoints, recursive vs breadth-first Douglas-Peucker (load {os.getloadavg()[0]:.1f})\n")
    print("| path | points | waypoints | identical | recursive (s) | array (s) |\n|---|---|---|---|---|---|")
    print("\n".join(rows))
    print(f"\nidentical {same}/{len(rows)}; total {t_old:.2f} s -> {t_new:.2f} s (x{t_old / max(t_new, 1e-9):.1f})")
    return 0 if same == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main())
