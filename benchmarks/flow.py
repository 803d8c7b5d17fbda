"""Document 000's streamline planner from many random starts: the corrected field and the
document's variants side by side, and the streamline throughput.

    .venv/bin/python benchmarks/flow.py --starts 500 --out results/bench-flow
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io import scenario as sc
from auvplan.planners.flow import FlowField, FlowParams, integrate_streamlines
from auvplan.world import Sphere


def scenes():
    w, m = sc.build(sc.load("flow-spheres"))
    yield "flow-spheres", w, np.asarray(m.goal)
    w, m = sc.build(sc.load("flow-ellipsoid"))
    yield "flow-ellipsoid", w, np.asarray(m.goal)
    yield "flow-ellipsoid, rotated goal", w, np.array([28.0, 28.0, 0.0])
    extra = (Sphere((15.0, 5.0, 0.0), 3.0), Sphere((-12.0, -6.0, 2.0), 2.5))
    yield "flow-ellipsoid + spheres", replace(w, obstacles=w.obstacles + extra), np.asarray(m.goal)


def row(name, world, goal, params, n, seed=0):
    field = FlowField(world.obstacles, goal, params, world.margins.obstacle)
    rng = np.random.default_rng(seed)
    p = rng.uniform(-15, 25, (8 * n, 3))
    p = p[(field.distances(p).min(axis=1) > 0.2) & (np.linalg.norm(p - goal, axis=1) > 2.0)]
    p = p[~field.inside_body(p)][:n]
    t0 = time.perf_counter()
    sl = integrate_streamlines(field, p)
    wall = time.perf_counter() - t0
    pen = sum(any(ob.segments_hit(np.stack([q[:-1], q[1:]], 1), 0.0).any() for ob in world.obstacles) for q in sl.paths)
    clear = min(min(ob.distance(q).min() for ob in world.obstacles) for q in sl.paths)
    ratio = np.median([np.linalg.norm(np.diff(q, axis=0), axis=1).sum() / np.linalg.norm(q[0] - goal)
                       for q in sl.paths])
    return (f"| {name} | {params.field} | {params.weights} | {100 * sl.arrived.mean():.1f} % | {pen} | {clear:.3f} | "
            f"{ratio:.4f} | {len(p) / wall:.0f} |")


def figure(path: Path, n: int = 60) -> None:
    """Document 000's figure: streamlines from ``n`` starts on a plane upstream of the spheres."""
    from auvplan.viz.plots import streamlines

    w, m = sc.build(sc.load("flow-spheres"))
    goal = np.asarray(m.goal)
    field = FlowField(w.obstacles, goal, FlowParams(), w.margins.obstacle)
    g = np.linspace(-12.0, 12.0, int(np.sqrt(n)))
    p = np.array([[-15.0, a, b] for a in g for b in g])
    p = p[~field.inside_body(p) & (field.distances(p).min(axis=1) > 0.2)]
    sl = integrate_streamlines(field, p)
    streamlines(w, sl.paths, goal, sl.status).savefig(path, dpi=150)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=500)
    ap.add_argument("--out", default="results/bench-flow")
    args = ap.parse_args(argv)
    lines = ["| scene | field | weights | arrival | penetrating streamlines | min clearance (m) | "
             "median length / straight | streamlines per s |", "|---|---|---|---|---|---|---|---|"]
    for name, world, goal in scenes():
        for params in (FlowParams(), FlowParams(field="document"), FlowParams(weights="document")):
            if params.field == "document" and not any(isinstance(o, Sphere) for o in world.obstacles):
                continue
            lines.append(row(name, world, goal, params, args.starts))
    text = f"# Streamlines from {args.starts} random starts (0.5 m safety margin)\n\n" + "\n".join(lines) + "\n"
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.md").write_text(text)
    figure(out / "streamlines.png")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
