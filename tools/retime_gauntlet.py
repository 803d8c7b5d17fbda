"""Re-time ``avoidance-gauntlet``'s moving obstacles to meet today's default global plan (issue #36 point 4).

The built-in's twelve tracks were timed for an older global path (the pinned curved one of
``tests/data/dynamic_terrain_apf_pin.json``); today's plan (scenario seed 1) is a near-straight line
that they no longer come within 34 m of.  Each obstacle keeps its kind, size, speed and heading: its
meeting with the vehicle on the old path (the time t₀ of its closest approach to a vehicle flying that
path at cruise speed, at the fraction f of its length) is moved to the same fraction of today's plan
at the time t₁ the vehicle gets there, M'(t) = M(t + t₀ − t₁) + Δ with Δ = P_new(f) − M(t₀) (the
random walk, whose draws start at t = 0, is translated only: M'(t) = M(t) + P_new(f) − M(t₁)).

    git show e2fce85:src/auvplan/data/scenarios/avoidance-gauntlet.toml > /tmp/gauntlet-before-36.toml
    .venv/bin/python tools/retime_gauntlet.py --scenario /tmp/gauntlet-before-36.toml

(run on the file as it was before issue #36; on the re-timed file it only prints each track's closest
approach to today's plan, ``--check``.)

It prints, per obstacle, the old and new closest approach (surface distance to the nominal vehicle),
then the TOML values pasted into ``src/auvplan/data/scenarios/avoidance-gauntlet.toml``.
"""

from __future__ import annotations

import argparse
import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.sim import mission_route, planning_problem
from auvplan.world import CircleMotion, LinearMotion, RandomWalkMotion, WaypointMotion

PIN = Path(__file__).resolve().parents[1] / "tests" / "data" / "dynamic_terrain_apf_pin.json"


def nominal(route: np.ndarray, speed: float, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The vehicle on ``route`` at cruise ``speed`` at times ``t``: positions, fractions, length."""
    cum = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(route, axis=0), axis=1))]
    s = np.clip(speed * t, 0.0, cum[-1])
    pos = np.stack([np.interp(s, cum, route[:, k]) for k in range(3)], axis=1)
    return pos, s / cum[-1], float(cum[-1])


def at_fraction(route: np.ndarray, f: float) -> tuple[np.ndarray, float]:
    """Point of ``route`` at fraction ``f`` of its length and the length flown to it."""
    cum = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(route, axis=0), axis=1))]
    s = f * cum[-1]
    return np.array([np.interp(s, cum, route[:, k]) for k in range(3)]), float(s)


def retime(motion, tau: float, delta: np.ndarray, t1: float, target: np.ndarray):
    """``motion`` shifted by ``tau`` s in time and ``delta`` in space (see the module notes)."""
    if isinstance(motion, LinearMotion):
        return replace(motion, start=tuple(np.asarray(motion.start) + np.asarray(motion.velocity) * tau + delta))
    if isinstance(motion, CircleMotion):
        return replace(motion, center=tuple(np.asarray(motion.center) + delta),
                       phase=(motion.phase + 2 * math.pi * tau / motion.period) % (2 * math.pi))
    if isinstance(motion, WaypointMotion):
        pts = np.asarray(motion.points)
        x = np.asarray(motion.position(tau))
        seg = np.diff(np.vstack([pts, pts[:1]]), axis=0)
        cum = np.r_[0.0, np.cumsum(np.linalg.norm(seg, axis=1))]
        d = (motion.speed * tau) % cum[-1]
        k = int(np.searchsorted(cum, d, side="right")) - 1
        order = [pts[(k + 1 + j) % len(pts)] for j in range(len(pts))]
        return replace(motion, points=np.vstack([x] + order) + delta)
    if isinstance(motion, RandomWalkMotion):
        return replace(motion, start=tuple(np.asarray(motion.start) + target - np.asarray(motion.position(t1))))
    raise TypeError(type(motion).__name__)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="avoidance-gauntlet", help="built-in name or TOML file")
    ap.add_argument("--check", action="store_true", help="only print the closest approaches to today's plan")
    args = ap.parse_args(argv)
    world, mission = sc.build(sc.load(args.scenario))
    speed = mission.vehicle.speed
    old_route = np.array(json.loads(PIN.read_text())["route"])
    new_route = mission_route(world, mission, plan(planning_problem(world, mission), mission.planner,
                                                   rng=mission.seed).path)
    t = np.arange(0.0, 6000.0, 0.5)
    v_old, f_old, _ = nominal(old_route, speed, t)
    v_new, _, _ = nominal(new_route, speed, t)
    for o in world.moving:
        r = o.shape.bounding_radius
        c = np.asarray(o.motion.position(t))
        if args.check:
            d = np.linalg.norm(c - v_new, axis=1) - r
            print(f"{o.name:16s} closest approach to a vehicle on today's plan: {d.min():7.1f} m from its surface "
                  f"(centre {d.min() + r:.2f} m) at t = {t[np.argmin(d)]:.0f} s")
            continue
        d_old = np.linalg.norm(c - v_old, axis=1) - r
        k = int(np.argmin(d_old))
        f = float(f_old[k])
        target, s1 = at_fraction(new_route, f)
        t0, t1 = float(t[k]), s1 / speed
        delta = target - np.asarray(o.motion.position(t0))
        m2 = retime(o.motion, t0 - t1, delta, t1, target)
        before = float((np.linalg.norm(c - v_new, axis=1) - r).min())
        after = np.linalg.norm(np.asarray(m2.position(t)) - v_new, axis=1) - r
        print(f"{o.name:16s} {type(o.motion).__name__:16s} old path: {d_old[k]:7.1f} m at t = {t0:6.0f} s "
              f"(f = {f:.2f}); today's plan: {before:7.1f} m -> {after.min():7.1f} m "
              f"at t = {t[np.argmin(after)]:6.0f} s")
        if isinstance(m2, LinearMotion):
            print(f"    start = [{', '.join(f'{x:.1f}' for x in m2.start)}]")
        elif isinstance(m2, CircleMotion):
            print(f"    center = [{', '.join(f'{x:.1f}' for x in m2.center)}]\n    phase = {m2.phase:.4f}")
        elif isinstance(m2, WaypointMotion):
            print("    points = [" + ", ".join("[" + ", ".join(f"{x:.1f}" for x in p) + "]" for p in m2.points) + "]")
        else:
            print(f"    start = [{', '.join(f'{x:.1f}' for x in m2.start)}]")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
