"""Edges 12: the operator surfaces never read "fine" where auvplan's own verdict is FAIL (each test failed on the
code before its fix)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import shapely

from helpers import WIDE_RIDGE, ZONES_PLANE

_TOML = '\nname = "surfaces"' + ZONES_PLANE + """min_altitude_m = 20.0
min_depth_m = 1.0
max_depth_m = 300.0
[[zones]]
name = "shallows"
polygon = [[600.0, 300.0], [900.0, 300.0], [900.0, 700.0], [600.0, 700.0]]
top_m = 0.0
bottom_m = 5.0
"""


def _check(tmp_path, capsys, name: str, text: str, scenario: str = _TOML, *extra: str) -> tuple[int, dict]:
    from auvplan.cli import main

    scen = tmp_path / "s.toml"
    scen.write_text(scenario)
    f = tmp_path / name
    f.write_text(text)
    code = main(["mission", "check", str(f), "--scenario", str(scen), "--json", *extra])
    return code, json.loads(capsys.readouterr().out)


@pytest.mark.parametrize(("name", "text", "extra", "failed"), [
    ("zone.csv", "x,y,z\n100,500,-3\n2100,500,-3\n", "", "zones"),  # 3 m deep through the 0-5 m band
    ("steep.csv", "x,y,z\n1000,500,-150\n1100,500,-10\n1300,500,-10\n", "", "vehicle"),  # a 54.5 deg climb
    ("energy.csv", "x,y,z\n100,500,-150\n2100,500,-10\n", "[vehicle]\nbattery_wh = 1.0\n", "energy"),
])
def test_mission_check_json_ok_is_the_exit_code_s_verdict(tmp_path, capsys, name, text, extra, failed):
    """Oracle: the exit code.  ``--json``'s top-level ``ok`` was the seabed check's alone (``MissionCheck.ok``): a
    file entering a zone, breaking the vehicle's pitch or the energy budget read ``"ok": true`` with exit 1."""
    code, rec = _check(tmp_path, capsys, name, text, _TOML + extra)
    assert code == 1 and rec["ok"] is False
    assert rec["check_ok"] is True  # the seabed/obstacles/surface/band/bounds verdict, kept under its own name
    assert {"zones": any(z["entered_legs"] for z in rec.get("zones", [])), "vehicle": not rec["vehicle"]["ok"],
            "energy": rec["energy"]["energy_status"] == "RESERVE_BROKEN"}[failed]


def test_mission_check_json_ok_is_true_when_every_check_passes(tmp_path, capsys):
    code, rec = _check(tmp_path, capsys, "fine.csv", "x,y,z\n100,500,-150\n2100,500,-10\n")
    assert code == 0 and rec["ok"] is True and rec["check_ok"] is True


def _prism_distance(poly: shapely.Polygon, top: float, bottom: float, p: np.ndarray) -> float:
    """Least 3D distance of points ``(N, 3)`` to a prism between depths ``top`` and ``bottom`` (m), by shapely."""
    horizontal = shapely.distance(poly, shapely.points(p[:, 0], p[:, 1]))
    depth = -p[:, 2]
    vertical = np.maximum(0.0, np.maximum(top - depth, depth - bottom))
    return float(np.hypot(horizontal, vertical).min())


