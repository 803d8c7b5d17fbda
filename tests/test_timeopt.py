"""Time-optimal planning in currents that change with time: exact answers and invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve

from auvplan._types import Status
from auvplan.planners import PlannerSpec, PlanningProblem, plan
from auvplan.planners.params import TimeoptParams
from auvplan.planners.timeopt.kernels import leg_time
from auvplan.planners.timeopt.planner import departure_sweep
from auvplan.planners.timeopt.search import CurrentTable, timed_traverse
from auvplan.world import Bounds, GriddedCurrent, Margins, World

V = 1.0
START = np.array([0.0, 0.0, -50.0])
GOAL = np.array([20000.0, 0.0, -50.0])
TIDE = 44712.0  # M2 period (s)
SPEC = PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=500.0, levels=1))


def uniform_world(cfun, tmax: float = 40000.0, dt: float = 60.0):
    """Open water with a spatially uniform current c(t) tabulated every ``dt`` (linear in between)."""
    t = np.arange(0.0, tmax + dt, dt)
    c = np.array([cfun(s) for s in t], dtype=float)
    u = np.broadcast_to(c[:, 0, None, None, None], (t.size, 1, 2, 2)).copy()
    v = np.broadcast_to(c[:, 1, None, None, None], (t.size, 1, 2, 2)).copy()
    cur = GriddedCurrent([-1e5, 1e5], [-1e5, 1e5], [0.0], u, v, t=t)
    world = World(Bounds(-2000, 22000, -6000, 6000, -100, 0), currents=cur, margins=Margins(0, 0, 100))
    return world, t, c


def min_time(t, c, goal, speed) -> float:
    """The exact answer: the smallest T with |G - ∫0^T c dt| <= V T (c piecewise linear: trapezoids)."""
    drift = np.vstack([np.zeros(2), np.cumsum(0.5 * (c[1:] + c[:-1]) * np.diff(t)[:, None], axis=0)])

    def gap(T):
        return math.hypot(goal[0] - np.interp(T, t, drift[:, 0]), goal[1] - np.interp(T, t, drift[:, 1])) - speed * T

    grid = np.linspace(1.0, t[-1], 4000)
    k = int(np.flatnonzero(np.array([gap(T) for T in grid]) <= 0.0)[0])
    return brentq(gap, grid[k - 1], grid[k], xtol=1e-6)


CASES = {
    "steady": lambda s: (0.3, 0.4),
    "sinusoidal": lambda s: (0.6 * math.sin(2 * math.pi * s / TIDE), 0.5 * math.cos(2 * math.pi * s / TIDE)),
    "reversing": lambda s: (0.9 * math.cos(2 * math.pi * s / TIDE), 0.0),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_uniform_current_minimum_time_within_one_percent(case):
    world, t, c = uniform_world(CASES[case])
    exact = min_time(t, c, GOAL, V)
    r = plan(PlanningProblem(world, START, GOAL, speed=V), SPEC)
    assert r.status is Status.EXACT
    assert r.cost == pytest.approx(r.cost_terms["duration_s"])
    assert r.times is not None and r.times[0] == 0.0 and r.times[-1] == pytest.approx(r.cost)
    assert abs(r.cost - exact) <= 0.01 * exact
    assert r.cost >= exact * (1 - 1e-3)  # no plan beats the exact minimum (up to the table's time step)


def test_steady_uniform_current_gives_the_straight_crab_line():
    world, _, _ = uniform_world(CASES["steady"])
    r = plan(PlanningProblem(world, START, GOAL, speed=V), SPEC)
    d = GOAL - START
    rel = (r.path - START)[:, :2]
    e = d[:2] / np.linalg.norm(d[:2])
    off = np.abs(rel[:, 0] * e[1] - rel[:, 1] * e[0])
    assert off.max() < 1.0
    c = np.array([0.3, 0.4])
    ground = c @ e + math.sqrt(V**2 - (c @ c - (c @ e) ** 2))
    assert r.cost == pytest.approx(np.linalg.norm(d) / ground, rel=1e-6)


def test_zermelo_linear_shear():
    """Current u = s y: the optimal heading obeys tan θ(t) = tan θ0 - s t (Bryson and Ho, §2.7);
    shooting on (θ0, T) with that law gives the exact minimum time."""
    s = 1.0e-4

    def shoot(z):
        th0, T = z

        def f(t, q):
            th = math.atan(math.tan(th0) - s * t)
            return [V * math.cos(th) + s * q[1], V * math.sin(th)]

        return solve_ivp(f, (0.0, T), [0.0, 0.0], rtol=1e-11, atol=1e-6).y[:, -1] - GOAL[:2]

    th0, exact = fsolve(shoot, [0.5, 15000.0], xtol=1e-12)
    assert np.abs(shoot([th0, exact])).max() < 1e-3
    u = np.array([[[-s * 8000.0] * 2, [s * 8000.0] * 2]])  # linear in y: bilinear interpolation is exact
    cur = GriddedCurrent([-5000.0, 25000.0], [-8000.0, 8000.0], [0.0], u, np.zeros_like(u))
    world = World(Bounds(-2000, 22000, -7000, 7000, -100, 0), currents=cur, margins=Margins(0, 0, 100))
    r = plan(PlanningProblem(world, START, GOAL, speed=V), SPEC)
    assert r.status is Status.EXACT
    assert abs(r.cost - exact) <= 0.005 * exact
    assert r.path[:, 1].max() > 2000.0  # it rides the faster current north of the line


def _table(u: float, v: float = 0.0, nt: int = 2) -> CurrentTable:
    cur = np.zeros((nt, 2, 2, 1, 3), dtype=np.float32)
    cur[..., 0], cur[..., 1] = u, v
    return CurrentTable(cur, np.array([0.0, 0.0, 0.0]), np.array([1e5, 1e5, 1.0]), 0.0, 1e5)


def test_current_faster_than_the_vehicle_blocks_legs_without_nan():
    head = _table(-1.5)  # a head current faster than the vehicle
    assert math.isinf(timed_traverse(head, [[0, 0, 0], [1000, 0, 0]], 0.0, V, 100.0).times[-1])
    cross = _table(0.0, 1.2)  # a cross current the vehicle cannot crab against
    assert math.isinf(timed_traverse(cross, [[0, 0, 0], [1000, 0, 0]], 0.0, V, 100.0).times[-1])
    follow = timed_traverse(_table(-1.5), [[1000, 0, 0], [0, 0, 0]], 0.0, V, 100.0)
    assert follow.duration == pytest.approx(1000.0 / 2.5)
    world, _, _ = uniform_world(lambda s: (-1.2, 0.0))
    r = plan(PlanningProblem(world, START, GOAL, speed=V), SPEC)
    assert r.status is Status.INFEASIBLE and "block" in r.message
    assert not np.isnan(r.cost)


def test_legs_are_fifo():
    """Leaving later never arrives earlier (the property the label-setting search relies on)."""
    world, t, c = uniform_world(CASES["reversing"])
    from auvplan.planners.timeopt.planner import setup

    ts = setup(PlanningProblem(world, START, GOAL, speed=V), SPEC, 0.0, 0.0)
    departs = np.arange(0.0, 30000.0, 97.0)
    arrive = np.array([leg_time(*ts.table.args(), 0.0, 0.0, -50.0, 2000.0, 1000.0, -50.0, d, V, 250.0)
                       for d in departs])
    assert np.all(np.isfinite(arrive)) and np.all(np.diff(arrive) > 0.0)


def test_energy_objective_trades_speed_for_power():
    world, _, _ = uniform_world(CASES["steady"])
    problem = PlanningProblem(world, START, GOAL, speed=V, hotel_power=5.0, drag_k=20.0)
    fast = plan(problem, SPEC)
    spec = PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=500.0, levels=1, objective="energy"))
    cheap = plan(problem, spec)
    assert cheap.status is Status.EXACT
    assert cheap.cost_terms["speed_m_s"] < V
    assert cheap.cost_terms["energy_j"] < fast.cost_terms["energy_j"]
    assert cheap.cost_terms["duration_s"] > fast.cost_terms["duration_s"]


def test_departure_sweep_beats_straight_and_steady_plans():
    world, _, _ = uniform_world(CASES["reversing"], tmax=80000.0)
    rows, _ = departure_sweep(PlanningProblem(world, START, GOAL, speed=V), SPEC, np.arange(0.0, 45000.0, 5000.0))
    for r in rows:
        assert r.duration_s <= r.straight_duration_s * (1 + 1e-6)
        assert r.duration_s <= r.steady_duration_s * (1 + 1e-6)
    d = np.array([r.duration_s for r in rows])
    assert d.max() > 1.3 * d.min()  # the tide matters: with it, against it


def test_cli_departure_sweep(tmp_path, capsys):
    import json

    from auvplan.cli import main

    code = main(["plan", "juan-de-fuca-tides", "--depart-between", "+0h", "2026-06-15T06:00:00Z", "--step", "6h",
                 "--out", str(tmp_path), "--json"])
    assert code == 0
    doc = json.loads(capsys.readouterr().out)
    assert [r["depart_s"] for r in doc["rows"]] == [0.0, 21600.0]
    s = doc["summary"]
    assert s["best_duration_s"] <= s["worst_duration_s"] and s["feasible_departures"] == 2
    assert s["best_depart_utc"] in ("2026-06-15T00:00:00Z", "2026-06-15T06:00:00Z")
    for r in doc["rows"]:
        assert r["duration_s"] <= r["steady_duration_s"] * (1 + 1e-6)
        assert {"energy_wh", "margin_wh", "pnr_lat", "pnr_lon", "pnr_t_s"} <= set(r)  # issue 38: per departure
    assert {p.name for p in tmp_path.iterdir()} >= {"sweep.csv", "sweep_summary.json", "sweep.png"}
    assert main(["plan", "juan-de-fuca-tides", "--depart-between", "+0h", "+1h", "--step", "soon"]) == 2
    assert "argument --step: 'soon': not a duration" in capsys.readouterr().err


def test_energy_sweep_picks_least_energy_per_departure():
    world, _, _ = uniform_world(CASES["reversing"], tmax=80000.0)
    problem = PlanningProblem(world, START, GOAL, speed=V, hotel_power=5.0, drag_k=20.0)
    spec = PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=500.0, levels=1, objective="energy"))
    rows, _ = departure_sweep(problem, spec, [0.0, 20000.0])
    for r in rows:
        assert r.energy_j <= min(r.straight_energy_j, r.steady_energy_j) * (1 + 1e-6)
    # against the tide (second departure) a slower, cheaper speed wins over cruise speed
    assert rows[1].energy_j < 0.95 * rows[1].straight_energy_j
