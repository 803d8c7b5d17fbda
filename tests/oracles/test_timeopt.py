"""Time-optimal planning in currents that change with time: exact answers and invariants."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve

from auvplan._types import FloatArray, Status
from auvplan.planners import PlannerSpec, PlanningProblem, plan
from auvplan.planners.core.params import TimeoptParams
from auvplan.planners.timeopt.kernels import leg_reach, leg_time
from auvplan.planners.timeopt.planner import departure_sweep
from auvplan.planners.timeopt.search import CurrentTable, timed_traverse
from auvplan.world import Bounds, GriddedCurrent, Margins, Sphere, World

V = 1.0
START = np.array([0.0, 0.0, -50.0])
GOAL = np.array([20000.0, 0.0, -50.0])
TIDE = 44712.0  # M2 period (s)
SPEC = PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=500.0, levels=1, method="lattice"))


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
    assert r.cost >= exact * (1 - 1e-4)  # never below the exact minimum (durations flown through the World)


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


def _ramp_table(c0: float, c1: float, span: float) -> CurrentTable:
    """A uniform current along +x going linearly from ``c0`` to ``c1`` over ``span`` seconds (then held)."""
    cur = np.zeros((2, 2, 2, 1, 3), dtype=np.float32)
    cur[0, ..., 0], cur[1, ..., 0] = c0, c1
    return CurrentTable(cur, np.array([0.0, 0.0, 0.0]), np.array([1e5, 1e5, 1.0]), 0.0, span)


def test_leg_drifts_back_on_its_line_while_the_current_beats_the_vehicle():
    """A head current easing from 1.5 to -1.5 m/s... i.e. c(t) = -1.5 + 0.003 t along a 1000 m leg at
    V = 1: holding the line, s(t) = -0.5 t + 0.0015 t², so the vehicle drifts back 41.67 m (at
    t = 166.7 s) and arrives at exactly t = 1000 s.  Legs no heading can hold are rejected as inf,
    never nan: a cross current above V, and a steady head current above V (the vehicle drifts back
    past a leg length)."""
    ramp = _ramp_table(-1.5, 1.5, 1000.0)
    tp = timed_traverse(ramp, [[0, 0, 0], [1000, 0, 0]], 0.0, V, 100.0)
    assert tp.duration == pytest.approx(1000.0, abs=2.0)
    assert tp.back is not None and tp.back[0] == pytest.approx(0.5**2 / (4 * 0.0015), rel=0.02)
    arrive, back = leg_reach(*ramp.args(), 0.0, 0.0, 0.0, 1000.0, 0.0, 0.0, 0.0, V, 100.0, math.inf)
    assert arrive == pytest.approx(tp.times[-1], rel=1e-9) and back == pytest.approx(tp.back[0], rel=1e-6)
    head = _table(-1.5)
    assert math.isinf(timed_traverse(head, [[0, 0, 0], [1000, 0, 0]], 0.0, V, 100.0).times[-1])
    cross = _table(0.0, 1.2)  # a cross current the vehicle cannot crab against
    assert math.isinf(timed_traverse(cross, [[0, 0, 0], [1000, 0, 0]], 0.0, V, 100.0).times[-1])
    follow = timed_traverse(_table(-1.5), [[1000, 0, 0], [0, 0, 0]], 0.0, V, 100.0)
    assert follow.duration == pytest.approx(1000.0 / 2.5) and follow.back is not None and follow.back[0] == 0.0
    for tab in (head, cross, ramp):
        assert not np.isnan(timed_traverse(tab, [[0, 0, 0], [700, 300, 0], [1000, 0, 0]], 0.0, V, 100.0).times).any()


def least_time_ode(cfun, goal, speed, depart: float = 0.0, t_max: float = 80000.0) -> tuple[float, FloatArray]:
    """Independent oracle for a spatially uniform current c(t) (the continuous function, not a table).

    The drift D(T) = ∫ c dt is integrated by ``solve_ivp``; in a uniform current the points
    reachable at T form the disc |x - D(T)| <= V T, so the least time is the first root of
    |G - D(T)| - V T (bisection after a scan).  The constant heading towards G - D(T) is then flown
    with ``solve_ivp`` and must land on G.  Returns the least time and that flight's track (2, K)."""
    g = np.asarray(goal, dtype=float)[:2]
    drift = solve_ivp(lambda t, x: cfun(t), (depart, depart + t_max), [0.0, 0.0], dense_output=True, rtol=1e-10,
                      atol=1e-6, max_step=300.0)

    def gap(T):
        return float(np.hypot(*(g - drift.sol(depart + T)))) - speed * T

    grid = np.linspace(1.0, t_max, 2000)
    k = int(np.flatnonzero(np.array([gap(T) for T in grid]) <= 0.0)[0])
    T = brentq(gap, grid[k - 1], grid[k], xtol=1e-6)
    h = (g - drift.sol(depart + T)) / np.hypot(*(g - drift.sol(depart + T)))
    fly = solve_ivp(lambda t, x: np.asarray(cfun(t)) + speed * h, (depart, depart + T), [0.0, 0.0], rtol=1e-10,
                    atol=1e-6, max_step=60.0)
    assert np.hypot(*(fly.y[:, -1] - g)) < 1.0
    return T, fly.y