def test_a_held_mission_s_closest_approach_is_measured_on_the_executor_s_track(tmp_path, capsys):
    """Oracle: shapely on the executor's track sampled every 0.5 m, built by hand.  A MOOS mission climbing from
    150 m to 10 m over 2 km levels at 10 m within 140 / tan 15° = 522.5 m, and flies over the 0-5 m band (x 600-900)
    5 m below it; its straight leg passes it 94-115 m deep.  ``mission check`` reported the straight leg's
    89 m, the track's 5 m is the clearance the vehicle keeps."""
    from auvplan.io.missions import formats

    w = np.array([[100.0, 500.0, -150.0], [2100.0, 500.0, -10.0]])
    code, rec = _check(tmp_path, capsys, "early.moos", formats.to_moos(w, 1.5))
    level = np.array([100.0 + 140.0 / math.tan(math.radians(15.0)), 500.0, -10.0])
    s = np.linspace(0.0, 1.0, 4001)[:, None]
    track = np.vstack([w[0] + s * (level - w[0]), level + s * (w[1] - level)])
    poly = shapely.box(600.0, 300.0, 900.0, 700.0)
    oracle, straight = _prism_distance(poly, 0.0, 5.0, track), _prism_distance(poly, 0.0, 5.0, w[0] + s * (w[1] - w[0]))
    assert abs(oracle - 5.0) < 1e-9 and straight > 80.0
    (zone,) = rec["zones"]
    assert code == 0 and zone["entered_legs"] == [] and abs(zone["closest_m"] - oracle) < 0.5
    assert rec["zones_measured_on"] == "the executor's track at 15° pitch"
    code, rec = _check(tmp_path, capsys, "early.csv", "x,y,z\n100,500,-150\n2100,500,-10\n")  # a ramp: its leg
    assert rec["zones_measured_on"] == "the straight legs" and abs(rec["zones"][0]["closest_m"] - straight) < 12.5


@pytest.mark.parametrize("pitch", [8.0, 30.0])
def test_the_held_closest_approach_follows_the_pitch(tmp_path, capsys, pitch):
    """Oracle: as above at another ``--pitch``: the track levels at x = 100 + 140 / tan(pitch)."""
    from auvplan.io.missions import formats

    w = np.array([[100.0, 500.0, -150.0], [2100.0, 500.0, -10.0]])
    rec = _check(tmp_path, capsys, "p.moos", formats.to_moos(w, 1.5), _TOML, "--pitch", str(pitch))[1]
    level = np.array([100.0 + 140.0 / math.tan(math.radians(pitch)), 500.0, -10.0])
    s = np.linspace(0.0, 1.0, 4001)[:, None]
    track = np.vstack([w[0] + s * (level - w[0]), level + s * (w[1] - level)])
    oracle = _prism_distance(shapely.box(600.0, 300.0, 900.0, 700.0), 0.0, 5.0, track)
    assert abs(rec["zones"][0]["closest_m"] - oracle) < 12.5


def test_a_held_leg_whose_envelope_alone_enters_reports_no_clearance(tmp_path, capsys):
    """Oracle: the envelope (10-150 m deep) meets a 60-120 m band at x 1500-1800 that the track (10 m) and the
    straight leg (52-31 m) pass above: entered, so its closest approach is 0, not the track's 50 m."""
    from auvplan.io.missions import formats

    slow = '[[zones]]\nname = "slow"\npolygon = [[1500.0, 300.0], [1800.0, 300.0], [1800.0, 700.0], [1500.0, 700.0]]\n'
    w = np.array([[100.0, 500.0, -150.0], [2100.0, 500.0, -10.0]])
    scenario = _TOML + slow + "top_m = 60.0\nbottom_m = 120.0\n"
    code, rec = _check(tmp_path, capsys, "e.moos", formats.to_moos(w, 1.5), scenario)
    assert code == 1 and rec["ok"] is False
    assert rec["zones"][1] == {"name": "slow", "closest_m": 0.0, "entered_legs": [0]}  # leg 0 leaves waypoint 0


