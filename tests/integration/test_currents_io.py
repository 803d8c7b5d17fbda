"""CF current files as CMEMS, HYCOM and ROMS write them: velocities survive projection, units and time.

Oracle: the files hold analytic fields, linear in longitude/latitude (so the bilinear resampling
is exact at the nodes) or in depth and time; the local vector is compared with the east/north
vector turned by pyproj's meridian convergence of the local frame, an independent computation.
Tolerance: 2e-4 m/s (the azimuthal-equidistant frame is not conformal: directions within
~5e-5 rad at 100 km from the origin).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from pyproj import Proj

from auvplan import cli
from auvplan.errors import DataError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.ocean.currents import CurrentsFileSpec, read_currents
from auvplan.io.scenario import loader as sc

ORIGIN = (48.05, -125.75)
FRAME = LocalFrame(*ORIGIN)
BOUNDS = (0.0, 20_000.0, 0.0, 20_000.0)


def cover_box(bounds=BOUNDS, frame=FRAME):
    """The lat/lon box of the local rectangle's corners (its extremes for this origin)."""
    x = np.array([bounds[0], bounds[1], bounds[1], bounds[0]])
    y = np.array([bounds[2], bounds[2], bounds[3], bounds[3]])
    lon, lat = frame.inverse(x, y)
    return lat.min(), lat.max(), lon.min(), lon.max()


def east_north(lon, lat):
    return 0.4 + 0.3 * (lon + 125.75), -0.2 + 0.5 * (lat - 48.05)


def expected_local(x, y, speed_east, speed_north, frame=FRAME):
    """East/north → local x/y with pyproj's meridian convergence (an independent rotation)."""
    lon, lat = frame.inverse(x, y)
    proj = Proj(f"+proj=aeqd +lat_0={frame.lat0} +lon_0={frame.lon0} +datum=WGS84")
    gamma = np.deg2rad(proj.get_factors(lon, lat).meridian_convergence)
    # pyproj's convergence gamma > 0 east of the origin: true north points to (-sin, cos) there
    ue, vn = speed_east, speed_north
    return ue * np.cos(gamma) - vn * np.sin(gamma), ue * np.sin(gamma) + vn * np.cos(gamma)


def cmems(tmp_path, *, units="m s-1", scale=1.0, land=True, name="cmems.nc"):
    la0, la1, lo0, lo1 = cover_box()
    lat = np.linspace(la0, la1, 9)
    lon = np.linspace(lo0, lo1, 11)
    depth = np.array([0.494, 10.0, 50.0])
    time = np.array(["2024-03-01T00:00", "2024-03-01T06:00"], dtype="datetime64[ns]")
    la, lo = np.meshgrid(lat, lon, indexing="ij")
    ue, vn = east_north(lo, la)
    u = np.broadcast_to(ue, (2, 3, *la.shape)).copy() * scale
    v = np.broadcast_to(vn, (2, 3, *la.shape)).copy() * scale
    if land:
        u[:, :, -2:, -3:] = np.nan  # an island in the north-east corner
        v[:, :, -2:, -3:] = np.nan
        u[:, 2, :3, :3] = np.nan  # the seabed between 10 m and 50 m in the south-west
        v[:, 2, :3, :3] = np.nan
    attrs = {"units": units}
    ds = xr.Dataset(
        {"uo": (("time", "depth", "latitude", "longitude"), u, {"standard_name": "eastward_sea_water_velocity",
                                                                 **attrs}),
         "vo": (("time", "depth", "latitude", "longitude"), v, {"standard_name": "northward_sea_water_velocity",
                                                                 **attrs})},
        coords={"time": time, "depth": ("depth", depth, {"positive": "down", "standard_name": "depth"}),
                "latitude": ("latitude", lat, {"units": "degrees_north"}),
                "longitude": ("longitude", lon, {"units": "degrees_east"})},
    )
    for k in ("uo", "vo"):
        ds[k].encoding["_FillValue"] = -32767.0
    p = tmp_path / name
    ds.to_netcdf(p)
    return p, lat, lon