STRONG = {  # uniform currents stronger than the vehicle (V = 1) for part of the way: departure, table step
    "reversing-head": (lambda s: (-1.2 * math.cos(2 * math.pi * s / TIDE), 0.0), 0.0, 600.0),
    "reversing-cross": (lambda s: (-1.2 * math.sin(2 * math.pi * s / TIDE), 0.3), 7200.0, 600.0),
    "reversing-cross-coarse-table": (lambda s: (-1.2 * math.sin(2 * math.pi * s / TIDE), 0.3), 7200.0, 3600.0),
    "elliptic": (lambda s: (-1.4 * math.cos(2 * math.pi * s / TIDE) + 0.2, 0.6 * math.sin(2 * math.pi * s / TIDE)),
                 0.0, 600.0),
}


@pytest.mark.parametrize("case", sorted(STRONG))
def test_uniform_current_stronger_than_the_vehicle_within_one_percent(case):
    """Against the constant-heading ODE oracle: within 1 %, never below it (the plan's duration is
    flown through the World's current, not the table: with a 1 h table the table's own times are
    0.2 % below the least time), and on the rectilinear cases (the exact track is the straight
    line) the drift back equals the oracle's."""
    cfun, depart, dt = STRONG[case]
    world, _, _ = uniform_world(cfun, tmax=90000.0)
    exact, track = least_time_ode(cfun, GOAL, V, depart)
    spec = PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=500.0, levels=1, depart_s=depart, dt=dt,
                                                             method="lattice"))
    r = plan(PlanningProblem(world, START, GOAL, speed=V), spec)
    assert r.status is Status.EXACT and not np.isnan(r.cost)
    assert exact * (1 - 3e-5) <= r.cost <= 1.01 * exact
    if case != "elliptic":
        assert -track[0].min() > 500.0  # the exact flight drifts back with the current
        assert r.cost_terms["drift_back_m"] == pytest.approx(-track[0].min(), rel=0.02)


