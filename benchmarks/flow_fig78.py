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
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan._types import Status
from auvplan.guidance.fit_limits import fit_turns
from auvplan.guidance.mission import build_waypoints
from auvplan.io.scenario import loader as sc
from auvplan.planners.flow.body import frame
from auvplan.planners.flow.design import design_body, offset_surface
from auvplan.planners.flow.ellipsoid import design_ellipsoid_body
from auvplan.planners.flow.field import SAG_PAD, FlowField
from auvplan.planners.flow.stream import integrate_streamlines
from auvplan.planners.params import FlowParams
from auvplan.sim import simulate
from auvplan.sim.pipeline import fitted_route
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


def row(name, obstacles, params, n, turn_radius, scene=None, cap=40):
    try:
        field = FlowField(obstacles, GOAL, params, MARGIN)
    except ValueError as err:
        return f"| {name} | {params.rankine} | not runnable: {err} |" + " |" * 10, None
    p = near_surface_starts(obstacles, field, n)
    close = np.min([ob.distance(p) for ob in obstacles], axis=0) <= 1.0
    sl = integrate_streamlines(field, p)
    pen = np.array([any(ob.segments_hit(np.stack([q[:-1], q[1:]], 1), MARGIN).any() for ob in obstacles)
                    for q in sl.paths])
    tr = np.array([turns(q) for q in sl.paths])
    kinds = ", ".join(f"{b.kind} {b.volume / _inflated(ob):.2f}×" for b, ob in zip(field.bodies, field.ellipsoids))
    status = ", ".join(f"{k} {c}" for k, c in zip(*np.unique(sl.status, return_counts=True)))
    flown = "" if scene is None else " " + missions(scene, obstacles, sl, turn_radius, cap) + " |"
    line = (f"| {name} | {params.rankine} ({kinds}) | {len(p)} ({int(close.sum())} within 1 m) | {status} | "
            f"{int(sl.arrived[close].sum())}/{int(close.sum())} | {int(pen.sum())} | {int(sl.exits.sum())} | "
            f"{int((sl.corrections > 0).sum())} | {tr[:, 0].max():.0f}° (median {np.median(tr[:, 0]):.1f}°) | "
            f"{int((tr[:, 0] >= 90).sum())} | {tr[:, 1].min():.2g} m; {int((tr[:, 1] >= turn_radius).sum())} |"
            + flown)
    return line, tr


def missions(scene, obstacles, sl, turn_radius, cap):
    """What leaves auvplan for ``cap`` arrived streamlines evenly spread over the starts (building a mission
    takes seconds on these dense scenes), as the pipeline builds it (:func:`mission_route`'s
    steps: key waypoints, unflyable fly-by corners dropped where the new leg is free, the vehicle's limits
    checked): how many missions fit the vehicle's turn (every fly-by arc of radius >= R, else the plan is
    reported INFEASIBLE, never a corner), their least fly-by radius, and the closed-loop flight of each
    (the scenario's hybrid guidance + predictive avoidance): arrivals, contacts, least distance to a real
    surface."""
    world, mission = scene
    world = replace(world, obstacles=tuple(obstacles))
    ok = arrived = contact = 0
    tight, least = np.inf, np.inf
    picked = np.flatnonzero(sl.arrived)
    picked = picked[np.unique(np.linspace(0, len(picked) - 1, min(cap, len(picked))).astype(int))]
    for i in picked:
        q = sl.paths[i]
        w = fit_turns(build_waypoints(q, world), world, turn_radius)
        fit = fitted_route(world, mission, w)
        if not fit.ok:
            continue
        ok += 1
        tight = min(tight, fit.report.tightest_turn_m)
        run = simulate(world, mission, route=fit.waypoints)
        arrived += int(run.arrived)
        contact += int(run.status is Status.COLLISION)
        least = min(least, float(np.min([ob.distance(run.position) for ob in obstacles])))
    return (f"{ok}/{len(picked)} (least fly-by radius {tight:.1f} m) | {arrived}/{ok} arrive, "
            f"{contact} contacts, least distance {least:.2f} m")


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


