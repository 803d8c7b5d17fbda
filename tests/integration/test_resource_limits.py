"""Issue #32, one resource estimator before any allocation: data files from their headers (NetCDF,
GeoTIFF, currents, ``data inspect``, ``run.npz``), a regrid at a cell the coordinates make absurd,
``[planner.timeopt]`` and ``[formation] sample_m``; each refusal names the file or key, the size
and the limit.  The fuzz draws declared sizes and a budget; the oracle is the documented estimate
(24 B a declared cell, the member's bytes), computed independently of the reader."""

from __future__ import annotations

import io
import math
import tomllib
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from auvplan import cli
from auvplan.errors import DataError, ScenarioError
from auvplan.io.data.elevation import read_elevation
from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.ocean.currents import CurrentsFileSpec, read_currents
from auvplan.io.files import limits
from auvplan.io.files.limits import BudgetError, Limits, budget
from auvplan.io.scenario import loader as scenario_io

SIZES = st.integers(min_value=2, max_value=400_000)
BUDGET_MB = st.floats(min_value=0.05, max_value=2.0)  # small: a file under it is read for real, and quickly
_MIB = 1024.0 * 1024.0


def _sparse_netcdf(path: Path, ny: int, nx: int, *, name: str = "elevation", axes: bool = False) -> Path:
    """A NetCDF-4 file that declares ``ny × nx`` float32 cells and stores none of them (a few kB)."""
    import netCDF4

    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("lat", ny)
        nc.createDimension("lon", nx)
        lat = nc.createVariable("lat", "f8", ("lat",))
        lon = nc.createVariable("lon", "f8", ("lon",))
        lat.units, lon.units = "degrees_north", "degrees_east"
        if axes:
            lat[:] = np.linspace(14.0, 15.0, ny)
            lon[:] = np.linspace(158.0, 159.0, nx)
        chunks = (min(ny, 1024), min(nx, 1024))
        for n in (name, "v") if name == "u" else (name,):
            v = nc.createVariable(n, "f4", ("lat", "lon"), chunksizes=chunks, fill_value=np.float32(-3000.0))
            v.units = "m" if n == "elevation" else "m s-1"
            if n == "elevation":
                v.standard_name = "height_above_mean_sea_level"
    return path


def _sparse_geotiff(path: Path, ny: int, nx: int) -> Path:
    """A tiled GeoTIFF that declares ``ny × nx`` pixels with no tile written (sparse)."""
    import rasterio
    from rasterio.transform import from_origin

    with rasterio.open(path, "w", driver="GTiff", width=nx, height=ny, count=1, dtype="float32",
                       crs="EPSG:4326", transform=from_origin(158.0, 15.0, 1e-5, 1e-5), tiled=True,
                       blockxsize=1024, blockysize=1024, sparse_ok=True, BIGTIFF="YES"):
        pass
    return path


def _expect(call, cells: float, mb: float, *needles: str) -> None:
    """The oracle: refused (BudgetError naming ``needles`` and the limit) iff 24 B × cells > the budget."""
    over = cells * limits.BYTES_PER_DATA_CELL > mb * _MIB
    with budget(Limits(memory_mb=mb)):
        try:
            call()
        except BudgetError as exc:
            msg = str(exc)
            assert over, msg
            assert "\n" not in msg and f"over the limit of {mb:g} MiB" in msg, msg
            for n in needles:
                assert n in msg, (n, msg)
            return
        except DataError:
            pass  # under the budget, a file with no stored values may fail for what it holds, not its size
    assert not over, cells


@settings(max_examples=25, deadline=None)
@given(SIZES, SIZES, BUDGET_MB)
def test_netcdf_bathymetry_declared_size_fuzz(tmp_path_factory, ny, nx, mb):
    p = _sparse_netcdf(tmp_path_factory.mktemp("nc") / "g.nc", ny, nx)
    _expect(lambda: read_elevation(p), float(ny) * nx, mb, str(p), "variable 'elevation'", f"{ny:,} × {nx:,}")


@settings(max_examples=15, deadline=None)
@given(SIZES, SIZES, BUDGET_MB)
def test_geotiff_declared_size_fuzz(tmp_path_factory, ny, nx, mb):
    p = _sparse_geotiff(tmp_path_factory.mktemp("tif") / "g.tif", ny, nx)
    assert p.stat().st_size < 5_000_000
    _expect(lambda: read_elevation(p), float(ny) * nx, mb, str(p), "band 1", f"{ny:,} × {nx:,}")


@settings(max_examples=15, deadline=None)
@given(st.integers(2, 20_000), st.integers(2, 20_000), BUDGET_MB)
def test_netcdf_currents_declared_size_fuzz(tmp_path_factory, ny, nx, mb):
    p = _sparse_netcdf(tmp_path_factory.mktemp("cur") / "c.nc", ny, nx, name="u", axes=True)
    _expect(lambda: read_currents(CurrentsFileSpec(str(p), u="u", v="v"), LocalFrame(14.5, 158.5)), float(ny) * nx, mb,
            str(p), "variable 'u'")