def test_the_seabed_following_track_has_the_exact_extremes_of_a_bilinear_seabed():
    """Oracle: the seabed sampled every 2 cm along a diagonal leg over a random bilinear grid (its elevation a
    quadratic in each cell along the leg).  Every vertex lies on the commanded altitude above the seabed, and the
    track's shallowest and deepest vertices are the sampled extremes."""
    from auvplan.guidance.mission.terrain_legs import terrain_track
    from auvplan.world.terrain import Terrain

    rng = np.random.default_rng(12)
    t = Terrain(np.arange(0.0, 501.0, 50.0), np.arange(0.0, 301.0, 30.0), rng.uniform(-120.0, -20.0, (11, 11)))
    w = np.array([[10.0, 5.0, -60.0], [470.0, 290.0, 0.0], [480.0, 20.0, -90.0]])
    w[1, 2] = float(t.elevation(470.0, 290.0)) + 12.0  # altitudes: 60 + zb(w0) ... 12 ... ends at w2's
    track, leg = terrain_track(t, w, [True, False])
    assert leg[-1] == 1 and (leg[:-1] == 0).all() and np.array_equal(track[-1], w[-1])
    ha = w[0, 2] - float(t.elevation(10.0, 5.0))
    s = np.linspace(0.0, 1.0, 27_000)  # 540 m / 2 cm
    xy = w[0, :2] + s[:, None] * (w[1, :2] - w[0, :2])
    z = t.elevation(xy[:, 0], xy[:, 1]) + ha + s * (12.0 - ha)
    on = track[:-1]
    sv = np.hypot(*(on[:, :2] - w[0, :2]).T) / np.hypot(*(w[1, :2] - w[0, :2]))
    np.testing.assert_allclose(on[:, 2], t.elevation(on[:, 0], on[:, 1]) + ha + sv * (12.0 - ha), atol=1e-9)
    # between two vertices the track is monotone: its extremes, every kink (grid line) and every turn, are vertices
    k = np.clip(np.searchsorted(sv, s, side="right") - 1, 0, sv.size - 2)
    lo, hi = np.minimum(on[k, 2], on[k + 1, 2]), np.maximum(on[k, 2], on[k + 1, 2])
    assert ((z >= lo - 1e-6) & (z <= hi + 1e-6)).all()
    assert z.max() - 1e-9 <= on[:, 2].max() and z.min() + 1e-9 >= on[:, 2].min()


_RIDGE = '\nname = "ridge-shallows"' + WIDE_RIDGE + """[[zones]]
name = "shallows"
polygon = [[4000.0, 0.0], [6000.0, 0.0], [6000.0, 2000.0], [4000.0, 2000.0]]
top_m = 0.0
bottom_m = 20.0
"""


def _plan(items: list[tuple[float, float, int, float]]) -> str:
    """A QGC plan by hand: home on the surface above the first item, then ``(x, y, frame, altitude)`` items."""
    from auvplan.io.data.geo import LocalFrame

    f = LocalFrame(48.0, -125.0)
    ll = [f.inverse(x, y) for x, y, _, _ in items]
    return json.dumps({"fileType": "Plan", "version": 1, "groundStation": "QGroundControl", "mission": {
        "plannedHomePosition": [float(ll[0][1]), float(ll[0][0]), 0.0], "items": [
            {"type": "SimpleItem", "command": 16, "frame": fr, "params": [0, 2, 0, None, float(lat), float(lon), h]}
            for (_, _, fr, h), (lon, lat) in zip(items, ll, strict=True)]}})


def _ridge_oracle(x0: float, x1: float, h: float) -> np.ndarray:
    """The seabed-following track by hand: the analytic ridge (200 m deep, a 50 m deep crest at x = 5 km, 2 km
    flanks) sampled every 0.5 m, ``h`` above it."""
    x = np.linspace(x0, x1, int((x1 - x0) / 0.5) + 1)
    zb = -200.0 + 150.0 * np.clip(1.0 - np.abs(x - 5000.0) / 2000.0, 0.0, None)
    return np.column_stack([x, np.full_like(x, 1000.0), zb + h])


