"""Hostile input, round 4: the surfaces of the last two waves (charted ``[[zones]]``, corridor surveys, the
dask flags, mission files) attacked where no earlier round had.

Each case asserts the contract: exit 2 (or ``ScenarioError``/``DataError``) with one line naming the file,
the key and the value; never a traceback, never minutes of work before the refusal.  docs/hostile-input.md
lists every case tried, handled before or fixed here.
"""

from __future__ import annotations

import pytest

from auvplan.cli import main
from helpers import SLOPING_PLANE

PLANE = '\nname = "plane"' + SLOPING_PLANE
TRANSIT = PLANE.replace("goal = [200.0, -300.0, -2.0]", "goal = [5000.0, 3000.0, -10.0]")


def _refused(tmp_path, capsys, text, *needles, command=("validate",)):
    """``auvplan validate`` (or ``command``) of the scenario ``text``: exit 2, one line naming ``needles``."""
    scen = tmp_path / "s.toml"
    scen.write_text(text, encoding="utf-8")
    assert main([*command, str(scen)]) == 2
    out, err = capsys.readouterr()
    assert "Traceback" not in err and err.count("\n") == 1, err
    assert err.startswith(f"auvplan: error: {scen}: "), err
    for needle in needles:
        assert needle in err, err
    return err


# ---------------------------------------------------------------- corridor surveys
@pytest.mark.parametrize(("survey", "needles"), [
    # a centre line that crosses itself (was: AttributeError 'MultiLineString' ... offset_curve)
    ("centerline_xy = [[500.0, 0.0], [4500.0, 2500.0], [4500.0, 0.0], [500.0, 2500.0]]\nwidth_m = 300.0",
     ("[survey] centerline", "crosses itself")),
    # a bend radius too large for the legs (the same traceback)
    ("centerline_xy = [[500.0, 0.0], [2500.0, 2500.0], [4500.0, 0.0], [5000.0, 2000.0]]\nwidth_m = 300.0\n"
     "bend_radius_m = 1e4", ("[survey] centerline", "cannot be rounded to 10000 m")),
])
def test_a_corridor_that_cannot_be_built_is_refused_naming_the_key(tmp_path, capsys, survey, needles):
    _refused(tmp_path, capsys, PLANE + "[survey]\n" + survey + "\n", *needles)


# ---------------------------------------------------------------- [[zones]] written in the scenario
@pytest.mark.parametrize(("zone", "needles"), [
    # metres GEOS cannot take (was: GEOSException orientationIndex encountered NaN/Inf, a traceback)
    ("polygon = [[-1e300, -1e300], [1e300, -1e300], [1e300, 1e300]]", ("[[zones]] #1 polygon", "[-1e+300, -1e+300]")),
    # a radius GEOS cannot buffer (was: 'ValueError: setting an array element with a sequence', 13 lines)
    ("point = [1000.0, 1000.0]\nradius_m = 1e300", ("[[zones]] #1 radius_m = 1e+300",)),
    ("line = [[0.0, 0.0], [1000.0, 0.0]]\nbuffer_m = 1e15", ("[[zones]] #1 buffer_m = 1000000000000000.0",)),
])
def test_a_zone_of_astronomic_size_is_refused_naming_the_key(tmp_path, capsys, zone, needles):
    _refused(tmp_path, capsys, TRANSIT + '[[zones]]\nname = "z"\n' + zone + "\n", *needles, "circumference")


def test_a_zone_at_the_bound_is_accepted():
    from auvplan.io.data.vector.zones import parse_zones

    (spec,) = parse_zones([{"name": "z", "point": [4.0e7, 0.0], "radius_m": 4.0e7}], "s.toml")
    assert spec.coords == ((4.0e7, 0.0),) and spec.radius_m == 4.0e7


# ---------------------------------------------------------------- where the tasks run
@pytest.mark.parametrize("command", [("plan", "track-arc", "--depart-between", "+0h", "+30min"), ("bench",),
                                     ("survey", "shelf-survey")])