def test_cmems_exact_cover_units_and_land(tmp_path):
    p, lat, lon = cmems(tmp_path)
    g = read_currents(CurrentsFileSpec(str(p)), FRAME, extent_m=BOUNDS, start_time="2024-03-01T03:00:00Z")
    assert g.covers(*BOUNDS)
    assert np.allclose(g.t, [-3 * 3600.0, 3 * 3600.0])
    # open water, interior nodes of the source grid: the analytic east/north field, turned into x/y
    la, lo = np.meshgrid(lat[1:5], lon[1:6], indexing="ij")
    x, y = FRAME.forward(lo, la)
    pts = np.column_stack([x.ravel(), y.ravel(), np.full(x.size, -5.0)])
    got = g.velocity(pts, 0.0)
    ex, ey = expected_local(x.ravel(), y.ravel(), *east_north(lo.ravel(), la.ravel()))
    assert np.abs(got[:, 0] - ex).max() < 2e-4 and np.abs(got[:, 1] - ey).max() < 2e-4
    # land (NaN at every depth): zero current
    xl, yl = FRAME.forward(lon[-1], lat[-1])
    assert np.allclose(g.velocity([[xl, yl, -5.0]]), 0.0)
    # below the seabed (NaN at 50 m only): the 10 m value carried down, not a pull towards zero
    xs, ys = FRAME.forward(lon[1], lat[1])
    top, deep = g.velocity([[xs, ys, -10.0], [xs, ys, -50.0]])
    assert np.allclose(top, deep) and abs(top[0]) > 0.01


def test_cm_per_second_and_knots_are_converted(tmp_path):
    p_m, *_ = cmems(tmp_path, land=False, name="m.nc")
    p_cm, *_ = cmems(tmp_path, units="cm s-1", scale=100.0, land=False, name="cm.nc")
    p_kt, *_ = cmems(tmp_path, units="knots", scale=1.0 / 0.514444, land=False, name="kt.nc")
    ref = read_currents(CurrentsFileSpec(str(p_m)), FRAME, extent_m=BOUNDS)
    cm = read_currents(CurrentsFileSpec(str(p_cm)), FRAME, extent_m=BOUNDS)
    kt = read_currents(CurrentsFileSpec(str(p_kt)), FRAME, extent_m=BOUNDS)
    pts = np.array([[5000.0, 7000.0, -3.0], [15000.0, 1000.0, -30.0]])
    assert np.allclose(cm.velocity(pts), ref.velocity(pts), atol=1e-12)
    assert np.allclose(kt.velocity(pts), ref.velocity(pts), atol=1e-6)
    assert 0.3 < np.abs(ref.velocity(pts)[:, 0]).max() < 0.6  # m/s, not cm/s


def hycom(tmp_path, name="hycom.nc", **overrides):
    """HYCOM's layout: water_u/water_v (time, depth, lat, lon), hours since 2000, 0-360 longitudes."""
    la0, la1, lo0, lo1 = cover_box()
    lat = np.linspace(la0 - 0.04, la1 + 0.04, 8)
    lon = np.linspace(lo0 - 0.04, lo1 + 0.04, 8) + 360.0
    depth = np.array([0.0, 20.0, 100.0])
    hours = 216_000.0 + np.arange(4) * 3.0  # 2024-08-22T00:00 + 3 h steps
    u = (0.1 + 0.001 * depth[None, :, None, None] + 0.01 * np.arange(4)[:, None, None, None]) * np.ones((4, 3, 8, 8))
    v = np.zeros((4, 3, 8, 8))
    ds = xr.Dataset(
        {"water_u": (("time", "depth", "lat", "lon"), u, {"units": "m/s"}),
         "water_v": (("time", "depth", "lat", "lon"), v, {"units": "m/s"})},
        coords={"time": ("time", hours, {"units": "hours since 2000-01-01 00:00:00", "calendar": "gregorian"}),
                "depth": ("depth", depth, {"positive": "down", "units": "m"}),
                "lat": ("lat", lat, {"units": "degrees_north"}), "lon": ("lon", lon, {"units": "degrees_east"})},
    )
    for k, val in overrides.items():
        ds[k].attrs.update(val)
    p = tmp_path / name
    ds.to_netcdf(p)
    return p


