"""The vehicle's limits: pitch, fly-by turns, depth rating; terrain following within them."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import shapely

from auvplan import cli
from auvplan._types import Status
from auvplan.errors import ScenarioError
from auvplan.guidance.mission.envelopes import envelopes_free
from auvplan.guidance.mission.fit import fit_turns
from auvplan.guidance.mission.flycheck import fly_check
from auvplan.io.scenario import loader as scenario_io
from auvplan.path import resample_polyline
from auvplan.path.flyable import (
    PITCH_SLACK_DEG,
    VehicleLimits,
    check_limits,
    flyby_arcs,
    leg_pitch_deg,
    leg_turn_radius,
)
from auvplan.path.pitch import (
    cone_max,
    pitch_profile,
)
from auvplan.planners import plan
from auvplan.planners.core.base import PlanResult
from auvplan.planners.core.vehicle_limits import enforce_limits
from auvplan.sim.pipeline import mission_route, planned_route, planning_problem
from helpers import RIDGE_ROUTE, build_toml, ridge_toml

RIDGE = ridge_toml(route=True, follow_altitude_m=20.0)


# ---------------------------------------------------------------------- geometry against independent computations
def test_flyby_turn_geometry_against_shapely_offsets() -> None:
    """Centre of the fly-by arc = intersection of the two legs offset by R inwards (shapely); its
    tangent points = the centre's feet on the legs, at R tan(Δψ/2) from the corner."""
    rng = np.random.default_rng(4)
    for _ in range(20):
        p = np.c_[rng.uniform(-100, 100, (3, 2)), np.zeros(3)]
        u, v = p[1, :2] - p[0, :2], p[2, :2] - p[1, :2]
        dpsi = math.acos(np.clip(u @ v / np.linalg.norm(u) / np.linalg.norm(v), -1, 1))
        if not 0.1 < dpsi < 2.8:
            continue
        r = 7.5
        entry, exit_, centre = flyby_arcs(p, r)
        left = u[0] * v[1] - u[1] * v[0] > 0
        side = "left" if left else "right"
        leg1 = shapely.LineString(p[:2, :2]).offset_curve(r if left else -r)
        leg2 = shapely.LineString(p[1:, :2]).offset_curve(r if left else -r)
        a1, b1 = np.asarray(leg1.coords)[[0, -1]]
        a2, b2 = np.asarray(leg2.coords)[[0, -1]]
        far1 = shapely.LineString([a1 - 1e3 * (b1 - a1), b1 + 1e3 * (b1 - a1)])
        far2 = shapely.LineString([a2 - 1e3 * (b2 - a2), b2 + 1e3 * (b2 - a2)])
        c = np.asarray(far1.intersection(far2).coords)[0]
        np.testing.assert_allclose(centre[1], c, atol=1e-6, err_msg=side)
        foot1 = np.asarray(shapely.LineString(p[:2, :2]).interpolate(
            shapely.LineString(p[:2, :2]).project(shapely.Point(c))).coords)[0]
        np.testing.assert_allclose(entry[1], foot1, atol=1e-6)
        assert np.linalg.norm(exit_[1] - p[1, :2]) == pytest.approx(r * math.tan(dpsi / 2), rel=1e-9)
        assert np.linalg.norm(exit_[1] - c) == pytest.approx(r, rel=1e-9)


def test_largest_radius_of_a_leg_is_analytic() -> None:
    # a square corner on 5 m legs: R tan(45°) = R must fit in 5 m; a 60° turn at both ends of a 20 m leg
    sq = np.array([[0, 0, 0], [5, 0, 0], [5, 5, 0]], float)
    assert leg_turn_radius(sq) == pytest.approx([5.0, 5.0])
    z = np.array([[0, 0, 0], [20, 0, 0], [30, 10 * math.sqrt(3), 0], [50, 10 * math.sqrt(3), 0]], float)
    want = 20.0 / (2 * math.tan(math.radians(30)))
    assert leg_turn_radius(z)[1] == pytest.approx(want, rel=1e-12)
    assert leg_pitch_deg(np.array([[0, 0, 0], [10, 0, 10]], float)) == pytest.approx([45.0])


