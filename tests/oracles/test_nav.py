"""Navigation error budget, fix planning and clearance under the error (issue 52; docs/navigation.md).

Oracles: σ's closed form per lock state and at a lock switch, a reset at a fix, a loop-by-loop σ, the
uncertain clearance against brute-force sampling of the discs round a leg, the fewest fixes against
every subset of candidates, the drifting estimate's second moment against σ².
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from auvplan.errors import ScenarioError
from auvplan.nav import (
    NavParams,
    apply_fixes,
    check_navigation,
    leg_slack,
    mission_budget,
    periodic_fixes,
    plan_fixes,
    route_profile,
    safe_radius,
)
from auvplan.nav.budget import drift_increments, lock_fraction, sigma_profile
from auvplan.nav.clearance import lattice_step
from auvplan.path.flyable import VehicleLimits, check_limits
from auvplan.sim.drift import NavDrift
from auvplan.world import Bounds, Margins, Terrain, World

NAV = NavParams(drift_pct=0.4, drift_pct_no_lock=2.5, dvl_range_m=100.0, fix_error_m=4.0, max_error_m=200.0,
                confidence=2.0)


def _world(depth: float = 1000.0, nx: int = 31, ny: int = 17, sx: float = 30000.0, sy: float = 12000.0,
           z=None, min_altitude: float = 20.0) -> World:
    """A non-square, non-square-celled seabed (flat unless ``z`` is given)."""
    x, y = np.linspace(0.0, sx, nx), np.linspace(0.0, sy, ny)
    zz = np.full((ny, nx), -depth) if z is None else z(*np.meshgrid(x, y))
    return World(Bounds(0.0, sx, 0.0, sy, -6000.0, 0.0), Terrain(x, y, zz, name="test"),
                 margins=Margins(min_altitude=min_altitude, min_depth=0.0), name="test")


def _closed(nav: NavParams, d_lock: float, d_free: float, sigma_fix: float | None = None) -> float:
    """confidence × σ after ``d_lock`` m with bottom lock and ``d_free`` m without, from a fix."""
    s0 = nav.fix_error_m if sigma_fix is None else sigma_fix
    return nav.confidence * math.hypot(s0, d_lock * nav.drift_pct / 100 + d_free * nav.drift_pct_no_lock / 100)


@pytest.mark.parametrize("altitude, locked", [(50.0, True), (400.0, False)])
def test_sigma_is_linear_in_distance_per_lock_state(altitude, locked):
    w = _world()
    z = -1000.0 + altitude
    pts = np.array([[1000.0, 2000.0, z], [4000.0, 6000.0, z], [11000.0, 6000.0, z], [11000.0, 9000.0, z]])
    b = mission_budget(w, pts, ("",) * 4, NAV)
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pts[:, :2], axis=0).T))]
    want = [_closed(NAV, d if locked else 0.0, 0.0 if locked else d) for d in s]
    np.testing.assert_allclose(b.error_m, want, rtol=1e-9)
    np.testing.assert_allclose(b.leg_error_m, want[1:], rtol=1e-9)
    np.testing.assert_allclose(b.leg_lock, 1.0 if locked else 0.0)


def test_lock_switches_with_altitude_on_a_descending_leg_and_over_a_seabed_step():
    w = _world()
    # altitude falls linearly from 300 m to 50 m: lock (≤ 100 m) on the last (100 - 50) / (300 - 50) of the leg
    pts = np.array([[1000.0, 6000.0, -700.0], [9000.0, 6000.0, -950.0]])
    b = mission_budget(w, pts, ("", ""), NAV)
    assert b.leg_lock[0] == pytest.approx(0.2, abs=1e-9)
    assert b.error_m[-1] == pytest.approx(_closed(NAV, 0.2 * 8000.0, 0.8 * 8000.0), rel=1e-9)
    # a level leg over a seabed that rises from -1000 to -850 m between x = 10 and 11 km (one cell: linear)
    step = _world(z=lambda x, y: np.where(x >= 11000.0, -850.0, -1000.0))
    pts = np.array([[2000.0, 6000.0, -800.0], [18000.0, 6000.0, -800.0]])
    b = mission_budget(step, pts, ("", ""), NAV)
    # altitude 200 m up to x = 10 km, 50 m from 11 km; 100 m at x = 10 + (200 - 100) / 150 km
    lock = 18000.0 - (10000.0 + 1000.0 * 100.0 / 150.0)
    assert b.leg_lock[0] == pytest.approx(lock / 16000.0, rel=1e-9)
    assert b.error_m[-1] == pytest.approx(_closed(NAV, lock, 16000.0 - lock), rel=1e-9)


def test_a_fix_resets_the_error_and_the_drift_restarts_from_it():
    w = _world()
    z = -950.0
    pts = np.array([[1000.0, 6000.0, z], [6000.0, 6000.0, z], [7000.0, 6000.0, 0.0], [8000.0, 6000.0, z],
                    [14000.0, 6000.0, z]])
    kinds = ("", "", "gps", "", "")
    b = mission_budget(w, pts, kinds, NAV)
    climb = math.hypot(1000.0, 0.0)  # horizontal metres of the climb, no lock above 100 m altitude
    lock_climb = 1000.0 * 50.0 / 950.0  # the climb's first 50 m of height keep lock (altitude 50 → 100 m)
    before = _closed(NAV, 5000.0 + lock_climb, climb - lock_climb)
    assert b.leg_error_m[1] == pytest.approx(before, rel=1e-9)
    assert b.error_m[2] == pytest.approx(NAV.confidence * NAV.fix_error_m, rel=1e-12)  # after the fix
    dive = 1000.0
    assert b.error_m[3] == pytest.approx(_closed(NAV, lock_climb, dive - lock_climb), rel=1e-9)
    assert b.error_m[4] == pytest.approx(_closed(NAV, lock_climb + 6000.0, dive - lock_climb), rel=1e-9)


def test_sigma_profile_against_a_loop():
    rng = np.random.default_rng(3)
    inc = rng.uniform(0.0, 5.0, 40)
    resets, fixes = np.array([7, 19, 33]), np.array([3.0, 9.0, 1.5])
    before, after = sigma_profile(inc, resets, fixes, 2.0)
    d, s0 = 0.0, 2.0
    for k in range(41):
        if k:
            d += inc[k - 1]
        assert before[k] == pytest.approx(math.hypot(s0, d))
        if k in resets:
            d, s0 = 0.0, float(fixes[list(resets).index(k)])
        assert after[k] == pytest.approx(math.hypot(s0, d))


def test_lock_fraction_and_increments_read_percent():
    share = lock_fraction(np.array([50.0, 150.0, 150.0, 90.0]), 100.0)
    np.testing.assert_allclose(share, [0.5, 0.0, 10.0 / 60.0])  # 150 → 90 m: below 100 m on the last 10 of 60
    inc = drift_increments(np.array([100.0, 100.0, 60.0]), share, NAV)
    np.testing.assert_allclose(inc, [100 * (0.5 * 0.004 + 0.5 * 0.025), 100 * 0.025,
                                     60 * (10 / 60 * 0.004 + 50 / 60 * 0.025)], rtol=1e-12)


def _brute_slack(terrain: Terrain, a, b, r: float, nt: int = 161, nr: int = 24, na: int = 72) -> float:
    """min over t and |q − p(t)| ≤ r of z(t) − zb(q), sampled: discs round points of the segment."""
    t = np.linspace(0.0, 1.0, nt)
    p = a[None] + t[:, None] * (b - a)[None]
    rad = np.linspace(0.0, r, nr)
    ang = np.linspace(0.0, 2 * np.pi, na, endpoint=False)
    ox = (rad[:, None] * np.cos(ang)[None]).ravel()
    oy = (rad[:, None] * np.sin(ang)[None]).ravel()
    zb = terrain.elevation(p[:, 0, None] + ox[None], p[:, 1, None] + oy[None])
    return float((p[:, 2, None] - zb).min())


@pytest.mark.parametrize("seed", [0, 1])
def test_uncertain_clearance_against_brute_force_on_real_bathymetry(seed):
    from auvplan.io.scenario import loader

    world, _ = loader.build(loader.load("mariana-nav"))
    t = world.terrain
    rng = np.random.default_rng(seed)
    lip, h = t.max_slope, lattice_step(t)
    for _ in range(6):
        a = np.r_[rng.uniform(150e3, 175e3), rng.uniform(40e3, 110e3), 0.0]
        b = a + np.r_[rng.uniform(-900, 900, 2), 0.0]
        a[2], b[2] = t.elevation(a[0], a[1]) + rng.uniform(40, 200), t.elevation(b[0], b[1]) + rng.uniform(40, 200)
        for r in (0.0, 150.0, 400.0):
            ours = float(leg_slack(t, a[None], b[None], r)[0])
            brute = _brute_slack(t, a, b, r)
            assert ours <= brute + 1e-6  # never above the true least altitude (brute ≥ true)
            grown = _brute_slack(t, a, b, r + 2 * h)
            assert ours >= grown - 2.0 * lip * h - 1e-6  # and within the lattice's own bound of it


def test_safe_radius_is_the_inverse_of_the_stadium_test():
    w = _world(z=lambda x, y: -1000.0 + 300.0 * np.exp(-((x - 15000.0) ** 2 + (y - 6000.0) ** 2) / 2.0e6))
    a, b = np.array([[12000.0, 4500.0, -760.0]]), np.array([[18000.0, 4500.0, -760.0]])
    r = float(safe_radius(w.terrain, a, b, 20.0, 2000.0, tol=0.25)[0])
    assert 0.0 < r < 2000.0
    assert leg_slack(w.terrain, a, b, r)[0] >= 20.0
    assert leg_slack(w.terrain, a, b, r + 0.5)[0] < 20.0


def test_fewest_fixes_equals_the_best_subset_of_candidates_and_beats_the_period():
    w = _world(depth=300.0)
    nav = NavParams(drift_pct=0.5, drift_pct_no_lock=1.5, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=120.0,
                    confidence=2.0, surface_s=30.0)
    route = np.array([[1000.0, 2000.0, -250.0], [9000.0, 2000.0, -100.0], [16000.0, 9000.0, -260.0],
                      [27000.0, 9000.0, -250.0]])
    prof = route_profile(w, route, nav, 20.0, 1.5, step=100.0)
    spacing = 2500.0
    plan = plan_fixes(prof, nav, 1.5, spacing=spacing)
    assert plan.ok
    every = int(round(spacing / (prof.s[-1] / (prof.s.size - 1))))
    cands = prof.s[np.arange(every, prof.s.size - 1, every)]
    best = None
    # the oracle: every subset of the candidates, smallest first, made into the mission and budgeted (on a flat
    # seabed 40 m below the route's deepest point the clearance never binds: the budget decides)
    for n in range(0, len(cands) + 1):
        for sub in itertools.combinations(cands, n):
            pts, kinds = apply_fixes(route, np.array(sub), ("gps",) * n, prof.tan_pitch)
            if mission_budget(w, pts, kinds, nav, step=100.0).max_error_m <= nav.max_error_m:
                best = n
                break
        if best is not None:
            break
    assert plan.count == best >= 2
    assert check_navigation(w, *apply_fixes(route, plan.s, plan.kinds, prof.tan_pitch), nav, step=100.0).ok
    period = periodic_fixes(prof, nav, 0.9 * float(prof.t[-1]) / (best + 1), 1.5)
    assert period.count >= plan.count


def test_surfacings_keep_the_track_the_pitch_limit_and_only_lift_the_schedule():
    route = np.array([[0.0, 0.0, -400.0], [5000.0, 0.0, -300.0], [9000.0, 3000.0, -500.0], [15000.0, 3000.0, -450.0]])
    tan = math.tan(math.radians(19.98))
    pts, kinds = apply_fixes(route, np.array([4000.0, 7000.0, 12000.0]), ("gps", "usbl", "gps"), tan)
    assert [k for k in kinds if k] == ["gps", "usbl", "gps"]
    surf = pts[[i for i, k in enumerate(kinds) if k == "gps"]]
    np.testing.assert_allclose(surf[:, 2], 0.0, atol=1e-9)
    assert check_limits(pts, VehicleLimits(20.0, 1.0, 6000.0)).ok
    sv = np.r_[0.0, np.cumsum(np.hypot(*np.diff(route[:, :2], axis=0).T))]
    sp = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pts[:, :2], axis=0).T))]
    for i in range(2):  # the horizontal track is the route's, point for point
        np.testing.assert_allclose(pts[:, i], np.interp(sp, sv, route[:, i]), atol=1e-6)
    assert sp[-1] == pytest.approx(sv[-1])
    assert np.all(pts[:, 2] >= np.interp(sp, sv, route[:, 2]) - 1e-9)


def test_the_drifting_estimate_has_the_budget_s_second_moment():
    nav = NavParams(drift_pct=0.3, drift_pct_no_lock=1.5, dvl_range_m=100.0, fix_error_m=6.0, max_error_m=300.0)
    rng = np.random.default_rng(11)
    sq_before, sq_after = [], []
    for _ in range(3000):
        d = NavDrift(nav, rng)
        for _ in range(10):
            d.advance(400.0, 60.0)  # 4 km with lock
        d.advance(3000.0, 900.0)  # 3 km without
        sq_before.append(float(d.error @ d.error))
        d.fix("gps", (0.0, 0.0, 0.0))
        d.advance(1000.0, 500.0)
        sq_after.append(float(d.error @ d.error))
    sigma = math.hypot(6.0, 4000 * 0.003 + 3000 * 0.015)
    assert np.mean(sq_before) == pytest.approx(sigma ** 2, rel=0.06)
    assert np.mean(sq_after) == pytest.approx(6.0 ** 2 + 15.0 ** 2, rel=0.06)


def test_navigation_table_is_read_and_bad_values_name_the_key():
    from auvplan.io.scenario import loader

    base = """name = "t"