def test_a_cluster_of_100000_workers_is_a_usage_error(capsys, monkeypatch, command):
    """``--workers 100000`` spawned a LocalCluster of 100 000 processes (the machine froze, > 180 s)."""
    import os

    monkeypatch.setattr("auvplan.runtime.parallel.Runner._connect",
                        lambda *a: pytest.fail("the cluster was started"))
    assert main([*command, "--workers", "100000"]) == 2
    err = capsys.readouterr().err
    cap = max(4, 4 * (os.cpu_count() or 1))
    assert f"argument --workers: 100000 must be <= {cap} (4 worker processes per CPU" in err
    assert err.strip().splitlines()[-1].startswith(f"auvplan {command[0]}: error: argument --workers")
    # the bound itself parses (the parser alone: nothing runs)
    from auvplan.cli.parser import _parser

    assert _parser().parse_args(["bench", "--workers", str(cap)]).workers == cap


@pytest.mark.parametrize("address", ["garbage", "tcp://[::1", "tcp://127.0.0.1:99999", ""])
def test_a_scheduler_address_dask_cannot_parse_is_a_usage_error(capsys, address):
    """It surfaced after the job's set-up as ``auvplan: error: ValueError: missing port number in address``."""
    assert main(["plan", "track-arc", "--depart-between", "+0h", "+30min", "--scheduler", address]) == 2
    err = capsys.readouterr().err
    assert f"argument --scheduler: {address!r} is not a dask scheduler address" in err


def test_no_scheduler_at_the_address_names_the_flag():
    """A closed port: one line naming ``--scheduler`` and the address, not ``OSError: Timed out ...``."""
    dask = pytest.importorskip("dask")
    pytest.importorskip("distributed")
    from auvplan.errors import AuvplanError
    from auvplan.runtime.parallel import Runner

    with dask.config.set({"distributed.comm.timeouts.connect": "0.5s"}), \
            pytest.raises(AuvplanError, match=r"^--scheduler 'tcp://127.0.0.1:1': no dask scheduler reached there "
                          r"within 0.5 s \("):  # dask's own connect timeout, when under SCHEDULER_CONNECT_S
        Runner(scheduler="tcp://127.0.0.1:1").map(abs, [1, 2])
    from auvplan.cli.parser import _parser

    assert _parser().parse_args(["bench", "--scheduler", "tcp://127.0.0.1:8786"]).scheduler == "tcp://127.0.0.1:8786"


def test_a_dead_scheduler_is_given_up_after_the_short_connect_timeout(monkeypatch):
    """dask waits ``distributed.comm.timeouts.connect`` (30 s) on an address where nothing answers: the Runner
    passes its own bound, 5 s (SCHEDULER_CONNECT_S), and says it.  Oracle: the timeout handed to ``Client``."""
    pytest.importorskip("distributed")
    import dask
    import dask.distributed

    from auvplan.errors import AuvplanError
    from auvplan.runtime import parallel
    from auvplan.runtime.parallel import SCHEDULER_CONNECT_S, Runner

    seen = {}

    def dead(address, timeout=None, **kw):  # type: ignore[no-untyped-def]
        seen.update(address=address, timeout=timeout)
        raise OSError(f"Timed out trying to connect to {address} after {timeout} s")

    monkeypatch.setattr(dask.distributed, "Client", dead)
    # the handshake heard first, within the same bound (audit18: dask's Client waits for it with none)
    monkeypatch.setattr(parallel, "_handshake", lambda address, wait: seen.update(handshake=wait))
    assert dask.config.get("distributed.comm.timeouts.connect") == "30s" and SCHEDULER_CONNECT_S == 5.0
    with pytest.raises(AuvplanError, match=r"^--scheduler 'tcp://10.255.255.1:8786': no dask scheduler reached "
                                           r"there within 5 s \(Timed out"):
        Runner(scheduler="tcp://10.255.255.1:8786").map(abs, [1, 2])
    assert seen == {"handshake": 5.0, "address": "tcp://10.255.255.1:8786", "timeout": 5.0}