def _npz_with_header(shape: tuple[int, ...], dtype: str = "<f8", payload: bytes = b"") -> bytes:
    """An .npz whose one member's header declares ``shape`` (the data stored: ``payload`` only)."""
    head = io.BytesIO()
    np.lib.format.write_array_header_1_0(head, {"descr": dtype, "fortran_order": False, "shape": shape})
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("sim_t.npy", head.getvalue() + payload)
    return buf.getvalue()


@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(0, 10**6), min_size=1, max_size=3), BUDGET_MB)
def test_npz_member_declared_size_fuzz(tmp_path_factory, shape, mb):
    p = tmp_path_factory.mktemp("npz") / "run.npz"
    p.write_bytes(_npz_with_header(tuple(shape)))
    over = math.prod(shape) * 8 > mb * _MIB
    try:
        limits.check_npz(p, Limits(memory_mb=mb))
    except BudgetError as exc:
        assert over and "member 'sim_t'" in str(exc) and str(p) in str(exc) and f"{mb:g} MiB" in str(exc)
        return
    assert not over


def test_report_refuses_a_run_npz_that_declares_16_gb(tmp_path, capsys):
    out = tmp_path / "r"
    assert cli.main(["-q", "plan", "flow-spheres", "--out", str(out)]) == 0
    (out / "run.npz").write_bytes(_npz_with_header((2_000_000_000,)))
    assert cli.main(["report", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "run.npz: member 'sim_t' declares shape (2000000000,)" in err
    assert "over the limit of 2048 MiB" in err and "run.json" not in err


def test_data_inspect_refuses_a_sparse_file_declaring_400000_squared(tmp_path, capsys):
    p = _sparse_netcdf(tmp_path / "huge.nc", 400_000, 400_000)
    assert p.stat().st_size < 5_000_000
    assert cli.main(["data", "inspect", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"{p}: variable 'elevation' declares 400,000 × 400,000 = 1.6e+11 cells" in err
    assert "over the limit of 2048 MiB" in err


def test_degrees_labelled_as_utm_are_refused_before_the_regrid(tmp_path):
    """Coordinates in degrees under a UTM grid_mapping: the data's own cell is 0.01 'm', the local grid
    over the scenario's 20 km would hold 4e12 nodes; refused naming the file, the cell and the hint."""
    import xarray as xr
    from pyproj import CRS

    from auvplan.io.data.bathymetry import read_bathymetry

    lon, lat = np.arange(158.0, 158.5, 0.01), np.arange(14.5, 15.0, 0.01)
    z = np.full((lat.size, lon.size), -3000.0)
    ds = xr.Dataset({"elevation": (("y", "x"), z, {"units": "m", "grid_mapping": "crs"}),
                     "crs": ((), 0, CRS.from_epsg(32657).to_cf())},
                    coords={"x": ("x", lon, {"standard_name": "projection_x_coordinate", "units": "m"}),
                            "y": ("y", lat, {"standard_name": "projection_y_coordinate", "units": "m"})})
    p = tmp_path / "mislabelled.nc"
    ds.to_netcdf(p)
    with pytest.raises(BudgetError, match=r"at a cell of 0\.01 m .*degrees labelled as metres"):
        read_bathymetry(p, frame=LocalFrame(15.1, 158.8), extent_m=(0.0, 20_000.0, 0.0, 20_000.0))


_BUILTINS = Path(__file__).parents[2] / "src" / "auvplan" / "data" / "scenarios"
_TIDES = (_BUILTINS / "juan-de-fuca-tides.toml").read_text()
_FORMATION = (_BUILTINS / "chagos-formation.toml").read_text()


@pytest.mark.parametrize("key, value", [("dt", 1e-3), ("levels", 100_000), ("cell", 0.01), ("horizon_s", 1e12)])
def test_timeopt_sizes_are_estimated_naming_the_keys(key, value):
    data = tomllib.loads(_TIDES)
    assert data["planner"]["name"] == "timeopt"
    data["planner"]["timeopt"][key] = value
    with pytest.raises(ScenarioError, match=rf"t.toml: \[planner.timeopt\] .*{key} = .*over the limit of 2048 MiB"):
        scenario_io.build(scenario_io.from_dict(data, "t.toml"))


def test_formation_sample_m_is_estimated_naming_the_key():
    data = tomllib.loads(_FORMATION)
    data["formation"]["sample_m"] = 1e-6
    with pytest.raises(ScenarioError, match=r"f.toml: \[formation\] sample_m = 1e-06 .*over the limit of 2048 MiB"):
        scenario_io.build(scenario_io.from_dict(data, "f.toml"))
