"""The executable mission: safe under every executor's depth semantics, in every format, read back
by real parsers; `mission check`; simulate == run; flow plans as routes; export sizes."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.cli import main
from auvplan.guidance.mission.envelopes import envelope_hits, envelopes_free
from auvplan.guidance.mission.flycheck import fly_check
from auvplan.guidance.mission.waypoints import build_waypoints
from auvplan.io.missions import export, formats
from auvplan.io.results import records
from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.sim import RunRecord, SimResult, decimate, mission_route, planning_problem, route_from_path
from auvplan.world import Sphere
from helpers import WIDE_RIDGE

ORIGIN = (48.0, -125.0)
_ARRAYS = ("t", "position", "heading", "speed", "rudder", "cross_track", "route_error", "progress", "altitude",
           "obstacle_distance")
MIN_ALT = 20.0

_RIDGE_TOML = '\nname = "ridge-check"' + WIDE_RIDGE


@pytest.fixture(scope="module")
def ridge():
    """A seabed rising from 200 m to a 50 m deep ridge crest at x = 5 km (bilinear grid, 100 m),
    and a dense path over it 22 m above the seabed (a planner's output)."""
    world, _ = sc.build(sc.loads(_RIDGE_TOML, "ridge.toml"))
    x = np.arange(0.0, 10001.0, 100.0)
    zb = -200.0 + 150.0 * np.clip(1.0 - np.abs(x - 5000.0) / 2000.0, 0.0, None)  # the analytic seabed
    np.testing.assert_allclose(world.terrain.elevation(x, 1000.0), zb, atol=1e-9)
    assert world.margins.min_altitude == MIN_ALT and world.origin == ORIGIN
    s = np.linspace(500.0, 9500.0, 200)
    path = np.column_stack([s, np.full_like(s, 1000.0), np.maximum(-150.0, np.interp(s, x, zb) + MIN_ALT + 2.0)])
    return world, path


def _held_executor(world, w, pitch_deg, step=1.0):
    """Least altitude of a MOOS-like vehicle: on leg i it steers towards the depth of point i + 1
    at ``pitch_deg`` (depth carried over from leg to leg), sampled every ``step`` metres."""
    z = w[0, 2]
    worst = np.inf
    slope = math.tan(math.radians(min(pitch_deg, 89.9)))
    for a, b in zip(w[:-1], w[1:]):
        length = float(np.hypot(*(b[:2] - a[:2])))
        s = np.linspace(0.0, length, max(int(length / step), 1) + 1)
        zs = z + np.sign(b[2] - z) * np.minimum(np.abs(b[2] - z), s * slope)
        xy = a[:2] + (b[:2] - a[:2]) * (s / max(length, 1e-12))[:, None]
        worst = min(worst, float((zs - world.terrain.elevation(xy[:, 0], xy[:, 1])).min()))
        z = zs[-1]
    return worst


def test_mission_is_safe_with_depth_held_or_ramped_over_a_rising_seabed(ridge):
    world, path = ridge
    w = build_waypoints(path, world)
    assert np.allclose(w[0], path[0]) and np.allclose(w[-1], path[-1])
    assert len(w) < len(path)  # simplified (a staircase: 22 m above a 7.5 % slope leaves 2 m to spare)
    assert envelopes_free(world, w[:-1], w[1:]).all()
    for sem in ("held", "ramp"):
        assert fly_check(world, w, sem).min_altitude_m >= MIN_ALT
    # independent oracle: a vehicle holding each leg's end depth, changing depth at a finite pitch
    for pitch in (15.0, 30.0, 90.0):
        sampled = _held_executor(world, w, pitch)
        exact = fly_check(world, w, "held", pitch).executor_min_altitude_m  # held_track + exact segment test
        assert sampled >= MIN_ALT - 1e-9 and exact >= MIN_ALT - 1e-9
        assert exact <= sampled + 1e-9 and sampled - exact < 0.2  # 1 m samples on slopes <= 0.075
    # the old export (end depth held from the start of each leg, few waypoints) runs into the ridge
    naive = route_from_path(path, 2500.0)
    assert world.path_free(naive)  # fine as a 3D polyline ...
    assert fly_check(world, naive, "held").min_altitude_m < 0  # ... below the seabed when depth is held
    assert _held_executor(world, naive, 30.0) < 0
    assert fly_check(world, naive, "held", 30.0).executor_min_altitude_m < 0


def test_every_format_round_trips_and_rechecks_safe(ridge, tmp_path):
    world, path = ridge
    w = build_waypoints(path, world)
    record = RunRecord("ridge", 0, None, w, w[[0, -1]], None)
    files = export.write_exports(tmp_path, record, ORIGIN, 1.5)
    assert {p.name for p in files} == {f"mission.{f}" for f in export.EXPORT_FORMATS}
    for p in files:
        got, semantics, fmt = formats.read_mission(p, ORIGIN)
        if fmt == "qgc":
            np.testing.assert_allclose(got[0], [w[0, 0], w[0, 1], 0.0], atol=1e-3)  # surface home
            got = got[1:]
        np.testing.assert_allclose(got, w, atol=2e-3, err_msg=p.name)
        assert semantics == ("held" if fmt == "moos" else "ramp")
        check, _ = formats.check_mission_file(p, world)
        assert check.ok and check.min_altitude_m >= MIN_ALT, (p.name, check.as_dict())


def test_exports_parse_with_real_libraries(ridge, tmp_path):
    gpxpy = pytest.importorskip("gpxpy")
    yaml = pytest.importorskip("yaml")
    world, path = ridge
    w = build_waypoints(path, world)
    track = path + np.array([0.0, 2.0, -1.0])
    sim = SimResult(Status.EXACT, True, np.arange(len(track)) * 10.0, track, *(np.zeros(len(track)),) * 6,
                    np.full(len(track), 50.0), np.empty((len(track), 0)), (), "hybrid", 0.0)
    record = RunRecord("ridge", 0, None, w, w[[0, -1]], sim)
    export.write_exports(tmp_path, record, ORIGIN, 1.5)
    g = gpxpy.parse((tmp_path / "mission.gpx").read_text())
    assert len(g.routes) == 1 and len(g.routes[0].points) == len(w)
    assert len(g.tracks[0].segments[0].points) == len(decimate(sim).t)
    np.testing.assert_allclose([p.elevation for p in g.routes[0].points], w[:, 2], atol=1e-3)
    doc = yaml.safe_load((tmp_path / "mission.yaml").read_text())
    assert doc["header"]["frame_id"] == "map" and len(doc["poses"]) == len(w)
    q = doc["poses"][0]["pose"]["orientation"]
    assert math.isclose(sum(q[k] ** 2 for k in "xyzw"), 1.0, rel_tol=1e-5)
    plan_doc = json.loads((tmp_path / "mission.plan").read_text())
    assert plan_doc["fileType"] == "Plan" and plan_doc["mission"]["vehicleType"] == 12  # MAV_TYPE_SUBMARINE
    items = plan_doc["mission"]["items"]
    assert items[0]["command"] == 178 and items[0]["params"][:3] == [1, 1.5, -1]  # the planned speed, leading
    # (a climb or dive has its own horizontal speed command after its waypoint: WPNav keeps a 178's speed level)
    assert all(i["command"] == 16 and i["frame"] == 3 and i["params"][6] < 0 for i in items[1:] if i["command"] != 178)
    assert plan_doc["mission"]["plannedHomePosition"][2] == 0
    text = (tmp_path / "mission.moos").read_text()
    assert "initialize   DEPLOY = false" in text and text.count("BHV_ConstantDepth") == len(w) - 1


def test_envelope_test_matches_brute_force_sampling():
    rng = np.random.default_rng(4)
    shape = Sphere((0.0, 0.0, 0.0), 3.0)
    agree = 0
    for _ in range(150):
        a, b = rng.uniform(-8, 8, 3), rng.uniform(-8, 8, 3)
        hit = envelope_hits(shape, a, b)[0]
        lo, hi = min(a[2], b[2]), max(a[2], b[2])
        s, z = np.meshgrid(np.linspace(0, 1, 120), np.linspace(lo, hi, 120))
        pts = np.column_stack([(a[0] + s * (b[0] - a[0])).ravel(), (a[1] + s * (b[1] - a[1])).ravel(), z.ravel()])
        d = float(shape.distance(pts).min())
        if abs(d) > 0.25:  # away from grazing contact the sampled answer is certain
            assert hit == (d < 0.0)
            agree += 1
    assert agree > 120


def test_mission_check_cli_flags_a_tampered_file(ridge, tmp_path, monkeypatch, capsys):
    world, path = ridge
    w = build_waypoints(path, world)
    (tmp_path / "m.moos").write_text(formats.to_moos(w, 1.5))
    (tmp_path / "scenario.toml").write_text(_RIDGE_TOML)
    scen = str(tmp_path / "scenario.toml")
    assert main(["mission", "check", str(tmp_path / "m.moos"), "--scenario", scen, "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["ok"] and rec["semantics"] == "held" and rec["min_altitude_m"] >= MIN_ALT
    bad = w.copy()
    bad[len(w) // 2, 2] -= 60.0  # 60 m deeper on one leg near the crest
    (tmp_path / "bad.moos").write_text(formats.to_moos(bad, 1.5))
    assert main(["mission", "check", str(tmp_path / "bad.moos"), "--scenario", scen]) == 1
    out = capsys.readouterr().out
    assert "FAIL" in out and "no static obstacle in the scenario" in out and "inf m" not in out
    (tmp_path / "broken.plan").write_text("{\"mission\": 3}")
    assert main(["mission", "check", str(tmp_path / "broken.plan"), "--scenario", scen]) == 2
    assert "broken.plan" in capsys.readouterr().err




def test_flow_plan_route_legs_pass_the_exact_test():
    world, mission = sc.build(sc.load("flow-spheres"))
    planned = plan(planning_problem(world, mission), mission.planner, mission.seed)
    assert planned.status.ok
    route = mission_route(world, mission, planned.path)
    seg = np.stack([route[:-1], route[1:]], axis=1)
    assert world.segments_free(seg, moving=False).all()
    assert envelopes_free(world, route[:-1], route[1:]).all()
    assert len(route) <= len(planned.path)
    old = route_from_path(planned.path, 4 * mission.hybrid.switch_radius)  # the former conversion
    assert not world.path_free(old)


def test_simulate_and_run_fly_the_same_track(tmp_path, capsys):
    a, b = tmp_path / "sim", tmp_path / "run"
    assert main(["simulate", "dynamic-terrain", "--out", str(a), "--json", "--full"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["avoidance"] == "apf"  # the scenario's avoidance, reported as used
    assert main(["run", "dynamic-terrain", "--out", str(b), "--full", "--json"]) == 0
    run = json.loads(capsys.readouterr().out)
    ta = np.loadtxt(a / "track.csv", delimiter=",", skiprows=1)
    tb = np.loadtxt(b / "track.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(ta, tb)
    assert rec["distance_m"] == run["simulation"]["distance_m"]
    for f in sorted(b.glob("mission.*")):
        check, _ = formats.check_mission_file(f, sc.build(sc.load("dynamic-terrain"))[0])
        assert check.ok and check.min_altitude_m >= 30.0, f.name


def test_track_exports_of_a_200_km_mission_stay_under_2_mb(tmp_path):
    n = 200_000 // 0.15  # 200 km at 1.5 m/s, one sample every 0.1 s
    n = int(n)
    t = np.arange(n) * 0.1
    s = t * 1.5
    pos = np.column_stack([s * 0.8, s * 0.6, -500.0 + 100.0 * np.sin(s / 5000.0)])
    sim = SimResult(Status.EXACT, True, t, pos, *(np.zeros(n),) * 6, np.full(n, 80.0), np.empty((n, 0)), (),
                    "hybrid", 0.0)
    w = pos[:: n // 40]
    record = RunRecord("long", 0, None, w, w[[0, -1]], sim)
    export.write_exports(tmp_path, record, ORIGIN, 1.5)
    records.write_sim(tmp_path, sim, "long", 0)
    for f in list(tmp_path.glob("mission.*")) + [tmp_path / "track.csv"]:
        assert f.stat().st_size <= 2_000_000, (f.name, f.stat().st_size)
    d = decimate(sim)
    gaps = np.linalg.norm(np.diff(d.position, axis=0), axis=1)
    assert gaps.max() <= 20.0 + 1.5 * 0.1 + 1e-9  # one sample every 20 m at most
    short = replace(record, sim=replace(sim, **{k: getattr(sim, k)[:20_000] for k in _ARRAYS}))
    export.write_exports(tmp_path / "dec", short, ORIGIN, 1.5, ("kml",))
    export.write_exports(tmp_path / "full", short, ORIGIN, 1.5, ("kml",), full=True)  # every sample on request
    assert (tmp_path / "full" / "mission.kml").stat().st_size > 10 * (tmp_path / "dec" / "mission.kml").stat().st_size


def test_decimate_keeps_the_extremes():
    n = 5000
    t = np.arange(n) * 0.1
    pos = np.column_stack([t, np.zeros(n), np.zeros(n)])
    alt = np.full(n, 50.0)
    alt[1234] = 3.0
    sim = SimResult(Status.EXACT, True, t, pos, *(np.zeros(n),) * 6, alt, np.empty((n, 0)), (), "hybrid", 0.0)
    d = decimate(sim)
    assert d.altitude.min() == 3.0 and d.t[0] == 0.0 and d.t[-1] == t[-1]
    assert replace(sim).t.size == n


def test_held_track_changes_depth_at_the_pitch_and_carries_the_lag_over():
    from auvplan.guidance.mission.flycheck import held_track

    w = np.array([[0.0, 0.0, -100.0], [100.0, 0.0, -50.0], [200.0, 0.0, -50.0]])
    np.testing.assert_allclose(held_track(w, 45.0), [[0, 0, -100], [50, 0, -50], [100, 0, -50], [200, 0, -50]],
                               atol=1e-9)
    t = math.tan(math.radians(10.0))
    np.testing.assert_allclose(held_track(w, 10.0), [[0, 0, -100], [100, 0, -100 + 100 * t],
                                                     [200, 0, -100 + 200 * t]], atol=1e-9)


def test_a_plan_without_flight_exports_its_executable_mission(tmp_path):
    out = tmp_path / "p"
    assert main(["plan", "dynamic-terrain", "--out", str(out)]) == 0
    assert main(["export", str(out), "--format", "moos", "plan"]) == 0
    world, mission = sc.build(sc.load("dynamic-terrain"))
    record, _ = records.read_run(out)
    expected = mission_route(world, mission, record.plan.path)
    np.testing.assert_allclose(formats.parse_moos((out / "mission.moos").read_text()), expected, atol=1e-3)
    for name in ("mission.moos", "mission.plan"):
        check, _ = formats.check_mission_file(out / name, world)
        assert check.ok and check.min_altitude_m >= world.margins.min_altitude