# ---------------------------------------------------------------- the planner's budget on the command line
def test_a_budget_of_hours_on_the_command_line_is_refused_as_the_key_is(capsys, monkeypatch):
    """``[planner] budget = 1e12`` was refused at load, ``plan --budget 1e12`` ran for hours (> 180 s seen)."""
    monkeypatch.setattr("auvplan.planners.plan", lambda *a, **k: pytest.fail("the plan ran"))
    assert main(["plan", "track-arc", "--budget", str(10**12)]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("auvplan: error: --budget: budget = 1000000000000 evaluations × samples = "), err
    assert "path samples to cost, over the 2e+09 allowed" in err


# ---------------------------------------------------------------- [[zones]] read from files
def _geojson(path, rings, crs=None):
    import json

    doc = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "big"}, "geometry": {"type": "Polygon", "coordinates": [ring]}}
        for ring in rings]}
    if crs:
        doc["crs"] = {"type": "name", "properties": {"name": crs}}
    path.write_text(json.dumps(doc).replace('"NAN"', "NaN"), encoding="utf-8")
    return path


_EARTH = [[-180.0, -90.0], [180.0, -90.0], [180.0, 90.0], [-180.0, 90.0], [-180.0, -90.0]]
_HEMISPHERE = [[-179.0, -89.0], [-1.0, -89.0], [-1.0, 89.0], [-179.0, 89.0], [-179.0, -89.0]]


@pytest.mark.parametrize("lon0", [-125.0, 179.95], ids=["pacific", "antimeridian"])
@pytest.mark.parametrize("ring", [_EARTH, _HEMISPHERE], ids=["earth", "hemisphere"])
def test_a_zone_the_size_of_the_earth_holds_the_start(tmp_path, capsys, ring, lon0):
    """The whole Earth projected into a shape that held nothing (validate said OK); a hemisphere took minutes
    to index (> 180 s).  Cut to the area, each holds the start: the scenario is refused naming the zone."""
    if lon0 > 0 and ring is _HEMISPHERE:  # the hemisphere about the seam, its longitudes past 180
        ring = [[x + 270.0, y] for x, y in ring]
    _geojson(tmp_path / "z.geojson", [ring])
    text = TRANSIT.replace("lon = -125.0", f"lon = {lon0}") + '[[zones]]\nname = "chart"\nfile = "z.geojson"\n'
    _refused(tmp_path, capsys, text, "[mission] start", "inside a no-go zone (chart: big)")


@pytest.mark.parametrize(("ring", "crs", "needles"), [
    ([[-125.0, 48.0], [-124.99, 48.0], [-124.99, 95.0], [-125.0, 48.0]], "EPSG:4326",
     ("(-124.99, 95) is not a longitude/latitude",)),  # a latitude of 95: was dropped with a warning
    ([[-125.0, 48.0], [-124.99, 48.0], [-124.99, "NAN"], [-125.0, 48.0]], "EPSG:4326",
     ("a coordinate is not a number",)),  # NaN: two RuntimeWarnings of two lines each, then OK
])
def test_a_feature_that_is_not_on_the_earth_is_refused_naming_it(tmp_path, capsys, ring, crs, needles):
    _geojson(tmp_path / "z.geojson", [ring], crs)
    text = TRANSIT + '[[zones]]\nname = "chart"\nfile = "z.geojson"\n'
    _refused(tmp_path, capsys, text, "[[zones]] #1 file = ", "z.geojson': feature 'big': ", *needles)


def test_a_shapefile_in_metres_without_its_crs_is_refused_saying_so(tmp_path, capsys):
    """No ``.prj``: read as longitude/latitude, its metres were dropped as 'no feature reaches the area'."""
    import numpy as np
    import pyogrio.raw
    import shapely

    wkb = np.array([shapely.to_wkb(shapely.box(1000.0, 1000.0, 2000.0, 2000.0))], dtype=object)
    with pytest.warns(UserWarning, match="crs"):
        pyogrio.raw.write(tmp_path / "z.shp", wkb, [np.array(["big"], dtype=object)], ["name"],
                          driver="ESRI Shapefile", geometry_type="Polygon", crs=None)
    text = TRANSIT + '[[zones]]\nname = "chart"\nfile = "z.shp"\n'
    _refused(tmp_path, capsys, text, "z.shp': feature 'big': (1000, 2000) is not a longitude/latitude; the file "
             "states no CRS")