def sweep() -> list[str]:
    """The default (``rankine = "ellipsoid"``) body and the line body round the unturned (8, 4, 3) ellipsoid
    for goals 35 m away in the 26 lattice directions: volume over the inflated ellipsoid's and the share of
    18 240 points of the inflated surface it contains."""
    lines = ["| goal direction | default body: kind | volume / inflated ellipsoid | contains the inflated surface | "
             "design (s) | line body: kind | volume / inflated | least body of revolution about the goal axis / "
             "inflated |", "|---|---|---|---|---|---|---|---|"]
    dense = offset_surface(ALIGNED, MARGIN, 95)
    for d in itertools.product((-1, 0, 1), repeat=3):
        if not any(d):
            continue
        e = np.asarray(d, dtype=float) / np.linalg.norm(d)
        goal = 35.0 * e
        t0 = time.perf_counter()
        body = design_ellipsoid_body(ALIGNED, goal, 1.0, MARGIN, SAG_PAD * 8.0)
        dt = time.perf_counter() - t0
        line = design_body(ALIGNED, goal, "line", 1.0, MARGIN, SAG_PAD * 8.0)
        lines.append(f"| {d} | {body.kind} | {body.volume / _inflated(ALIGNED):.3f} | "
                     f"{100 * body.inside(dense).mean():.2f} % | {dt:.2f} | {line.kind} | "
                     f"{line.volume / _inflated(ALIGNED):.2f} | {hull_ratio(ALIGNED, e):.2f} |")
        print(lines[-1], flush=True)
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--starts", type=int, default=510)
    ap.add_argument("--out", default="results/bench-flow-fig78")
    ap.add_argument("--figure", help="also write the summary as this figure file (docs/figures/flow-fig78.md)")
    ap.add_argument("--no-sweep", action="store_true", help="skip the 26-direction body sweep")
    ap.add_argument("--missions", type=int, default=40, help="streamlines per scene made into missions and flown")
    ap.add_argument("--no-flights", action="store_true", help="skip building and flying the missions")
    args = ap.parse_args(argv)
    vehicle = VehicleParams()
    R = vehicle.turning_radius
    load = os.getloadavg()
    t0 = time.perf_counter()
    scene = None if args.no_flights else sc.build(sc.load("flow-fig8"))
    head = ["| scene | body sizing | starts | status | arrived, starts ≤ 1 m | penetrating | exits | pushed back | "
            "largest turn between steps | streamlines with a turn ≥ 90° | tightest radius; streamlines whose "
            f"tightest radius ≥ {R:.1f} m | missions within the {R:.0f} m turn (of {args.missions}) | flown (hybrid + "
            "predictive) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, obstacles in scenes():
        for params in (FlowParams(), FlowParams(rankine="document")):
            line, _ = row(name, obstacles, params, args.starts, R, scene if params == FlowParams() else None,
                          args.missions)
            head.append(line)
            print(line, flush=True)
    text = (f"Document 000 Figs. 7-8 at the goal (28, 28, 0): {args.starts} starts 0.5-5 m from the surfaces per "
            f"scene, seed 0, margin {MARGIN} m, `FlowParams()` defaults (`rankine = \"ellipsoid\"`) and the "
            f"document's sizing. The vehicle (VehicleParams defaults): {vehicle.speed} m/s, full-rudder turn radius "
            f"{R:.1f} m ({np.degrees(vehicle.speed / R):.1f}°/s, {np.degrees(0.5 / R):.1f}° over a 0.5 m step). "
            f"Missions: {args.missions} arrived streamlines per scene, evenly spread over the starts, each made "
            "into the mission the pipeline exports (key waypoints, fly-by "
            "corners that do not fit the turn dropped where the new leg is free, the limits checked: a mission "
            "that does not fit is reported INFEASIBLE) and flown by the closed loop (`flow-fig8`'s settings: "
            "hybrid guidance, predictive avoidance, seed 1).\n\n" + "\n".join(head) + "\n")
    if not args.no_sweep:
        text += ("\nBodies round the unturned (8, 4, 3) ellipsoid (0.5 m margin) for goals 35 m away in the 26 "
                 "lattice directions:\n\n" + "\n".join(sweep()) + "\n")
    text += (f"\nMeasured {time.strftime('%Y-%m-%d')}, load average {load[0]:.2f} at start, "
             f"{os.getloadavg()[0]:.2f} at end on 2 cores, {time.perf_counter() - t0:.0f} s "
             f"(`benchmarks/flow_fig78.py --starts {args.starts}`).\n")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.md").write_text(text)
    if args.figure:
        Path(args.figure).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