def test_cone_envelope_against_brute_force() -> None:
    rng = np.random.default_rng(1)
    s = np.sort(rng.uniform(0, 1000, 300))
    g = rng.normal(0, 30, 300)
    k = math.tan(math.radians(17))
    brute = np.max(g[None, :] - k * np.abs(s[:, None] - s[None, :]), axis=1)
    np.testing.assert_allclose(cone_max(s, g, k), brute, atol=1e-9)


def test_pitch_profile_keeps_limit_floor_and_ends() -> None:
    rng = np.random.default_rng(2)
    s = np.cumsum(rng.uniform(1, 20, 400))
    s -= s[0]
    seabed = -100 + np.cumsum(rng.normal(0, 3, 400))
    floor = seabed + 10
    k = math.tan(math.radians(15))
    z0, z1 = floor[0] + 5, floor[-1] + 50
    f = floor.copy()
    f[[0, -1]] = -np.inf
    z, ok = pitch_profile(s, floor + 20, f, k, z0, z1)
    assert ok and z[0] == pytest.approx(z0) and z[-1] == pytest.approx(z1)
    assert np.all(np.abs(np.diff(z) / np.diff(s)) <= k + 1e-9)
    assert np.all(z[1:-1] >= floor[1:-1] - 1e-9)


# ---------------------------------------------------------------------- the mission builder
def test_ridge_steeper_than_the_pitch_limit_is_climbed_early() -> None:
    world, mission = build_toml(RIDGE)
    assert mission.vehicle.max_pitch_deg == 20.0  # the REMUS-class default
    planned, route = planned_route(world, mission, 1)
    assert planned is None and route is not None
    k = math.tan(math.radians(20.0))
    assert np.all(np.abs(leg_pitch_deg(route)) <= 20.0 + 1e-9)
    # the seabed rises 40 m over 60 m (33.7°): hold 20 m altitude, climbing at 20° from
    # x = 1000 - 40 / tan 20° = 890 m, 50 m before the ridge's foot (x = 940 m)
    x_climb = 1000.0 - 40.0 / k
    z_at = np.interp(np.array([850.0, 900.0, 940.0, 1000.0]), route[:, 0], route[:, 2])
    flat, crest = -80.0, -40.0
    assert z_at[0] == pytest.approx(flat, abs=1.1)
    assert z_at[2] == pytest.approx(flat + (940.0 - x_climb) * k, abs=1.5)  # already 18 m up at the foot
    assert z_at[3] == pytest.approx(crest, abs=1.5)
    for semantics in ("ramp", "held"):
        check = fly_check(world, route, semantics, 20.0)
        assert check.min_altitude_m >= 10.0 and check.ok
    # without the climb spread the vehicle would need 33.7°: the check names the leg and the limit
    naive = np.array([[100, 200, -80], [940, 200, -80], [1000, 200, -40], [1060, 200, -80], [1900, 200, -80]],
                     float)
    report = check_limits(naive, VehicleLimits(20.0, 10.0))
    assert [(v.leg, v.limit) for v in report.violations] == [(1, "max_pitch_deg"), (2, "max_pitch_deg")]


ZIGZAG = ridge_toml() + ('route = [[100.0, 200.0, -80.0], [106.0, 204.0, -80.0], [112.0, 200.0, -80.0], '
                         '[118.0, 204.0, -80.0], [1900.0, 200.0, -80.0]]\n')


