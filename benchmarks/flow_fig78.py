"""Document 000's Figs. 7-8 at the document's own goal (28, 28, 0): starts 0.5-5 m from every surface,
the bodies' volumes for goals in 26 directions, and the largest turn between steps on every streamline.

    .venv/bin/python benchmarks/flow_fig78.py --starts 510 --out results/bench-flow-fig78

Scenes (0.5 m safety margin, goal (28, 28, 0)):

* **document reading** - the document computes the ellipsoid's flow with the obstacle on the x axis and
  then turns the whole frame towards the goal (§3.1 steps i-iv), so its ellipsoid's long axis points at
  the goal: the (8, 4, 3) ellipsoid at yaw 45° (built-in ``flow-fig8``), alone (Fig. 7) and with the two
  spheres of the project's Fig. 8 scene (Fig. 8);
* **axis-aligned** - the project's harder reading: the same ellipsoid unturned (long axis along x), so the
  goal lies 45° off its long axis.

Starts: for each obstacle in turn, a seeded uniform direction on its surface and a distance s uniform in
(0.5, 5] m from the *real* surface along the normal there (the nearest point of a convex surface), kept
when it lies outside every obstacle inflated by the margin and 2 m from the goal; equal numbers per
obstacle (``--starts`` in all).  "Penetrating" = a leg closer than the margin to a real obstacle (exact
segment tests); "contact" = the integrator stopped against a surface (not a penetration).  Turns: the
angle between consecutive legs; the tightest local radius = mean adjacent leg / that angle (rad).
"""

from __future__ import annotations

import argparse
import itertools
import os
import time
from pathlib import Path

import numpy as np

from auvplan.planners.core.params import FlowParams
from auvplan.planners.flow.body import frame
from auvplan.planners.flow.design import design_body, offset_surface
from auvplan.planners.flow.field import SAG_PAD, FlowField
from auvplan.planners.flow.stream import integrate_streamlines
from auvplan.planners.flow.turning import flyable_path
from auvplan.vehicles import VehicleParams
from auvplan.world import Ellipsoid, Sphere

GOAL = np.array([28.0, 28.0, 0.0])
MARGIN = 0.5
TURNED = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0), yaw=np.pi / 4)
ALIGNED = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0))
SPHERES = (Sphere((15.0, 5.0, 0.0), 3.0), Sphere((-12.0, -6.0, 2.0), 2.5))


def near_surface_starts(obstacles, field, n, seed=0, lo=0.5, hi=5.0):
    """``n`` starts (equal numbers per obstacle) lo-hi m from each obstacle's real surface, outside every
    inflated obstacle and 2 m from the goal."""
    rng = np.random.default_rng(seed)
    per = int(np.ceil(n / len(obstacles)))
    out = []
    for ob in obstacles:
        got: list[np.ndarray] = []
        while len(got) < per:
            v = rng.normal(size=(4 * per, 3))
            v /= np.linalg.norm(v, axis=1, keepdims=True)
            s = rng.uniform(lo, hi, 4 * per)
            if isinstance(ob, Sphere):
                p = np.asarray(ob.center) + (ob.radius + s)[:, None] * v
            else:
                a = np.asarray(ob.semi_axes)
                q = v * a
                nb = q / a**2
                nb /= np.linalg.norm(nb, axis=1, keepdims=True)
                p = (q + s[:, None] * nb) @ ob._rot.T + np.asarray(ob.center)
            ok = (field.clearance(p) > 1e-9) & (np.linalg.norm(p - field.target, axis=1) > 2.0)
            got += list(p[ok])
        out += got[:per]
    return np.array(out[:n]) if len(out) >= n else np.array(out)


def turns(path):
    """Largest turn between consecutive legs (deg) and the tightest local radius (m) of a polyline."""
    d = np.diff(path, axis=0)
    length = np.linalg.norm(d, axis=1)
    keep = length > 1e-9
    d, length = d[keep] / length[keep, None], length[keep]
    if len(d) < 2:
        return 0.0, np.inf
    ang = np.arccos(np.clip((d[:-1] * d[1:]).sum(axis=1), -1.0, 1.0))
    radius = 0.5 * (length[:-1] + length[1:]) / np.maximum(ang, 1e-12)
    return float(np.degrees(ang.max())), float(radius.min())