@pytest.mark.parametrize(("zone", "needles"), [
    # [lat, lon] across the antimeridian, far from the origin: read as metres, a zone 358 m long at the
    # origin, accepted silently (validate OK) 1.6 km off the area
    ("polygon = [[-7.0, 179.0], [-7.0, -179.0], [-6.0, -179.0], [-6.0, 179.0]]",
     ("[[zones]] #1 polygon = [[-7.0, 179.0]", "wholly outside the operating area (x 600 .. 6500, y -2500 .. 4500 m)",
      "read as metres [x, y], not all being within 5° of [origin] lat = 48, lon = -125")),
    ("point = [-20000.0, 0.0]\nradius_m = 100.0", ("[[zones]] #1 point = [[-20000.0, 0.0]]", "wholly outside")),
])
def test_a_zone_written_far_outside_the_area_is_refused(tmp_path, capsys, zone, needles):
    east = TRANSIT.replace("x = [-500.0, 5500.0]", "x = [1600.0, 5500.0]").replace(
        "start = [200.0, -300.0, -2.0]", "start = [2000.0, -300.0, -2.0]")  # the origin 1.6 km off the area
    _refused(tmp_path, capsys, east + '[[zones]]\nname = "z"\n' + zone + "\n", *needles)


def test_a_zone_outside_the_bounds_whose_buffer_reaches_them_is_kept():
    """The neighbour accepted: a point 1.5 km beyond the bounds' margin whose radius reaches the area."""
    from auvplan.io.data.vector.zones import parse_zones, read_zones

    specs = parse_zones([{"name": "w", "point": [-3000.0, 0.0], "radius_m": 2000.0}], "s.toml")
    zones = read_zones(specs, None, None, (-500.0, 5500.0, -1500.0, 3500.0))
    assert len(zones.zones) == 1 and zones.zones[0].footprint.bounds[2] > -1500.0


