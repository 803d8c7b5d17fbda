"""Hostile input, round 22 (wave 18): data files whose values are not metres of seabed, and the page's long work.

Each case is one the earlier rounds had not tried, with what it did before (docs/hostile-input.md, "Round 22"):
exit 2 (or ``DataError``, HTTP 4xx) with one line naming the file, variable or key and its value; the neighbour
of each bound accepted.
"""

from __future__ import annotations

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