def test_hycom_depth_time_and_0_360(tmp_path):
    from datetime import datetime, timedelta

    start = datetime(2000, 1, 1) + timedelta(hours=216_000 + 4.5)
    g = read_currents(CurrentsFileSpec(str(hycom(tmp_path))), FRAME, extent_m=BOUNDS, start_time=start.isoformat())
    assert np.allclose(g.t, (np.arange(4) * 3.0 - 4.5) * 3600.0)
    # u = 0.1 + 0.001 depth + 0.01 step (east), linear in depth and time: exact interpolation
    p = np.array([[10_000.0, 10_000.0, -60.0]])
    for t, step in ((0.0, 1.5), (3600.0, 1.5 + 1.0 / 3.0)):
        want_e = 0.1 + 0.001 * 60.0 + 0.01 * step
        ex, ey = expected_local(p[:, 0], p[:, 1], want_e, 0.0)
        got = g.velocity(p, t)[0]
        assert got[0] == pytest.approx(ex[0], abs=2e-4) and got[1] == pytest.approx(ey[0], abs=2e-4)


def test_projected_grid_mapping(tmp_path):
    """A current file on a UTM grid with a CF grid_mapping: east/north velocities, projected axes."""
    from pyproj import CRS, Transformer

    crs = CRS.from_epsg(32610)
    tr = Transformer.from_crs("EPSG:4326", crs, always_xy=True)
    e0, n0 = tr.transform(ORIGIN[1], ORIGIN[0])
    e = np.arange(e0 - 3000.0, e0 + 25_000.0, 1000.0)
    n = np.arange(n0 - 3000.0, n0 + 25_000.0, 1000.0)
    u = np.full((n.size, e.size), 0.25)
    ds = xr.Dataset(
        {"u": (("y", "x"), u, {"standard_name": "eastward_sea_water_velocity", "units": "m s-1",
                               "grid_mapping": "crs"}),
         "v": (("y", "x"), np.zeros_like(u), {"standard_name": "northward_sea_water_velocity", "units": "m s-1",
                                              "grid_mapping": "crs"}),
         "crs": ((), 0, crs.to_cf())},
        coords={"x": ("x", e, {"standard_name": "projection_x_coordinate", "units": "m"}),
                "y": ("y", n, {"standard_name": "projection_y_coordinate", "units": "m"})},
    )
    p = tmp_path / "utm.nc"
    ds.to_netcdf(p)
    g = read_currents(CurrentsFileSpec(str(p)), FRAME, extent_m=BOUNDS)
    pts = np.array([[1000.0, 2000.0, 0.0], [19_000.0, 18_000.0, 0.0]])
    ex, ey = expected_local(pts[:, 0], pts[:, 1], 0.25, 0.0)
    assert np.allclose(g.velocity(pts)[:, 0], ex, atol=1e-5) and np.allclose(g.velocity(pts)[:, 1], ey, atol=1e-5)


# ---------------------------------------------------------------------- scenario: plans and flies
SCENARIO = """
name = "cf-exact"
seed = 2
[origin]
lat = 48.05
lon = -125.75
[bounds]
x = [0.0, 20000.0]
y = [0.0, 20000.0]
z = [-120.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 100.0
slope = [0.0005, 0.0]
cell_m = 250.0
[currents]
file = "{file}"
[mission]
start = [1000.0, 1000.0, -40.0]
goal = [4000.0, 5000.0, -40.0]
min_altitude_m = 10.0
min_depth_m = 5.0
start_time = "{start}"
[vehicle]
speed = 1.5
[planner]
name = "grid"
"""


def scenario_file(tmp_path, current, start="2024-03-01T02:00:00Z", **kw):
    text = SCENARIO.replace("{file}", current.name).replace("{start}", start)
    for old, new in kw.items():
        text = text.replace(old, new)
    p = tmp_path / "s.toml"
    p.write_text(text)
    return p


def test_exactly_covering_latlon_file_plans_and_flies(tmp_path, capsys):
    p, *_ = cmems(tmp_path, land=False)
    s = scenario_file(tmp_path, p)
    world, _ = sc.build(sc.load(s))
    assert world.currents.covers(0.0, 20_000.0, 0.0, 20_000.0)
    assert cli.main(["run", str(s), "--json"]) == 0
    import json

    rec = json.loads(capsys.readouterr().out)
    assert rec["simulation"]["arrived"] and rec["simulation"]["collisions"] == 0
    assert rec["plan"]["status"] in ("EXACT", "APPROXIMATE") and rec["plan"]["collisions"] == 0