def scenes():
    yield "Fig. 7, document reading (long axis at the goal)", (TURNED,)
    yield "Fig. 8, document reading + 2 spheres", (TURNED,) + SPHERES
    yield "Fig. 7, axis-aligned (goal 45° off the long axis)", (ALIGNED,)
    yield "Fig. 8, axis-aligned + 2 spheres", (ALIGNED,) + SPHERES


def row(name, obstacles, params, n, turn_radius):
    try:
        field = FlowField(obstacles, GOAL, params, MARGIN)
    except ValueError as err:
        return f"| {name} | {params.rankine} | not runnable: {err} |" + " |" * 9, None
    p = near_surface_starts(obstacles, field, n)
    close = np.min([ob.distance(p) for ob in obstacles], axis=0) <= 1.0
    sl = integrate_streamlines(field, p)
    pen = np.array([any(ob.segments_hit(np.stack([q[:-1], q[1:]], 1), MARGIN).any() for ob in obstacles)
                    for q in sl.paths])
    tr = np.array([turns(q) for q in sl.paths])
    kinds = ", ".join(f"{b.kind} {b.volume / _inflated(ob):.2f}×" for b, ob in zip(field.bodies, field.ellipsoids))
    status = ", ".join(f"{k} {c}" for k, c in zip(*np.unique(sl.status, return_counts=True)))
    line = (f"| {name} | {params.rankine} ({kinds}) | {len(p)} ({int(close.sum())} within 1 m) | {status} | "
            f"{int(sl.arrived[close].sum())}/{int(close.sum())} | {int(pen.sum())} | {int(sl.exits.sum())} | "
            f"{int((sl.corrections > 0).sum())} | {tr[:, 0].max():.0f}° (median {np.median(tr[:, 0]):.1f}°) | "
            f"{int((tr[:, 0] >= 90).sum())} | {tr[:, 1].min():.2g} m; {int((tr[:, 1] >= turn_radius).sum())} |")
    return line, tr


def flyable_row(name, obstacles, n, radius):
    """The default plan's path (``FlowParams.path = "flyable"``: a vehicle steering by the flow, turning at most
    1/R per metre) from the same starts: arrived / unflyable, penetrating legs (exact), largest turn between
    steps against the vehicle's turn over one step (step / R)."""
    field = FlowField(obstacles, GOAL, FlowParams(), MARGIN)
    p = near_surface_starts(obstacles, field, n)
    close = np.min([ob.distance(p) for ob in obstacles], axis=0) <= 1.0

    def free(seg):
        return ~np.any([ob.segments_hit(seg, MARGIN) for ob in obstacles], axis=0)

    out = [flyable_path(field.velocity, free, q, GOAL, radius, FlowParams().arrive) for q in p]
    ok = np.array([o.status == "arrived" for o in out])
    pen = sum(any(ob.segments_hit(np.stack([o.path[:-1], o.path[1:]], 1), MARGIN).any() for ob in obstacles)
              for o in out if len(o.path) > 1)
    worst = max(o.max_turn_deg for o in out)
    step = radius / 20.0
    return (f"| {name} | {len(p)} | {int(ok.sum())} ({int(ok[close].sum())}/{int(close.sum())} within 1 m) | "
            f"{int((~ok).sum())} | {pen} | {worst:.2f}° (vehicle: {np.degrees(step / radius):.2f}° over a "
            f"{step:.2f} m step) | {int(ok.sum())} |")


def _inflated(ob):
    return 4.0 / 3.0 * np.pi * np.prod(np.asarray(ob.semi_axes) + MARGIN)


def hull_ratio(ob, e, n=300, bins=120):
    """Volume of the inflated obstacle revolved about the axis e through its centre (the least volume of
    any body of revolution about that axis that contains it) over the inflated obstacle's volume."""
    q = (offset_surface(ob, MARGIN, n) - np.asarray(ob.center)) @ frame(e)
    x, rho = q[:, 0], np.hypot(q[:, 1], q[:, 2])
    edges = np.linspace(x.min(), x.max(), bins + 1)
    k = np.clip(np.digitize(x, edges) - 1, 0, bins - 1)
    top = np.zeros(bins)
    np.maximum.at(top, k, rho)
    return float(np.sum(np.pi * top**2 * np.diff(edges)) / _inflated(ob))