def test_zigzag_tighter_than_the_turn_radius_is_infeasible() -> None:
    world, mission = build_toml(ZIGZAG)
    planned, route = planned_route(world, mission, 1)
    assert route is None and planned is not None and planned.status is Status.INFEASIBLE
    assert "leg 1: its turns fit a radius of 5.4 m only < turn_radius_m = 10" in planned.message
    # (7.2 m legs, 67° turns: 2 x 10 tan(33.7°) = 13.3 m needed); at a 3 m turn radius 4 m fit
    world, mission = build_toml(ZIGZAG.replace("[mission]", "[vehicle]\nturn_radius_m = 3.0\n[mission]"))
    planned, route = planned_route(world, mission, 1)
    assert planned is None and route is not None and len(route) == 5


def test_fitted_turns_keep_their_tangent_lengths() -> None:
    # terrain following along a route that turns 90° on the ridge's crest: the profile changes
    # there, yet no waypoint lies inside the turn region (R tan 45° = 10 m from the corner)
    text = RIDGE.replace(RIDGE_ROUTE,
                         'route = [[100.0, 200.0, -80.0], [1000.0, 200.0, -40.0], [1000.0, 380.0, -40.0]]').replace(
        "goal = [1900.0, 200.0, -80.0]", "goal = [1000.0, 380.0, -40.0]")
    world, mission = build_toml(text)
    _, route = planned_route(world, mission, 1)
    assert route is not None
    corner = np.flatnonzero((route[:, 0] == 1000.0) & (route[:, 1] == 200.0))
    assert corner.size == 1
    others = np.delete(route[:, :2], corner, axis=0)
    assert np.hypot(*(others - [1000.0, 200.0]).T).min() >= 10.0 - 1e-9
    report = check_limits(route, VehicleLimits(20.0, 10.0))
    assert report.ok and report.tightest_turn_m >= 10.0 and report.max_pitch_deg <= 20.0 + 1e-9
    assert fly_check(world, route, "ramp").ok and fly_check(world, route, "held", 20.0).ok


# ---------------------------------------------------------------------- planners
def test_every_planner_result_is_held_to_the_limits() -> None:
    world, mission = scenario_io.build(scenario_io.load("flow-ellipsoid"))
    # the line body (wave 4's default): its streamline climbs steeper than the limit, which the hold repairs
    # (the exact ellipsoid body of wave 5 stays within 25° on this scene)
    spec = replace(mission.planner, name="flow", flow=replace(mission.planner.flow, rankine="line", path="streamline"))
    raw = plan(replace(planning_problem(world, mission), limits=None), spec)
    assert raw.status is Status.EXACT and np.abs(leg_pitch_deg(raw.path)).max() > 30.0
    held = plan(planning_problem(world, mission), spec)
    assert held.status is Status.EXACT and "repaired" in held.message
    assert np.abs(leg_pitch_deg(held.path)).max() <= 20.0 + 1e-9 and world.path_free(held.path)
    np.testing.assert_array_equal(held.path[:, :2], raw.path[:, :2])  # the track is kept, the depths change
    hairpin = np.array([[-30, 0, -5], [-20, 0, -5], [-20, 4, -5], [30, 4, 0]], float)
    fake = replace(raw, path=hairpin)
    out = enforce_limits(planning_problem(world, mission), mission.planner, fake)
    assert out.status is Status.INFEASIBLE and "turn_radius_m = 10" in out.message


def test_depth_rating_bounds_the_mission() -> None:
    text = RIDGE.replace("[mission]", "[vehicle]\nmax_depth_m = 50.0\n[mission]")
    with pytest.raises(ScenarioError, match="deeper than max_depth 50"):
        build_toml(text)


