"""mutants20: the ends of the readers' new bounds (docs/mutants.md section 7): a tidal station file's ranges
(``tidecheck``), a GeoJSON's ``crs`` member (``jsoncrs``) and the 50 m/s current cap.

Oracles: each range's physical meaning, both ends accepted and the next float past them refused — latitude
±90°, longitude and directions within a turn either way (-360° .. 360° / 720°), depth 0 .. 12 000 m (the deepest
ocean is under 11 km), UTC offsets -14 .. +14 h, currents and amplitudes up to 20 m/s, harmonic speeds 0 .. 360°/h,
node factors 0 .. 10, phases and equilibrium arguments ±1e6°, years 1678 .. 2261 (numpy's datetime64[ns] span);
a ``crs`` of the ``link`` form is refused whatever else it holds; the message quotes 200 characters of the member."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from pyproj import CRS

from auvplan.errors import DataError
from auvplan.io.data.ocean.tidecheck import check_tide_doc
from auvplan.io.data.vector.jsoncrs import check_geojson_crs


def _doc():
    station = {"name": "S", "lat": 48.0, "lon": -125.0, "depth_m": 10.0, "flood_dir_deg": 90.0, "ebb_dir_deg": 270.0,
               "mean_m_s": 0.0, "zone_hours": -8.0, "amplitude_m_s": {"M2": 1.0}, "phase_deg": {"M2": 10.0}}
    return {"constituents": ["M2"], "speed_deg_per_hour": [28.984104], "first_year": 2020,
            "equilibrium_deg": [[0.0]], "node_factor": [[1.0]], "stations": [station]}


_STATION = [("lat", -90.0, 90.0), ("lon", -360.0, 360.0), ("depth_m", 0.0, 12_000.0), ("flood_dir_deg", -360.0, 720.0),
            ("ebb_dir_deg", -360.0, 720.0), ("mean_m_s", -20.0, 20.0), ("zone_hours", -14.0, 14.0)]


def _set(doc, path, v):
    *head, last = path
    node = doc
    for k in head:
        node = node[k]
    node[last] = v
    return doc


_RANGES = ([(("stations", 0, k), lo, hi) for k, lo, hi in _STATION]
           + [(("stations", 0, "amplitude_m_s", "M2"), 0.0, 20.0), (("stations", 0, "phase_deg", "M2"), -1e6, 1e6),
              (("speed_deg_per_hour", 0), 0.0, 360.0), (("equilibrium_deg", 0, 0), -1e6, 1e6),
              (("node_factor", 0, 0), 0.0, 10.0)])


@pytest.mark.parametrize(("path", "lo", "hi"), _RANGES,
                         ids=[str(r[0][2] if r[0][0] == "stations" else r[0][0]) for r in _RANGES])
def test_each_tide_range_takes_its_ends_and_refuses_the_next_float(path, lo, hi):
    for v in (lo, hi):
        check_tide_doc(_set(_doc(), path, v), "t.json")
    for v in (np.nextafter(lo, -math.inf), np.nextafter(hi, math.inf)):
        with pytest.raises(DataError, match=re.escape(f"expected a finite number in [{lo:g}, {hi:g}]")):
            check_tide_doc(_set(_doc(), path, float(v)), "t.json")


def test_the_years_and_the_constituent_names():
    for year in (1678, 2261):
        check_tide_doc(_set(_doc(), ("first_year",), year), "t.json")
    for year in (1677, 2262):
        with pytest.raises(DataError, match="expected a year in 1678..2261"):
            check_tide_doc(_set(_doc(), ("first_year",), year), "t.json")
    for bad in ("", "M\n2", 2):
        doc = _doc()
        doc["constituents"] = ["M2", bad]
        doc["speed_deg_per_hour"] = [28.98, 30.0]
        doc["equilibrium_deg"], doc["node_factor"] = [[0.0], [0.0]], [[1.0], [1.0]]
        with pytest.raises(DataError, match=r"constituents\[1\] = .*expected a constituent's name"):
            check_tide_doc(doc, "t.json")
    check_tide_doc(_doc(), "t.json")  # one station and one constituent are enough (a list's least length is 1)


def _geo(path, crs):
    path.write_text(json.dumps({"type": "FeatureCollection", "crs": crs, "features": []}))
    return path


def test_a_link_crs_is_refused_even_when_it_holds_a_name(tmp_path):
    link = {"type": "link", "properties": {"name": "EPSG:4326", "href": "http://example.org/crs"}}
    with pytest.raises(DataError, match="a 'name' or 'EPSG' member is read, not a link"):
        check_geojson_crs(_geo(tmp_path / "z.geojson", link), "z", DataError, CRS("EPSG:4326"))
    code = {"type": "EPSG", "properties": {"code": 32633, "name": "EPSG:4326"}}  # the code decides, as GDAL reads it
    check_geojson_crs(_geo(tmp_path / "c.geojson", code), "z", DataError, CRS("EPSG:32633"))


def test_the_files_not_read_as_geojson_are_left_alone(tmp_path):
    bad = {"type": "name", "properties": {"name": "EPSG:99999"}}
    (tmp_path / "empty.geojson").write_bytes(b"")
    (tmp_path / "dir.geojson").mkdir()
    for p in (tmp_path / "empty.geojson", tmp_path / "dir.geojson", _geo(tmp_path / "z.txt", bad)):
        check_geojson_crs(p, "z", DataError, CRS("EPSG:4326"))
    with pytest.raises(DataError, match="cannot be built"):
        check_geojson_crs(_geo(tmp_path / "z.JSON", bad), "z", DataError, CRS("EPSG:4326"))


def test_the_message_quotes_200_characters_of_the_member(tmp_path):
    member = {"type": "name", "properties": {"name": "X" * 400}}
    with pytest.raises(DataError) as err:
        check_geojson_crs(_geo(tmp_path / "z.geojson", member), "z", DataError, CRS("EPSG:4326"))
    shown = json.dumps(member)[:200]
    assert f"crs {shown} cannot be built" in str(err.value)


def _current_file(path, u):
    """A 6 x 7 CMEMS-like grid of 0.3 m/s with ``u`` (m/s, east) at one node."""
    import xarray as xr

    lat, lon = np.linspace(47.9, 48.2, 6), np.linspace(-125.9, -125.4, 7)
    field = np.full((1, lat.size, lon.size), 0.3)
    uo = field.copy()
    uo[0, 2, 3] = u
    dims = ("time", "latitude", "longitude")
    ds = xr.Dataset({"uo": (dims, uo, {"units": "m s-1", "standard_name": "eastward_sea_water_velocity"}),
                     "vo": (dims, field, {"units": "m s-1", "standard_name": "northward_sea_water_velocity"})},
                    coords={"time": np.array(["2024-03-01T00:00"], dtype="datetime64[ns]"),
                            "latitude": ("latitude", lat, {"units": "degrees_north"}),
                            "longitude": ("longitude", lon, {"units": "degrees_east"})})
    ds.to_netcdf(path)
    return path


def test_a_current_of_exactly_50_m_s_is_read_and_the_next_float_refused(tmp_path):
    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.data.ocean.currents import MAX_CURRENT_MPS, CurrentsFileSpec, read_currents

    frame, box = LocalFrame(48.05, -125.65), (-5000.0, 5000.0, -5000.0, 5000.0)
    ok = read_currents(CurrentsFileSpec(str(_current_file(tmp_path / "a.nc", MAX_CURRENT_MPS))), frame, extent_m=box)
    assert np.nanmax(np.abs(ok.u)) <= MAX_CURRENT_MPS
    over = float(np.nextafter(MAX_CURRENT_MPS, 99.0))
    with pytest.raises(DataError, match="over the 50 m/s"):
        read_currents(CurrentsFileSpec(str(_current_file(tmp_path / "b.nc", over))), frame, extent_m=box)
