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


def test_mariana_nav_plans_fewer_fixes_than_the_best_period_and_mission_check_fails_without_them(tmp_path):
    from auvplan.cli import main
    from auvplan.io.missions.formats import mission_csv
    from auvplan.io.scenario import loader
    from auvplan.sim.pipeline import navigation_plan, planned_route

    world, mission = loader.build(loader.load("mariana-nav"))
    _, route = planned_route(world, mission, 1)
    plan = navigation_plan(world, mission, route)
    assert plan is not None and plan.ok
    m = plan.metrics()
    assert m["fixes"] <= 0.8 * m["fixes_fixed_period"]  # issue 52: at least 20 % fewer
    assert m["nav_error_max_m"] <= mission.navigation.max_error_m
    (tmp_path / "bare.csv").write_text(mission_csv(route, world.origin, 1.5))
    (tmp_path / "fixed.csv").write_text(mission_csv(plan.points, world.origin, 1.5))
    assert main(["mission", "check", str(tmp_path / "bare.csv"), "--scenario", "mariana-nav", "--json"]) == 1
    assert main(["mission", "check", str(tmp_path / "fixed.csv"), "--scenario", "mariana-nav", "--json"]) == 0


def test_the_closed_loop_steers_by_a_drifting_estimate_only_when_asked_and_a_fix_resets_it():
    from dataclasses import replace

    from auvplan.sim import Mission, SimParams, simulate

    w = _world(depth=300.0)
    route = np.array([[1000.0, 6000.0, -250.0], [3000.0, 6000.0, -250.0], [4000.0, 6000.0, 0.0],
                      [5000.0, 6000.0, -250.0], [7000.0, 6000.0, -250.0]])
    nav = NavParams(drift_pct=3.0, drift_pct_no_lock=6.0, dvl_range_m=100.0, fix_error_m=1.0, max_error_m=900.0)
    base = Mission("t", tuple(route[0]), tuple(route[-1]), sim=SimParams(dt=1.0, record_every=2))
    plain = simulate(w, base, route=route, rng=4)
    quiet = simulate(w, replace(base, navigation=nav), route=route, rng=4)  # drift off by default: nothing changes
    np.testing.assert_array_equal(plain.position, quiet.position)
    assert plain.nav_error is None
    flown = simulate(w, replace(base, navigation=nav, nav_drift=True), route=route, rng=4)
    assert flown.arrived and flown.nav_error is not None
    at_fix = int(np.argmin(np.hypot(flown.position[:, 0] - 4000.0, flown.position[:, 2])))
    before, after = flown.nav_error[:at_fix - 5], flown.nav_error[at_fix + 5:]
    assert before.max() > 20.0 * after[0]  # reset to the fix's own error, then growing again
    assert after[-1] > after[0]


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