def test_the_current_never_pushes_the_vehicle_back_into_an_obstacle():
    """The reversing head current pushes the vehicle 552 m back west of the start on the straight
    line; a sphere 400 m west of the start is in the way.  The plan must leave at an angle so that
    its drift misses the sphere: each leg re-flown here (s' = c·ŝ + √(V² - c⊥²) by ``solve_ivp``,
    independently of the planner) arrives at the plan's times and drifts back clear of the sphere."""
    cfun = STRONG["reversing-head"][0]
    world, _, _ = uniform_world(cfun, tmax=90000.0)
    centre, radius = np.array([-400.0, 0.0, -50.0]), 100.0
    world = replace(world, obstacles=(Sphere(tuple(centre), radius),))
    r = plan(PlanningProblem(world, START, GOAL, speed=V), SPEC)
    exact, _ = least_time_ode(cfun, GOAL, V)
    assert r.status is Status.EXACT and exact <= r.cost <= 1.01 * exact
    assert r.times is not None and r.cost_terms["drift_back_m"] > 300.0
    for a, b, ta, tb in zip(r.path[:-1], r.path[1:], r.times[:-1], r.times[1:]):
        length = float(np.linalg.norm(b - a))
        if length == 0.0:
            continue
        e = (b - a) / length

        def speed(t, s, e=e):
            c = np.array([*cfun(t), 0.0])
            return [c @ e + math.sqrt(V**2 - (c @ c - (c @ e) ** 2))]

        def arrive(t, s, length=length):
            return s[0] - length

        arrive.terminal = True
        leg = solve_ivp(speed, (ta, ta + 40000.0), [0.0], events=arrive, rtol=1e-9, atol=1e-6, max_step=60.0)
        assert leg.t_events[0][0] == pytest.approx(tb, rel=1e-4)
        back = max(-leg.y[0].min(), 0.0)
        d = np.linalg.norm(np.cross(centre - a, e))  # the sphere from the drift's line, and along it
        along = (centre - a) @ e
        assert d > radius or not (-back - radius < along < radius)


def test_steady_current_stronger_than_the_vehicle_analytic():
    """Steady uniform current U > V: the goal is reachable iff it lies in the downstream cone, in the
    least time T = (G·c - √((G·c)² - (U² - V²)|G|²)) / (U² - V²) (the smaller root of
    |G - c T| = V T); upstream of the cone, no heading works: INFEASIBLE, no nan."""
    c = np.array([1.5, 0.6])
    gvec = (GOAL - START)[:2]
    gc, k = gvec @ c, c @ c - V**2
    exact = (gc - math.sqrt(gc**2 - k * (gvec @ gvec))) / k
    world, _, _ = uniform_world(lambda s: tuple(c))
    r = plan(PlanningProblem(world, START, GOAL, speed=V), SPEC)
    assert r.status is Status.EXACT and r.cost == pytest.approx(exact, rel=1e-5)
    world, _, _ = uniform_world(lambda s: (-1.2, 0.0))
    r = plan(PlanningProblem(world, START, GOAL, speed=V), SPEC)
    assert r.status is Status.INFEASIBLE and "no heading" in r.message
    assert not np.isnan(r.cost)