def _fails(tmp_path, capsys, toml, *words):
    assert cli.main(["validate", str(toml)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    for w in words:
        assert w in err, (w, err)


def test_malformed_current_files_exit_2(tmp_path, capsys):
    p, *_ = cmems(tmp_path, land=False)
    # start time outside the file's time span
    _fails(tmp_path, capsys, scenario_file(tmp_path, p, start="2025-01-01T00:00:00"), "cmems.nc", "'time'",
           "2024-03-01T00:00:00 .. 2024-03-01T06:00:00", "outside")
    # bounds larger than the file: the uncovered side is named
    _fails(tmp_path, capsys, scenario_file(tmp_path, p, **{"y = [0.0, 20000.0]": "y = [0.0, 30000.0]"}),
           "cmems.nc", "'uo'", "uncovered on the north")
    # units that are not a velocity
    bad = hycom(tmp_path, "degc.nc", water_u={"units": "degC"})
    _fails(tmp_path, capsys, scenario_file(tmp_path, bad, start="2024-08-22T03:00:00"), "degc.nc", "'water_u'",
           "not a velocity")
    bad = hycom(tmp_path, "junkunits.nc", water_v={"units": "metres per banana"})
    _fails(tmp_path, capsys, scenario_file(tmp_path, bad, start="2024-08-22T03:00:00"), "junkunits.nc",
           "'water_v'", "cannot be parsed")
    # no northward component
    ds = xr.open_dataset(p).drop_vars("vo")
    ds.to_netcdf(tmp_path / "nov.nc")
    _fails(tmp_path, capsys, scenario_file(tmp_path, tmp_path / "nov.nc"), "nov.nc", "northward_sea_water_velocity")
    # every value missing
    ds = xr.open_dataset(p)
    ds["uo"][:] = np.nan
    ds.to_netcdf(tmp_path / "nan.nc")
    _fails(tmp_path, capsys, scenario_file(tmp_path, tmp_path / "nan.nc"), "nan.nc", "'uo'", "every value")
    # a bad ISO time in the scenario
    _fails(tmp_path, capsys, scenario_file(tmp_path, p, start="yesterday"), "[mission]", "start_time", "ISO 8601")


def test_string_file_form_and_bad_time_units(tmp_path):
    p, *_ = cmems(tmp_path, land=False)
    s = sc.load(scenario_file(tmp_path, p))
    assert s.currents.file.path == "cmems.nc"
    ds = xr.open_dataset(p, decode_times=False)
    ds["time"].attrs["units"] = "fortnights"
    ds.to_netcdf(tmp_path / "tu.nc")
    with pytest.raises(DataError, match="'time'.*fortnights"):
        read_currents(CurrentsFileSpec(str(tmp_path / "tu.nc")), FRAME, extent_m=BOUNDS)


def test_data_inspect_currents(tmp_path, capsys):
    p, *_ = cmems(tmp_path, units="cm s-1", scale=100.0)
    assert cli.main(["data", "inspect", str(p)]) == 0
    out = capsys.readouterr().out
    for w in ("as currents: u 'uo', v 'vo'", "units cm s-1 → × 0.01 to m/s", "54 missing value(s)",
              "time 'time': 2 steps, 2024-03-01T00:00:00 .. 2024-03-01T06:00:00", "depth 'depth': 3 levels"):
        assert w in out, (w, out)


def test_non_standard_calendar_decoded_with_cftime(tmp_path):
    """A climate-model 360-day calendar: days since 2000-01-01; start_time on day 2.5 of that calendar."""
    p = hycom(tmp_path, "c360.nc")
    ds = xr.open_dataset(p, decode_times=False)
    ds["time"] = ("time", np.array([0.0, 1.0, 2.0, 3.0]), {"units": "days since 2000-01-01", "calendar": "360_day"})
    ds.to_netcdf(tmp_path / "c360b.nc")
    g = read_currents(CurrentsFileSpec(str(tmp_path / "c360b.nc")), FRAME, extent_m=BOUNDS,
                      start_time="2000-01-03T12:00:00")
    assert np.allclose(g.t, (np.arange(4) - 2.5) * 86400.0)
    with pytest.raises(DataError, match=r"'time' covers 2000-01-01T00:00:00 .. 2000-01-04T00:00:00"):
        read_currents(CurrentsFileSpec(str(tmp_path / "c360b.nc")), FRAME, extent_m=BOUNDS,
                      start_time="2001-01-01T00:00:00")
