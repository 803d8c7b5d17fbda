"""Issue 51: what leaves auvplan is deployable — datum, safety envelope, payload events, terrain-following
altitude, honest inputs.

Every format is read back with an independent parser of its syntax (a small MOOS block parser written here,
json, yaml, xml.etree, csv) and checked against the scenario: the datum (and its round trip through pyproj's
azimuthal equidistant frame about the file's own origin, within 1 cm), the envelope (its polygon holds every
waypoint and not a planted outside point, by a ray-casting test written here), the payload events (from the
survey labels the test made), the altitudes (z − seabed).  The hard case: ``marcus-terrain-follow`` (real
ETOPO1, a 49 km route 50 m above the seabed, 1 594 waypoints).
"""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
import re
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import yaml
from pyproj import Geod, Transformer

from auvplan import cli
from auvplan.io.missions import export, formats
from auvplan.io.missions.deploy import DeployInfo, deploy_info, payload_from_labels
from auvplan.io.scenario import loader as sc_io
from auvplan.io.scenario.defaults import PRESETS, energy_defaults
from auvplan.io.scenario.inputs.currentspan import file_span, zero_beyond
from auvplan.io.scenario.saved import with_derived_frame
from auvplan.sim import RunRecord
from auvplan.sim.pipeline import fitted_route
from auvplan.world.currents.fields import GriddedCurrent

SPEED = 1.5


# ---------------------------------------------------------------------- independent helpers
def inside(poly: np.ndarray, p: np.ndarray) -> bool:
    """Ray casting (even-odd), written here: is the point inside the polygon?"""
    x, y, n, c = p[0], p[1], len(poly), False
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            c = not c
    return c


def moos_parse(text: str) -> tuple[dict[str, str], list[str], list[tuple[str, list[tuple[str, str]]]]]:
    """A MOOS-IvP file's globals (top-level brace block), ``initialize`` lines and behaviour blocks."""
    glob: dict[str, str] = {}
    init, blocks, cur, header = [], [], None, None
    for raw in text.splitlines():
        line = raw.split("//")[0].strip()
        if not line:
            continue
        if line == "{":
            cur = [] if header is not None else None
            glob_block = header is None
            continue
        if line == "}":
            if header is not None:
                blocks.append((header, cur))
            header, cur = None, None
            continue
        if cur is not None:
            k, v = line.split("=", 1)
            cur.append((k.strip().lower(), v.strip()))
        elif line.startswith("Behavior"):
            header = line.split("=", 1)[1].strip()
        elif line.startswith("initialize"):
            init.append(line.split(None, 1)[1].replace(" ", ""))
        elif glob_block:
            k, v = line.split("=", 1)
            glob[k.strip()] = v.strip()
    return glob, init, blocks


def aeqd(origin: tuple[float, float]) -> Transformer:
    """The project's local frame, built here with pyproj: azimuthal equidistant about the origin, WGS 84."""
    proj = f"+proj=aeqd +lat_0={origin[0]} +lon_0={origin[1]} +datum=WGS84 +units=m +no_defs"
    return Transformer.from_crs(proj, "EPSG:4326", always_xy=True)


def datum_round_trip_m(file_origin: tuple[float, float], scen_origin: tuple[float, float], xy: np.ndarray) -> float:
    """Largest geodesic distance between each waypoint placed through the file's origin and the scenario's."""
    lon_f, lat_f = aeqd(file_origin).transform(xy[:, 0], xy[:, 1])
    lon_s, lat_s = aeqd(scen_origin).transform(xy[:, 0], xy[:, 1])
    return float(np.max(Geod(ellps="WGS84").inv(lon_f, lat_f, lon_s, lat_s)[2]))


def expected_events(payload: np.ndarray) -> list[tuple[int, bool]]:
    """Sensor switches at waypoints, from the per-leg states (written here: on where a leg starts a run)."""
    out, prev = [], False
    for i, on in enumerate([*payload, False]):
        if bool(on) != prev:
            out.append((i, bool(on)))
            prev = bool(on)
    return out


