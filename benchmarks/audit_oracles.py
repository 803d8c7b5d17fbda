"""Independent oracles of the time-optimal planner and of the navigation error bound (the audit of 2026-12-07).

    /work/heavy .venv/bin/python benchmarks/audit_oracles.py [--out results/audit-oracles]    (make audit-oracles)

1. **Zermelo in a linear shear** ``u = k y`` (steady, tabulated exactly: the grid's linear interpolation of a
   linear field is the field): the extremals of Zermelo's heading equation are ``θ̇ = −k cos²θ``; the least time
   is the earliest extremal through the goal (headings scanned every ½°, the closest approach's signed miss
   solved by ``brentq``, ``solve_ivp`` at 10⁻¹¹).  The shear makes the current stronger than the vehicle over part
   of the box (``|k y| > V``).  Non-square, non-uniform current axes, a cell that does not divide the box.
2. **The reported time against an independent flight**: every leg of the returned path held as a line (the
   ground speed ``c·e + √(V² − |c|² + (c·e)²)``), its time integrated with classical RK4 in the distance along the
   leg (5–20 m steps) through the World's own current, against the planner's ``cost``.
3. **FIFO**: a shear that reverses with the tide (``u = k y (cos ωt + 0.3)``), a departure every 30 min over a
   tidal period: the arrival ``depart + cost`` never decreases, each flown independently as in 2.
4. **The navigation error bound**: the budget's error model (a fix's circular normal of total variance σ_fix² plus
   the drift ``D`` in one uniform random direction) against ``confidence × σ``: the worst share outside it over
   ``D`` by the Rice survival function and a 2·10⁶-draw Monte Carlo (seed 0), against the circular normal's
   ``exp(−c²)``.

Prints a summary and writes ``audit.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.stats import rice

from auvplan._types import Status
from auvplan.planners import PlannerSpec, PlanningProblem, plan
from auvplan.planners.core.params import TimeoptParams
from auvplan.world import Bounds, GriddedCurrent, Margins, World

V = 1.0
TIDE = 44712.0


def shear_world(k: float, box: tuple[float, float, float, float], xs: np.ndarray, ys: np.ndarray,
                tide: bool = False) -> World:
    """A World whose current is ``u = k y`` (times ``cos ωt + 0.3`` with ``tide``) on the axes given."""
    if tide:
        t = np.arange(0.0, 100000.0 + 300.0, 300.0)
        f = np.cos(2.0 * math.pi * t / TIDE) + 0.3
        u = f[:, None, None, None] * (k * ys)[None, None, :, None] * np.ones((t.size, 1, ys.size, xs.size))
        cur = GriddedCurrent(xs, ys, [0.0], u, np.zeros_like(u), t=t)
    else:
        u = (k * ys)[None, :, None] * np.ones((1, ys.size, xs.size))
        cur = GriddedCurrent(xs, ys, [0.0], u, np.zeros_like(u))
    return World(Bounds(*box, -100, 0), currents=cur, margins=Margins(0, 0, 100))


def zermelo_shear(k: float, start: np.ndarray, goal: tuple[float, float], t_max: float = 60000.0) -> float:
    """The least time in the steady shear ``u = k y`` (module notes, 1.)."""

    def closest(th0: float) -> tuple[float, float, float]:
        def f(_t: float, s: np.ndarray) -> list[float]:
            return [V * math.cos(s[2]) + k * s[1], V * math.sin(s[2]), -k * math.cos(s[2]) ** 2]

        def approach(_t: float, s: np.ndarray) -> float:  # d/dt of half the squared distance to the goal
            return (s[0] - goal[0]) * (V * math.cos(s[2]) + k * s[1]) + (s[1] - goal[1]) * V * math.sin(s[2])

        sol = solve_ivp(f, (0.0, t_max), [start[0], start[1], th0], rtol=1e-11, atol=1e-8, events=approach,
                        dense_output=True)
        best = (math.inf, math.nan, math.inf)
        for te in sol.t_events[0]:
            s = sol.sol(te)
            d = math.hypot(s[0] - goal[0], s[1] - goal[1])
            vx, vy = V * math.cos(s[2]) + k * s[1], V * math.sin(s[2])
            if d < best[0]:
                best = (d, float(te), math.copysign(d, vx * (goal[1] - s[1]) - vy * (goal[0] - s[0])))
        return best

    heads = np.linspace(-math.pi, math.pi, 721)
    miss = [closest(h) for h in heads]
    times = []
    for a, b, ra, rb in zip(heads[:-1], heads[1:], miss[:-1], miss[1:], strict=True):
        if ra[0] < 2000.0 and rb[0] < 2000.0 and ra[2] * rb[2] < 0.0:
            r = closest(brentq(lambda h: closest(h)[2], a, b, xtol=1e-12))
            if r[0] < 1e-2:
                times.append(r[1])
    return min(times)


def flown_time(world: World, path: np.ndarray, depart: float, ds: float = 10.0) -> float:
    """The path flown independently (module notes, 2.): each leg held as a line, RK4 in the distance."""
    t = depart
    for a, b in zip(path[:-1], path[1:], strict=True):
        length = float(np.linalg.norm(b - a))
        if length == 0.0:
            continue
        e = (b - a) / length

        def pace(s: float, tt: float, a: np.ndarray = a, e: np.ndarray = e) -> float:
            c = world.currents.velocity((a + e * s)[None, :], tt)[0]
            along = float(c @ e)
            return 1.0 / (along + math.sqrt(V * V - float(c @ c) + along * along))

        n = max(1, math.ceil(length / ds))
        h = length / n
        for i in range(n):
            s0 = i * h
            k1 = pace(s0, t)
            k2 = pace(s0 + h / 2, t + h / 2 * k1)
            k3 = pace(s0 + h / 2, t + h / 2 * k2)
            k4 = pace(s0 + h, t + h * k3)
            t += h * (k1 + 2 * k2 + 2 * k3 + k4) / 6
    return t - depart


def timeopt(world: World, start: np.ndarray, goal: tuple[float, float], depart: float, cell: float):  # noqa: ANN201
    spec = PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=cell, levels=1, depart_s=depart, dt=300.0))
    return plan(PlanningProblem(world, start, np.array([*goal, -50.0]), speed=V), spec)


def shear_cases() -> list[dict[str, object]]:
    rows: list[dict[str, object]] = []
    rng = np.random.default_rng(0)
    cases = [  # k, goal, box, cells, current axes (non-square; the last non-uniform), start
        (1e-4, (15000.0, 3000.0), (-3000, 20000, -8000, 12000), (1000.0, 500.0), None, (0.0, -2000.0)),
        (1.5e-4, (-12000.0, 4000.0), (-16000, 4000, -6000, 14000), (1000.0, 500.0), None, (0.0, -2000.0)),
        (2e-4, (0.0, 9000.0), (-20000, 20000, -4000, 14000), (1000.0, 500.0), None, (0.0, -2000.0)),
        (1.2e-4, (14321.0, 4567.0), (-3100, 17300, -8300, 12700), (700.0, 1300.0), "random", (137.0, -1933.0)),
    ]
    for k, goal, box, cells, axes, st in cases:
        if axes is None:
            xs = np.linspace(box[0] - 5000, box[1] + 5000, 41)
            ys = np.linspace(box[2] - 5000, box[3] + 5000, 23)
        else:
            xs = np.sort(np.r_[box[0] - 6000, rng.uniform(box[0] - 5000, box[1] + 5000, 17), box[1] + 7000])
            ys = np.sort(np.r_[box[2] - 6000, rng.uniform(box[2] - 5000, box[3] + 5000, 29), box[3] + 7000])
        world = shear_world(k, box, xs, ys)
        start = np.array([*st, -50.0])
        exact = zermelo_shear(k, start[:2], goal)
        for cell in cells:
            t0 = time.process_time()
            r = timeopt(world, start, goal, 0.0, cell)
            cpu = time.process_time() - t0
            flown = flown_time(world, r.path, 0.0, 5.0) if r.status is Status.EXACT else math.nan
            rows.append({"k": k, "goal": goal, "cell": cell, "status": r.status.name, "least_s": exact,
                         "plan_s": r.cost, "plan_vs_least_pct": 100 * (r.cost / exact - 1), "flown_s": flown,
                         "flown_vs_reported_pct": 100 * (flown / r.cost - 1), "max_current": abs(k) * max(
                             abs(box[2]), abs(box[3])), "cpu_s": cpu})
    return rows


def fifo_sweep() -> list[dict[str, float]]:
    box = (-3000, 20000, -8000, 12000)
    world = shear_world(1.5e-4, box, np.linspace(-8000, 25000, 31), np.linspace(-13000, 17000, 43), tide=True)
    start, goal = np.array([0.0, -2000.0, -50.0]), (15000.0, 6000.0)
    rows = []
    for dep in np.arange(0.0, TIDE, 1800.0):
        r = timeopt(world, start, goal, float(dep), 1000.0)
        ok = r.status is Status.EXACT
        flown = flown_time(world, r.path, float(dep), 20.0) if ok else math.nan
        rows.append({"depart_s": float(dep), "status": r.status.name, "plan_s": r.cost,
                     "arrive_s": float(dep) + r.cost if ok else math.nan, "flown_s": flown})
    return rows


def error_bound() -> list[dict[str, float]]:
    rng = np.random.default_rng(0)
    d = np.linspace(0.0, 20.0, 4001)  # D / σ_fix
    s = 1.0 / math.sqrt(2.0)  # per-axis σ of a fix with σ_fix = 1
    rows = []
    for c in (1.0, 1.4, 1.5, 2.0, 3.0):
        p = rice.sf(c * np.hypot(1.0, d) / s, d / s)
        worst_d = float(d[int(np.argmax(p))])
        n = 2_000_000
        e = rng.normal(0.0, s, (n, 2))
        a = rng.uniform(0.0, 2 * math.pi, n)
        e += worst_d * np.column_stack([np.cos(a), np.sin(a)])
        mc = float(np.mean(np.hypot(*e.T) > c * math.hypot(1.0, worst_d)))
        rows.append({"confidence": c, "nominal_outside": math.exp(-c * c), "worst_outside_rice": float(p.max()),
                     "at_d_over_sigma_fix": worst_d, "monte_carlo_outside": mc})
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="results/audit-oracles")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    shear = shear_cases()
    for r in shear:
        print(f"shear k={r['k']:g} goal={r['goal']} cell={r['cell']:g}: {r['status']} {r['plan_s']:.1f} s, least "
              f"{r['least_s']:.1f} s ({r['plan_vs_least_pct']:+.4f} %), flown independently "
              f"{r['flown_vs_reported_pct']:+.5f} % of reported, current up to {r['max_current']:.2f} m/s, "
              f"CPU {r['cpu_s']:.2f} s", flush=True)
    fifo = fifo_sweep()
    arrive = np.array([r["arrive_s"] for r in fifo])
    gap = np.array([abs(r["flown_s"] / r["plan_s"] - 1) for r in fifo])
    print(f"FIFO: {sum(r['status'] == 'EXACT' for r in fifo)}/{len(fifo)} planned, arrivals non-decreasing: "
          f"{bool(np.all(np.diff(arrive) >= -1e-6))} (least step {np.diff(arrive).min():.1f} s), flown vs reported "
          f"within {100 * gap.max():.5f} %", flush=True)
    bound = error_bound()
    for r in bound:
        print(f"nav bound c={r['confidence']:g}: outside c·σ at worst {r['worst_outside_rice']:.3e} (Rice; MC "
              f"{r['monte_carlo_outside']:.3e}) at D/σ_fix = {r['at_d_over_sigma_fix']:.2f}, circular normal "
              f"{r['nominal_outside']:.3e}", flush=True)
    (out / "audit.json").write_text(json.dumps({"shear": shear, "fifo": fifo, "bound": bound}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
