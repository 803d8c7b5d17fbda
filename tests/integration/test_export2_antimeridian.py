"""GeoJSON and KML exports of a mission across the antimeridian are cut there, and read back whole (helper export2,
wave 17).

The exports wrote a line from 179.995° to -179.995° as it is, which a viewer joining longitudes on a plane (QGIS,
Leaflet, geojson.io) draws the long way round the Earth.  RFC 7946 §3.1.9: cut it into a ``MultiLineString``
(``MultiPolygon``); KML's longitudes are ``angle180Type`` (-180..180 in the OGC schema), so its safe form is the same
cut, a ``MultiGeometry`` of pieces (:mod:`auvplan.io.missions.antimeridian`).

Oracles, on the files' own text (``json``, ``xml.etree``): no step of any written line or ring is longer than 180°
of longitude and no longitude is outside [-180, 180]; the pieces, unwrapped, are the route (Hausdorff distance
below 1e-8° and the same length); read back by ``read_mission`` they are the waypoints (1 mm), and the envelope
read back holds the mission (``mission check``'s deploy check) while a waypoint 70 km off is outside it.  A mission
that does not cross is written as before (one LineString / Polygon).
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import shapely

from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions import export
from auvplan.io.missions.deploy import deploy_info
from auvplan.io.missions.formats import read_mission
from auvplan.io.missions.readback.deploy_read import file_deploy_check
from auvplan.io.scenario import loader
from auvplan.sim.result import RunRecord

KML = "{http://www.opengis.net/kml/2.2}"
SCENARIO = """
name = "dateline"
[origin]
lat = LAT
lon = LON
[bounds]
x = [0.0, 3000.0]
y = [0.0, 3000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 150.0
cell_m = 50.0
[mission]
start = [300.0, 300.0, -60.0]
goal = [2700.0, 2700.0, -60.0]
"""
# zig-zags east and west so that the line crosses ±180° three times (at -33°, 179.99°: x 934 m; at 45°, 179.986°:
# x 1 103 m)
W = np.array([[300.0, 300.0, -60.0], [1500.0, 800.0, -60.0], [700.0, 1400.0, -70.0], [2200.0, 2400.0, -80.0],
              [2700.0, 2700.0, -60.0]])


def _export(tmp_path, lat, lon):
    scen = tmp_path / "s.toml"
    scen.write_text(SCENARIO.replace("LAT", str(lat)).replace("LON", str(lon)))
    world, mission = loader.build(loader.load(str(scen)))
    record = RunRecord("dateline", 1, None, W, W[1:3], None)
    info = deploy_info(world, mission, W, 1.5)
    export.write_exports(tmp_path, record, world.origin, 1.5, ("geojson", "kml"), deploy=info)
    return world


def _geojson_lines(doc):
    """Every line and ring of the document: (feature name, geometry type, list of [lon, lat(, z)] arrays)."""
    out = []
    for f in doc["features"]:
        g, name = f["geometry"], f["properties"].get("name")
        parts = {"LineString": lambda c: [c], "MultiLineString": lambda c: c, "Polygon": lambda c: c,
                 "MultiPolygon": lambda c: [r for p in c for r in p], "MultiPoint": lambda c: []}[g["type"]]
        out.append((name, g["type"], [np.asarray(p, dtype=float) for p in parts(g["coordinates"])]))
    return out


def _kml_lines(root):
    out = []
    for pm in root.iter(f"{KML}Placemark"):
        name = pm.findtext(f"{KML}name")
        lines = [np.array([[float(v) for v in s.split(",")] for s in c.text.split()])
                 for c in pm.iter(f"{KML}coordinates")]
        out.append((name, pm.find(f"{KML}MultiGeometry") is not None, lines))
    return out


def _unwrapped(pieces, ref):
    return [np.column_stack([(p[:, 0] - ref + 180.0) % 360.0 - 180.0 + ref, p[:, 1]]) for p in pieces]


def _check_written(pieces, route_lonlat):
    for p in pieces:
        assert np.all(np.abs(p[:, 0]) <= 180.0)
        assert np.all(np.abs(np.diff(p[:, 0])) < 180.0), p[:, 0]
    ref = float(route_lonlat[0, 0])
    got = shapely.MultiLineString(_unwrapped(pieces, ref))
    want = shapely.LineString(_unwrapped([route_lonlat], ref)[0])
    assert got.hausdorff_distance(want) < 1e-8 and got.length == pytest.approx(want.length, abs=1e-8)  # 9 decimals


@pytest.mark.parametrize(("lat", "lon"), [(-33.0, 179.99), (45.0, 179.986)])
def test_a_route_across_the_antimeridian_is_cut_there_and_read_back_whole(tmp_path, lat, lon):
    world = _export(tmp_path, lat, lon)
    lo, la = LocalFrame(*world.origin).inverse(W[:, 0], W[:, 1])
    route = np.column_stack([lo, la])
    assert np.abs(np.diff(lo)).max() > 180.0  # the route crosses: the case under test
    doc = json.loads((tmp_path / "mission.geojson").read_text())
    kinds = {}
    for name, kind, pieces in _geojson_lines(doc):
        kinds[name] = kind
        for p in pieces:
            assert np.all(np.abs(np.diff(p[:, 0])) < 180.0), (name, p[:, 0])
        if name in ("mission", "plan"):
            assert kind == "MultiLineString" and len(pieces) == 4  # three crossings
            _check_written(pieces, route)
    assert kinds["envelope"] == "MultiPolygon"
    root = ET.fromstring((tmp_path / "mission.kml").read_text())
    for name, multi, pieces in _kml_lines(root):
        for p in pieces:
            assert np.all(np.abs(p[:, 0]) <= 180.0) and np.all(np.abs(np.diff(p[:, 0])) < 180.0), (name, p[:, 0])
        if name in ("mission", "plan", "envelope"):
            assert multi, name
        if name == "mission":
            _check_written(pieces, route)
    for fmt, reader in (("geojson", "geojson"), ("kml", "kml")):
        path = tmp_path / f"mission.{fmt}"
        points = read_mission(path, world.origin)[0]
        np.testing.assert_allclose(points, W, atol=1e-3)  # the waypoints, the cut points dropped
        rec, line = file_deploy_check(path, world.origin, points, reader, 50.0, 3000.0)
        assert rec["envelope"]["ok"], line
        far = points.copy()
        far[2, :2] += 50_000.0
        rec, line = file_deploy_check(path, world.origin, far, reader, 50.0, 3000.0)
        assert not rec["envelope"]["ok"] and "1 waypoints outside" in line, line


def test_a_route_away_from_the_antimeridian_is_one_line(tmp_path):
    world = _export(tmp_path, -33.0, 12.3)
    doc = json.loads((tmp_path / "mission.geojson").read_text())
    kinds = {name: kind for name, kind, _ in _geojson_lines(doc)}
    assert kinds["mission"] == "LineString" and kinds["envelope"] == "Polygon"
    root = ET.fromstring((tmp_path / "mission.kml").read_text())
    assert all(not multi for _, multi, _ in _kml_lines(root))
    for fmt in ("geojson", "kml"):
        np.testing.assert_allclose(read_mission(tmp_path / f"mission.{fmt}", world.origin)[0], W, atol=1e-3)


def test_cut_and_join_are_inverse_with_waypoints_on_the_antimeridian():
    """Random lines about ±180° (some waypoints exactly on it, either sign): the pieces never step over 180°, and
    joined they are the line; a ring's pieces joined are the ring (its area, unwrapped)."""
    from auvplan.io.missions.antimeridian import cut_line, cut_ring, join_line, join_rings

    rng = np.random.default_rng(7)
    for _ in range(200):
        n = int(rng.integers(2, 12))
        lon = 180.0 + rng.uniform(-0.5, 0.5, n)
        on = rng.random(n) < 0.2
        lon[on] = 180.0
        lon = np.where(rng.random(n) < 0.5, (lon + 180.0) % 360.0 - 180.0, np.where(lon > 180.0, lon - 360.0, lon))
        line = np.column_stack([lon, rng.uniform(-60.0, 60.0, n), rng.uniform(-500.0, 0.0, n)]).round(9)
        pieces = cut_line(line)
        for p in pieces:
            assert np.all(np.abs(np.diff(p[:, 0])) < 180.0) and np.all(np.abs(p[:, 0]) <= 180.0)
        np.testing.assert_array_equal(join_line(pieces), line)
    lon, lat = np.array([179.9, -179.8, -179.8, 179.9]), np.array([10.0, 10.0, 10.5, 10.5])
    parts = cut_ring(lon, lat)
    assert len(parts) == 2 and all(np.all(np.abs(np.diff(np.r_[p[:, 0], p[:1, 0]])) < 180.0) for p in parts)
    back = join_rings(parts)
    un = np.where(back[:, 0] < 0.0, back[:, 0] + 360.0, back[:, 0])
    assert shapely.Polygon(np.column_stack([un, back[:, 1]])).area == pytest.approx(0.3 * 0.5, rel=1e-9)
    assert len(back) == 4