def test_mission_check_flags_a_steep_leg_and_a_tight_turn(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scen = tmp_path / "ridge.toml"
    scen.write_text(ridge_toml(route=True))
    f = tmp_path / "mission.csv"
    f.write_text("x,y,z\n100,200,-80\n500,200,-80\n520,200,-60\n800,200,-60\n803,203,-60\n1900,203,-60\n")
    assert cli.main(["mission", "check", str(f), "--scenario", str(scen), "--json"]) == 1
    rec = json.loads(capsys.readouterr().out)["vehicle"]
    bad = {(v["leg"], v["limit"]) for v in rec["violations"]}
    assert bad == {(1, "max_pitch_deg"), (3, "turn_radius_m")}
    assert rec["max_pitch_deg"] == pytest.approx(45.0) and rec["max_pitch_leg"] == 1
    assert rec["tightest_turn_m"] == pytest.approx(math.hypot(3, 3) / (2 * math.tan(math.radians(22.5))), rel=1e-9)
    good = tmp_path / "ok.csv"
    good.write_text("x,y,z\n100,200,-80\n500,200,-80\n600,200,-45\n1900,200,-45\n")
    assert cli.main(["mission", "check", str(good), "--scenario", str(scen)]) == 0
    assert "vehicle: OK — largest pitch 19.3° (leg 1; max_pitch_deg 20)" in capsys.readouterr().out


def test_plan_result_message_names_leg_and_limit() -> None:
    r = PlanResult(Status.EXACT, np.array([[0, 0, -50], [10, 0, -50], [10, 3, -50]], float), 1.0, {}, 1, 1, 0.0,
                   np.empty(0), "grid")
    world, mission = build_toml(RIDGE)
    out = enforce_limits(planning_problem(world, mission), mission.planner, r)
    assert out.status is Status.INFEASIBLE
    assert out.message.endswith("leg 1: its turns fit a radius of 3.0 m only < turn_radius_m = 10")


def test_terrain_following_on_real_bathymetry_climbs_as_late_as_the_pitch_allows() -> None:
    """marcus-terrain-follow (real ETOPO1, written in lat/lon): every leg within 12°, never below
    min_altitude under either depth semantics, and the scheduled depth is the least 12°-limited
    profile above seabed + 50 m (independent O(N²) cone envelope along the route)."""
    world, mission = scenario_io.build(scenario_io.load("marcus-terrain-follow"))
    assert mission.follow_altitude_m == 50.0 and mission.vehicle.max_pitch_deg == 12.0
    planned, route = planned_route(world, mission, 1)
    assert planned is None and route is not None
    assert np.abs(leg_pitch_deg(route)).max() <= 12.0 + 1e-9
    assert fly_check(world, route, "ramp").min_altitude_m >= 20.0
    held = fly_check(world, route, "held", 12.0)
    assert held.ok and held.min_altitude_m >= 20.0
    d = resample_polyline(route, 50.0)
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(d[:, :2], axis=0).T))]
    g = world.seabed(d[:, 0], d[:, 1]) + 50.0
    k = math.tan(math.radians(12.0 - PITCH_SLACK_DEG))  # the builder keeps 0.05° for export rounding
    brute = np.max(g[None, :] - k * np.abs(s[:, None] - s[None, :]), axis=1)
    diff = d[:, 2] - brute
    assert -2.0 <= diff.min() and diff.max() <= 3.5 and np.percentile(np.abs(diff), 99) <= 2.0
    assert np.mean(np.abs(d[:, 2] - g) <= 5.0) > 0.5  # holds 50 ± 5 m on over half the route