# ---------------------------------------------------------------------- the hard case
@pytest.fixture(scope="module")
def tf(tmp_path_factory):
    """marcus-terrain-follow's fitted mission with two survey lines, exported in every format."""
    world, mission = sc_io.build(sc_io.load("marcus-terrain-follow"))
    w = fitted_route(world, mission, np.asarray(mission.route)).waypoints
    labels = np.full(len(w), -2)
    labels[100:600], labels[600:603], labels[603:1200] = 0, -1, 1  # transit, line 0, turn, line 1, transit
    payload = (labels[:-1] == labels[1:]) & (labels[:-1] >= 0)
    record = RunRecord("marcus-terrain-follow", 1, None, w, w[[0, -1]], None)
    deploy = export.deploy_for(world, mission, record, SPEED, payload_from_labels(labels))
    out = tmp_path_factory.mktemp("tf")
    export.write_exports(out, record, world.origin, SPEED, export.EXPORT_FORMATS, deploy=deploy)
    predicted = flown_duration(w, SPEED, sc_io.load("marcus-terrain-follow").currents.uniform)
    return world, mission, w, payload, out, predicted


def flown_duration(w: np.ndarray, speed: float, current) -> float:
    """The mission's duration as flown (written here, closed form in a uniform current ``c``): the launch's vertical
    dive from the surface at ArduSub's 1.5 m/s, then each leg along its unit direction ``e`` at the ground speed
    ``c·e + sqrt(V² − |c|² + (c·e)²)`` (the time-out's base since wave 18: the still-water ``L / V`` before)."""
    c = np.asarray(current, dtype=float)
    d = np.diff(w, axis=0)
    n = np.linalg.norm(d, axis=1)
    ce = (d[n > 0] / n[n > 0, None]) @ c
    dive = -w[0, 2] / math.sqrt(1.5**2 - c @ c)
    return float(dive + np.sum(n[n > 0] / (ce + np.sqrt(speed**2 - c @ c + ce * ce))))


def _followed_pitch(world, a: np.ndarray, b: np.ndarray) -> float:
    """The steepest pitch of the leg flown following the seabed (altitude linear from a's to b's), sampled every
    0.25 m (degrees)."""
    n = max(int(np.hypot(*(b[:2] - a[:2])) / 0.25), 1) + 1
    s = np.linspace(0.0, 1.0, n)
    xy = a[:2] + s[:, None] * (b[:2] - a[:2])
    ha, hb = a[2] - world.seabed(a[0], a[1]), b[2] - world.seabed(b[0], b[1])
    z = world.seabed(xy[:, 0], xy[:, 1]) + ha + s * (hb - ha)
    dl = np.hypot(*(b[:2] - a[:2])) / (n - 1)
    return float(np.degrees(np.arctan(np.abs(np.diff(z)).max() / dl)))


def _checked(path: Path, scenario: str) -> dict:
    """``auvplan mission check --json`` of one file: its record."""
    import contextlib

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        cli.main(["mission", "check", str(path), "--scenario", scenario, "--json"])
    doc = json.loads(buf.getvalue())
    return doc if "file" in doc else doc["files"][0]


def planted(world) -> np.ndarray:
    """Points just outside the bounds (1 m past the east side, 1 m past the north side)."""
    b = world.bounds
    return np.array([[b.xmax + 1.0, 0.5 * (b.ymin + b.ymax)], [0.5 * (b.xmin + b.xmax), b.ymax + 1.0]])


