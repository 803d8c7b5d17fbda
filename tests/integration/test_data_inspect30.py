"""``data inspect`` and the readers' messages (issue 30, point 5): the uncovered side of each edge, a short
CRS line, pint's redefinitions silenced, missing current values in open water named and placed."""

from __future__ import annotations

import logging
import subprocess
import sys
from importlib import resources

import numpy as np
import pytest
import xarray as xr
from pyproj import CRS

from auvplan.errors import DataError
from auvplan.io.data.bathymetry import read_bathymetry
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.grids import HorizontalGrid
from auvplan.io.data.inspect import inspect_file
from auvplan.io.data.ocean.currents import CurrentsFileSpec, read_currents

LAT = np.arange(10.0, 10.51, 0.05)
LON = np.arange(20.0, 20.51, 0.05)
FRAME = LocalFrame(10.25, 20.25)


@pytest.fixture(scope="module")
def grid_file(tmp_path_factory):
    la, lo = np.meshgrid(LAT, LON, indexing="ij")
    ds = xr.Dataset({"elevation": (("lat", "lon"), -1000.0 - 100 * np.sin(la * 30) * np.cos(lo * 20), {"units": "m"})},
                    coords={"lat": ("lat", LAT, {"units": "degrees_north"}),
                            "lon": ("lon", LON, {"units": "degrees_east"})})
    path = tmp_path_factory.mktemp("edges") / "g.nc"
    ds.to_netcdf(path)
    return path


@pytest.mark.parametrize("side", ["west", "east", "south", "north"])
def test_the_uncovered_side_is_named(grid_file, side):
    """The data span about ±27 km about the frame; an extent reaching 40 km past one edge names that edge only."""
    ext = {"west": (-40_000.0, 0.0, -1000.0, 1000.0), "east": (0.0, 40_000.0, -1000.0, 1000.0),
           "south": (-1000.0, 1000.0, -40_000.0, 0.0), "north": (-1000.0, 1000.0, 0.0, 40_000.0)}[side]
    with pytest.raises(DataError) as err:
        read_bathymetry(grid_file, frame=FRAME, extent_m=ext)
    msg = str(err.value)
    assert f"uncovered on the {side} side" in msg
    assert all(other not in msg.split("uncovered")[1] for other in {"west", "east", "south", "north"} - {side})


def test_crs_line_is_short():
    utm = HorizontalGrid("projected", np.array([0.0, 1.0]), np.array([0.0, 1.0]), CRS.from_epsg(32633), "x")
    assert "EPSG:32633" in utm.describe() and "{" not in utm.describe()
    stere = CRS.from_cf({"grid_mapping_name": "polar_stereographic", "straight_vertical_longitude_from_pole": 70.0,
                         "latitude_of_projection_origin": 90.0, "standard_parallel": 60.0, "earth_radius": 6371000.0})
    line = HorizontalGrid("projected", np.array([0.0, 1.0]), np.array([0.0, 1.0]), stere, "x").describe()
    assert "+proj=stere" in line and "{" not in line and len(line) < 300


def test_pint_redefinitions_are_silenced():
    """A fresh process that converts units prints no pint "Redefining" warning (it printed 11)."""
    code = ("import logging; logging.basicConfig(level=logging.WARNING); "
            "from auvplan.io.data.ocean.currents import velocity_factor; print(velocity_factor('cm s-1', 'x'))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "0.01"
    assert "Redefining" not in out.stderr


def test_missing_current_values_in_open_water_are_warned(tmp_path, caplog):
    """A hole in a water column (values below it) and a gap at one time are counted and placed; land (a whole
    column at every time) is not."""
    depth = np.array([0.0, 10.0, 20.0])
    u = np.full((2, 3, LAT.size, LON.size), 0.3)
    u[:, :, 0, 0] = np.nan  # land: the whole column at every time
    u[:, 2, 1, 1] = np.nan  # seabed: below the deepest value
    u[0, 0, 4, 5] = np.nan  # a hole: the surface value missing above valid ones
    u[1, :, 6, 2] = np.nan  # a gap in time: the whole column at one time only
    v = np.zeros_like(u)
    coords = {"time": ("time", [0.0, 3600.0], {"units": "seconds since 2020-01-01"}),
              "depth": ("depth", depth, {"units": "m", "positive": "down"}),
              "lat": ("lat", LAT, {"units": "degrees_north"}), "lon": ("lon", LON, {"units": "degrees_east"})}
    dims = ("time", "depth", "lat", "lon")
    ds = xr.Dataset({"uo": (dims, u, {"units": "m s-1", "standard_name": "eastward_sea_water_velocity"}),
                     "vo": (dims, v, {"units": "m s-1", "standard_name": "northward_sea_water_velocity"})},
                    coords=coords)
    path = tmp_path / "c.nc"
    ds.to_netcdf(path)
    with caplog.at_level(logging.WARNING, logger="auvplan.io.data.ocean.currents"):
        read_currents(CurrentsFileSpec(str(path)), FRAME)
    msgs = [r.getMessage() for r in caplog.records if "open water" in r.getMessage()]
    assert len(msgs) == 1
    assert "'uo': 4 missing value(s) in open water" in msgs[0]  # 1 hole + 3 levels of the time gap
    assert f"lat {LAT[4]:.4f}, lon {LON[5]:.4f}" in msgs[0]
    text = inspect_file(path)
    assert "WARNING uo: 4 missing value(s) in open water" in text and "WARNING vo" not in text


def test_inspect_states_the_frame_and_angle_of_real_files():
    data = resources.files("auvplan") / "data"
    stere = inspect_file(str(data / "norkyst800_stere_cut.nc"))
    assert "vectors: grid axes (standard_name 'x_sea_water_velocity'); turned to east/north by the grid's angle 65." \
        in stere
    assert "Polar Stereographic" in stere and "{" not in stere
    roms = inspect_file(str(data / "nordic4km_slevels_cut.nc"))
    assert "ROMS/CROCO s-levels" in roms and "Vtransform 2, hc 30 m" in roms
    assert "turned to east/north by 47." in roms
