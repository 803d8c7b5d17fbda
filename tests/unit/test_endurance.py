"""Endurance in currents (issue 38): the energy model, the per-leg budget, the point of no return and
the speed per leg, each against an answer worked out by hand; the `run --out` contract."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from auvplan import cli
from auvplan._types import Status
from auvplan.endurance import (
    EnergyModel,
    choose_speeds,
    fit_power,
    flown_energy,
    mission_budget,
    optimal_speed,
    point_of_no_return,
    traverse,
)
from auvplan.errors import ScenarioError
from auvplan.io.scenario import loader as sc
from auvplan.vehicles import VehicleParams
from auvplan.world import Bounds, UniformCurrent, World

H, K = 15.0, 5.82  # W, W s³/m³
V = 1.5
P = H + K * V**3  # power at 1.5 m/s


def open_water(current=(0.0, 0.0, 0.0)) -> World:
    return World(Bounds(-1e5, 1e5, -1e5, 1e5, -500.0, 0.0), currents=UniformCurrent(current))


def model(battery_wh: float = 1000.0, usable: float = 0.9, reserve: float = 0.2) -> EnergyModel:
    return EnergyModel(H, K, battery_wh, usable, reserve, 0.5, 2.5)


LEG = np.array([[0.0, 0.0, -20.0], [3000.0, 0.0, -20.0]])


# ------------------------------------------------------------------ 1. energy model
def test_fit_recovers_known_coefficients_exactly_and_under_seeded_noise():
    v = np.array([0.6, 0.9, 1.2, 1.5, 1.8, 2.1, 2.4])
    fit = fit_power(v, 12.5 + 7.25 * v**3)
    assert fit.hotel_w == pytest.approx(12.5, abs=1e-9) and fit.k == pytest.approx(7.25, rel=1e-12)
    assert fit.rms_w < 1e-9
    noisy = 12.5 + 7.25 * v**3 + np.random.default_rng(3).normal(0.0, 0.2, v.size)
    fit = fit_power(v, noisy)
    assert fit.hotel_w == pytest.approx(12.5, abs=0.5) and fit.k == pytest.approx(7.25, rel=0.03)
    held = fit_power(v, 20.0 + 3.0 * v**3, hotel_w=20.0)  # hotel held: only k fitted
    assert held.hotel_w == 20.0 and held.k == pytest.approx(3.0, rel=1e-12)
    with pytest.raises(ValueError, match="k > 0"):
        fit_power(v, 40.0 - v**3)


def test_vehicle_power_table_sets_the_model_every_planner_uses():
    v = (0.5, 1.0, 1.5, 2.0)
    vp = VehicleParams(power_table=tuple((s, 9.0 + 4.0 * s**3) for s in v))
    assert vp.hotel_power == pytest.approx(9.0) and vp.drag_k == pytest.approx(4.0)
    assert VehicleParams(hotel_w=22.0).hotel_power == 22.0
    m = EnergyModel.from_vehicle(VehicleParams())
    # REMUS-class defaults: k = ½ ρ C_D A / η = 0.5 · 1025 · 0.2 · 0.0284 / 0.5
    assert m.k == pytest.approx(0.5 * 1025 * 0.2 * 0.0284 / 0.5) and m.budget_wh == pytest.approx(700.0)


@pytest.mark.parametrize("table, needle", [
    ("reserve = 0.95", "reserve"),
    ("battery_wh = -1.0", "battery_wh"),
    ("power_table = [[1.0, 10.0]]", "pairs"),
])
def test_bad_battery_keys_are_scenario_errors(table, needle):
    text = f"[mission]\nstart = [0.0, 0.0, -10.0]\ngoal = [500.0, 0.0, -10.0]\n[vehicle]\n{table}\n"
    with pytest.raises(ScenarioError, match=needle):
        sc.loads(text, "s.toml")


# ------------------------------------------------------------------ 2. budget
@pytest.mark.parametrize("u, ground", [(0.5, 2.0), (-0.5, 1.0), (0.0, 1.5)])
def test_uniform_current_along_and_against_a_straight_leg(u, ground):
    b = mission_budget(open_water((u, 0.0, 0.0)), LEG, model(), V, ds=70.0)
    t = 3000.0 / ground  # by hand: 1500 s with, 3000 s against, 2000 s in still water
    assert b.t_end[0] == pytest.approx(t, rel=1e-12)
    assert b.energy_wh == pytest.approx(P * t / 3600.0, rel=1e-12)
    assert b.speed_ground[0] == pytest.approx(ground, rel=1e-12)
    assert b.remaining_wh[0] == pytest.approx(900.0 - P * t / 3600.0, rel=1e-12)


def test_cross_current_makes_the_vehicle_crab():
    b = mission_budget(open_water((0.0, 0.9, 0.0)), LEG, model(), V)
    assert b.t_end[0] == pytest.approx(3000.0 / math.sqrt(V**2 - 0.9**2), rel=1e-12)  # 1.2 m/s over ground
    blocked = mission_budget(open_water((0.0, 1.6, 0.0)), LEG, model(), V)
    assert blocked.status is Status.INFEASIBLE and "beats the vehicle" in blocked.message


def test_a_battery_that_just_suffices_and_one_that_just_fails():
    need = P * 2000.0 / 3600.0  # still water, 3 km at 1.5 m/s
    enough = need / (0.9 - 0.2)
    ok = mission_budget(open_water(), LEG, model(enough), V)
    assert ok.status is Status.EXACT and abs(ok.margin_wh) < 1e-9
    short = mission_budget(open_water(), LEG, model(enough * (1 - 1e-6)), V)
    assert short.status is Status.RESERVE_BROKEN and "RESERVE BROKEN" in short.message
    assert short.margin_wh == pytest.approx(-(enough * 1e-6) * 0.7, rel=1e-6)


def test_time_varying_current_integrates_to_the_closed_form():
    class Ramp(UniformCurrent):  # u(t) = a t along the leg: x(t) = V t + a t²/2
        def velocity(self, points, t=0.0):
            p = np.asarray(points, dtype=float)
            return np.broadcast_to(np.array([2e-4 * t, 0.0, 0.0]), p.shape).copy()

    world = World(Bounds(-1e5, 1e5, -1e5, 1e5, -500.0, 0.0), currents=Ramp())
    t = traverse(world, LEG, V, 0.0, ds=20.0).duration
    exact = (-V + math.sqrt(V**2 + 2 * 2e-4 * 3000.0)) / 2e-4
    assert t == pytest.approx(exact, rel=1e-6)


def test_flown_energy_of_a_recorded_track_in_a_uniform_current():
    # a track at 1.5 m/s through the water with a 0.4 m/s following current: 1.9 m/s over ground
    ts = np.arange(0.0, 1000.0 + 1e-9, 0.1)
    pos = np.column_stack([1.9 * ts, np.zeros_like(ts), np.full_like(ts, -20.0)])
    fe = flown_energy(open_water((0.4, 0.0, 0.0)), ts, pos, model())
    assert fe.energy_wh == pytest.approx(P * 1000.0 / 3600.0, rel=1e-9)


# ------------------------------------------------------------------ 3. point of no return
@pytest.mark.parametrize("u", [0.3, -0.3, 0.0])
def test_point_of_no_return_on_a_straight_leg_in_a_uniform_current(u):
    long_leg = np.array([[0.0, 0.0, -20.0], [40000.0, 0.0, -20.0]])
    m = model(battery_wh=200.0)  # budget 140 Wh: not enough to go 40 km and come back
    world = open_water((u, 0.0, 0.0))
    b = mission_budget(world, long_leg, m, V)
    pnr = point_of_no_return(world, b.traverse, m, tol=0.01)
    budget_j = m.budget_wh * 3600.0
    s_star = budget_j * (V**2 - u**2) / (2.0 * P * V)  # P s (1/(V+u) + 1/(V-u)) = budget
    assert not pnr.whole_mission and pnr.status is Status.EXACT
    assert pnr.s_m == pytest.approx(s_star, abs=0.02)
    assert pnr.t_s == pytest.approx(s_star / (V + u), abs=0.02)
    assert pnr.energy_out_wh + pnr.energy_back_wh == pytest.approx(m.budget_wh, abs=1e-3)


def test_pnr_flies_the_return_in_the_currents_of_the_turn_back_time():
    class Slack(UniformCurrent):  # 0.5 m/s along the leg until t = 1000 s, slack water after
        def velocity(self, points, t=0.0):
            p = np.asarray(points, dtype=float)
            return np.broadcast_to(np.array([0.5 if t < 1000.0 else 0.0, 0.0, 0.0]), p.shape).copy()

    world = World(Bounds(-1e5, 1e5, -1e5, 1e5, -500.0, 0.0), currents=Slack())
    leg = np.array([[0.0, 0.0, -20.0], [20000.0, 0.0, -20.0]])
    m = model(battery_wh=P * 5000.0 / 3600.0 / 0.7)  # budget: 5000 s of flight
    b = mission_budget(world, leg, m, V, ds=10.0)
    pnr = point_of_no_return(world, b.traverse, m, tol=0.01, ds=10.0)
    # out: 2000 m by t = 1000 s, then 1.5 m/s; back in slack water: 1000 + (s − 2000)/1.5 + s/1.5 = 5000
    assert pnr.s_m == pytest.approx((1.5 * 4000.0 + 2000.0) / 2.0, abs=2.0)
    assert pnr.t_s == pytest.approx(1000.0 + 2000.0 / 1.5, abs=2.0)


def test_return_route_retraces_the_route_round_an_obstacle():
    from auvplan.endurance import return_route
    from auvplan.world import Margins, Sphere

    world = World(Bounds(-2000, 3000, -2000, 3000, -100.0, 0.0), obstacles=(Sphere((500.0, 500.0, -20.0), 200.0),),
                  margins=Margins(0.0, 0.0, 100.0))
    pts = np.array([[0.0, 0.0, -20.0], [1000.0, 0.0, -20.0], [1000.0, 1000.0, -20.0], [0.0, 1200.0, -20.0]])
    here = np.array([1000.0, 900.0, -20.0])  # the line home passes 50 m from the sphere's centre
    back = return_route(world, pts, here, 1, pts[0])
    assert back == pytest.approx(np.array([here, pts[1], pts[0]]))
    near = np.array([1000.0, 100.0, -20.0])  # from here the straight line home is clear
    assert return_route(world, pts, near, 1, pts[0]) == pytest.approx(np.array([near, pts[0]]))
    far = np.array([800.0, 1040.0, -20.0])  # leg 2: retrace to the first waypoint that sees home (B)
    assert return_route(world, pts, far, 2, pts[0]) == pytest.approx(np.array([far, pts[2], pts[1], pts[0]]))


def test_rally_point_and_whole_mission():
    world = open_water()
    b = mission_budget(world, LEG, model(), V)
    home = point_of_no_return(world, b.traverse, model())
    assert home.whole_mission and home.s_m == pytest.approx(3000.0)
    # a rally point 1 km behind home: turning back at s costs s + (s + 1000) metres of flight
    rally = np.array([-1000.0, 0.0, -20.0])
    m = model(battery_wh=P * (5000.0 / V) / 3600.0 / 0.7)  # budget = 5000 m of flight → s* = 2000 m
    b = mission_budget(world, LEG, m, V)
    pnr = point_of_no_return(world, b.traverse, m, recovery=rally, tol=0.01)
    assert not pnr.whole_mission and pnr.s_m == pytest.approx(2000.0, abs=0.02)
    assert pnr.recovery == (-1000.0, 0.0, -20.0)
    short = model(battery_wh=P * (500.0 / V) / 3600.0 / 0.7)  # 500 m of flight: the rally is 1000 m away
    none = point_of_no_return(world, mission_budget(world, LEG, short, V).traverse, short, recovery=rally)
    assert none.status is Status.INFEASIBLE and "even from the start" in none.message


# ------------------------------------------------------------------ 4. speed per leg
def test_still_water_speed_choice_is_the_analytic_optimum():
    v_star = optimal_speed(H, K)
    assert v_star == pytest.approx((H / (2 * K)) ** (1 / 3), rel=1e-15)
    numeric = minimize_scalar(lambda v: (H + K * v**3) / v, bounds=(0.1, 3.0), method="bounded",
                              options={"xatol": 1e-10}).x
    assert v_star == pytest.approx(numeric, abs=1e-6)
    route = np.array([[0.0, 0.0, -20.0], [2000.0, 0.0, -20.0], [2000.0, 1500.0, -30.0]])
    plan = choose_speeds(open_water(), route, model(), V, "energy")
    assert plan.speeds == pytest.approx([v_star, v_star], abs=1e-5)


def test_deadline_and_battery_are_met_with_equal_speeds_in_still_water():
    # still water: the Lagrangian gives one speed for every leg; a deadline of 2500 s over 3.5 km → 1.4 m/s
    route = np.array([[0.0, 0.0, -20.0], [2000.0, 0.0, -20.0], [2000.0, 1500.0, -20.0]])
    plan = choose_speeds(open_water(), route, model(), V, "energy", deadline_s=2500.0)
    assert plan.speeds == pytest.approx([1.4, 1.4], abs=1e-3) and plan.duration_s <= 2500.0 + 1e-6
    m = model(battery_wh=(H + K * 2.0**3) * 3500.0 / 2.0 / 3600.0 / 0.7)  # battery for 2 m/s exactly
    fast = choose_speeds(open_water(), route, m, V, "time")
    assert fast.speeds == pytest.approx([2.0, 2.0], abs=1e-4) and fast.energy_wh <= m.budget_wh + 1e-9


def test_following_current_leg_is_flown_slower_for_least_energy():
    # energy per metre (H + K v³) / (v + u) with u = +0.5 along leg 0, −0.5 against leg 1
    route = np.array([[0.0, 0.0, -20.0], [2000.0, 0.0, -20.0], [0.0, 0.0, -20.0]])
    plan = choose_speeds(open_water((0.5, 0.0, 0.0)), route, model(), V, "energy")
    for v, u in zip(plan.speeds, (0.5, -0.5)):
        best = minimize_scalar(lambda s, u=u: (H + K * s**3) / (s + u), bounds=(0.51, 2.5), method="bounded",
                               options={"xatol": 1e-10}).x
        assert v == pytest.approx(best, abs=1e-4)
    assert plan.speeds[0] < plan.speeds[1]


# ------------------------------------------------------------------ contract: run --out
SCENARIO = """
name = "endurance-line"
seed = 1
[bounds]
x = [0.0, 3000.0]
y = [0.0, 1000.0]
z = [-100.0, 0.0]
[currents]
uniform = [0.3, 0.0, 0.0]
[mission]
start = [100.0, 500.0, -20.0]
goal = [2100.0, 500.0, -20.0]
route = [[100.0, 500.0, -20.0], [1100.0, 500.0, -20.0], [2100.0, 500.0, -20.0]]
[vehicle]
speed = 1.5
battery_wh = {battery}
[sim]
dt = 0.2
"""


P_RUN = VehicleParams().hotel_power + VehicleParams().drag_k * V**3  # the scenario's default vehicle


def _run(tmp_path, capsys, battery):
    path = tmp_path / "line.toml"
    path.write_text(SCENARIO.format(battery=battery))
    out = tmp_path / f"out{battery}"
    code = cli.main(["run", str(path), "--out", str(out)])
    return code, out, capsys.readouterr().out


def test_run_writes_legs_csv_and_the_energy_metrics(tmp_path, capsys):
    code, out, text = _run(tmp_path, capsys, 1000.0)
    assert code == 0 and "point of no return" in text
    with (out / "legs.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0])[:4] == ["leg", "t_start_s", "t_end_s", "energy_wh"]
    assert [float(r["t_end_s"]) for r in rows] == pytest.approx([1000.0 / 1.8, 2000.0 / 1.8], rel=1e-9)
    m = json.loads((out / "metrics.json").read_text())
    assert m["energy_wh"] == pytest.approx(P_RUN * 2000.0 / 1.8 / 3600.0, rel=1e-9)
    assert m["margin_wh"] == pytest.approx(700.0 - m["energy_wh"], rel=1e-9)
    assert set(m["point_of_no_return"]) >= {"lat", "lon", "t_s"}
    flown = json.loads((out / "sim_metrics.json").read_text())["energy_wh"]
    assert flown == pytest.approx(m["energy_wh"], rel=0.02)  # the loop flies the same mission
    page = (out / "report.html").read_text()
    assert "<h2>Energy</h2>" in page and "point of no return" in page and "usable charge left" in page


def test_run_that_breaks_the_reserve_exits_1_and_says_so(tmp_path, capsys):
    need = P_RUN * 2000.0 / 1.8 / 3600.0
    code, out, text = _run(tmp_path, capsys, round(0.99 * need / 0.7, 3))
    assert code == 1 and "RESERVE_BROKEN" in text and "RESERVE BROKEN" in text
    assert json.loads((out / "run.json").read_text())["status"] == "RESERVE_BROKEN"
    assert json.loads((out / "metrics.json").read_text())["energy_status"] == "RESERVE_BROKEN"
    assert cli.main(["mission", "check", str(out / "mission.moos"), "--scenario", str(tmp_path / "line.toml")]) == 1
    assert "energy RESERVE_BROKEN" in capsys.readouterr().out


def test_mission_check_passes_a_mission_that_keeps_its_reserve(tmp_path, capsys):
    code, out, _ = _run(tmp_path, capsys, 1000.0)
    assert cli.main(["mission", "check", str(out / "mission.csv"), "--scenario", str(tmp_path / "line.toml"),
                     "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["energy"]["energy_status"] == "EXACT" and rec["energy"]["margin_wh"] > 0


def test_run_flies_the_chosen_leg_speeds(tmp_path, capsys):
    path = tmp_path / "line.toml"
    path.write_text(SCENARIO.format(battery=1000.0) + '[endurance]\nspeeds = "energy"\n')
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "--out", str(out)]) == 0
    m = json.loads((out / "metrics.json").read_text())
    k = VehicleParams().drag_k
    best = minimize_scalar(lambda s: (15.0 + k * s**3) / (s + 0.3), bounds=(0.5, 2.5), method="bounded",
                           options={"xatol": 1e-10}).x  # least energy per metre with a 0.3 m/s following current
    assert m["leg_speeds_mps"] == pytest.approx([best, best], abs=1e-4)
    with (out / "legs.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:  # the closed loop flew those speeds: its leg times match the prediction
        assert float(r["flown_t_end_s"]) - float(r["flown_t_start_s"]) == pytest.approx(
            float(r["duration_s"]), rel=0.03)
    capsys.readouterr()
    assert cli.main(["mission", "check", str(out / "mission.moos"), "--scenario", str(path), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)["energy"]  # the check budgets the speeds the file carries
    assert rec["leg_speeds_mps"] == pytest.approx([best, best], abs=1e-4)
    assert rec["energy_wh"] == pytest.approx(m["energy_wh"], rel=1e-6)


def test_exports_carry_the_speed_of_each_leg():
    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.missions import deploy, formats

    pts = np.array([[0.0, 0.0, -10.0], [300.0, 0.0, -20.0], [300.0, 400.0, -20.0]])
    v = [1.0, 2.0]
    assert deploy.planned_times(pts, v) == pytest.approx([0.0, np.hypot(300, 10) / 1.0, np.hypot(300, 10) + 200.0])
    moos = formats.to_moos(pts, v)
    assert "runflag   = WPT_UPDATE = speed=1" in moos and "runflag   = WPT_UPDATE = speed=2" in moos
    assert "updates        = WPT_UPDATE" in moos and formats.parse_moos(moos) == pytest.approx(pts)
    plan = formats.to_qgc_plan(pts, (48.0, -124.0), v)
    change = [it["params"][1] for it in plan["mission"]["items"] if it["command"] == 178]
    # the launch's (the leading item), then after waypoint i leg i's, horizontal (audit 20: WPNav keeps a 178's
    # speed level, so leg 0, 10 m down over 300 m, is commanded at 1.0 cos γ)
    assert change == [round(300 / np.hypot(300, 10), 4), 2.0]  # a 178 only where the command changes (export22)
    back = formats.parse_qgc_plan(plan, LocalFrame(48.0, -124.0))
    assert back[1:] == pytest.approx(pts, abs=1e-3)
    rows = formats.mission_csv(pts, None, v).splitlines()
    assert rows[0].endswith(",speed") and [float(r.split(",")[-1]) for r in rows[1:]] == [1.0, 1.0, 2.0]
    assert "runflag" not in formats.to_moos(pts, 1.5)  # one speed: the file is as before


def test_departure_sweep_reports_energy_margin_and_pnr_for_every_departure():
    from auvplan.endurance import departure_endurance
    from auvplan.planners import PlannerSpec, PlanningProblem
    from auvplan.planners.core.params import TimeoptParams
    from auvplan.planners.timeopt.planner import departure_sweep
    from auvplan.world import GriddedCurrent, Margins

    t = np.arange(0.0, 90000.0, 600.0)
    u = np.broadcast_to((0.5 * np.cos(2 * np.pi * t / 44712.0))[:, None, None, None], (t.size, 1, 2, 2)).copy()
    cur = GriddedCurrent([-1e5, 1e5], [-1e5, 1e5], [0.0], u, np.zeros_like(u), t=t)
    world = World(Bounds(-2000, 22000, -6000, 6000, -100, 0), currents=cur, margins=Margins(0, 0, 100))
    problem = PlanningProblem(world, np.array([0.0, 0.0, -50.0]), np.array([20000.0, 0.0, -50.0]), speed=1.0)
    spec = PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=500.0, levels=1))
    departs = np.arange(0.0, 40000.0, 10000.0)
    plans: list = []
    rows, _ = departure_sweep(problem, spec, departs, paths=plans)
    vp = VehicleParams(speed=1.0, battery_wh=60.0)
    energy = departure_endurance(world, plans, departs, vp)
    assert len(energy) == len(rows) == departs.size
    budget = EnergyModel.from_vehicle(vp).budget_wh
    for r, e, d in zip(rows, energy, departs):
        assert e["energy_wh"] == pytest.approx(r.energy_j / 3600.0, rel=2e-3)  # the planner's own integration
        assert e["margin_wh"] == pytest.approx(budget - e["energy_wh"], rel=1e-12)
        assert d <= e["pnr_t_s"] <= d + r.duration_s + 1e-6
    assert np.ptp([e["energy_wh"] for e in energy]) > 1.0  # the tide changes the budget with the departure


@pytest.mark.parametrize("endurance, needle", [
    ('recovery = "boat"\n', "recovery = 'boat'"),
    ('recovery = "boat"\nrally = [{name = "boat", point = [5000.0, 500.0, -20.0]}]\n', "rally 'boat' point"),
    ('speeds = "fast"\n', "speeds = 'fast'"),
])
def test_bad_endurance_input_exits_2_naming_the_key(tmp_path, capsys, endurance, needle):
    path = tmp_path / "bad.toml"
    path.write_text(SCENARIO.format(battery=1000.0) + "[endurance]\n" + endurance)
    assert cli.main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert needle in err and "[endurance]" in err and len(err.strip().splitlines()) == 1


def test_mission_files_give_back_the_speed_of_each_leg(tmp_path):
    from auvplan.io.missions import formats
    from auvplan.io.missions.readback.speeds import read_leg_speeds

    pts = np.array([[0.0, 0.0, -10.0], [300.0, 0.0, -20.0], [300.0, 400.0, -20.0], [0.0, 400.0, -20.0]])
    v = [1.0, 2.0, 1.25]
    (tmp_path / "m.moos").write_text(formats.to_moos(pts, v))
    (tmp_path / "m.csv").write_text(formats.mission_csv(pts, None, v))
    (tmp_path / "m.plan").write_text(json.dumps(formats.to_qgc_plan(pts, (48.0, -124.0), v)))
    assert read_leg_speeds(tmp_path / "m.moos", 3) == pytest.approx(v)
    assert read_leg_speeds(tmp_path / "m.csv", 3) == pytest.approx(v)
    # QGC: home on the surface is a waypoint too, reached at the first leg's speed
    # (the speeds it commands are horizontal, audit 20: leg 0 dives 10 m over 300 m, the launch is vertical)
    cos0 = 300 / np.hypot(300, 10)
    assert read_leg_speeds(tmp_path / "m.plan", 4) == pytest.approx([cos0, cos0, 2.0, 1.25], abs=5e-5)
    assert formats.read_mission(tmp_path / "m.plan", (48.0, -124.0))[0].shape == (5, 3)
    assert read_leg_speeds(tmp_path / "m.moos", 2) is None  # not the file's legs