def test_moos_file_carries_datum_envelope_payload_and_altitude(tf):
    world, mission, w, payload, out, predicted = tf
    glob, init, blocks = moos_parse((out / "mission.moos").read_text())
    origin = (float(glob["LatOrigin"]), float(glob["LongOrigin"]))
    assert origin == pytest.approx(world.origin, abs=1e-9)
    assert {"DEPLOY=false", "RETURN=false", "ABORT=false", "PAYLOAD=off"} <= set(init)
    (op,) = [dict(b) for t, b in blocks if t == "BHV_OpRegion"]
    poly = np.array([[float(c) for c in p.split(",")] for p in op["polygon"].split(":")])
    assert all(inside(poly, p) for p in w[:, :2])  # every waypoint in the operating region
    assert not any(inside(poly, p) for p in planted(world))  # and a point 1 m outside is not
    assert float(op["max_depth"]) == pytest.approx(world.margins.max_depth) and float(op["max_depth"]) >= -w[:, 2].min()
    assert float(op["min_altitude"]) == pytest.approx(world.margins.min_altitude)
    assert float(op["max_time"]) == pytest.approx(1.5 * predicted, abs=0.1)  # time-out = 1.5 x predicted
    flags = [v for t, b in blocks if t == "BHV_OpRegion" for k, v in b if k.startswith("breached_")]
    assert len(flags) == 4 and all(f.replace(" ", "") == "ABORT=true" for f in flags)
    (wpt,) = [b for t, b in blocks if t == "BHV_Waypoint"]
    assert {v.replace(" ", "") for k, v in wpt if k == "endflag"} >= {"RETURN=true", "PAYLOAD=off"}
    assert ("condition", "ABORT = false") in wpt
    # payload: the depth behaviour of the leg where the sensor switches posts it
    got = []
    for t, b in blocks:
        d = dict(b)
        flag = [v for k, v in b if k == "runflag" and v.startswith("PAYLOAD")]
        if t == "BHV_ConstantDepth" and flag:
            leg = int(re.search(r"WPT_INDEX = (\d+)", " ".join(v for k, v in b if k == "condition")).group(1))
            got.append((leg, flag[0].endswith("on")))
            assert ("condition", "ABORT = false") in b and "depth" in d
    assert got == [e for e in expected_events(payload) if e[0] < len(w) - 1]
    # terrain following: one altitude behaviour per leg, at most the target, never below min_altitude_m
    alts = [float(dict(b)["min_altitude"]) for t, b in blocks if t == "BHV_MinAltitudeX"]
    assert len(alts) == len(w) - 1 and max(alts) <= 50.0 + 1e-9 and min(alts) >= world.margins.min_altitude
    # the datum round-trips: every waypoint placed through the file's own origin lands within 1 cm
    pts = np.array([[float(c) for c in p.split(",")] for p in dict(wpt)["points"].split(":")])
    assert datum_round_trip_m(origin, world.origin, pts) < 0.01


def test_qgc_plan_carries_geofence_terrain_frame_and_relay_items(tf):
    world, mission, w, payload, out, _ = tf
    doc = json.loads((out / "mission.plan").read_text())
    fence = doc["geoFence"]["polygons"]
    (inc,) = [np.asarray(p["polygon"]) for p in fence if p["inclusion"]]
    items = doc["mission"]["items"]
    wps = [i for i in items if i["command"] == 16]
    ll = np.array([[i["params"][4], i["params"][5]] for i in wps])
    assert all(inside(inc, p) for p in ll)
    to_geo = aeqd(world.origin)
    lon, lat = to_geo.transform(planted(world)[:, 0], planted(world)[:, 1])
    assert not any(inside(inc, p) for p in np.column_stack([lat, lon]))
    # terrain frame: the altitude above the chart's seabed the mission was planned at, on every leg ArduSub can
    # follow the seabed within the pitch limit (oracle: the track sampled every 0.25 m); the others at their depth
    frame = np.array([i["frame"] for i in wps])
    steep = np.array([_followed_pitch(world, w[k - 1], w[k]) for k in range(1, len(w))])
    limit = mission.vehicle.max_pitch_deg
    assert frame[0] == 10 and set(frame) == {3, 10} and doc["mission"]["globalPlanAltitudeMode"] == 0
    assert (steep[frame[1:] == 10] <= limit + 0.05).all() and (steep[frame[1:] == 3] > limit - 0.05).all()
    assert 0 < (frame == 3).sum() < 0.05 * len(wps)  # a few legs over the steepest slopes
    height = np.where(frame == 10, w[:, 2] - world.seabed(w[:, 0], w[:, 1]), w[:, 2])
    np.testing.assert_allclose([i["params"][6] for i in wps], height, atol=1e-3)
    assert all(i["AltitudeMode"] == (4 if f == 10 else 1) for i, f in zip(wps, frame, strict=True))
    rec = _checked(out / "mission.plan", "marcus-terrain-follow")  # and flown as written, within the limits
    assert rec["ok"] is True and rec["vehicle"]["violations"] == [] and rec["vehicle"]["max_pitch_deg"] <= limit
    assert rec["terrain_following"]["legs"] == [k for k in range(1, len(wps)) if frame[k] == 10]
    got, k = [], -1
    for i in items:
        k += i["command"] == 16
        if i["command"] == 181:
            got.append((k, i["params"][1] == 1))
    assert got == expected_events(payload)