def test_a_terrain_frame_plan_over_the_ridge_is_checked_as_flown(tmp_path, capsys):
    """Oracle: the track sampled by hand.  Items 100 m above the 125 m deep seabed at x = 4 and 6 km: the straight
    leg runs 25 m deep, 25 m over the 50 m deep crest (OK, and under the 0-20 m shallows: "shallows: OK" before);
    ArduSub, holding 100 m above the seabed, climbs with it and would leave the water 50 m over the crest, through
    the shallows."""
    code, rec = _check(tmp_path, capsys, "ridge.plan", _plan([(4000.0, 1000.0, 10, 100.0),
                                                               (6000.0, 1000.0, 10, 100.0)]), _RIDGE)
    track = _ridge_oracle(4000.0, 6000.0, 100.0)
    poly = shapely.box(4000.0, 0.0, 6000.0, 2000.0)
    depth = -track[:, 2]
    inside = shapely.contains_xy(poly, track[:, 0], track[:, 1]) & (depth >= 0.0) & (depth <= 20.0)
    assert inside.any() and depth.min() == pytest.approx(-50.0)
    assert rec["check_ok"] is True  # the straight legs alone: what was checked before
    tf = rec["terrain_following"]
    assert code == 1 and rec["ok"] is False and tf["ok"] is False and tf["legs"] == [1]
    assert tf["shallowest_m"] == pytest.approx(float(depth.min()), abs=1e-6) and tf["above_surface_legs"] == [1]
    assert tf["min_altitude_m"] == pytest.approx(100.0, abs=1e-6)
    (zone,) = rec["zones"]
    # (the launch, leg 0, descends from the home through the shallows' 0-20 m at x = 4 km, on its face)
    assert zone["entered_legs"] == [0, 1] and zone["closest_m"] == pytest.approx(-10.0)  # 10 m inside the 20 m band
    plan = _plan([(4000.0, 1000.0, 10, 100.0), (6000.0, 1000.0, 10, 100.0)])
    code, rec = _check(tmp_path, capsys, "ridge.plan", plan, _RIDGE.split("[[zones]]")[0])
    assert code == 1 and rec["ok"] is False and rec["check_ok"] is True  # without the zone: the track alone fails


def test_a_terrain_frame_plan_clear_of_the_shallows_is_measured_on_its_track(tmp_path, capsys):
    """Oracle: as above, 25 m above the seabed from x = 3.5 to 6.5 km: the crest at 25 m deep, 5 m under the
    shallows (shapely on the sampled track), least altitude 25 m; the straight leg (137.5 m deep) meets the ridge,
    but ArduSub does not fly it: the seabed check is the track's too, and the file passes."""
    code, rec = _check(tmp_path, capsys, "low.plan", _plan([(3500.0, 1000.0, 10, 25.0), (6500.0, 1000.0, 10, 25.0)]),
                       _RIDGE)
    track = _ridge_oracle(3500.0, 6500.0, 25.0)
    oracle = _prism_distance(shapely.box(4000.0, 0.0, 6000.0, 2000.0), 0.0, 20.0, track)
    tf = rec["terrain_following"]
    assert tf["ok"] is True and tf["shallowest_m"] == pytest.approx(25.0, abs=1e-6)
    assert tf["min_altitude_m"] == pytest.approx(25.0, abs=1e-6)
    straight_crest = -137.5 - (-200.0 + 150.0)  # the straight leg's altitude over the 50 m deep crest: -87.5 m
    assert straight_crest < 0.0 and rec["min_altitude_m"] == pytest.approx(25.0, abs=1e-6)
    assert rec["check_ok"] is True and rec["ok"] is True and code == 0 and rec["obstacle_hits"] == 0
    (zone,) = rec["zones"]
    assert zone["entered_legs"] == [] and abs(zone["closest_m"] - oracle) < 0.5 and oracle == pytest.approx(5.0)
    assert "terrain-frame" in rec["zones_measured_on"]


