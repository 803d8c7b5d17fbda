"""Hostile input, round 22 (wave 18): data files whose values are not metres of seabed, and the page's long work.

Each case is one the earlier rounds had not tried, with what it did before (docs/hostile-input.md, "Round 22"):
exit 2 (or ``DataError``, HTTP 4xx) with one line naming the file, variable or key and its value; the neighbour
of each bound accepted.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.errors import DataError

xr = pytest.importorskip("xarray")

_LAT = np.linspace(47.95, 48.1, 16)
_LON = np.linspace(-125.05, -124.9, 20)

_SCENARIO = """
name = "t"
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 4000.0]
y = [0.0, 4000.0]
z = [-300.0, 0.0]
[terrain]
file = "t.nc"
[mission]
start = [500.0, 500.0, -100.0]
goal = [3500.0, 3500.0, -100.0]
min_altitude_m = 5.0
"""


def _one_error_line(capsys, *needles):
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.count("auvplan: error:") == 1, err
    line = err.strip().splitlines()[-1]
    for needle in needles:
        assert needle in line, line
    return line


def _grid(path, values, name="elevation", **attrs):
    """A 16 x 20 NetCDF grid about (48 N, 125 W) holding ``values`` (a number or an array)."""
    z = np.broadcast_to(np.asarray(values, dtype=float), (_LAT.size, _LON.size)).copy()
    ds = xr.Dataset({name: (("lat", "lon"), z)}, coords={"lat": _LAT, "lon": _LON})
    ds[name].attrs.update(attrs)
    ds["lat"].attrs["units"], ds["lon"].attrs["units"] = "degrees_north", "degrees_east"
    ds.to_netcdf(path)


# ---------------------------------------------------------------- the units of an elevation grid
@pytest.mark.parametrize(("units", "metres"), [
    ("ft", 0.3048), ("feet", 0.3048), ("fathoms", 1.8288), ("km", 1000.0), ("cm", 0.01),
    ("feet below sea level", 0.3048),
    ("m", 1.0), ("meters", 1.0), ("M", 1.0), ("m.a.s.l.", 1.0), ("m (MSL)", 1.0), ("Meters", 1.0),  # as before
    ("m above mean sea level", 1.0), ("", 1.0)])
def test_a_grid_in_feet_or_fathoms_is_read_in_metres(tmp_path, units, metres):
    """A depth grid in feet (NOAA's soundings) was read as metres: 200 ft of water (61 m) became a 200 m deep
    seabed, and a mission 100 m deep passed ``validate`` (through the rock); in km a 2 km deep basin was 2 m."""
    from auvplan.io.data.elevation import read_elevation

    _grid(tmp_path / "t.nc", 200.0, name="depth", positive="down", units=units)
    eg = read_elevation(tmp_path / "t.nc")
    assert eg.z.shape == (_LAT.size, _LON.size)
    np.testing.assert_allclose(eg.z, -200.0 * metres, rtol=1e-5)  # the unit's length in metres, by hand
    if metres != 1.0:
        assert f"units {units!r}" in eg.positive  # what ``data inspect`` prints says so


def test_validate_of_a_mission_below_a_seabed_in_feet_is_refused(tmp_path, capsys):
    """The operator's view of the case above: the seabed 61 m down, the mission at 100 m."""
    _grid(tmp_path / "t.nc", 200.0, name="depth", positive="down", units="ft")
    (tmp_path / "s.toml").write_text(_SCENARIO, encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    _one_error_line(capsys, "[mission] start = [500.00, 500.00, -100.00] m: not a free point", "(seabed at -61.0 m)")


@pytest.mark.parametrize("units", ["m s-1", "degC", "degrees"])
def test_a_grid_whose_units_are_not_a_length_is_refused_naming_them(tmp_path, units):
    """A variable in m/s or °C picked as the elevation was read as metres of seabed."""
    from auvplan.io.data.elevation import read_elevation

    _grid(tmp_path / "t.nc", -200.0, units=units)
    with pytest.raises(DataError) as err:
        read_elevation(tmp_path / "t.nc")
    assert str(err.value).startswith(f"{tmp_path / 't.nc'}: variable 'elevation': units {units!r} are not a length")


# ---------------------------------------------------------------- values no seabed on Earth has
@pytest.mark.parametrize(("value", "shown"), [(-1e30, "-1e+30 m"), (-32767.0, "-32767 m"),
                                              (9.96921e36, "9.96921e+36 m")])
def test_an_undeclared_fill_value_is_refused_not_flown_as_a_seabed(tmp_path, capsys, value, shown):
    """A land cell filled with -1e30 (or -32767) that the file does not declare as ``_FillValue``: read as a
    seabed 10^30 m deep, ``validate`` and ``plan`` OK through the land (the currents' reader refuses 1e30 m/s
    since round 20; the seabed's did not)."""
    z = np.full((_LAT.size, _LON.size), -200.0)
    z[3:5, 7:9] = value
    _grid(tmp_path / "t.nc", z, units="m")
    (tmp_path / "s.toml").write_text(_SCENARIO, encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    _one_error_line(capsys, "t.nc:elevation: elevation holds", shown, f"at lat {_LAT[3]:.4f}, lon {_LON[7]:.4f}",
                    "4 such values", "_FillValue")


def test_the_deepest_and_highest_places_on_earth_are_read():
    """The neighbours: the Challenger Deep (-10 935 m) and Everest (8 849 m) are a seabed and a mountain."""
    from auvplan.io.data.bathymetry import MAX_ELEVATION_M, terrain_from_xy

    x, y = np.linspace(0.0, 1000.0, 5), np.linspace(0.0, 800.0, 4)
    z = np.full((4, 5), -10_935.0)
    z[0, 0] = 8_849.0
    t = terrain_from_xy(x, y, z, name="deep")
    assert float(t.z.min()) == -10_935.0 and float(t.z.max()) == 8_849.0
    z = z.copy()
    z[1, 2] = -MAX_ELEVATION_M * 1.001
    with pytest.raises(DataError, match=r"^deep: elevation holds -12012 m \(at x 500.0, y 266.7; 1 such value\)"):
        terrain_from_xy(x, y, z, name="deep")


# ---------------------------------------------------------------- vector files: geometries GEOS chokes on
_ZONES = """
name = "t"
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 4000.0]
y = [0.0, 4000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 200.0
[mission]
start = [500.0, 500.0, -20.0]
goal = [3500.0, 3500.0, -20.0]
"""
_SQUARE = [[-124.99, 48.01], [-124.98, 48.01], [-124.98, 48.02], [-124.99, 48.02], [-124.99, 48.01]]


def _features(*geometries, crs=None):
    import json

    doc = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": f"f{i}"}, "geometry": g} for i, g in enumerate(geometries)]}
    if crs:
        doc["crs"] = {"type": "name", "properties": {"name": crs}}
    return json.dumps(doc)


_EMPTY_PART = {"MultiPolygon": {"type": "MultiPolygon", "coordinates": [[_SQUARE], []]},
               "MultiLineString": {"type": "MultiLineString", "coordinates": [_SQUARE[:2], []]}}


def test_a_multipart_feature_with_an_empty_part_does_not_crash_the_process(tmp_path):
    """A MultiPolygon with an empty part (``[[ring], []]``): GEOS's segmentize dereferenced the empty part and the
    process died of a segmentation fault (exit -11, no message; in ``serve`` the whole server) on ``validate`` of
    a ``[[zones]]`` file (``[land]`` unions its polygons first, which drops the part).  Run as a separate process
    so that the fault, planted back, fails the test and not the suite."""
    import subprocess
    import sys

    (tmp_path / "z.geojson").write_text(_features(_EMPTY_PART["MultiPolygon"]), encoding="utf-8")
    (tmp_path / "s.toml").write_text(_ZONES + '[[zones]]\nname = "z"\nfile = "z.geojson"\n', encoding="utf-8")
    code = "import sys; from auvplan.cli import main; sys.exit(main(['validate', sys.argv[1]]))"
    p = subprocess.run([sys.executable, "-c", code, str(tmp_path / "s.toml")], capture_output=True, text=True,
                       timeout=300, env={**__import__("os").environ, "AUVPLAN_CACHE": "0"})
    assert p.returncode == 0, (p.returncode, p.stderr[-2000:])  # the part that is there is the zone / the land
    assert "Traceback" not in p.stderr


@pytest.mark.parametrize("kind", sorted(_EMPTY_PART))
def test_the_reader_drops_empty_parts_and_keeps_the_others(tmp_path, kind):
    from auvplan.io.data.vector.reader import read_vector

    (tmp_path / "z.geojson").write_text(_features(_EMPTY_PART[kind], {"type": "Point", "coordinates": [1, 2]}),
                                        encoding="utf-8")
    geoms = read_vector(tmp_path / "z.geojson", "z", DataError).geometries
    import shapely

    parts = shapely.get_parts(geoms[0])
    assert geoms[0].geom_type == kind and len(parts) == 1 and not parts[0].is_empty  # the drawn part, whole
    np.testing.assert_array_equal(shapely.get_coordinates(parts[0]), np.asarray(_EMPTY_PART[kind]["coordinates"][0])
                                  .reshape(-1, 2))
    assert geoms[1].equals(shapely.Point(1, 2))  # the other features untouched


@pytest.mark.parametrize(("geometry", "crs", "needles"), [
    ({"type": "Polygon", "coordinates": [_SQUARE[:4]]}, None,  # GDAL warns 'Non closed ring', GEOS then raised
     ("z.geojson': feature #1: not a geometry GEOS reads", "closed linestring")),
    ({"type": "Polygon", "coordinates": [_SQUARE[:2]]}, None, ("feature #1: not a geometry GEOS reads",)),
    ({"type": "Polygon", "coordinates": [[[1e300, 7e5], [1.001e6, 7e5], [1.001e6, 7.01e5], [1e300, 7e5]]]},
     "EPSG:32610", ("feature 'f0': (1e+300, 700000) in its CRS has no place in the local frame",)),
])
@pytest.mark.filterwarnings("error::RuntimeWarning")  # numpy's 'invalid value' lines printed before the error
def test_a_feature_geos_cannot_build_is_refused_naming_it(tmp_path, capsys, geometry, crs, needles):
    """Each was a ``shapely.errors.GEOSException`` traceback (exit 1): an unclosed ring, a ring of two points, a
    projected coordinate of 1e300 m (projected to inf)."""
    (tmp_path / "z.geojson").write_text(_features(geometry, crs=crs), encoding="utf-8")
    (tmp_path / "s.toml").write_text(_ZONES + '[[zones]]\nname = "z"\nfile = "z.geojson"\n', encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    _one_error_line(capsys, *needles)


# ---------------------------------------------------------------- mission files: the envelope's numbers
@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """A short mission over dynamic-terrain's seamount flank (test_deploy's), exported with its datum and envelope."""
    from test_deploy import MINI, SPEED

    from auvplan.io.missions import export
    from auvplan.io.scenario import loader as sc_io
    from auvplan.sim import RunRecord

    world, mission = sc_io.build(sc_io.load("dynamic-terrain"))
    record = RunRecord("dynamic-terrain", 1, None, MINI, MINI[[0, -1]], None)
    out = tmp_path_factory.mktemp("exported")
    export.write_exports(out, record, world.origin, SPEED, ("yaml", "geojson", "kml", "csv"),
                         deploy=export.deploy_for(world, mission, record, SPEED))
    return out


def _edited(exported, tmp_path, name, old, new):
    text = (exported / name).read_text(encoding="utf-8")
    assert old in text, text[:400]
    (tmp_path / name).write_text(text.replace(old, new, 1), encoding="utf-8")
    return tmp_path / name


@pytest.mark.parametrize(("name", "old", "new", "needles"), [
    # a 400-digit integer in the envelope's polygon: 'OverflowError: int too large to convert to float', a traceback
    ("mission.yaml", "polygon: [[", "polygon: [[" + "9" * 400 + ", 0.0], [", ("the datum, envelope or payload",
                                                                            "int too large to convert to float")),
    # NaN / inf limits: 'envelope OK — max_depth_m nan', exit 0 (an executor given a NaN depth limit)
    ("mission.yaml", "max_depth_m: ", "max_depth_m: .nan, x: ", ("envelope max_depth_m = nan: expected a finite",)),
    ("mission.yaml", "max_time_s: ", "max_time_s: -.inf, x: ", ("envelope max_time_s = -inf: expected a finite",)),
    ("mission.geojson", '"max_depth_m": ', '"max_depth_m": NaN, "x": ', ("envelope max_depth_m = nan",)),
    ("mission.kml", '<Data name="min_altitude_m"><value>', '<Data name="min_altitude_m"><value>inf</value><value>',
     ("envelope min_altitude_m = inf",)),
    # a polygon vertex of 1e308 or NaN: numpy's overflow warning, then a verdict on it
    ("mission.yaml", "polygon: [[", "polygon: [[1e308, .nan], [", ("envelope polygon: vertex 0 = (1e+308, nan)",)),
    # a CSV latitude of 1e308: numpy's 'invalid value' warning, then 'origin must be a valid latitude/longitude'
    ("mission.csv", ",15.279495679,", ",1e308,", ("line 2: lat = 1e+308, lon = 158.750026469",)),
])
@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_an_envelope_or_datum_that_is_not_numbers_is_refused_naming_it(exported, tmp_path, capsys, name, old, new,
                                                                       needles):
    path = _edited(exported, tmp_path, name, old, new)
    assert main(["mission", "check", str(path), "--scenario", "dynamic-terrain", "-q"]) == 2
    _one_error_line(capsys, f"{path}: ", *needles)


def test_the_exported_envelopes_are_read_as_written(exported, capsys):
    """The neighbours: every exported file's envelope is read and holds the mission."""
    for name in ("mission.yaml", "mission.geojson", "mission.kml", "mission.csv"):
        assert main(["mission", "check", str(exported / name), "--scenario", "dynamic-terrain", "-q"]) == 0, name
        out = capsys.readouterr().out
        assert ("envelope OK" in out) == (name != "mission.csv"), out


# ---------------------------------------------------------------- how many vortices a current may sum
def _vortices(n):
    items = ", ".join(f"{{ x = {100.0 + i}, y = 2000.0, gamma = 1000.0, delta = 300.0 }}" for i in range(n))
    return _SCENARIO.replace('[terrain]\nfile = "t.nc"\n', f"[currents]\nvortices = [{items}]\n")


def test_a_current_of_1000_vortices_is_refused_at_load(tmp_path, capsys):
    """10⁵ vortices: ``validate`` OK in 5 s, then ``plan`` ran for hours; 1 000 took 45 s to plan a 5-iteration
    swarm (every current sample sums them all; in ``serve`` the page's long work was busy all that time)."""
    (tmp_path / "s.toml").write_text(_vortices(1_000), encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    _one_error_line(capsys, "s.toml: [currents] vortices: 1,000 vortices, over the 100 a scenario may hold")


def test_the_hundredth_vortex_is_accepted():
    from auvplan.io.scenario import loader
    from auvplan.io.scenario.specs import MAX_VORTICES

    assert len(loader.loads(_vortices(MAX_VORTICES), "s.toml").currents.vortices) == MAX_VORTICES
    with pytest.raises(Exception, match=r"^s.toml: \[currents\] vortices: 101 vortices"):
        loader.loads(_vortices(MAX_VORTICES + 1), "s.toml")


# ---------------------------------------------------------------- the page: text JSON allows and UTF-8 does not
@pytest.fixture(scope="module")
def page(tmp_path_factory):
    pytest.importorskip("starlette")
    from starlette.testclient import TestClient

    from auvplan.cli.serve import make_session
    from auvplan.serve.app import LOCAL_HOSTS, make_app

    session = make_session("track-single", [str(tmp_path_factory.mktemp("page22"))])
    return session, TestClient(make_app(session, (*LOCAL_HOSTS, "testserver")), raise_server_exceptions=False)


@pytest.mark.parametrize(("path", "body", "needle"), [
    # the error line held the lone surrogate itself: encoding the answer failed, HTTP 500 and a traceback in the log
    ("/api/set", '{"table": "\\ud800", "key": "x", "value": 1}', "[\\ud800]: the page edits only vehicle"),
    # 'UnicodeEncodeError: ... surrogates not allowed', naming neither the key nor the value
    ("/api/open", '{"scenario": "a\\ud800"}', "'a\\ud800': not a file name"),
    ("/api/survey", '{"file": "a\\ud800.geojson"}', "'a\\ud800.geojson': not a file name"),
])
def test_a_lone_surrogate_is_400_naming_it(page, path, body, needle):
    """JSON may escape a lone UTF-16 surrogate (``"\\ud800"``), which no file name and no UTF-8 answer can hold."""
    session, client = page
    before = session.waypoints.copy()
    r = client.post(path, content=body.encode("ascii"), headers={"content-type": "application/json"})
    assert r.status_code == 400, (r.status_code, r.text[:300])
    error = r.json()["error"]
    assert error.startswith("auvplan: error: ") and needle in error and "UnicodeEncodeError" not in error, error
    np.testing.assert_array_equal(session.waypoints, before)
    assert client.get("/api/state").status_code == 200  # the server answers on


# ---------------------------------------------------------------- the page: long work it can stop
@pytest.mark.parametrize(("path", "body", "what"), [
    ("/api/fly", {}, "the flight"), ("/api/plan", {"planner": "iabc", "seed": 3}, "the plan with iabc")])
def test_a_running_plan_or_flight_stops_on_request(tmp_path, monkeypatch, path, body, what):
    """A flight within the command line's bounds runs up to 2·10⁷ time steps (a slow vehicle over a long survey:
    tens of minutes), a plan up to 2·10⁹ path samples, and the page sends its requests one at a time: it waited
    behind them, every other long request 'busy', with no way to stop them but to kill the server (no /api/stop:
    404).  Now ``POST /api/stop`` makes the running work raise at its next step (a plan's iteration, a flight's
    simulated minute): its request answers 409 ``stopped`` and nothing of it is kept.

    Deterministic: the work is held at its first step (a gate in the session's stop point) until the stop has
    been answered, then released; the real planner and simulator run up to there."""
    import threading

    pytest.importorskip("starlette")
    from starlette.testclient import TestClient

    from auvplan.cli.serve import make_session
    from auvplan.serve.app import LOCAL_HOSTS, make_app

    session = make_session("track-single", [str(tmp_path)])
    client = TestClient(make_app(session, (*LOCAL_HOSTS, "testserver")))
    reached, release = threading.Event(), threading.Event()
    real = session.stop_point
    steps = []

    def gate(label):
        steps.append(label)
        if len(steps) == 1:
            reached.set()
            assert release.wait(60), "the stop was never answered"  # a safety net, not a wait for time
        real(label)

    monkeypatch.setattr(session, "stop_point", gate)
    before = (session.waypoints.copy(), len(session.candidates), session.flight)
    answers = {}
    worker = threading.Thread(target=lambda: answers.update(long=client.post(path, json=body)))
    worker.start()
    try:
        assert reached.wait(120), "the long work never reached its first step"
        assert client.post("/api/plan", json={}).status_code == 503  # still one long job at a time
        stop = client.post("/api/stop", json={})
        assert stop.status_code == 200 and stop.json()["result"]["stopping"].startswith(("a flight", "a plan"))
    finally:
        release.set()
        worker.join(120)
    r = answers["long"]
    assert r.status_code == 409 and r.json()["stopped"] is True, r.text[:300]
    assert r.json()["error"].startswith(f"auvplan: error: {what}") and "stopped on request" in r.json()["error"]
    assert len(steps) == 1  # it stopped at the step after the request, not at the end
    np.testing.assert_array_equal(session.waypoints, before[0])  # nothing of it kept
    assert len(session.candidates) == before[1] and session.flight is before[2]
    # nothing to stop now: said so; the next long work is not stopped by the old request
    assert client.post("/api/stop", json={}).json()["result"]["stopping"] == ""
    monkeypatch.setattr(session, "stop_point", real)
    assert client.post(path, json=body).status_code == 200


@pytest.mark.parametrize(("crs", "needle"), [
    # pyproj.exceptions.ProjError: Error creating Transformer from CRS (a traceback, exit 1)
    ('LOCAL_CS["site grid",UNIT["metre",1],AXIS["X",EAST],AXIS["Y",NORTH]]', "crs 'site grid' (Engineering CRS)"),
    ("EPSG:4978", "crs 'WGS 84' (Geocentric CRS)"),  # read as a map: 'no feature reaches the area', validate OK
    ("EPSG:5703", "crs 'NAVD88 height' (Vertical CRS)"),  # a GEOSException traceback
])
def test_a_layer_in_a_crs_that_is_not_a_map_is_refused_naming_it(tmp_path, capsys, crs, needle):
    import shapely
    from pyogrio.raw import write

    write(tmp_path / "z.gpkg", np.array([shapely.to_wkb(shapely.box(1000.0, 1000.0, 1200.0, 1200.0))], dtype=object),
          field_data=[np.array(["f0"], dtype=object)], fields=["name"], geometry_type="Polygon", crs=crs,
          driver="GPKG")
    (tmp_path / "s.toml").write_text(_ZONES + '[[zones]]\nname = "z"\nfile = "z.gpkg"\n', encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    _one_error_line(capsys, "z.gpkg': " + needle + " is not longitude/latitude or a map projection")


# ---------------------------------------------------------------- GeoTIFF grids that are not north-up maps
@pytest.mark.parametrize(("crs", "transform", "needle"), [
    # pyproj.exceptions.ProjError: Error creating Transformer from CRS (a traceback, exit 1)
    ('LOCAL_CS["site grid",UNIT["metre",1],AXIS["X",EAST],AXIS["Y",NORTH]]', (250.0, 0.0, 0.0, 0.0, -250.0, 4000.0),
     "crs 'site grid' (Engineering CRS) is not longitude/latitude or a map projection"),
    # rioxarray numbered the pixels: read as lat 0..19, lon 0..19 (near the origin (0, 0): a seabed silently wrong)
    ("EPSG:4326", (0.01, 0.002, -125.05, 0.001, -0.01, 48.1), "the GeoTIFF's grid is rotated or sheared"),
])
def test_a_geotiff_that_is_not_a_north_up_map_is_refused(tmp_path, capsys, crs, transform, needle):
    rasterio = pytest.importorskip("rasterio")

    with rasterio.open(tmp_path / "t.tif", "w", driver="GTiff", height=20, width=20, count=1, dtype="float64",
                       crs=crs, transform=rasterio.Affine(*transform)) as out:
        out.write(np.full((20, 20), -200.0), 1)
    (tmp_path / "s.toml").write_text(_SCENARIO.replace("t.nc", "t.tif"), encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    _one_error_line(capsys, "t.tif: " + needle)


# ---------------------------------------------------------------- a file of several layers, none named
_S57 = Path(__file__).resolve().parents[1] / "data" / "US4MD81M_zones.000"


def test_a_chart_of_several_layers_without_a_layer_is_refused_naming_them(tmp_path, capsys):
    """A NOAA S-57 cell given without ``layer``: GDAL's first layer, the DSID record (no geometry), was read alone,
    'no feature' was a warning and ``validate`` said OK with no zone at all (every cable, wreck and restricted
    area of the chart left out)."""
    (tmp_path / "s.toml").write_text(_ZONES + f'[[zones]]\nname = "chart"\nfile = "{_S57}"\nbuffer_m = 20.0\n'
                                     "radius_m = 50.0\n", encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 2
    _one_error_line(capsys, "US4MD81M_zones.000': the file holds 6 layers (DSID (no geometry), CBLARE (Polygon), "
                    "OBSTRN (Unknown), PIPSOL (Unknown), RESARE (Polygon), WRECKS (Unknown)); name the one to read "
                    "with layer = ")


def test_a_layer_named_or_a_file_of_one_layer_is_read():
    from auvplan.io.data.vector.reader import read_vector

    assert len(read_vector(_S57, "c", DataError, layer="RESARE").present()) > 0  # the neighbour: a layer named
    one = Path(__file__).resolve().parents[2] / "src" / "auvplan" / "data" / "ne_10m_reefs_chagos.geojson"
    assert len(read_vector(one, "r", DataError).present()) > 0  # one layer: no name needed


def test_data_inspect_of_a_grid_without_extent_says_so(tmp_path, capsys):
    """Latitudes 10⁻¹² ° apart: the footprint's centroid was a ``GEOSException`` traceback (``getX called on empty
    Point``) out of ``data inspect``'s seabed-model costs (``validate`` refused it by the memory estimate)."""
    z = np.full((_LAT.size, _LON.size), -200.0)
    ds = xr.Dataset({"elevation": (("lat", "lon"), z)}, coords={"lat": 48.0 + np.arange(_LAT.size) * 1e-12,
                                                                "lon": _LON})
    ds.to_netcdf(tmp_path / "t.nc")
    assert main(["data", "inspect", str(tmp_path / "t.nc")]) == 0
    out = capsys.readouterr().out
    assert "seabed model: not measured (t.nc:elevation: empty extent" in out, out


@pytest.mark.parametrize(("units", "metres"), [("km", 1000.0), ("dbar", 1.0)])
def test_a_current_file_s_depth_levels_are_read_in_metres(tmp_path, units, metres):
    """A current file whose depth axis is in km: levels 0, 0.05, 0.2 km read as 0, 0.05, 0.2 m — the whole water
    column below 20 cm took the deepest level's current (1 m/s where the file says 0.5 m/s at 50 m), silently."""
    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.data.ocean.currents import CurrentsFileSpec, read_currents

    levels = np.array([0.0, 50.0, 200.0]) / metres
    u = np.broadcast_to(np.array([0.1, 0.5, 1.0])[None, :, None, None], (2, 3, _LAT.size, _LON.size))
    ds = xr.Dataset({"u": (("time", "depth", "lat", "lon"), u), "v": (("time", "depth", "lat", "lon"), 0 * u)},
                    coords={"time": [0.0, 3600.0], "depth": levels, "lat": _LAT, "lon": _LON})
    ds["time"].attrs["units"] = "seconds since 2024-01-01"
    ds["u"].attrs["units"] = ds["v"].attrs["units"] = "m s-1"
    ds["depth"].attrs.update(units=units, positive="down")
    ds.to_netcdf(tmp_path / "c.nc")
    g = read_currents(CurrentsFileSpec(str(tmp_path / "c.nc")), LocalFrame(48.0, -125.0),
                      extent_m=(0.0, 4000.0, 0.0, 4000.0))
    np.testing.assert_allclose(g.z, [-200.0, -50.0, 0.0], rtol=1e-4)  # ascending, up: the levels in metres


# ---------------------------------------------------------------- a scenario file of gigabytes
def test_a_scenario_file_of_gigabytes_is_refused_unread(tmp_path, capsys, monkeypatch):
    """A 1.5 GB file given as the scenario (a sparse file, or a data file named .toml): read whole — 3.1 GB
    resident, over the 2 GiB memory budget, 20 s — before 'invalid TOML'.  Now refused by its size, unread (a read
    of it fails the test); the page's open is bounded the same way."""
    big = tmp_path / "s.toml"
    with big.open("wb") as fh:
        fh.truncate(1_500_000_000)  # sparse: no disk used
    monkeypatch.setattr(type(big), "read_bytes", lambda self: pytest.fail("read whole"))
    assert main(["validate", str(big)]) == 2
    _one_error_line(capsys, f"{big}: 1,500,000,000 bytes, over the 16,777,216 a scenario file may have")


def test_a_scenario_file_at_the_bound_is_read(tmp_path):
    from auvplan.io.scenario.loader import MAX_SCENARIO_BYTES, loads, scenario_text

    text = _SCENARIO.replace('[terrain]\nfile = "t.nc"\n', "")
    padded = text + "#" * (MAX_SCENARIO_BYTES - len(text.encode()) - 1) + "\n"
    p = tmp_path / "s.toml"
    p.write_text(padded, encoding="utf-8")
    assert loads(scenario_text(p), str(p)).name == "t"
    p.write_text(padded + "#", encoding="utf-8")
    with pytest.raises(Exception, match=r"16,777,217 bytes, over the 16,777,216"):
        scenario_text(p)


def test_a_results_folder_s_scenario_of_gigabytes_is_refused_unread(tmp_path, monkeypatch):
    """``report``/``export`` read a results folder's ``scenario.toml`` whole as well (``read_text``)."""
    from test_hostile_round20 import _results

    from auvplan.io.results.readback import read_run

    folder = _results(tmp_path / "h")
    with (folder / "scenario.toml").open("wb") as fh:
        fh.truncate(1_500_000_000)
    monkeypatch.setattr(type(folder), "read_text", lambda *a, **k: pytest.fail("read whole"))
    with pytest.raises(DataError, match=r"scenario.toml: 1,500,000,000 bytes, over the 16,777,216 a scenario file"):
        read_run(folder)