def test_ros_yaml_carries_datum_envelope_and_payload(tf):
    world, mission, w, payload, out, predicted = tf
    doc = yaml.load((out / "mission.yaml").read_text(), Loader=yaml.CSafeLoader)  # libyaml: the same grammar
    origin = (doc["datum"]["lat"], doc["datum"]["lon"])
    assert origin == pytest.approx(world.origin, abs=1e-9)
    poly = np.asarray(doc["envelope"]["polygon"])
    xy = np.array([[p["pose"]["position"]["x"], p["pose"]["position"]["y"]] for p in doc["poses"]])
    assert all(inside(poly, p) for p in xy) and not any(inside(poly, p) for p in planted(world))
    assert doc["envelope"]["max_time_s"] == pytest.approx(1.5 * predicted, abs=0.1)
    assert [(e["waypoint"], e["sensor"]) for e in doc["payload_events"]] == expected_events(payload)
    assert datum_round_trip_m(origin, world.origin, xy) < 0.01


def test_geojson_and_kml_carry_envelope_and_payload(tf):
    world, mission, w, payload, out, predicted = tf
    lon, lat = aeqd(world.origin).transform(planted(world)[:, 0], planted(world)[:, 1])
    outside = np.column_stack([lon, lat])
    doc = json.loads((out / "mission.geojson").read_text())
    feats = {f["properties"]["name"]: f for f in doc["features"]}
    ring = np.asarray(feats["envelope"]["geometry"]["coordinates"][0])
    mission_ll = np.asarray(feats["mission"]["geometry"]["coordinates"])[:, :2]
    assert all(inside(ring, p) for p in mission_ll) and not any(inside(ring, p) for p in outside)
    assert feats["envelope"]["properties"]["max_time_s"] == pytest.approx(1.5 * predicted, abs=0.1)
    events = [(e["waypoint"], e["sensor"] == "on") for e in feats["mission"]["properties"]["payload_events"]]
    assert events == expected_events(payload)
    ns = {"k": "http://www.opengis.net/kml/2.2"}
    root = ET.fromstring((out / "mission.kml").read_text())
    pms = {pm.findtext("k:name", namespaces=ns): pm for pm in root.iter("{http://www.opengis.net/kml/2.2}Placemark")}
    coords = pms["envelope"].find("k:Polygon/k:outerBoundaryIs/k:LinearRing/k:coordinates", ns).text.split()
    ring = np.array([[float(v) for v in c.split(",")] for c in coords])
    assert all(inside(ring, p) for p in mission_ll) and not any(inside(ring, p) for p in outside)
    data = {d.get("name"): d.findtext("k:value", namespaces=ns) for d in pms["mission"].iter(f"{{{ns['k']}}}Data")}
    assert [(int(a), b == "on") for a, b in (e.split(":") for e in data["payload_events"].split())] \
        == expected_events(payload)