def test_the_seabed_check_meets_an_obstacle_on_the_seabed_following_track(tmp_path, capsys):
    """Oracle: the track 25 m above the analytic ridge is 25 m deep over the crest (x = 5 km); a 5 m sphere there
    sits on it, 112.5 m above the straight leg (137.5 m deep).  Measured as flown the leg meets it: one hit, exit 1."""
    sphere = '[[obstacles]]\ntype = "sphere"\ncenter = [5000.0, 1000.0, -25.0]\nradius = 5.0\n'
    scenario = _RIDGE.split("[[zones]]")[0] + sphere
    track = _ridge_oracle(3500.0, 6500.0, 25.0)
    oracle = float(np.min(np.linalg.norm(track - [5000.0, 1000.0, -25.0], axis=1))) - 5.0
    assert oracle == pytest.approx(-5.0, abs=0.01)
    code, rec = _check(tmp_path, capsys, "low.plan", _plan([(3500.0, 1000.0, 10, 25.0), (6500.0, 1000.0, 10, 25.0)]),
                       scenario)
    assert code == 1 and rec["check_ok"] is False and rec["obstacle_hits"] == 1
    assert rec["min_obstacle_distance_m"] <= 0.0 and rec["terrain_following"]["obstacle_hits"] >= 1


def test_the_seabed_check_s_least_altitude_is_the_track_s(tmp_path, capsys):
    """Oracle: items 60 m then 25 m above the seabed across the ridge; the track's altitude goes linearly from 60 to
    25 m (least 25 m, at the second item), the launch leg's least is 60 m and the straight leg meets the crest."""
    code, rec = _check(tmp_path, capsys, "taper.plan",
                       _plan([(3500.0, 1000.0, 10, 60.0), (6500.0, 1000.0, 10, 25.0)]), _RIDGE.split("[[zones]]")[0])
    x = np.linspace(3500.0, 6500.0, 6001)
    seabed = -200.0 + 150.0 * np.clip(1.0 - np.abs(x - 5000.0) / 2000.0, 0.0, None)
    altitude = 60.0 + (25.0 - 60.0) * (x - 3500.0) / 3000.0  # the track's, above the seabed
    straight = np.interp(x, [3500.0, 6500.0], [seabed[0] + 60.0, seabed[-1] + 25.0]) - seabed
    assert straight.min() < 0.0 and altitude.min() == pytest.approx(25.0)
    assert rec["min_altitude_m"] == pytest.approx(float(altitude.min()), abs=1e-6) and rec["min_altitude_leg"] == 1
    assert code == 0 and rec["check_ok"] is True


def test_a_terrain_frame_leg_over_a_steep_ridge_breaks_the_pitch_limit_as_flown(tmp_path, capsys):
    """Oracle: a ridge 150 m high on 300 m flanks slopes atan(150 / 300) = 26.57°; items 25 m above the flat seabed
    on both sides: the straight leg is level (0°), the seabed-following flight climbs and dives at 26.57° > 20°."""
    steep = _RIDGE.split("[[zones]]")[0].replace("ridge_width = 2000.0", "ridge_width = 300.0") + \
        '[vehicle]\nmax_pitch_deg = 20.0\n'
    code, rec = _check(tmp_path, capsys, "steep.plan", _plan([(4000.0, 1000.0, 10, 25.0), (6000.0, 1000.0, 10, 25.0)]),
                       steep)
    slope = math.degrees(math.atan(150.0 / 300.0))
    v = rec["vehicle"]
    # the leg named as the rest of the file's report names it: leg 1 from the home (leg 0 the launch; audit 15)
    assert code == 1 and v["max_pitch_deg"] == pytest.approx(slope, abs=1e-6) and v["max_pitch_leg"] == 1
    assert [(x["leg"], x["limit"]) for x in v["violations"]] == [(1, "max_pitch_deg")] == \
        [(k, "max_pitch_deg") for k in rec["terrain_following"]["legs"]]
    assert rec["terrain_following"]["ok"] is True  # the track itself keeps its altitude: the helm cannot fly it
