"""Hostile input, round 17: zone files that are not data (a FIFO, a device, an OGR VRT or WFS description that
makes GDAL fetch from a server), a polygon of a million vertices, a file of 200 000 features, a reef drawn
the long way round the antimeridian; mission files that are FIFOs or ``/dev/zero``, QGC positions that are
``true`` or ``"48.0"``, a CSV with a byte-order mark or 10⁵ columns; a scenario name with a right-to-left
override.  Each asserts the contract (one line naming the file, the key and the value; no hang, no
traceback) and what each did before is in its docstring.  docs/hostile-input.md, round 17.
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
import shapely
from test_hostile_round4 import TRANSIT, _refused

from auvplan.cli import main
from auvplan.errors import DataError, ScenarioError

ZONE = '[[zones]]\nname = "chart"\nfile = "{}"\n'
SQ = [[-124.99, 48.0], [-124.98, 48.0], [-124.98, 48.01], [-124.99, 48.01], [-124.99, 48.0]]


def _fc(*rings, kind="Polygon"):
    return json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": f"f{i}"}, "geometry": {"type": kind, "coordinates": r}}
        for i, r in enumerate(rings)]})


# ---------------------------------------------------------------- zone files that are not data
@pytest.mark.parametrize("cache", ["0", "1"])
def test_a_zone_file_that_is_a_fifo_is_refused_not_waited_on(tmp_path, capsys, monkeypatch, cache):
    """A FIFO: GDAL's open blocked for ever (validate killed after 60 s).  With the readers' cache on (a user's
    default; the suite runs with it off) the cache's key hashed the FIFO's bytes before the reader could refuse
    it, and validate hung there (docwalk20): an alarm ends the test if it hangs again."""
    import signal

    monkeypatch.setenv("AUVPLAN_CACHE", cache)
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path / "cache"))
    os.mkfifo(tmp_path / "z.geojson")

    class Hung(BaseException):  # not an OSError (TimeoutError is one, and the cache reads on after an OSError)
        pass

    def hung(*_):  # noqa: ANN002
        raise Hung("validate waited on the FIFO")

    previous = signal.signal(signal.SIGALRM, hung)
    signal.alarm(10)
    try:
        _refused(tmp_path, capsys, TRANSIT + ZONE.format("z.geojson"), "[[zones]] #1 file = '",
                 "z.geojson': is a FIFO")
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


@pytest.mark.parametrize(("name", "text", "needle"), [
    # validate hung > 200 s on a server that accepts and never answers
    ("z.vrt", "<OGRVRTDataSource><OGRVRTLayer name='z'><SrcDataSource>/vsicurl/http://127.0.0.1:9/z.geojson"
     "</SrcDataSource></OGRVRTLayer></OGRVRTDataSource>", "is an OGR VRT"),
    ("z.xml", "<OGRWFSDataSource><URL>http://127.0.0.1:9/wfs?</URL></OGRWFSDataSource>", "is a WFS service"),
    ("z.gdalg.json", '{"type": "gdal_streamed_alg", "command_line": "gdal vector read x.shp"}', "is a GDAL pipeline"),
])
def test_a_zone_file_that_describes_other_sources_is_refused(tmp_path, capsys, name, text, needle):
    (tmp_path / name).write_text(text, encoding="utf-8")
    _refused(tmp_path, capsys, TRANSIT + ZONE.format(name), f"{name}': {needle}", "auvplan reads local data")


def test_gdal_reads_a_vector_file_off_the_network():
    """The backstop for a description the first bytes do not show (a compressed zip holding a WFS file waited
    for its server for ever): /vsicurl/ opens nothing and GDAL's HTTP gives up within seconds, then the
    configuration is put back."""
    import pyogrio

    from auvplan.io.data.vector.guard import NETWORK_OFF, offline

    before = pyogrio.get_gdal_config_option("GDAL_HTTP_TIMEOUT")
    with offline():
        assert pyogrio.get_gdal_config_option("GDAL_HTTP_TIMEOUT") == 3
        assert pyogrio.get_gdal_config_option("GDAL_HTTP_MAX_RETRY") == 0
        assert pyogrio.get_gdal_config_option("CPL_VSIL_CURL_ALLOWED_EXTENSIONS") == \
            NETWORK_OFF["CPL_VSIL_CURL_ALLOWED_EXTENSIONS"]
    assert pyogrio.get_gdal_config_option("GDAL_HTTP_TIMEOUT") == before


# ---------------------------------------------------------------- zone files that cost too much
def test_a_polygon_of_25000_vertices_is_made_lean_and_still_contains_itself():
    """A 300 m ring of 10⁶ vertices rounded to 10⁻⁷° (the brief's input): GEOS's pad buffer took 110 s and
    7.8 GB, then ``std::bad_alloc`` (a traceback).  Oracle: the footprint contains every vertex and edge of the
    ring, lies within 0.2 m of it (simplified within 0.1, grown by 0.2) and has a few hundred vertices."""
    from auvplan.io.data.vector.zones import _footprint

    t = np.linspace(0.0, 2 * np.pi, 25_000, endpoint=False)
    rng = np.random.default_rng(17)
    ring = np.c_[300 * np.cos(t), 300 * np.sin(t)] + rng.uniform(-0.005, 0.005, (t.size, 2))  # 1 cm rounding
    poly = shapely.make_valid(shapely.Polygon(ring))
    fp = _footprint(poly, 0.0, 0.0, "s.toml: [[zones]] #1")
    assert shapely.get_num_coordinates(fp) < 1000
    assert fp.contains(poly)
    assert shapely.hausdorff_distance(fp.exterior, poly.exterior) <= 0.2 + 0.02


def test_a_polygon_of_few_vertices_is_kept_exactly():
    from auvplan.io.data.vector.zones import _footprint

    poly = shapely.Polygon([(0, 0), (100, 0), (100, 50), (0, 50)])
    assert _footprint(poly, 0.0, 0.0, "w").equals(poly)


def test_a_file_of_more_zones_than_allowed_is_refused_naming_it(tmp_path, monkeypatch):
    """200 000 points in the area: 68 s, then 'out of memory' naming nothing (40 000 took 14 s and 800 MB)."""
    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.data.vector import dense
    from auvplan.io.data.vector.zones import parse_zones, read_zones

    monkeypatch.setattr(dense, "MAX_ZONES", 5)
    pts = [[-124.99 + 0.001 * i, 48.0] for i in range(8)]
    (tmp_path / "z.geojson").write_text(_fc(*pts, kind="Point"), encoding="utf-8")
    specs = parse_zones([{"name": "w", "file": "z.geojson", "radius_m": 5.0}], "s.toml")
    with pytest.raises(DataError, match=r"s.toml: \[\[zones\]\] #1 file = '.*z.geojson': more than 5 features"):
        read_zones(specs, LocalFrame(48.0, -125.0), None, (-500.0, 5500.0, -1500.0, 3500.0), base_dir=tmp_path)
    monkeypatch.setattr(dense, "MAX_ZONES", 8)  # the bound itself is accepted
    assert len(read_zones(specs, LocalFrame(48.0, -125.0), None, (-500.0, 5500.0, -1500.0, 3500.0),
                          base_dir=tmp_path).zones) == 8


# ---------------------------------------------------------------- the antimeridian
AM = TRANSIT.replace("lon = -125.0", "lon = 179.98")


def test_a_reef_drawn_the_long_way_round_the_antimeridian_is_refused(tmp_path, capsys):
    """179.99 → -179.99: read as written, the band round the Earth without the reef; the zone kept 10.7 km² of
    the area out and left the reef's 1.7 km² open (validate OK)."""
    ring = [[179.99, 48.0], [-179.99, 48.0], [-179.99, 48.01], [179.99, 48.01], [179.99, 48.0]]
    (tmp_path / "z.geojson").write_text(_fc([ring]), encoding="utf-8")
    _refused(tmp_path, capsys, AM + ZONE.format("z.geojson"), "feature 'f0': its edge (179.99, 48) → (-179.99, 48) "
             "spans 359.98° of longitude", "past ±180")


def test_a_reef_continued_past_180_is_the_small_zone(tmp_path, capsys):
    ring = [[179.99, 48.0], [180.01, 48.0], [180.01, 48.01], [179.99, 48.01], [179.99, 48.0]]
    (tmp_path / "z.geojson").write_text(_fc([ring]), encoding="utf-8")
    (tmp_path / "s.toml").write_text(AM + ZONE.format("z.geojson"), encoding="utf-8")
    from auvplan.io.scenario import loader

    world, _ = loader.build(loader.load(str(tmp_path / "s.toml")))
    (zone,) = world.zones.zones
    assert 1.5e6 < zone.footprint.area < 1.8e6  # 0.02° × 0.01° at 48° N: 1.49 km × 1.11 km


# ---------------------------------------------------------------- mission files
def test_a_mission_file_that_is_a_fifo_is_refused_not_waited_on(tmp_path, capsys):
    """``mission check`` of a FIFO blocked for ever; of a link to /dev/zero it filled the memory ('out of memory',
    naming no file)."""
    os.mkfifo(tmp_path / "m.plan")
    (tmp_path / "s.toml").write_text(TRANSIT, encoding="utf-8")
    assert main(["mission", "check", "--scenario", str(tmp_path / "s.toml"), str(tmp_path / "m.plan")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"auvplan: error: {tmp_path / 'm.plan'}: is a FIFO"), err


def test_a_mission_file_that_is_a_device_is_refused(tmp_path):
    from auvplan.io.missions.formats import read_mission

    (tmp_path / "m.csv").symlink_to("/dev/zero")
    with pytest.raises(DataError, match=r"m.csv: is a device, not a regular file"):
        read_mission(tmp_path / "m.csv")


def _plan(lat, lon):
    wp = {"type": "SimpleItem", "command": 16, "frame": 3, "autoContinue": True, "doJumpId": 1,
          "params": [0, 0, 0, None, lat, lon, -10.0]}
    return json.dumps({"fileType": "Plan", "mission": {"plannedHomePosition": [48.0, -125.0, 0],
                                                       "items": [wp, dict(wp, params=[0, 0, 0, None, 48.001,
                                                                                      -124.99, -10.0])]}})


@pytest.mark.parametrize(("lat", "lon", "needle"), [
    (True, -124.99, "mission.items[0].params[4] = true: expected a number (latitude)"),  # was: lat 1°, FAIL
    (48.0, "-124.99", 'mission.items[0].params[5] = "-124.99": expected a number (longitude)'),  # was: read
])
def test_a_qgc_position_that_is_not_a_number_is_refused_naming_it(tmp_path, lat, lon, needle):
    from auvplan.io.missions.formats import read_mission

    (tmp_path / "m.plan").write_text(_plan(lat, lon), encoding="utf-8")
    with pytest.raises(DataError) as exc:
        read_mission(tmp_path / "m.plan", (48.0, -125.0))
    assert str(exc.value) == f"{tmp_path / 'm.plan'}: QGC plan: {needle}"


def test_a_csv_mission_with_a_byte_order_mark_and_mixed_line_ends_is_read(tmp_path):
    """A spreadsheet's BOM: 'not a readable csv mission (no field of name x)'."""
    from auvplan.io.missions.formats import read_mission

    (tmp_path / "m.csv").write_bytes("\ufeffx,y,z,speed\r\n200,-300,-2,1\n1000,0,-10,1.5\r5000,3000,-10,2\n"
                                     .encode("utf-8"))
    w, _, fmt = read_mission(tmp_path / "m.csv")
    assert fmt == "csv" and w.tolist() == [[200, -300, -2], [1000, 0, -10], [5000, 3000, -10]]
    from auvplan.io.missions.readback.speeds import read_leg_speeds

    assert read_leg_speeds(tmp_path / "m.csv", 2).tolist() == [1.5, 2.0]


def test_a_csv_mission_of_100000_columns_reads_only_its_own(tmp_path):
    """10⁶ columns took numpy's named reader 3 minutes per read (twice per check); the wanted columns only."""
    from auvplan.io.missions.formats import read_mission

    n = 100_000
    head = ",".join([f"c{i}" for i in range(n)] + ["z", "y", "x"])
    rows = [",".join(["7"] * n + [str(-k), str(10 * k), str(100 * k)]) for k in (1, 2)]
    (tmp_path / "m.csv").write_text("\n".join([head, *rows]) + "\n", encoding="utf-8")
    w, _, _ = read_mission(tmp_path / "m.csv")
    assert w.tolist() == [[100, 10, -1], [200, 20, -2]]


# ---------------------------------------------------------------- the scenario's name
@pytest.mark.parametrize("name", ["a\u202eb", "a\u2028b", "a\x85b"])
def test_a_scenario_name_with_an_invisible_control_is_refused(name):
    """U+202E (right-to-left override) reversed every message and the report's title; U+2028 split a line."""
    from auvplan.io.scenario.names import check_scenario_name

    with pytest.raises(ScenarioError, match=r"s.toml: name = .*invisible formatting characters"):
        check_scenario_name("s.toml", name)
    check_scenario_name("s.toml", "Baie de l'Étoile ✓")  # letters and symbols of any script remain


def test_a_mission_file_of_more_waypoints_than_allowed_is_refused(tmp_path, monkeypatch):
    """A .plan of 10⁶ items was checked for 110-210 s (parsed 8 times), a KML of 2·10⁶ points refused by the
    endurance bound after 54 s; now refused when read (13 s and 11 s, the parsing)."""
    from auvplan.io.missions.formats import read_mission
    from auvplan.io.missions.readback import readers

    monkeypatch.setattr(readers, "MAX_MISSION_WAYPOINTS", 3)
    (tmp_path / "m.csv").write_text("x,y,z\n" + "".join(f"{k},0,-5\n" for k in range(4)), encoding="utf-8")
    with pytest.raises(DataError, match=r"m.csv: 4 waypoints, over the 3 a mission file may have"):
        read_mission(tmp_path / "m.csv")
    (tmp_path / "m.csv").write_text("x,y,z\n" + "".join(f"{k},0,-5\n" for k in range(3)), encoding="utf-8")
    assert read_mission(tmp_path / "m.csv")[0].shape == (3, 3)


# ---------------------------------------------------------------- the scenario's other data files
_NO_TERRAIN = TRANSIT[:TRANSIT.index("[terrain.synthetic]")] + TRANSIT[TRANSIT.index("[currents]"):]
_TIDES = TRANSIT.replace("[currents]\nuniform = [0.0, 0.1, 0.0]", '[currents]\ntides = "t.json"').replace(
    "[mission]\n", '[mission]\nstart_time = "2024-01-01T00:00:00Z"\n')


@pytest.mark.parametrize(("text", "name", "needle"), [
    # the GeoTIFF sniff opened the FIFO to read its magic number: blocked for ever
    (_NO_TERRAIN + '[terrain]\nfile = "t.tif"\n', "t.tif", "t.tif: the bathymetry file is not a regular file"),
    (TRANSIT.replace("uniform = [0.0, 0.1, 0.0]", 'file = "c.nc"'), "c.nc",
     "c.nc: the current file is not a regular file"),  # was 'current file not found'
    (_TIDES, "t.json", "[currents] tides = 't.json': not a regular file"),  # read_text: blocked for ever
])
def test_a_data_file_that_is_a_fifo_is_refused_not_waited_on(tmp_path, capsys, text, name, needle):
    os.mkfifo(tmp_path / name)
    _refused(tmp_path, capsys, text, needle)


def test_a_tide_file_linked_to_dev_zero_is_refused(tmp_path, capsys):
    """read_text of /dev/zero filled the memory."""
    (tmp_path / "t.json").symlink_to("/dev/zero")
    _refused(tmp_path, capsys, _TIDES, "[currents] tides = 't.json': not a regular file")