def test_csv_carries_altitude_payload_and_a_consistent_datum(tf):
    world, mission, w, payload, out, _ = tf
    rows = list(csv.DictReader(io.StringIO((out / "mission.csv").read_text())))
    x, y = np.array([[float(r["x"]), float(r["y"])] for r in rows]).T
    lon, lat = aeqd(world.origin).transform(x, y)
    assert np.max(Geod(ellps="WGS84").inv(lon, lat, [float(r["lon"]) for r in rows],
                                          [float(r["lat"]) for r in rows])[2]) < 0.01
    np.testing.assert_allclose([float(r["altitude"]) for r in rows], w[:, 2] - world.seabed(w[:, 0], w[:, 1]),
                               atol=1e-3)
    state = [r["payload"] == "1" for r in rows]
    assert state[:-1] == list(payload) and not state[-1]


# ---------------------------------------------------------------------- mission check
MINI = np.array([[37500.0, 57500.0, -2500.0], [38500.0, 58500.0, -2450.0], [40000.0, 60000.0, -2400.0],
                 [42500.0, 62500.0, -2400.0]])
"""A short mission over dynamic-terrain's real seamount flank (ETOPO1), well above its seabed."""


@pytest.fixture(scope="module")
def dt():
    return sc_io.build(sc_io.load("dynamic-terrain"))


def _mini(dt, tmp_path, origin=None, polygon=None) -> Path:
    world, mission = dt
    record = RunRecord("dynamic-terrain", 1, None, MINI, MINI[[0, -1]], None)
    d = export.deploy_for(world, mission, record, SPEED)
    env = d.envelope if polygon is None else dataclasses.replace(d.envelope, polygon=polygon)
    deploy = DeployInfo(origin or world.origin, env, None, None, 0.0)
    p = tmp_path / "m.moos"
    p.write_text(formats.to_moos(MINI, SPEED, deploy=deploy))
    return p


