"""Document 000's streamline planner from many random starts: the corrected fields and the document's
variants side by side, the streamline throughput, and the Rankine-type bodies' volumes.

    .venv/bin/python benchmarks/flow.py --starts 500 --out results/bench-flow

Starts are uniform in the box [-15, 25]³, outside every obstacle inflated by the 0.5 m margin and
2 m from the goal; none is dropped afterwards (starts inside a body leave it by the exit rule).
"Penetrating" counts streamlines with a leg closer than the margin to a real obstacle (exact segment
tests); "pushed back" those the integrator had to push back onto a surface the field drove them into.
The uniform-flow baseline (Fig. 5) has no sink: its streamlines end when they pass the goal's plane.
Figures: ``streamlines.png`` (Fig. 8 scene), ``fig5_sink.png`` beside ``fig5_uniform.png`` (Fig. 5;
streamlines that miss the goal in red).
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners.core.params import FlowParams
from auvplan.planners.flow.design import design_body
from auvplan.planners.flow.field import FlowField
from auvplan.planners.flow.stream import integrate_streamlines
from auvplan.world import Ellipsoid, Sphere

ELLIPSOID = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0))
LONG = Ellipsoid((5.0, -3.0, 2.0), (12.0, 3.0, 2.5), yaw=0.6, pitch=0.25)
SPHERES = (Sphere((15.0, 5.0, 0.0), 3.0), Sphere((-12.0, -6.0, 2.0), 2.5))
MARGIN = 0.5


def scenes():
    w, m = sc.build(sc.load("flow-spheres"))
    goal = np.asarray(m.goal)
    yield "flow-spheres", w.obstacles, goal, (FlowParams(), FlowParams(field="document"),
                                               FlowParams(weights="document"), FlowParams(field="uniform"))
    ell = (FlowParams(), FlowParams(rankine="pair"), FlowParams(rankine="document"))
    yield "ellipsoid (8, 4, 3), goal (30, 0, 0)", (ELLIPSOID,), np.array([30.0, 0.0, 0.0]), ell
    yield "ellipsoid, rotated goal (28, 28, 0)", (ELLIPSOID,), np.array([28.0, 28.0, 0.0]), ell
    yield "ellipsoid + 2 spheres (Fig. 8)", (ELLIPSOID,) + SPHERES, np.array([30.0, 0.0, 0.0]), \
        (FlowParams(), FlowParams(weights="document"), FlowParams(distance="ray", rankine="document"))


def _starts(field, n, seed=0):
    rng = np.random.default_rng(seed)
    p = rng.uniform(-15, 25, (8 * n, 3))
    return p[(field.clearance(p) > 0) & (np.linalg.norm(p - field.target, axis=1) > 2.0)][:n]


def variant(p: FlowParams) -> str:
    if p.field == "uniform":
        return "uniform flow + dipoles (Fig. 5)"
    parts = [{"exact": "exact image", "document": "document dipole"}[p.field]]
    parts.append(f"{p.rankine} body")
    if p.weights == "document":
        parts.append("product weights")
    if p.distance == "ray":
        parts.append("ray distance")
    return ", ".join(parts)


def row(name, obstacles, goal, params, n):
    direction = goal - np.array([5.0, 5.0, 5.0]) if params.field == "uniform" else None
    t0 = time.perf_counter()
    try:
        field = FlowField(obstacles, goal, params, MARGIN, direction=direction)
    except ValueError as err:
        return f"| {name} | {variant(params)} | — | not runnable: {err} | | | | | | |"
    design = time.perf_counter() - t0
    p = _starts(field, n)
    inside = int(field.inside_body(p).sum()) if field.contained else 0
    sl = integrate_streamlines(field, p)
    pen = sum(any(ob.segments_hit(np.stack([q[:-1], q[1:]], 1), MARGIN).any() for ob in obstacles) for q in sl.paths)
    ok = sl.arrived
    ratio = np.median([np.linalg.norm(np.diff(q, axis=0), axis=1).sum() / np.linalg.norm(q[0] - goal)
                       for q, a in zip(sl.paths, ok) if a]) if ok.any() else float("nan")
    clear = float(sl.min_distance[ok].min()) + MARGIN if ok.any() else float("nan")
    return (f"| {name} | {variant(params)} | {len(p)} ({inside} in a body) | {100 * ok.mean():.1f} % | {pen} | "
            f"{int((sl.corrections > 0).sum())} | {clear:.3f} | {ratio:.3f} | {len(p) / sl.wall_time_s:.0f} | "
            f"{design:.2f} |")


def peer(name, obstacles, goal, n: int = 40) -> str:
    """The same field integrated one start at a time by scipy's adaptive RK45 (solve_ivp, arrival event)."""
    from scipy.integrate import solve_ivp

    field = FlowField(obstacles, goal, FlowParams(), MARGIN)
    p = _starts(field, n, seed=7)

    def rhs(_, y):
        u = field.velocity(y[None])[0]
        return u / np.linalg.norm(u)

    def arrive(_, y):
        return np.linalg.norm(y - goal) - 0.5

    arrive.terminal = True
    integrate_streamlines(field, p[:2])  # compiled kernels warm
    rhs(0.0, p[0])
    t0 = time.perf_counter()
    ok = sum(solve_ivp(rhs, (0.0, 500.0), q, events=arrive, rtol=1e-6, atol=1e-6).status == 1 for q in p)
    peer_rate = n / (time.perf_counter() - t0)
    ours = integrate_streamlines(field, p)
    return (f"| {name} | {n} | {len(p) / ours.wall_time_s:.0f} ({int(ours.arrived.sum())} arrive) | "
            f"{peer_rate:.0f} ({ok} arrive) | {len(p) / ours.wall_time_s / peer_rate:.1f}× |")


