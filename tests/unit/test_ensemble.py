"""Current ensembles (issue 39): ``[currents] members``, scoring a route in every member, the robust plan and
``plan --json``'s ensemble fields; oracles are closed forms (uniform currents), numpy, and invariants."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.cli import main
from auvplan.io.scenario import loader
from auvplan.io.scenario.inputs.members import member_fields
from auvplan.sim.ensemble.robust import plan_robust, rank_key
from auvplan.sim.ensemble.score import EnsembleScore, percentile, score_route
from auvplan.world import UniformCurrent
from auvplan.world.currents.ensemble import MeanCurrent, PerturbedCurrent, ShiftedCurrent

V = 1.0
C1, C2 = (0.3, 0.0, 0.0), (-0.2, 0.4, 0.0)
START, GOAL = (500.0, 500.0, -50.0), (3500.0, 3000.0, -50.0)
TWO = f"""
name = "two-uniform"
[bounds]
x = [0.0, 4000.0]
y = [0.0, 4000.0]
z = [-200.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 200.0
cell_m = 100.0
[currents]
members = [ {{ uniform = {list(C1)} }}, {{ uniform = {list(C2)}, name = "second" }} ]
[mission]
start = {list(START)}
goal = {list(GOAL)}
[planner]
name = "grid"
robust = "p90"
[vehicle]
speed = {V}
"""


def _closed_form(c: tuple[float, float, float]) -> tuple[float, float]:
    """Arrival time and crab heading on the straight line START -> GOAL in a uniform current: the ground
    velocity g = Vg ŝ with |g - c| = V (a quadratic in Vg), the water velocity w = g - c, heading atan2(wx, wy)."""
    d = np.subtract(GOAL, START)[:2]
    length = float(np.hypot(*d))
    s = d / length
    cv = np.asarray(c[:2])
    # |Vg s - c|^2 = V^2  ->  Vg^2 - 2 (c.s) Vg + |c|^2 - V^2 = 0, larger root
    b, cc = float(cv @ s), float(cv @ cv) - V * V
    vg = b + math.sqrt(b * b - cc)
    w = vg * s - cv
    return length / vg, math.degrees(math.atan2(w[0], w[1])) % 360.0


@pytest.fixture(scope="module")
def two():
    sc = loader.loads(TWO)
    world, mission = loader.build(sc)
    members = member_fields(sc.currents.members, world.currents, None, (0.0, 4000.0, 0.0, 4000.0), source="t")
    return sc, world, mission, members


def test_members_parse_and_nominal_is_the_first(two):
    sc, world, _, members = two
    assert [n for n, _ in members] == ["member0", "second"]
    assert isinstance(world.currents, UniformCurrent) and world.currents.vector == C1


def test_two_uniform_members_closed_form(two):
    """Straight route in two uniform members: per-member arrival and crab heading, P50 = mean, P90 = 0.1 T1 + 0.9 T2."""
    _, world, mission, members = two
    score = score_route(world, members, np.array([START, GOAL]), mission.vehicle)
    (t1, h1), (t2, h2) = _closed_form(C1), _closed_form(C2)
    assert [m.arrival_s for m in score.members] == pytest.approx([t1, t2], rel=1e-9)
    assert [m.heading_deg for m in score.members] == pytest.approx([h1, h2], abs=1e-9)
    lo, hi = sorted((t1, t2))
    assert score.arrival_p50_s == pytest.approx(0.5 * (lo + hi), rel=1e-9)
    assert score.arrival_p90_s == pytest.approx(0.1 * lo + 0.9 * hi, rel=1e-9)
    assert score.success_probability == 1.0


def test_robust_plan_is_the_straight_line_at_the_closed_form_heading(two):
    """Uniform currents on open water: every member's time-optimal route is the straight line, so the robust
    route is too; its course is the bearing to the goal and each member's heading the closed-form crab."""
    _, world, mission, members = two
    r = plan_robust(world, mission, members, "p90", seed=1)
    route = r.chosen.route
    assert route is not None and route.shape[0] == 2  # the mission route of the lattice plan: one straight leg
    course = math.degrees(math.atan2(route[1, 0] - route[0, 0], route[1, 1] - route[0, 1]))
    assert course == pytest.approx(math.degrees(math.atan2(GOAL[0] - START[0], GOAL[1] - START[1])), abs=1e-9)
    assert [m.heading_deg for m in r.chosen.score.members] == pytest.approx([_closed_form(C1)[1], _closed_form(C2)[1]])
    assert {c.label for c in r.candidates} == {"nominal", "member0", "second", "mean"}
    assert rank_key(r.chosen.score, "p90") <= rank_key(r.nominal.score, "p90")  # never worse than the nominal


def test_reserve_and_blocked_members_fail(two):
    """A member whose current beats the vehicle does not arrive (inf, INFEASIBLE); a small battery breaks the
    reserve (arrives, not a success)."""
    from dataclasses import replace

    _, world, mission, _ = two
    members = [("calm", UniformCurrent((0.0, 0.0, 0.0))), ("gale", UniformCurrent((-1.5, -1.5, 0.0)))]
    s = score_route(world, members, np.array([START, GOAL]), mission.vehicle)
    assert [m.status for m in s.members] == [Status.EXACT, Status.INFEASIBLE]
    assert s.members[1].arrival_s == math.inf and s.success_probability == 0.5
    assert s.arrival_p50_s == math.inf and s.arrival_p90_s == math.inf
    small = replace(mission.vehicle, battery_wh=20.0)
    s2 = score_route(world, members[:1], np.array([START, GOAL]), small)
    assert s2.members[0].status is Status.RESERVE_BROKEN and math.isfinite(s2.members[0].arrival_s)
    assert s2.success_probability == 0.0


def test_collision_is_a_failure_in_every_member(two):
    _, world, mission, members = two
    s = score_route(world, members, np.array([START, (2000.0, 2000.0, -250.0), GOAL]), mission.vehicle)
    assert all(m.status is Status.COLLISION for m in s.members) and s.success_probability == 0.0


def test_percentile_matches_numpy_and_handles_inf():
    rng = np.random.default_rng(3)
    for n in (1, 2, 5, 10):
        v = rng.uniform(0, 100, n)
        for q in (0, 10, 50, 90, 100):
            assert percentile(v, q) == pytest.approx(float(np.percentile(v, q)), rel=1e-12)
    assert percentile([1.0, 2.0, math.inf], 50) == 2.0
    assert percentile([1.0, 2.0, math.inf], 90) == math.inf
    assert percentile([1.0, math.inf, math.inf, math.inf, math.inf, math.inf, math.inf, math.inf, math.inf,
                       math.inf, math.inf], 0) == 1.0


def test_rank_key_orders_by_objective():
    a = EnsembleScore((), 100.0, 200.0, 0.5)
    b = EnsembleScore((), 150.0, 250.0, 1.0)
    assert rank_key(a, "p90") < rank_key(b, "p90")
    assert rank_key(b, "success") < rank_key(a, "success")
    assert rank_key(None, "p90") > rank_key(b, "p90")


def test_perturbation_has_the_stated_spread_and_correlation():
    """Over many seeds the perturbation's variance is σ² and its correlation at distance L is exp(-1/2)."""
    sigma, L = 0.2, 5000.0
    p = np.array([[0.0, 0.0, -10.0], [L, 0.0, -10.0]])
    samples = np.array([PerturbedCurrent(UniformCurrent(), sigma, L, seed=s, modes=256).perturbation(p)
                        for s in range(600)])
    u = samples[:, :, 0]
    assert np.var(u[:, 0]) == pytest.approx(sigma**2, rel=0.15)
    assert np.corrcoef(u[:, 0], u[:, 1])[0, 1] == pytest.approx(math.exp(-0.5), abs=0.1)
    f = PerturbedCurrent(UniformCurrent((0.1, 0.0, 0.0)), sigma, L, seed=7)
    assert np.allclose(f.velocity(p) - f.perturbation(p), [0.1, 0.0, 0.0])
    again = PerturbedCurrent(UniformCurrent((0.1, 0.0, 0.0)), sigma, L, seed=7)
    assert np.array_equal(f.velocity(p), again.velocity(p))


def test_mean_and_shifted_fields():
    a, b = UniformCurrent((0.2, 0.0, 0.0)), UniformCurrent((0.0, -0.4, 0.0))
    assert np.allclose(MeanCurrent([a, b]).velocity(np.zeros((2, 3))), [[0.1, -0.2, 0.0]] * 2)

    class Clock(UniformCurrent):
        def velocity(self, points, t=0.0):
            return np.full(np.shape(points), t)

    assert np.allclose(ShiftedCurrent(Clock(), 3600.0).velocity(np.zeros((1, 3)), 10.0), 3610.0)


def test_plan_json_reports_the_ensemble(tmp_path, capsys):
    f = tmp_path / "two.toml"
    f.write_text(TWO)
    assert main(["plan", str(f), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    for key in ("arrival_p50_s", "arrival_p90_s", "success_probability", "members", "robust", "nominal"):
        assert key in rec
    assert [m["status"] for m in rec["members"]] == ["EXACT", "EXACT"]
    assert [m["arrival_s"] for m in rec["members"]] == pytest.approx([_closed_form(C1)[0], _closed_form(C2)[0]],
                                                                    rel=1e-6)
    assert rec["success_probability"] == 1.0


@pytest.mark.parametrize("member, key, value", [
    ('{ uniform = [0.3, 0.0] }', "uniform", "[0.3, 0.0]"),
    ('{ file = "nope.nc" }', "file", "'nope.nc'"),
    ('{ perturbation = { count = 0, spread_mps = 0.1, correlation_m = 1000.0 } }', "count", "0"),
    ('{ colour = 1 }', "colour", "colour"),
])
def test_bad_member_exits_2_naming_file_key_value(tmp_path, capsys, member, key, value):
    f = tmp_path / "bad.toml"
    f.write_text(TWO.replace("name = \"second\" }", f"name = \"second\" }}, {member}"))
    assert main(["plan", str(f), "--json"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.toml" in err[0] and "members[2]" in err[0] and key in err[0] and value in err[0]


def test_open_loop_drifts_by_the_forecast_error_times_the_planned_time(two):
    """Dead reckoning in uniform currents: the forecast's plan, flown in the truth, ends exactly at
    goal + (c_true - c_forecast) T_forecast; with a perfect forecast it arrives at the closed-form time."""
    from dataclasses import replace

    from auvplan.sim.ensemble.replan import ReplanParams, fly_open_loop, fly_replanning

    _, world, mission, _ = two
    c_true = (0.3, -0.2, 0.0)
    fc, true = UniformCurrent(C1), UniformCurrent(c_true)
    perfect = fly_open_loop(replace(world, currents=fc), fc, mission, ReplanParams(dt=30.0), seed=1)
    t1 = _closed_form(C1)[0]
    assert perfect.success and perfect.replans == 0 and perfect.arrival_s == pytest.approx(t1, rel=1e-6)
    truth = replace(world, currents=true)
    ol = fly_open_loop(truth, fc, mission, ReplanParams(dt=30.0), seed=1)
    k = int(np.argmin(np.abs(ol.times - t1)))  # the end of the first plan's schedule
    drift = (np.subtract(c_true, C1) * t1)[:2]
    assert ol.track[k, :2] == pytest.approx(np.add(GOAL[:2], drift), abs=1e-6)
    assert ol.replans == 1 and ol.arrived  # one homing plan from the fix
    rp = fly_replanning(truth, fc, mission, ReplanParams(interval_s=1200.0, dt=30.0), seed=1)
    assert rp.arrived and rp.replans >= 2 and rp.arrival_s < ol.arrival_s
    assert len(rp.plan_cpu_s) == rp.replans + 1


def test_real_two_models_robust_p90_below_the_nominal(lofoten_plan):
    """lofoten-two-models (Arctic-20km forecast, Nordic-4km hindcast, Feb 2016): the nominal plan, made on the
    forecast, is slowed by the coastal current the forecast misses; the robust plan's P90 over both models is
    lower, and so is its arrival in the other model (the truth).  Pinned from benchmarks/ensemble.py (±2 %).
    ``plan --json``'s record, shared with tests/golden/test_report_ensemble.py (tests/conftest.py)."""
    code, _, rec = lofoten_plan
    assert code == 0
    assert rec["robust"] == "p90" and rec["robust_candidate"] != "nominal"
    assert rec["arrival_p90_s"] < rec["nominal"]["arrival_p90_s"] - 3600.0
    assert rec["arrival_p90_s"] == pytest.approx(77871.3, rel=0.02)
    assert rec["nominal"]["arrival_p90_s"] == pytest.approx(92326.5, rel=0.02)
    assert [m["name"] for m in rec["members"]] == ["arctic20km", "nordic4km"]
    assert rec["success_probability"] == 1.0


def test_one_file_with_a_realisation_dimension(tmp_path, capsys):
    """An ensemble file (realization, y, x): one member per index, each with its own uniform value; a wrong
    dimension name is refused naming the file, the key and the value."""
    import xarray as xr

    x = np.linspace(0.0, 4000.0, 5)
    u = np.stack([np.full((5, 5), 0.1 * (k + 1)) for k in range(3)])
    ds = xr.Dataset({"u": (("realization", "y", "x"), u, {"units": "m s-1"}),
                     "v": (("realization", "y", "x"), -u, {"units": "m s-1"})},
                    coords={"x": ("x", x, {"units": "m"}), "y": ("y", x, {"units": "m"})})
    ds.to_netcdf(tmp_path / "ens.nc")
    text = TWO.replace(TWO[TWO.index("members = "):TWO.index("[mission]")],
                       'members = [ { file = "ens.nc", dimension = "realization" } ]\n')
    (tmp_path / "e.toml").write_text(text)
    sc = loader.load(tmp_path / "e.toml")
    world, _ = loader.build(sc)
    members = member_fields(sc.currents.members, world.currents, None, (0.0, 4000.0, 0.0, 4000.0), source="t",
                            base_dir=tmp_path)
    assert [n for n, _ in members] == ["ens[0]", "ens[1]", "ens[2]"]
    for k, (_, f) in enumerate(members):
        assert f.velocity(np.array([[1234.0, 2345.0, -50.0]]))[0] == pytest.approx([0.1 * (k + 1), -0.1 * (k + 1), 0])
    assert world.currents.velocity(np.zeros((1, 3)))[0, 0] == pytest.approx(0.1)  # the nominal: the first member
    (tmp_path / "e.toml").write_text(text.replace('dimension = "realization"', 'dimension = "member"'))
    assert main(["plan", str(tmp_path / "e.toml"), "--json"]) == 2
    err = capsys.readouterr().err
    assert "e.toml" in err and "dimension = 'member'" in err and "realization" in err


def test_validate_reads_every_member(tmp_path, capsys):
    f = tmp_path / "bad.toml"
    f.write_text(TWO.replace("name = \"second\" }", "name = \"second\" }, { file = \"nope.nc\" }"))
    assert main(["validate", str(f)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "members[2] file = 'nope.nc'" in err[0]
    f.write_text(TWO)
    assert main(["validate", str(f)]) == 0
    assert "2 current members: member0, second; [planner] robust = 'p90'" in capsys.readouterr().out