# ---------------------------------------------------------------- mission files
@pytest.mark.parametrize(("name", "text", "needle"), [
    ("m.csv", "x,y,z\n1e300,1e300,1e300\n-1e300,0,0\n", "waypoint 0 = (1e+300, 1e+300, 1e+300) m lies over 4e+07 m"),
    ("m.csv", "x,y,z\n200,-300,-10\n5000,3000,-1e308\n", "waypoint 1 = (5000, 3000, -1e+308) m lies over"),
])
def test_a_mission_waypoint_off_the_earth_is_refused_in_one_line(tmp_path, capsys, name, text, needle):
    """Was: numpy's overflow RuntimeWarnings (4 to 6 lines), then 'over a inf m mission of 2 legs'."""
    scen = tmp_path / "s.toml"
    scen.write_text(TRANSIT, encoding="utf-8")
    mission = tmp_path / name
    mission.write_text(text, encoding="utf-8")
    assert main(["mission", "check", str(mission), "--scenario", str(scen)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"auvplan: error: {mission}: {needle}"), err


def test_a_zone_name_with_a_newline_is_refused(tmp_path, capsys):
    """Was accepted: the one-line error folded it into 'inside a no-go zone (a b)', a name no zone has."""
    zone = '[[zones]]\nname = "a\\nb"\npolygon = [[-1000.0, -1000.0], [1000.0, -1000.0], [1000.0, 1000.0]]\n'
    _refused(tmp_path, capsys, TRANSIT + zone, "[[zones]] #1 name = 'a\\nb': a control character")


def test_a_corridor_a_nanometre_wide_is_checked_without_exploding(tmp_path, capsys):
    """The seabed check sampled the area every sqrt(area)/40: 4.6e7 x 7.4e7 points for a corridor 1e-9 m
    wide ('out of memory (24.1 PiB)', naming no key).  Sampled at most 400 x 400 over its box, it is checked
    (under water everywhere on the plane) and the survey is validated."""
    scen = tmp_path / "s.toml"
    scen.write_text(PLANE + "[survey]\ncenterline_xy = [[500.0, 0.0], [4500.0, 2500.0]]\nwidth_m = 1e-9\n")
    assert main(["validate", str(scen)]) == 0
    out, err = capsys.readouterr()
    assert "OK" in out and "corridor of 4.71e-12 km²" in out and "error" not in err


# ---------------------------------------------------------------- time-optimal planner options
def test_a_billion_headings_is_refused_at_load():
    """``[planner.timeopt] headings = 1e9`` validated OK; ``plan`` allocated its sines and cosines (16 GB) and
    was still swapping after 60 s.  The neighbour, 360 (a heading every degree), loads."""
    from auvplan.errors import ScenarioError
    from auvplan.io.scenario import loader

    text = TRANSIT.replace('name = "iabc"', 'name = "timeopt"') + "[planner.timeopt]\nheadings = {}\n"
    with pytest.raises(ScenarioError, match=r"^s.toml: \[planner.timeopt\] headings = 1000000000: must lie in "
                                            r"\[4, 360\]"):
        loader.loads(text.format(10**9), "s.toml")
    assert loader.loads(text.format(360), "s.toml") is not None


# ---------------------------------------------------------------- glider keys
@pytest.mark.parametrize(("value", "needle"), [
    ("1.0", "compressibility = 1 /Pa: the hull would shrink by 2.01e+06 of its volume"),
    ("1e-8", "the glider cannot climb at the mid depth of its yo (105 m; vertical speeds -0.326 / 0 m/s)"),
])
def test_a_glider_that_cannot_climb_is_refused_at_load(value, needle):
    """``compressibility = 1e-8`` (or 1) validated OK, and ``plan`` died in the yo's timing with a traceback
    (``ZeroDivisionError``: no steady climb with the ballast pumped).  The default (5e-10) loads."""
    from auvplan.errors import ScenarioError
    from auvplan.io.scenario import loader
    from auvplan.io.scenario.builtins import resolve

    text = resolve("glider-lofoten").read_text(encoding="utf-8")
    bad = text.replace("[vehicle.glider]\n", f"[vehicle.glider]\ncompressibility = {value}\n", 1)
    with pytest.raises(ScenarioError, match=r"^g.toml: \[vehicle.glider\] ") as err:
        loader.loads(bad, "g.toml")
    assert needle in str(err.value) and "\n" not in str(err.value)
    assert loader.loads(text.replace("[vehicle.glider]\n", "[vehicle.glider]\ncompressibility = 5e-10\n", 1),
                        "g.toml") is not None


def test_a_geometry_collection_is_refused_naming_the_file_and_the_feature(tmp_path, capsys):
    """The refusal named the scenario and the feature but not the file that holds it."""
    import json

    ring = [[-125.0, 48.0], [-124.99, 48.0], [-124.99, 48.01], [-125.0, 48.0]]
    gc = {"type": "GeometryCollection", "geometries": [{"type": "Polygon", "coordinates": [ring]},
                                                       {"type": "Point", "coordinates": [-125.0, 48.0]}]}
    (tmp_path / "z.geojson").write_text(json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "mix"}, "geometry": gc}]}), encoding="utf-8")
    text = TRANSIT + '[[zones]]\nname = "chart"\nfile = "z.geojson"\nradius_m = 10.0\n'
    _refused(tmp_path, capsys, text, "[[zones]] #1 file = 'z.geojson': 'chart: mix': unsupported geometry "
             "GeometryCollection (a zone is a polygon")