def volumes() -> list[str]:
    lines = ["| obstacle | goal | body | volume (m³) | / inflated ellipsoid | contains the inflated obstacle |",
             "|---|---|---|---|---|---|"]
    from auvplan.planners.flow.design import offset_surface

    cases = (("(8, 4, 3)", ELLIPSOID, np.array([30.0, 0.0, 0.0])),
             ("(8, 4, 3)", ELLIPSOID, np.array([28.0, 28.0, 0.0])),
             ("(12, 3, 2.5), yaw 34°, pitch 14°", LONG, np.asarray(LONG.center) + 30.0 * LONG._rot[:, 0]))
    for label, ob, goal in cases:
        v_in = 4.0 / 3.0 * np.pi * np.prod(np.asarray(ob.semi_axes) + MARGIN)
        dense = offset_surface(ob, MARGIN, 150)
        for sizing in ("line", "pair", "document"):
            try:
                b = design_body(ob, goal, sizing, 1.0, MARGIN, 0.002 * max(ob.semi_axes))
            except ValueError as err:
                lines.append(f"| {label} | {tuple(np.round(goal, 1).tolist())} | {sizing} | {err} | | |")
                continue
            lines.append(f"| {label} | {tuple(np.round(goal, 1).tolist())} | {b.kind} | {b.volume:.0f} | "
                         f"{b.volume / v_in:.2f} | {100 * b.inside(dense).mean():.2f} % of {len(dense)} points |")
    return lines


def figure(path: Path, n: int = 64) -> None:
    """Streamlines round the ellipsoid and spheres (Fig. 8 scene) from a plane of starts upstream."""
    from auvplan.viz.plots import streamlines
    from auvplan.world import Bounds, World

    obstacles = (ELLIPSOID,) + SPHERES
    goal = np.array([30.0, 0.0, 0.0])
    field = FlowField(obstacles, goal, FlowParams(), MARGIN)
    g = np.linspace(-10.0, 10.0, int(np.sqrt(n)))
    p = np.array([[-30.0, a, b] for a in g for b in g])
    sl = integrate_streamlines(field, p)
    w = World(Bounds(-40, 40, -40, 40, -30, 30), None, obstacles=obstacles)
    streamlines(w, sl.paths, goal, sl.status).savefig(path, dpi=150)


def figure_fig5(folder: Path, n: int = 49) -> None:
    """Document 000 Fig. 5: the sink field beside the uniform flow + dipole baseline on flow-spheres."""
    from auvplan.viz.plots import streamlines

    w, m = sc.build(sc.load("flow-spheres"))
    goal = np.asarray(m.goal)
    g = np.linspace(-12.0, 12.0, int(np.sqrt(n)))
    p = np.array([[-15.0, a, b] for a in g for b in g])
    for name, params in (("fig5_sink.png", FlowParams()), ("fig5_uniform.png", FlowParams(field="uniform"))):
        field = FlowField(w.obstacles, goal, params, MARGIN, direction=goal - np.array([-15.0, 0.0, 0.0]))
        q = p[field.clearance(p) > 0]
        sl = integrate_streamlines(field, q)
        streamlines(w, sl.paths, goal, sl.status).savefig(folder / name, dpi=150)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=500)
    ap.add_argument("--out", default="results/bench-flow")
    args = ap.parse_args(argv)
    load = os.getloadavg()
    lines = ["| scene | variant | starts | arrival | penetrating | pushed back | min clearance (m) | "
             "median length / straight | streamlines per s | field set-up (s) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for name, obstacles, goal, variants in scenes():
        for params in variants:
            lines.append(row(name, obstacles, goal, params, args.starts))
            print(lines[-1], flush=True)
    peers = ["| scene | starts | auvplan (streamlines/s) | scipy solve_ivp RK45 per start | ratio |",
             "|---|---|---|---|---|"]
    for name, obstacles, goal, _ in list(scenes())[:2]:
        peers.append(peer(name, obstacles, goal))
        print(peers[-1], flush=True)
    text = (f"# Streamlines from {args.starts} random starts (0.5 m safety margin)\n\n"
            f"Load average at start {load[0]:.1f}, at end {os.getloadavg()[0]:.1f} (shared 2-core machine).\n\n"
            + "\n".join(lines) + "\n\n## Throughput against a peer (same field, same run)\n\n" + "\n".join(peers)
            + "\n\n## Bodies round the ellipsoids\n\n" + "\n".join(volumes()) + "\n")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.md").write_text(text)
    figure(out / "streamlines.png")
    figure_fig5(out)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
