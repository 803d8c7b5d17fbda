"""The front method of the time-optimal planner against exact least times and ``hj_reachability`` (issue 55).

    /work/heavy .venv/bin/python benchmarks/timeopt_front.py [--out results/front]    (make bench-timeopt-front)

1. The uniform cases of ``tests/oracles/test_timeopt_front.py`` (steady current stronger than the vehicle,
   reversing, rotary 1.3 m/s with the goal behind the flood, cross-tide) at 1000 m and 500 m cells:
   the plan's duration (flown through the World's current) against the exact least time (the
   oracle of the test), CPU per plan.
2. ``rotary-tide``, every departure every ``--step`` minutes over ``--hours``: the plan (the
   scenario's settings, ``method = "front"``) against Zermelo's least time (drift by ``solve_ivp``).
3. The rotary case of 1. on its 500 m and 250 m grids (57 × 53 and 113 × 105 nodes) solved in the same run by the front
   alone and by ``hj_reachability`` (Hamilton–Jacobi level set, WENO5 + TVD-RK3, JAX on the CPU;
   forward reachability as the backward reachable set of the time-reversed dynamics
   ``ẏ = −c(t₀ − σ) − V u``, starting from the front method's own first front, the exact disc one
   τ = 2 h / V after departure): arrival time at the goal against
   the exact one, and CPU (``time.process_time``; jax's compilation counted apart).  ``hj_reachability``
   is optional (``pip install hj_reachability jax``); without it that part is skipped.

Writes ``front.json`` and prints a summary.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "oracles"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from test_timeopt_front import CASES, START, V, least_time, spec, world_of  # noqa: E402
from timeopt_labels import least_time as zermelo_bound  # noqa: E402

from auvplan.io.scenario import loader as scenario  # noqa: E402
from auvplan.planners import PlanningProblem, plan  # noqa: E402
from auvplan.planners.timeopt.front import build_grid, propagate  # noqa: E402
from auvplan.sim import planning_problem  # noqa: E402


def uniform_cases() -> list[dict]:
    rows = []
    for name, (cfun, goal, depart, box) in CASES.items():
        world, t, c = world_of(cfun, box)
        exact = least_time(t, c, goal, depart)
        for cell in (1000.0, 500.0):
            clock = time.process_time()
            r = plan(PlanningProblem(world, START, np.array([*goal, -50.0]), speed=V), spec(depart, cell))
            rows.append({"case": name, "cell": cell, "exact_s": exact, "plan_s": r.cost, "status": r.status.name,
                         "gap_pct": 100.0 * (r.cost / exact - 1.0), "cpu_s": time.process_time() - clock})
            print(f"{name:22s} {cell:6.0f} m  exact {exact:9.1f}  plan {r.cost:9.1f}  {rows[-1]['gap_pct']:+.4f} %  "
                  f"cpu {rows[-1]['cpu_s']:.2f} s", flush=True)
    return rows


def rotary_tide(hours: float, step: float) -> list[dict]:
    world, mission = scenario.build(scenario.load("rotary-tide"))
    problem = planning_problem(world, mission)
    rows = []
    for d in np.arange(0.0, hours * 3600.0 + 1.0, step * 60.0):
        bound = zermelo_bound(world, problem.start, problem.goal, problem.speed, float(d))
        clock = time.process_time()
        r = plan(problem, replace(mission.planner, timeopt=replace(mission.planner.timeopt, depart_s=float(d))))
        rows.append({"depart_h": d / 3600.0, "bound_s": bound, "plan_s": r.cost, "status": r.status.name,
                     "gap_pct": 100.0 * (r.cost / bound - 1.0), "cpu_s": time.process_time() - clock})
        print(f"rotary-tide +{d / 3600:5.1f} h  bound {bound:8.1f}  plan {r.cost:8.1f}  {rows[-1]['gap_pct']:+.4f} %  "
              f"cpu {rows[-1]['cpu_s']:.2f} s", flush=True)
    return rows


def against_hj(h: float = 500.0) -> dict:
    cfun, goal, depart, box = CASES["rotary-behind-flood"]
    world, t, c = world_of(cfun, box)
    exact = least_time(t, c, goal, depart)
    horizon = 1.3 * exact
    grid = build_grid(world, [box[0], box[2]], [box[1], box[3]], h, (-50.0, -50.0), depart, depart + horizon, 300.0)
    propagate(grid, START, goal, depart, V)  # compiled kernels
    clock = time.process_time()
    front = propagate(grid, START, goal, depart, V)
    out = {"exact_s": exact, "nodes": list(grid.g.shape[1:]), "front_s": front.arrival - depart,
           "front_cpu_s": time.process_time() - clock}
    try:
        import hj_reachability as hj
        import jax.numpy as jnp
    except ImportError:
        out["hj"] = "not installed"
        return out

    class Reversed(hj.ControlAndDisturbanceAffineDynamics):  # ẏ = −c(t0 − σ) − V u, |u| ≤ 1
        def __init__(self) -> None:
            super().__init__("min", "max", hj.sets.Ball(jnp.zeros(2), 1.0), hj.sets.Ball(jnp.zeros(1), 0.0))

        def open_loop_dynamics(self, state, time):
            w = 2.0 * math.pi / 44712.0
            s = depart + tau - time
            return -jnp.array([1.3 * jnp.cos(w * s), -1.3 * jnp.sin(w * s)])

        def control_jacobian(self, state, time):
            return -V * jnp.eye(2)

        def disturbance_jacobian(self, state, time):
            return jnp.zeros((2, 1))

    n = grid.g.shape[1:]
    hgrid = hj.Grid.from_lattice_parameters_and_boundary_conditions(
        hj.sets.Box(jnp.array([box[0], box[2]]), jnp.array([box[0] + h * (n[0] - 1), box[2] + h * (n[1] - 1)])), n)
    x = hgrid.states  # the same first front as the front method's: the exact disc one τ after departure
    tau = 2.0 * h / V
    w = 2.0 * math.pi / 44712.0
    drift = 1.3 / w * np.array([math.sin(w * (depart + tau)) - math.sin(w * depart),
                                math.cos(w * (depart + tau)) - math.cos(w * depart)])
    v0 = jnp.linalg.norm(x - jnp.array(START[:2] + drift), axis=-1) - V * tau
    times = -jnp.arange(0.0, horizon - tau, 120.0)
    settings = hj.SolverSettings.with_accuracy("very_high")
    clock = time.process_time()
    vals = hj.solve(settings, Reversed(), hgrid, times, v0, progress_bar=False)
    first = time.process_time() - clock
    clock = time.process_time()
    vals = np.asarray(hj.solve(settings, Reversed(), hgrid, times, v0, progress_bar=False))
    cpu = time.process_time() - clock
    at = np.array([float(hgrid.interpolate(jnp.asarray(v), jnp.array(goal))) for v in vals])
    k = int(np.flatnonzero(at <= 0.0)[0]) if (at <= 0.0).any() else -1
    frac = at[k - 1] / (at[k - 1] - at[k]) if k >= 1 else math.nan
    arr = math.inf if k < 1 else tau + float(-times[k - 1] + (times[k - 1] - times[k]) * frac)
    out.update({"hj_s": arr, "hj_cpu_s": cpu, "hj_first_call_cpu_s": first})
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hours", type=float, default=24.0)
    ap.add_argument("--step", type=float, default=60.0, help="minutes")
    ap.add_argument("--out", default="results/front")
    a = ap.parse_args()
    res = {"uniform": uniform_cases(), "rotary_tide": rotary_tide(a.hours, a.step),
           "hj": [against_hj(h) for h in (500.0, 250.0)], "load": os.getloadavg()}
    for hjr in res["hj"]:
        print(json.dumps(hjr))
    rot = res["rotary_tide"]
    print(f"rotary-tide: {sum(r['status'] == 'EXACT' for r in rot)}/{len(rot)} planned, gap "
          f"{min(r['gap_pct'] for r in rot):+.4f} … {max(r['gap_pct'] for r in rot):+.4f} %, "
          f"CPU mean {np.mean([r['cpu_s'] for r in rot]):.2f} s; load {res['load']}")
    Path(a.out).mkdir(parents=True, exist_ok=True)
    (Path(a.out) / "front.json").write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