def sweep(params: FlowParams) -> list[str]:
    """The body ``params`` builds round the unturned (8, 4, 3) ellipsoid for goals 35 m away along each of
    the 26 directions (±1, 0)³ \\ 0: its volume over the inflated ellipsoid's, the least body of revolution
    about the goal axis (:func:`hull_ratio`) and the share of the 18 240 offset-surface points it contains."""
    lines = ["| goal direction | body | volume / inflated ellipsoid | least body of revolution "
             "about the goal axis / inflated | contains the inflated surface (18 240 points) | design (s) |",
             "|---|---|---|---|---|---|"]
    dense = offset_surface(ALIGNED, MARGIN, 95)
    for d in itertools.product((-1, 0, 1), repeat=3):
        if not any(d):
            continue
        e = np.asarray(d, dtype=float) / np.linalg.norm(d)
        goal = 35.0 * e
        t0 = time.perf_counter()
        if params.rankine == "line":
            body = design_body(ALIGNED, goal, "line", 1.0, MARGIN, SAG_PAD * 8.0)
        else:
            body = FlowField((ALIGNED,), goal, params, MARGIN).bodies[0]
        dt = time.perf_counter() - t0
        lines.append(f"| {d} | {body.kind} | {body.volume / _inflated(ALIGNED):.3f} | {hull_ratio(ALIGNED, e):.2f} | "
                     f"{100 * body.inside(dense).mean():.2f} % | {dt:.2f} |")
        print(lines[-1], flush=True)
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=510)
    ap.add_argument("--out", default="results/bench-flow-fig78")
    ap.add_argument("--no-sweep", action="store_true", help="skip the 26-direction body sweep")
    ap.add_argument("--document", action="store_true", help="also run the document's sizing (rankine = 'document')")
    ap.add_argument("--figure", action="store_true",
                    help="also write the summary as the documented figure docs/figures/flow-fig78.md")
    args = ap.parse_args(argv)
    t_start = time.perf_counter()
    vehicle = VehicleParams()
    R = vehicle.turning_radius
    load = os.getloadavg()
    head = ["| scene | body sizing | starts | status | arrived, starts ≤ 1 m | penetrating | exits | pushed back | "
            "largest turn between steps | streamlines with a turn ≥ 90° | tightest local radius; streamlines "
            f"within the vehicle's turn (every turn ≤ the vehicle's over that step: radius ≥ {R:.1f} m) |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, obstacles in scenes():
        for params in (FlowParams(),) + ((FlowParams(rankine="document"),) if args.document else ()):
            line, _ = row(name, obstacles, params, args.starts, R)
            head.append(line)
            print(line, flush=True)
    fly = ["| scene | starts | arrived | unflyable (stopped before a leg that would enter a margin) | penetrating | "
           "largest turn between steps | arrived paths within the vehicle's turn "
           "(before the last ≤ 0.5 m leg to the goal) |",
           "|---|---|---|---|---|---|---|"]
    for name, obstacles in scenes():
        fly.append(flyable_row(name, obstacles, args.starts, R))
        print(fly[-1], flush=True)
    text = (f"Document 000 Figs. 7-8 at the goal (28, 28, 0): {args.starts} starts 0.5-5 m from the surfaces "
            f"(`benchmarks/flow_fig78.py --starts {args.starts}`).\n\n"
            f"Seed 0, margin {MARGIN} m, FlowParams defaults (body `rankine = \"{FlowParams().rankine}\"`), "
            f"{os.cpu_count()} cores, load average at start {load[0]:.1f}. The vehicle "
            f"(VehicleParams defaults): {vehicle.speed} m/s, full-rudder turn radius {R:.1f} m "
            f"({np.degrees(vehicle.speed / R):.1f}°/s).\n\nPure streamlines (`FlowParams(path=\"streamline\")`):\n\n"
            + "\n".join(head) + "\n\nThe default plan's path (`path = \"flyable\"`, R = the vehicle's "
            f"{R:.1f} m) from the same starts:\n\n" + "\n".join(fly) + "\n")
    if not args.no_sweep:
        text += (f"\nThe default body (`rankine = \"{FlowParams().rankine}\"`) round the unturned (8, 4, 3) ellipsoid "
                 "for goals 35 m away in 26 directions:\n\n" + "\n".join(sweep(FlowParams())) + "\n")
    text += (f"\nLoad average at end {os.getloadavg()[0]:.1f}; wall time {time.perf_counter() - t_start:.0f} s.\n")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.md").write_text(text)
    if args.figure:
        (Path(__file__).resolve().parents[1] / "docs" / "figures" / "flow-fig78.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