def test_terrain_following_holds_the_altitude_over_the_turn_arc() -> None:
    """A 90° turn on the ridge's flank: the fly-by arc cuts the corner towards the crest, over
    seabed higher than under either leg; the altitude is held over the arc (flyby_arcs), not
    only over the polyline."""
    text = RIDGE.replace(RIDGE_ROUTE,
                         'route = [[1015.0, 20.0, -50.0], [1015.0, 300.0, -50.0], [100.0, 300.0, -80.0]]').replace(
        "start = [100.0, 200.0, -80.0]", "start = [1015.0, 20.0, -50.0]").replace(
        "goal = [1900.0, 200.0, -80.0]", "goal = [100.0, 300.0, -80.0]")
    world, mission = build_toml(text)
    _, route = planned_route(world, mission, 1)
    assert route is not None
    k = int(np.flatnonzero((route[:, 0] == 1015.0) & (route[:, 1] == 300.0))[0])
    entry, exit_, centre = flyby_arcs(route[k - 1:k + 2], 10.0)
    a0 = np.arctan2(*(entry[1] - centre[1])[::-1])
    a1 = np.arctan2(*(exit_[1] - centre[1])[::-1])
    ang = a0 + ((a1 - a0 + np.pi) % (2 * np.pi) - np.pi) * np.linspace(0, 1, 201)
    arc = centre[1] + 10.0 * np.c_[np.cos(ang), np.sin(ang)]
    assert np.hypot(*(arc[100] - [1015.0, 300.0])) == pytest.approx(10.0 * (math.sqrt(2) - 1), rel=1e-6)
    over_arc = world.seabed(arc[:, 0], arc[:, 1]).max()
    under_legs = world.seabed(np.full(2, 1015.0), np.array([290.0, 300.0])).max()
    assert over_arc > under_legs + 1.5  # the arc passes closer to the crest
    # the depth the vehicle holds on the arc lies between those of the turn region's ends
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(route[:, :2], axis=0).T))]
    sk = s[k]
    z_lo = np.interp([sk - 10.0, sk, sk + 10.0], s, route[:, 2]).min()
    assert z_lo - over_arc >= 20.0 - 1.1  # follow_altitude_m 20 over the arc (1 m chord tolerance)


def test_planned_mission_drops_corners_whose_turns_do_not_fit() -> None:
    """A planned path with a 4 m jog (two 53° turns on 5 m legs: 10 m needs 2 x 5 m): the mission
    builder drops the jog where the straight leg is free; with an obstacle on the straight it drops
    other corners, keeping every leg's envelope free."""
    world, mission = build_toml(ridge_toml(route=True))
    path = np.array([[100, 200, -80], [500, 200, -80], [503, 204, -80], [506, 200, -80], [800, 200, -80]], float)
    assert not check_limits(path, VehicleLimits(20.0, 10.0)).ok
    route = mission_route(world, mission, path)
    assert check_limits(route, VehicleLimits(20.0, 10.0)).ok
    assert np.all(route[:, 1] == 200.0)  # the jog is gone
    blocked = build_toml(ridge_toml(route=True) + """
[[obstacles]]
center = [503.0, 199.0, -80.0]
radius = 1.5
""")
    kept = fit_turns(path, blocked[0], 10.0)
    assert envelopes_free(blocked[0], kept[:-1], kept[1:]).all() and check_limits(kept, VehicleLimits(20.0, 10.0)).ok
    assert not np.all(kept[:, 1] == 200.0)  # the straight leg meets the obstacle: the mission cuts another way


def test_a_turn_wider_than_the_earth_reads_straight():
    """Three points on a line, the middle one 1 nm off it (a lat/lon file's rounding): the fly-by radius is finite
    but absurd (~1e12 m); the helm line says the legs are straight, while a real 41 m turn is printed."""
    from auvplan.path.flyable import STRAIGHT_M, leg_turn_radius
    from auvplan.path.legs import helm_check

    p = np.array([[0.0, 0.0, -10.0], [500.0, 1e-9, -10.0], [1000.0, 0.0, -10.0]])
    r = leg_turn_radius(p)
    assert np.isfinite(r).all() and r.min() > STRAIGHT_M
    report = helm_check(p, VehicleLimits(20.0, 10.0, 300.0))
    assert "tightest turn none (straight)" in report.summary
    bent = np.array([[0.0, 0.0, -10.0], [100.0, 0.0, -10.0], [200.0, 100.0, -10.0]])
    assert f"tightest turn {helm_check(bent, VehicleLimits(20.0, 10.0, 300.0)).tightest_turn_m:.1f} m" in \
        helm_check(bent, VehicleLimits(20.0, 10.0, 300.0)).summary