def test_mission_check_verifies_datum_and_envelope(dt, tmp_path, capsys):
    world, _ = dt
    ok = _mini(dt, tmp_path)
    assert cli.main(["mission", "check", str(ok), "--scenario", "dynamic-terrain", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)["deploy"]
    assert rec["datum"]["offset_m"] < 0.001 and rec["envelope"]["ok"] and rec["envelope"]["vertices"] == 4
    # another datum (1e-4 deg north, ~11 m): refused, exit 2 naming both
    (tmp_path / "b").mkdir()
    moved = _mini(dt, tmp_path / "b", origin=(world.origin[0] + 1e-4, world.origin[1]))
    assert cli.main(["mission", "check", str(moved), "--scenario", "dynamic-terrain"]) == 2
    err = capsys.readouterr().err
    assert "datum" in err and "differs from the scenario's [origin]" in err and "11.06 m apart" in err
    # the tolerance is 1 cm: 1e-6 deg (11 cm) is refused, 5e-8 deg (5.5 mm) is the same datum
    (tmp_path / "d").mkdir()
    near = _mini(dt, tmp_path / "d", origin=(world.origin[0] + 1e-6, world.origin[1]))
    assert cli.main(["mission", "check", str(near), "--scenario", "dynamic-terrain"]) == 2
    assert "(0.11 m apart)" in capsys.readouterr().err
    same = _mini(dt, tmp_path / "d", origin=(world.origin[0] + 5e-8, world.origin[1]))
    assert cli.main(["mission", "check", str(same), "--scenario", "dynamic-terrain"]) == 0
    assert "= the scenario's (5.5 mm)" in capsys.readouterr().out
    # a CSV whose lat/lon columns were written about another origin: its datum (solved from the rows) differs
    (tmp_path / "m.csv").write_text(formats.mission_csv(MINI, (world.origin[0], world.origin[1] + 2e-4), SPEED))
    assert cli.main(["mission", "check", str(tmp_path / "m.csv"), "--scenario", "dynamic-terrain"]) == 2
    assert "21.5" in capsys.readouterr().err  # 2e-4 deg of longitude at 14.76 N: 21.5 m
    (tmp_path / "m.csv").write_text(formats.mission_csv(MINI, world.origin, SPEED))
    assert cli.main(["mission", "check", str(tmp_path / "m.csv"), "--scenario", "dynamic-terrain"]) == 0
    assert "= the scenario's (0.0 mm)" in capsys.readouterr().out
    # an envelope that leaves the last waypoint out: FAIL, exit 1
    (tmp_path / "c").mkdir()
    small = ((37000.0, 57000.0), (42000.0, 57000.0), (42000.0, 62000.0), (37000.0, 62000.0))
    cut = _mini(dt, tmp_path / "c", polygon=small)
    assert cli.main(["mission", "check", str(cut), "--scenario", "dynamic-terrain"]) == 1
    out = capsys.readouterr().out
    assert "envelope FAIL" in out and "leaves the envelope's polygon (1 waypoints outside)" in out


def test_a_file_written_before_issue_51_is_still_checked(dt, tmp_path, capsys):
    (tmp_path / "old.moos").write_text(formats.to_moos(MINI, SPEED))  # no datum, no envelope
    assert cli.main(["mission", "check", str(tmp_path / "old.moos"), "--scenario", "dynamic-terrain"]) == 0
    out = capsys.readouterr().out
    assert "no datum in the file" in out and "envelope: none in the file" in out
    assert "battery_wh = 1000 (default)" in out  # the energy verdict names the default it rests on


# ---------------------------------------------------------------------- honest inputs
SPAN = """name = "span-test"
[bounds]
x = [-1000.0, 25000.0]
y = [-1000.0, 1000.0]
z = [-100.0, 0.0]
[currents]
file = "c2h.nc"
{beyond}
[mission]
route = [[0.0, 0.0, -20.0], [21600.0, 0.0, -20.0]]
start = [0.0, 0.0, -20.0]
goal = [21600.0, 0.0, -20.0]
[sim]
dt = 2.0
"""


def _two_hour_file(folder: Path) -> None:
    import xarray as xr

    x, y, t = np.arange(-2000.0, 26001.0, 2000.0), np.arange(-2000.0, 2001.0, 1000.0), np.arange(3) * 3600.0
    u = np.full((3, y.size, x.size), 0.1)
    xr.Dataset({"u": (("time", "y", "x"), u, {"standard_name": "eastward_sea_water_velocity", "units": "m s-1"}),
                "v": (("time", "y", "x"), 0 * u, {"standard_name": "northward_sea_water_velocity", "units": "m s-1"})},
               coords={"time": ("time", t, {"units": "seconds since 2024-03-01 00:00:00"}),
                       "x": ("x", x, {"units": "m", "axis": "X"}),
                       "y": ("y", y, {"units": "m", "axis": "Y"})}).to_netcdf(folder / "c2h.nc")


def test_a_two_hour_current_file_and_a_four_hour_mission(tmp_path, capsys):
    _two_hour_file(tmp_path)
    (tmp_path / "s.toml").write_text(SPAN.format(beyond=""))
    assert cli.main(["run", str(tmp_path / "s.toml")]) == 2
    err = capsys.readouterr().err
    assert "covers 0.00 to 2.00 h from the start" in err and "4.00 h at the cruise speed" in err
    assert 'beyond = "hold"' in err and err.count("\n") == 1
    (tmp_path / "h.toml").write_text(SPAN.format(beyond='beyond = "hold"'))
    assert cli.main(["run", str(tmp_path / "h.toml"), "--json"]) == 0
    cap = capsys.readouterr()
    assert cap.err == ""  # --json: nothing on stderr on success
    notes = json.loads(cap.out)["notes"]
    assert any("covers 0.00 to 2.00 h" in n and 'beyond = "hold"' in n and "last 1.7" in n for n in notes)
    assert any("battery_wh = 1000 (default)" in n for n in notes)


def test_beyond_zero_stops_the_current_after_the_file(tmp_path):
    _two_hour_file(tmp_path)
    (tmp_path / "z.toml").write_text(SPAN.format(beyond='beyond = "zero"'))
    world, _ = sc_io.build(sc_io.load(str(tmp_path / "z.toml")))
    assert file_span(world.currents, "zero") == (0.0, 7200.0)
    p = np.array([[5000.0, 0.0, -20.0]])
    assert world.currents.velocity(p, 3600.0)[0, 0] == pytest.approx(0.1)
    assert world.currents.velocity(p, 7201.0)[0, 0] == 0.0 and world.currents.velocity(p, 5e5)[0, 0] == 0.0
    g = GriddedCurrent(np.array([0.0, 1.0]), np.array([0.0, 1.0]), np.array([0.0]), np.ones((2, 1, 2, 2)),
                       np.zeros((2, 1, 2, 2)), t=np.array([0.0, 10.0]))
    assert zero_beyond(g).velocity(np.zeros((1, 3)), 10.5)[0, 0] == pytest.approx(0.5)  # the 1 s ramp


def test_validate_prints_ok_only_after_every_check(tmp_path, capsys):
    text = Path(sc_io.resolve("shelf-survey")).read_text()
    text = re.sub(r"^polygon = .*$", 'file = "no-such-area.geojson"', text, count=1, flags=re.M)
    (tmp_path / "bad.toml").write_text(text)  # the world builds; the survey area (read last) is missing
    code = cli.main(["validate", str(tmp_path / "bad.toml")])
    cap = capsys.readouterr()
    assert code == 2 and cap.out == "" and "no-such-area.geojson" in cap.err


# ---------------------------------------------------------------------- presets, saved frame
def test_presets_give_published_figures_and_explicit_keys_override():
    base = ('name = "p"\n[mission]\nstart = [0, 0, -10]\ngoal = [100, 0, -10]\n[bounds]\nx = [-10, 200]\n'
            'y = [-50, 50]\nz = [-100, 0]\n[vehicle]\npreset = "{p}"\n{extra}')
    sc = sc_io.loads(base.format(p="bluefin9", extra="battery_wh = 2000.0\n"), "p.toml")
    assert sc.vehicle.battery_wh == 2000.0 and sc.vehicle.max_depth_m == 200.0 and sc.vehicle.hotel_power == 204.0
    assert energy_defaults(sc) == ["energy verdict rests on usable_fraction = 0.9 (default), reserve = 0.2 (default), "
                                   "hotel_w = 204 (preset bluefin9), speed = 1.54 (preset bluefin9)"]
    # hotel = battery / published endurance at 3 kn (2.5 kn) - 0.5 rho C_D (pi d^2 / 4) V^3 / eta
    for name, wh, hours, kn, d in (("remus100", 1000, 22, 3.0, 0.19), ("iver3", 800, 14, 2.5, 0.147),
                                   ("bluefin9", 1900, 8, 3.0, 0.238)):
        v = kn * 1852 / 3600
        hotel = wh / hours - 0.5 * 1025 * 0.2 * math.pi * d * d / 4 * v ** 3 / 0.5
        assert PRESETS[name]["hotel_w"] == pytest.approx(hotel, abs=0.3), name
        assert PRESETS[name]["speed"] == pytest.approx(v, abs=0.01)
    with pytest.raises(Exception, match="preset = 'remus'"):
        sc_io.loads(base.format(p="remus", extra=""), "p.toml")


def test_saved_scenario_holds_the_derived_origin_and_bounds(tf):
    world = tf[0]
    sc = sc_io.load("marcus-terrain-follow")
    text = Path(sc.source).read_text()
    assert "origin" not in tomllib.loads(text) and "bounds" not in tomllib.loads(text)
    saved = with_derived_frame(text, world)
    doc = tomllib.loads(saved)
    assert (doc["origin"]["lat"], doc["origin"]["lon"]) == world.origin
    assert doc["bounds"]["x"] == [world.bounds.xmin, world.bounds.xmax]
    assert doc["bounds"]["y"] == [world.bounds.ymin, world.bounds.ymax]
    again = sc_io.loads(saved, "saved.toml", base_dir=sc.base_dir)
    assert (again.origin.lat, again.origin.lon) == world.origin and again.mission.start == sc.mission.start
    assert with_derived_frame(saved, world) == saved  # nothing derived left to add


def test_json_leaves_stderr_empty(tmp_path, capsys):
    """`plan --json` drew its progress bar on stderr before issue 51."""
    assert cli.main(["plan", "dynamic-terrain", "--budget", "300", "--json", "--out", str(tmp_path / "p")]) == 0
    cap = capsys.readouterr()
    assert cap.err == "" and json.loads(cap.out)["status"] in ("EXACT", "APPROXIMATE")


def test_land_becomes_exclusions_and_a_route_across_it_fails(tmp_path):
    """admiralty-inlet (GSHHG shorelines): the land inside the bounds is the geofence's exclusions; a short leg
    in open water stays clear of them, the straight line over the Quimper Peninsula crosses them."""
    from auvplan.io.missions.deploy_formats import FENCE_STORAGE_BYTES, fence_bytes
    from auvplan.io.missions.readback.deploy_read import check_deploy

    world, mission = sc_io.build(sc_io.load("admiralty-inlet"))
    across = np.array([mission.start, mission.goal])
    short = np.array([mission.start, np.add(mission.start, (200.0, 0.0, 0.0))])
    for w, ok in ((short, True), (across, False)):
        d = deploy_info(world, mission, w, SPEED)
        assert d.envelope.exclusions
        p = tmp_path / f"{ok}.plan"
        p.write_text(json.dumps(formats.to_qgc_plan(w, world.origin, SPEED, deploy=d)))
        fence = json.loads(p.read_text())["geoFence"]["polygons"]
        # within ArduPilot's fence storage: the land simplified inside itself (test_edges17_fence_storage.py)
        assert 1 <= sum(not f["inclusion"] for f in fence) <= len(d.envelope.exclusions)
        assert fence_bytes([len(f["polygon"]) for f in fence]) <= FENCE_STORAGE_BYTES
        rec = check_deploy(p, world.origin, np.vstack([[w[0, 0], w[0, 1], 0.0], w]), 100.0, 100.0)
        assert rec["envelope"]["ok"] == ok
        assert ok or any("crosses exclusion" in r for r in rec["envelope"]["reasons"])


def test_an_envelope_removed_from_a_new_file_fails(dt, tmp_path, capsys):
    p = _mini(dt, tmp_path)
    p.write_text(re.sub(r"Behavior = BHV_OpRegion\n\{[^}]*\}\n", "", p.read_text()))
    assert "BHV_OpRegion" not in p.read_text() and "LatOrigin" in p.read_text()
    assert cli.main(["mission", "check", str(p), "--scenario", "dynamic-terrain"]) == 1
    assert "no envelope (BHV_OpRegion / envelope removed)" in capsys.readouterr().out


def test_survey_payload_is_read_back_from_lines_csv(tmp_path):
    """`export`/`report` of a survey folder: the legs joining consecutive points of one line are on."""
    route = np.array([[0, 0, -5], [10, 0, -5], [20, 0, -5], [20, 5, -5], [10, 5, -5], [0, 5, -5], [0, 9, -5]], float)
    (tmp_path / "lines.csv").write_text("line,x,y,z,lat,lon\n0,10,0,-5,,\n0,20,0,-5,,\n1,20,5,-5,,\n1,10,5,-5,,\n"
                                        "1,0,5,-5,,\n")
    flags = export.survey_payload(tmp_path, RunRecord("s", 0, None, route, route[:0], None))
    assert flags.tolist() == [False, True, False, True, True, False]
    assert export.survey_payload(tmp_path / "nowhere", RunRecord("s", 0, None, route, route[:0], None)) is None