[terrain.synthetic]
kind = "flat"
depth = 500.0
[bounds]
x = [0.0, 1000.0]
y = [0.0, 1000.0]
z = [-500.0, 0.0]
[mission]
start = [100.0, 100.0, -400.0]
goal = [900.0, 900.0, -400.0]
min_depth_m = 0.0
[navigation]
"""
    sc = loader.loads(base + 'drift_pct = 0.2\ndrift_pct_no_lock = 3\nfixes = 1800\nconfidence = 2.5\n', "t.toml")
    assert sc.navigation == NavParams(drift_pct=0.2, drift_pct_no_lock=3.0, fixes=1800.0, confidence=2.5)
    for bad, key in (('fixes = "sometimes"', "fixes"), ("drift_pct = 120", "drift_pct"),
                     ("dvl_rnage_m = 3", "dvl_rnage_m"), ("max_error_m = 1", "max_error_m")):
        with pytest.raises(ScenarioError, match=rf"t\.toml: \[navigation\].*{key}"):
            loader.loads(base + bad + "\n", "t.toml")
    with pytest.raises(ScenarioError, match=r"min_depth_m"):
        loader.build(loader.loads(base.replace("min_depth_m = 0.0", "min_depth_m = 5.0"), "t.toml"))


def test_mariana_nav_plans_fewer_fixes_than_the_best_period_and_mission_check_fails_without_them(tmp_path, capsys,
                                                                                               mariana_nav_plan):
    import json

    from auvplan.cli import main
    from auvplan.endurance import EnergyModel
    from auvplan.endurance import mission_budget as energy_budget
    from auvplan.io.missions.formats import mission_csv

    world, mission, route, plan = mariana_nav_plan
    assert plan is not None and plan.ok
    m = plan.metrics()
    # issue 52: fewer than the best fixed period; 6 against 7 (6287 s) since wave 17 times the periodic fixes through
    # the current (in still water they were 8 every 6229 s: the 0.05 m/s current slows the first leg by 2.7 %, and
    # 7 fixes every 6287 s, flown, keep 284.8 m; tests/oracles/test_nav23_periodic.py)
    assert (m["fixes"], m["fixes_fixed_period"]) == (6, 7) and m["fixed_period_s"] == pytest.approx(6287.0, abs=60.0)
    assert m["nav_error_max_m"] <= mission.navigation.max_error_m
    (tmp_path / "bare.csv").write_text(mission_csv(route, world.origin, 1.5))
    (tmp_path / "fixed.csv").write_text(mission_csv(plan.points, world.origin, 1.5))
    assert main(["mission", "check", str(tmp_path / "bare.csv"), "--scenario", "mariana-nav", "--json"]) == 1
    capsys.readouterr()
    assert main(["mission", "check", str(tmp_path / "fixed.csv"), "--scenario", "mariana-nav", "--json"]) == 0
    energy = json.loads(capsys.readouterr().out)["energy"]  # the surface dwells held in the file's budget too
    planned = energy_budget(world, plan.points, EnergyModel.from_vehicle(mission.vehicle), 1.5, dwell=plan.dwell_s)
    assert energy["duration_s"] == pytest.approx(planned.duration_s, abs=1.0)
    assert energy["duration_s"] > energy_budget(world, plan.points, EnergyModel.from_vehicle(mission.vehicle),
                                                1.5).duration_s + 0.99 * plan.dwell_s.sum()


def test_the_closed_loop_steers_by_a_drifting_estimate_only_when_asked_and_a_fix_resets_it():
    from dataclasses import replace

    from auvplan.sim import Mission, SimParams, simulate

    w = _world(depth=300.0)
    route = np.array([[1000.0, 6000.0, -250.0], [3000.0, 6000.0, -250.0], [4000.0, 6000.0, 0.0],
                      [5000.0, 6000.0, -250.0], [7000.0, 6000.0, -250.0]])
    nav = NavParams(drift_pct=3.0, drift_pct_no_lock=6.0, dvl_range_m=100.0, fix_error_m=1.0, max_error_m=900.0)
    base = Mission("t", tuple(route[0]), tuple(route[-1]), sim=SimParams(dt=1.0, record_every=1))
    plain = simulate(w, base, route=route, rng=4)
    quiet = simulate(w, replace(base, navigation=replace(nav, surface_s=0.0)), route=route, rng=4)  # drift off
    # with [navigation] the flight first dives from the surface above the start (wave 18: the budget's launch),
    # 250 m at 1.5 m/s in whole steps of 1 s, then flies as without it
    lag = math.ceil(250.0 / 1.5)
    assert np.all(quiet.position[:lag, :2] == route[0, :2]) and quiet.position[0, 2] == 0.0
    np.testing.assert_array_equal(plain.position, quiet.position[lag:])
    assert plain.nav_error is None
    flown = simulate(w, replace(base, navigation=nav, nav_drift=True), route=route, rng=4)
    assert flown.arrived and flown.nav_error is not None
    at_fix = int(np.argmin(np.hypot(flown.position[:, 0] - 4000.0, flown.position[:, 2])))
    before, after = flown.nav_error[:at_fix - 5], flown.nav_error[at_fix + 5:]
    assert before.max() > 20.0 * after[0]  # reset to the fix's own error, then growing again
    assert after[-1] > after[0]


def test_the_closed_loop_holds_the_surface_dwell_drifting_with_the_current_at_hotel_power():
    from dataclasses import replace

    from auvplan.endurance import EnergyModel, flown_energy
    from auvplan.sim import Mission, SimParams, simulate
    from auvplan.vehicles import VehicleParams
    from auvplan.world.currents.fields import UniformCurrent

    w = replace(_world(depth=300.0), currents=UniformCurrent((0.0, -0.05, 0.0)))  # across the track
    route = np.array([[1000.0, 6000.0, -250.0], [3000.0, 6000.0, -250.0], [4000.0, 6000.0, 0.0],
                      [5000.0, 6000.0, -250.0], [7000.0, 6000.0, -250.0]])
    nav = NavParams(drift_pct=1.0, drift_pct_no_lock=2.0, dvl_range_m=100.0, fix_error_m=1.0, max_error_m=900.0)
    base = Mission("t", tuple(route[0]), tuple(route[-1]), sim=SimParams(dt=0.5, record_every=1))
    flights = {s: simulate(w, replace(base, navigation=replace(nav, surface_s=s)), route=route, rng=4)
               for s in (0.0, 300.0)}
    assert all(f.arrived for f in flights.values())
    held, plain = flights[300.0], flights[0.0]
    # the dwell is flown time; regaining the track from the 15 m the current carried it across costs at most 15 m
    assert 300.0 <= held.t[-1] - plain.t[-1] <= 300.0 + 0.05 * 300.0 / 1.5
    still = np.flatnonzero(np.hypot(*(np.diff(held.position[:, :2], axis=0) / 0.5 - (0.0, -0.05)).T) < 1e-9)
    assert still.size * 0.5 == pytest.approx(300.0, abs=0.5)  # 300 s moving with the water only
    assert -held.position[still[0], 2] < 25.0  # at the surface waypoint (the switch radius before it)
    model = EnergyModel.from_vehicle(VehicleParams())
    extra = flown_energy(w, held.t, held.position, model).energy_wh - flown_energy(w, plain.t, plain.position,
                                                                                   model).energy_wh
    assert extra == pytest.approx(float(model.power(0.0)) * 300.0 / 3600.0, rel=0.05)  # the hotel load only


def test_the_surface_dwell_is_in_the_energy_budget_at_hotel_power():
    from auvplan.endurance import EnergyModel
    from auvplan.endurance import mission_budget as energy_budget
    from auvplan.vehicles import VehicleParams

    w = _world(depth=300.0)
    route = np.array([[1000.0, 6000.0, -250.0], [3000.0, 6000.0, 0.0], [5000.0, 6000.0, -250.0]])
    model = EnergyModel.from_vehicle(VehicleParams())
    plain = energy_budget(w, route, model, 1.5)
    held = energy_budget(w, route, model, 1.5, dwell=[0.0, 120.0, 0.0])
    assert held.duration_s == pytest.approx(plain.duration_s + 120.0, rel=1e-12)
    assert held.energy_wh - plain.energy_wh == pytest.approx(float(model.power(0.0)) * 120.0 / 3600.0, rel=1e-9)
    np.testing.assert_allclose(held.speed_ground, plain.speed_ground, rtol=1e-12)


def test_usbl_fixes_are_taken_at_depth_near_the_ship_with_their_slant_range_error():
    from auvplan.nav import UsblParams, plan_navigation
    from auvplan.nav.budget import fix_sigma

    w = _world(depth=300.0)
    nav = NavParams(drift_pct=0.5, drift_pct_no_lock=1.5, dvl_range_m=100.0, fix_error_m=3.0, max_error_m=120.0,
                    usbl=UsblParams(16.0, 145.0, 1.0), _usbl_xy=(8000.0, 6500.0))
    assert fix_sigma(nav, "usbl", (8000.0, 6000.0, -200.0), nav.usbl_xy) == pytest.approx(0.01 * math.hypot(500, 200))
    route = np.array([[1000.0, 6000.0, -150.0], [15000.0, 6000.0, -150.0]])  # 150 m up: no lock
    plan = plan_navigation(w, route, nav, 20.0, 1.5, nav.usbl_xy, step=100.0, compare=False)
    assert plan.ok and "usbl" in plan.kinds
    i = plan.kinds.index("usbl")
    assert plan.points[i, 2] == pytest.approx(-150.0)  # taken where the vehicle is, not at the surface
    assert plan.check.budget.error_m[i] == pytest.approx(
        nav.confidence * fix_sigma(nav, "usbl", plan.points[i], nav.usbl_xy), rel=1e-9)


_USBL_TOML = """name = "usbl-test"
seed = 1
[origin]
lat = 16.0
lon = 145.0
[bounds]
x = [0.0, 16000.0]
y = [0.0, 12000.0]
z = [-600.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 300.0
cell_m = 500.0
[mission]
start = [1000.0, 6000.0, -150.0]
goal = [15000.0, 6000.0, -150.0]
route = [[1000.0, 6000.0, -150.0], [15000.0, 6000.0, -150.0]]
min_altitude_m = 20.0
min_depth_m = 0.0
[navigation]
drift_pct = 0.5
drift_pct_no_lock = 1.5
dvl_range_m = 100.0
fix_error_m = 3.0
max_error_m = 120.0
usbl = { lat = 16.058726, lon = 145.0747642, error_pct = 1.0 }
"""


def test_mission_check_reads_the_usbl_fixes_back_from_fixes_csv(tmp_path, capsys):
    import json

    from auvplan.cli import main
    from auvplan.io.missions.formats import mission_csv
    from auvplan.io.results.records import write_navigation
    from auvplan.io.scenario import loader
    from auvplan.nav import plan_navigation

    toml = tmp_path / "usbl.toml"
    toml.write_text(_USBL_TOML)
    world, mission = loader.build(loader.load(str(toml)))
    nav = mission.navigation
    plan = plan_navigation(world, np.array(mission.route), nav, 20.0, 1.5, nav.usbl_xy, compare=False)
    assert plan.ok and plan.kinds.count("usbl") >= 1  # the ship is near: USBL fixes chosen
    (tmp_path / "with").mkdir()
    (tmp_path / "alone").mkdir()
    for d in ("with", "alone"):
        (tmp_path / d / "mission.csv").write_text(mission_csv(plan.points, world.origin, 1.5))
    write_navigation(tmp_path / "with", plan, world.origin)

    def check(d: str) -> tuple[int, dict]:
        capsys.readouterr()
        code = main(["mission", "check", str(tmp_path / d / "mission.csv"), "--scenario", str(toml), "--json"])
        return code, json.loads(capsys.readouterr().out)["navigation"]

    code, got = check("with")
    assert code == 0 and got["usbl_fixes"] == plan.kinds.count("usbl") and got["fixes"] == plan.metrics()["fixes"]
    np.testing.assert_allclose([leg["nav_error_m"] for leg in got["legs"]], plan.check.budget.leg_error_m, atol=0.01)
    code, got = check("alone")  # the same file without its fixes.csv: the USBL fixes are lost, the budget fails
    assert code == 1 and got["usbl_fixes"] == 0 and got["nav_error_max_m"] > nav.max_error_m
    rows = (tmp_path / "with" / "fixes.csv").read_text().splitlines()
    lat = float(rows[1].split(",")[0])
    rows[1] = rows[1].replace(f"{lat:.7f}", f"{lat + 0.001:.7f}", 1)  # 110 m off its waypoint
    (tmp_path / "with" / "fixes.csv").write_text("\n".join(rows) + "\n")
    assert main(["mission", "check", str(tmp_path / "with" / "mission.csv"), "--scenario", str(toml)]) == 2
    err = capsys.readouterr().err
    assert "fixes.csv: row 2" in err and "Traceback" not in err


def _band_mission():
    """A mission with a surfacing over a seabed step (lock lost and regained), and its error profile."""
    from auvplan.nav import error_profile

    w = _world(depth=300.0, z=lambda x, y: np.where(x < 15000.0, -180.0, -600.0))
    route = np.array([[1000.0, 3000.0, -100.0], [9000.0, 9000.0, -100.0], [12000.0, 9000.0, 0.0],
                      [14000.0, 8000.0, -150.0], [26000.0, 4000.0, -150.0]])
    kinds = ("", "", "gps", "", "")
    return w, route, kinds, error_profile(w, route, kinds, NAV)


def test_error_band_is_the_union_of_the_discs_along_the_route():
    """Oracle: brute force over discs round points every 5 m of the route, radius from the budget's closed form."""
    import shapely

    from auvplan.nav.band import error_band

    w, route, kinds, prof = _band_mission()
    b = mission_budget(w, route, kinds, NAV)
    np.testing.assert_allclose(prof.after_m[np.r_[0, prof.fix.nonzero()[0], -1]][[0, 1]], b.error_m[[0, 2]])
    assert prof.before_m.max() == pytest.approx(b.max_error_m, rel=1e-12)
    band = error_band(prof, quad_segs=16)
    s = np.linspace(0.0, prof.s_m[-1], 6000)  # centres and radii every 5 m, σ linear per sample interval
    cx, cy = np.interp(s, prof.s_m, prof.xyz[:, 0]), np.interp(s, prof.s_m, prof.xyz[:, 1])
    k = np.clip(np.searchsorted(prof.s_m, s, side="right") - 1, 0, prof.s_m.size - 2)
    f = (s - prof.s_m[k]) / (prof.s_m[k + 1] - prof.s_m[k])
    r = prof.after_m[k] + f * (prof.before_m[k + 1] - prof.after_m[k])
    rng = np.random.default_rng(7)
    q = np.column_stack([rng.uniform(0.0, 30000.0, 1500), rng.uniform(0.0, 12000.0, 1500)])
    q = np.vstack([q, np.column_stack([cx, cy])[::12] + rng.normal(0.0, 80.0, (500, 2)),  # near the route too
                   np.column_stack([cx, cy])[::7]])  # and on it: the band is connected, not beads of discs
    gap = np.min(np.hypot(q[:, None, 0] - cx[None, :], q[:, None, 1] - cy[None, :]) - r[None, :], axis=1)
    inside = shapely.contains_xy(band, q[:, 0], q[:, 1])
    tol = 0.01 * r.max()  # polygonal discs (16 segments a quarter) and the oracle's 5 m spacing
    assert np.all(inside[gap < -tol]) and not np.any(inside[gap > tol])
    assert (gap < -tol).sum() > 150 and (gap > tol).sum() > 150


def test_report_draws_the_band_and_the_error_against_time_and_the_folder_reads_it_back(tmp_path):
    import plotly.graph_objects as go
    import shapely

    from auvplan.app.results import load_results
    from auvplan.io.results.records import write_navigation, write_run
    from auvplan.io.scenario import loader
    from auvplan.nav import navigation_of, plan_navigation
    from auvplan.nav.band import error_band
    from auvplan.sim import RunRecord
    from auvplan.viz.navview import figure_nav_error, mark_error_band, nav_profile

    w, route, kinds, prof = _band_mission()
    nav = navigation_of(w, route, kinds, replace_surface(NAV, 100.0), 1.5)
    fig = go.Figure()
    mark_error_band(fig, nav_profile(w, nav), nav)
    band = next(t for t in fig.data if t.meta and t.meta["kind"] == "nav_band")
    ring = np.column_stack([band.x, band.y])
    ring = ring[np.isfinite(ring[:, 0])]
    exact = error_band(prof)
    assert shapely.Polygon(ring).symmetric_difference(exact).area < 1e-6 * exact.area  # the band drawn
    err = figure_nav_error(nav_profile(w, nav), nav)
    line = next(t for t in err.data if t.meta and t.meta["kind"] == "nav_error")
    t, e = np.asarray(line.x) * 3600.0, np.asarray(line.y)
    assert e.max() == pytest.approx(nav.check.budget.max_error_m, rel=1e-12)
    drop = int(np.argmin(np.diff(e)))  # the fix: before at its arrival, after once the 100 s dwell is over
    assert t[drop] == pytest.approx(nav.times_s[0], abs=1e-6) and t[drop + 1] - t[drop] == pytest.approx(100.0)
    assert e[drop + 1] == pytest.approx(NAV.confidence * NAV.fix_error_m)
    assert t[-1] == pytest.approx(np.linalg.norm(np.diff(route, axis=0), axis=1).sum() / 1.5 + 100.0)
    # a results folder written by `run` gives `report DIR` its fixes back (the USBL ones from fixes.csv)
    toml = tmp_path / "usbl.toml"
    toml.write_text(_USBL_TOML)
    world, mission = loader.build(loader.load(str(toml)))
    un = mission.navigation
    plan = plan_navigation(world, np.array(mission.route), un, 20.0, 1.5, un.usbl_xy, compare=False)
    out = tmp_path / "run"
    write_run(out, RunRecord("usbl-test", 1, None, plan.points, plan.points[:0], None, plan), toml.read_text(),
              origin=world.origin)
    write_navigation(out, plan, world.origin)
    record = load_results(out, [])[1]
    assert record.nav is not None and record.nav.kinds == plan.kinds and "usbl" in plan.kinds
    np.testing.assert_allclose(record.nav.check.budget.error_m, plan.check.budget.error_m, rtol=1e-12)


def replace_surface(nav: NavParams, surface_s: float) -> NavParams:
    from dataclasses import replace

    return replace(nav, surface_s=surface_s)


def test_serve_draws_the_band_of_the_mission_being_edited():
    import shapely

    from auvplan.nav.band import error_band
    from auvplan.serve.session import SIMPLIFY_M, nav_band
    from auvplan.sim import Mission

    w, route, kinds, prof = _band_mission()  # its surfacing is the one waypoint at depth 0: read as the fix
    base = Mission("t", tuple(route[0]), tuple(route[-1]))
    assert nav_band(w, base, route) is None  # no [navigation]: nothing drawn
    got = nav_band(w, Mission("t", tuple(route[0]), tuple(route[-1]), navigation=NAV), route)
    xy = np.column_stack([np.array(got["x"], dtype=float), np.array(got["y"], dtype=float)])
    rings = np.split(xy, np.flatnonzero(np.isnan(xy[:, 0])))
    drawn = shapely.union_all([shapely.Polygon(r[np.isfinite(r[:, 0])]) for r in rings if np.isfinite(r).sum() > 6])
    assert drawn.hausdorff_distance(error_band(prof)) <= SIMPLIFY_M + 1e-6
    assert got["max_error_m"] == pytest.approx(mission_budget(w, route, kinds, NAV).max_error_m, abs=0.01)
    assert got["fixes"] == 1 and got["budget_m"] == NAV.max_error_m