def test_planned_duration_is_the_closed_loop_flight_when_the_current_beats_the_vehicle():
    """3 km in a reversing current of 1.9 m/s (V = 1.5) with a cross set: the vehicle drifts back about
    110 m before the current turns.  The plan's duration is what the closed loop flies (both path
    followers) within 1 %, and its drift back what the flight shows within 5 %."""
    from auvplan.sim import Mission, SimParams, mission_route, run_mission, simulate

    def cfun(s):
        return (-1.9 * math.cos(2 * math.pi * s / 3600.0), 0.3)

    t = np.arange(0.0, 20020.0, 20.0)
    c = np.array([cfun(s) for s in t])
    u = np.broadcast_to(c[:, 0, None, None, None], (t.size, 1, 2, 2)).copy()
    v = np.broadcast_to(c[:, 1, None, None, None], (t.size, 1, 2, 2)).copy()
    world = World(Bounds(-1500, 4500, -1500, 1500, -100, 0), currents=GriddedCurrent([-1e5, 1e5], [-1e5, 1e5], [0.0],
                  u, v, t=t), margins=Margins(0, 0, 100))
    start, goal, speed = (0.0, 0.0, -50.0), (3000.0, 0.0, -50.0), 1.5
    spec = PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=100.0, levels=1, dt=60.0, method="lattice"))
    r = plan(PlanningProblem(world, np.array(start), np.array(goal), speed=speed), spec)
    exact, _ = least_time_ode(cfun, np.subtract(goal, start), speed, t_max=10000.0)
    assert r.status is Status.EXACT and exact * (1 - 1e-4) <= r.cost <= 1.01 * exact
    m = Mission("drift", start, goal, sim=SimParams(deadlock_time=20000.0))
    m = replace(m, vehicle=replace(m.vehicle, speed=speed))
    route = mission_route(world, m, r.path, r.times, speed)
    for guidance in ("los", "hybrid"):
        sim = simulate(world, m, route=route, guidance=guidance, rng=0, avoidance="none")
        assert sim.status is Status.EXACT
        assert sim.t[-1] == pytest.approx(r.cost, rel=0.01)
        assert -sim.position[:, 0].min() == pytest.approx(r.cost_terms["drift_back_m"], rel=0.05)
    # the pipeline plans and flies it with the default deadlock watch (120 s): a plan that drifts back
    # with the tide is not a deadlock
    rec = run_mission(world, replace(m, sim=SimParams(), planner=spec, guidance="los"), rng=0)
    assert rec.sim is not None and rec.sim.status is Status.EXACT
    assert rec.sim.t[-1] == pytest.approx(rec.plan.cost, rel=0.01)


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
    spec = PlannerSpec(name="timeopt",
                       timeopt=TimeoptParams(cell=500.0, levels=1, objective="energy", method="lattice"))
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
    from helpers import coarse_tides

    # the real tides and bathymetry on 2 km cells of one level (what is checked is the command's contract and the
    # per-departure bound, not the lattice: the default 500 m, 4 levels cost 15.6 s of CPU here, these 3.1)
    out = tmp_path / "out"
    code = main(["plan", coarse_tides(tmp_path), "--depart-between", "+0h", "2026-06-15T06:00:00Z", "--step", "6h",
                 "--out", str(out), "--json"])
    assert code == 0
    doc = json.loads(capsys.readouterr().out)
    assert [r["depart_s"] for r in doc["rows"]] == [0.0, 21600.0]
    s = doc["summary"]
    assert s["best_duration_s"] <= s["worst_duration_s"] and s["feasible_departures"] == 2
    assert s["best_depart_utc"] in ("2026-06-15T00:00:00Z", "2026-06-15T06:00:00Z")
    for r in doc["rows"]:
        assert r["duration_s"] <= r["steady_duration_s"] * (1 + 1e-6)
        assert {"energy_wh", "margin_wh", "pnr_lat", "pnr_lon", "pnr_t_s"} <= set(r)  # issue 38: per departure
    assert {p.name for p in out.iterdir()} >= {"sweep.csv", "sweep_summary.json", "sweep.png"}
    assert main(["plan", "juan-de-fuca-tides", "--depart-between", "+0h", "+1h", "--step", "soon"]) == 2
    assert "argument --step: 'soon': not a duration" in capsys.readouterr().err


def test_energy_sweep_picks_least_energy_per_departure():
    world, _, _ = uniform_world(CASES["reversing"], tmax=80000.0)
    problem = PlanningProblem(world, START, GOAL, speed=V, hotel_power=5.0, drag_k=20.0)
    spec = PlannerSpec(name="timeopt",
                       timeopt=TimeoptParams(cell=500.0, levels=1, objective="energy", method="lattice"))
    rows, _ = departure_sweep(problem, spec, [0.0, 20000.0])
    for r in rows:
        assert r.energy_j <= min(r.straight_energy_j, r.steady_energy_j) * (1 + 1e-6)
    # against the tide (second departure) a slower, cheaper speed wins over cruise speed
    assert rows[1].energy_j < 0.95 * rows[1].straight_energy_j