@pytest.mark.parametrize(("name", "text"), [
    ("m.csv", "x,y,z,speed\n200,-300,-10,0\n5000,3000,-10,1e300\n"),
    ("m.plan", '{"fileType": "Plan", "mission": {"cruiseSpeed": 1.5, "plannedHomePosition": [48.0, -125.0, 0],'
               ' "items": [{"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, 1e300, -1, 0, 0, 0, 0]},'
               ' {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, null, 48.01, -124.99, -10]}]}}'),
])
def test_a_leg_speed_of_1e300_is_refused_naming_the_leg(tmp_path, capsys, name, text):
    """A ``MAV_CMD_DO_CHANGE_SPEED`` (or a CSV ``speed``) of 1e300 m/s was flown: numpy's overflow warnings on
    stderr (4 lines) around the verdict.  The neighbour, 100 m/s, is read as carried."""
    from auvplan.io.missions.readback.speeds import read_leg_speeds

    scen = tmp_path / "s.toml"
    scen.write_text(TRANSIT, encoding="utf-8")
    mission = tmp_path / name
    mission.write_text(text, encoding="utf-8")
    assert main(["mission", "check", str(mission), "--scenario", str(scen)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"auvplan: error: {mission}: leg "), err
    assert "speed 1e+300 m/s (carried by the file) is over 100 m/s" in err
    mission.write_text(text.replace("1e300", "100"), encoding="utf-8")
    assert read_leg_speeds(mission, 1)[-1] == 100.0


def test_a_nanometre_substep_is_refused_at_load():
    """``[planner.timeopt] substep = 1e-9`` validated OK and ``plan`` integrated each edge for ever (> 60 s);
    the neighbour, cell / 1000, loads."""
    from auvplan.errors import ScenarioError
    from auvplan.io.scenario import loader

    text = TRANSIT.replace('name = "iabc"', 'name = "timeopt"') + "[planner.timeopt]\ncell = 100.0\nsubstep = {}\n"
    with pytest.raises(ScenarioError, match=r"^s.toml: \[planner.timeopt\] substep = 1e-09 m: 1e\+11 sub-steps per "
                                            r"cell of 100 m, over the 1000 allowed"):
        loader.build(loader.loads(text.format(1e-9), "s.toml"))
    loader.build(loader.loads(text.format(0.1), "s.toml"))


def test_a_departure_three_million_years_on_is_refused_naming_the_key():
    """``depart_s = 1e14`` validated OK; ``plan`` on a tidal scenario stopped with 'tidal prediction: years
    3170900-3170900 outside the tables', naming no key.  Bounded as ``--depart-between``'s offsets are."""
    from auvplan.errors import ScenarioError
    from auvplan.io.scenario import loader

    text = TRANSIT.replace('name = "iabc"', 'name = "timeopt"') + "[planner.timeopt]\ndepart_s = {}\n"
    with pytest.raises(ScenarioError, match=r"^s.toml: \[planner.timeopt\] depart_s = 1e\+14 s: must lie within "
                                            r"366 d of \[mission\] start_time"):
        loader.loads(text.format(1e14), "s.toml")
    assert loader.loads(text.format(-366 * 86400.0), "s.toml").planner.timeopt.depart_s == -366 * 86400.0


@pytest.mark.parametrize("speed", ['"fast"', "true", "[1]"])
def test_a_speed_command_whose_speed_is_not_a_number_is_refused(tmp_path, capsys, speed):
    """A ``MAV_CMD_DO_CHANGE_SPEED`` of ``"fast"`` was ignored silently: the check flew the vehicle's speed,
    which the file does not ask for.  Exit 2, one line naming the file and the item.  (``null``, QGroundControl's
    NaN, is no longer refused: ArduSub keeps its speed, as for -1 and 0 — tests/unit/test_plan_speed_null.py.)"""
    scen = tmp_path / "s.toml"
    scen.write_text(TRANSIT, encoding="utf-8")
    mission = tmp_path / "m.plan"
    mission.write_text('{"fileType": "Plan", "mission": {"cruiseSpeed": 1.5, "plannedHomePosition": [48.0, -125.0, 0],'
                       ' "items": [{"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, ' + speed +
                       ', -1, 0, 0, 0, 0]}, {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0,'
                       ' null, 48.01, -124.99, -10]}]}}', encoding="utf-8")
    assert main(["mission", "check", str(mission), "--scenario", str(scen)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"auvplan: error: {mission}: QGC plan: MAV_CMD_DO_CHANGE_SPEED at "
                                                   "mission.items[0]: speed "), err
    assert err.rstrip().endswith("is not a number")
