"""Bathymetry in every layout real producers write: GeoTIFF (EPSG:4326 and UTM), GEBCO, ETOPO 2022,
EMODnet, Ferret/GMT coordinate-less, GMT 3 native, 2-D lat/lon; boxes at the data's edge; exit 2.

Oracle: elevations linear in the source coordinates (lon/lat, or UTM easting/northing), so
every resampling step is exact at the source's own interpolation and the terrain must match
the analytic value at any local point to within the bilinear error of the local grid over a
field that is linear in the *source* coordinates: stated tolerance 0.05 m on a ~±300 m relief.
"""

from __future__ import annotations

import logging

import numpy as np
import pytest
import xarray as xr
from pyproj import CRS, Transformer

from auvplan import cli
from auvplan.errors import DataError
from auvplan.io.data.bathymetry import read_bathymetry
from auvplan.io.data.geo import LocalFrame

FRAME = LocalFrame(15.1, 158.8)
LAT = np.arange(14.8, 15.4001, 0.02)
LON = np.arange(158.5, 159.1001, 0.02)
TOL = 0.05


def relief(lat, lon):
    return -3000.0 + 400.0 * (lat - 15.1) - 300.0 * (lon - 158.8)


def grid():
    la, lo = np.meshgrid(LAT, LON, indexing="ij")
    return relief(la, lo)


def check(t, fn, n=400, margin=3000.0, frame=FRAME):
    rng = np.random.default_rng(0)
    x = rng.uniform(t.x[0] + margin, t.x[-1] - margin, n)
    y = rng.uniform(t.y[0] + margin, t.y[-1] - margin, n)
    lon, lat = frame.inverse(x, y)
    err = np.abs(t.elevation(x, y) - fn(lat, lon))
    assert err.max() < TOL, err.max()
    return err.max()


def write(tmp_path, name, ds):
    p = tmp_path / name
    ds.to_netcdf(p)
    return p


def test_gebco_netcdf(tmp_path):
    ds = xr.Dataset(
        {"elevation": (("lat", "lon"), np.round(grid()).astype("int16"),
                       {"standard_name": "height_above_mean_sea_level", "units": "m"})},
        coords={"lat": ("lat", LAT, {"standard_name": "latitude", "units": "degrees_north"}),
                "lon": ("lon", LON, {"standard_name": "longitude", "units": "degrees_east"})},
    )
    t = read_bathymetry(write(tmp_path, "gebco.nc", ds), frame=FRAME, method="linear")
    # int16 storage rounds to the metre
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-20_000, 20_000, (2, 200))
    lon, lat = FRAME.inverse(x, y)
    assert np.abs(t.elevation(x, y) - relief(lat, lon)).max() < 0.5 + TOL


def test_etopo2022_emodnet_and_descending(tmp_path):
    etopo = xr.Dataset({"z": (("lat", "lon"), grid().astype("float32"), {"units": "m"})},
                       coords={"lat": LAT, "lon": LON})
    check(read_bathymetry(write(tmp_path, "etopo.nc", etopo), frame=FRAME, method="linear"),
          lambda la, lo: relief(la, lo), n=200)
    # EMODnet: elevation beside statistics, latitude descending
    z = grid()[::-1]
    emod = xr.Dataset({"elevation": (("lat", "lon"), z), "stdev": (("lat", "lon"), np.ones_like(z)),
                       "min": (("lat", "lon"), z - 5)}, coords={"lat": LAT[::-1], "lon": LON})
    check(read_bathymetry(write(tmp_path, "emod.nc", emod), frame=FRAME, method="linear"), relief)


def test_ferret_gmt_coordinate_less_and_depth_down(tmp_path):
    """Dimensions without coordinates; 1-D lat/lon variables on them; depth positive down; 0-360."""
    ds = xr.Dataset({
        "depth": (("y", "x"), -grid(), {"positive": "down", "units": "m"}),
        "latitude": (("y",), LAT, {"units": "degrees_north"}),
        "longitude": (("x",), LON + 0.0, {"units": "degrees_east"}),
    })
    check(read_bathymetry(write(tmp_path, "ferret.nc", ds), frame=FRAME, method="linear"), relief)
    ds2 = xr.Dataset({"z": (("ny", "nx"), grid()), "lat": (("ny",), LAT), "lon": (("nx",), LON - 360.0)})
    check(read_bathymetry(write(tmp_path, "gmt.nc", ds2), frame=FRAME, method="linear"), relief)


def test_gmt3_native_layout(tmp_path):
    z = grid()[::-1].ravel()  # rows from the north
    ds = xr.Dataset({
        "x_range": (("side",), [LON[0], LON[-1]], {"units": "degrees"}),
        "y_range": (("side",), [LAT[0], LAT[-1]], {"units": "degrees"}),
        "z_range": (("side",), [z.min(), z.max()]),
        "spacing": (("side",), [0.02, 0.02]),
        "dimension": (("side",), np.array([LON.size, LAT.size], dtype="int32")),
        "z": (("xysize",), z, {"node_offset": 0}),
    })
    check(read_bathymetry(write(tmp_path, "gmt3.grd", ds), frame=FRAME, method="linear"), relief)


def test_two_d_latlon_rectilinear_and_curvilinear(tmp_path):
    la, lo = np.meshgrid(LAT, LON, indexing="ij")
    rect = xr.Dataset({"elevation": (("j", "i"), grid()), "lat": (("j", "i"), la), "lon": (("j", "i"), lo)})
    check(read_bathymetry(write(tmp_path, "rect.nc", rect), frame=FRAME, method="linear"), relief)
    # a grid rotated by 20 degrees (ROMS-like): linear in lon/lat, interpolated on triangles
    a = np.deg2rad(20.0)
    j, i = np.meshgrid(np.arange(40) - 20.0, np.arange(40) - 20.0, indexing="ij")
    lat2 = 15.1 + 0.015 * (j * np.cos(a) + i * np.sin(a))
    lon2 = 158.8 + 0.015 * (-j * np.sin(a) + i * np.cos(a))
    curv = xr.Dataset({"h": (("eta", "xi"), -relief(lat2, lon2), {"positive": "down"}),
                       "lat_rho": (("eta", "xi"), lat2, {"standard_name": "latitude"}),
                       "lon_rho": (("eta", "xi"), lon2, {"standard_name": "longitude"})})
    t = read_bathymetry(write(tmp_path, "roms.nc", curv), frame=FRAME, method="linear",
                        extent_m=(-20_000.0, 20_000.0, -20_000.0, 20_000.0))
    check(t, relief, margin=0.0)


def _tif(tmp_path, name, values, x, y, crs, nodata=None, driver="GTiff"):
    import rioxarray  # noqa: F401

    da = xr.DataArray(values.astype("float32"), dims=("y", "x"), coords={"y": y, "x": x})
    da = da.rio.write_crs(crs)
    if nodata is not None:
        da = da.rio.write_nodata(nodata, encoded=False)
    p = tmp_path / name
    da.rio.to_raster(p, driver=driver)
    return p


def test_geotiff_epsg4326_with_nodata(tmp_path):
    z = grid()[::-1].copy()  # GeoTIFF rows from the north
    p = _tif(tmp_path, "gebco.tif", z, LON, LAT[::-1], "EPSG:4326")
    check(read_bathymetry(p, frame=FRAME, method="linear"), relief)
    cog = _tif(tmp_path, "gebco_cog.tif", z, LON, LAT[::-1], "EPSG:4326", driver="COG")  # cloud-optimised
    check(read_bathymetry(cog, frame=FRAME, method="linear"), relief)
    z[10, 12] = -32768.0
    q = _tif(tmp_path, "hole.tif", z, LON, LAT[::-1], "EPSG:4326", nodata=-32768.0)
    with pytest.raises(DataError, match=r"hole.tif.*1 missing"):
        read_bathymetry(q, frame=FRAME, method="linear")
    t = read_bathymetry(q, frame=FRAME, method="linear", nan_policy="nearest")
    assert t.z.min() > -3300.0  # the nodata value never became a 32 km deep hole


def test_geotiff_utm(tmp_path):
    """A UTM zone 57N GeoTIFF (metres), elevation linear in easting/northing, 500 m pixels."""
    crs = CRS.from_epsg(32657)
    tr = Transformer.from_crs("EPSG:4326", crs, always_xy=True)
    e0, n0 = tr.transform(158.8, 15.1)
    e = np.arange(e0 - 30_000.0, e0 + 30_000.0, 500.0)
    n = np.arange(n0 + 30_000.0, n0 - 30_000.0, -500.0)
    ge, gn = np.meshgrid(e, n)

    def f(ee, nn):
        return -2500.0 + 0.004 * (ee - e0) - 0.003 * (nn - n0)

    p = _tif(tmp_path, "utm.tif", f(ge, gn), e, n, "EPSG:32657")
    t = read_bathymetry(p, frame=FRAME, method="linear", resample_m=500.0)
    assert t.x[-1] - t.x[0] > 55_000.0

    def truth(lat, lon):
        ee, nn = tr.transform(lon, lat)
        return f(np.asarray(ee), np.asarray(nn))

    check(t, truth)


def test_box_at_the_data_edge_loads_and_beyond_is_clipped_with_a_warning(tmp_path, caplog):
    ds = xr.Dataset({"elevation": (("lat", "lon"), grid())}, coords={"lat": LAT, "lon": LON})
    p = write(tmp_path, "edge.nc", ds)
    edge = (LAT[0], LAT[-1], LON[0], LON[-1])
    t = read_bathymetry(p, frame=FRAME, box=edge, method="linear")
    check(t, relief, margin=0.0)
    with caplog.at_level(logging.WARNING):
        t2 = read_bathymetry(p, frame=FRAME, box=(LAT[0], LAT[-1] + 0.5, LON[0], LON[-1]), method="linear")
    assert "clipped" in caplog.text and "north edge" in caplog.text
    assert t2.extent == pytest.approx(t.extent)
    with pytest.raises(DataError, match="uncovered on the north side"):
        read_bathymetry(p, frame=FRAME, box=(LAT[0], LAT[-1] + 0.5, LON[0], LON[-1]), method="linear",
                        extent_m=(-10_000.0, 10_000.0, -10_000.0, 60_000.0))


# ---------------------------------------------------------------------- through the CLI: exit 2
SCENARIO = """
name = "byo"
[origin]
lat = 15.1
lon = 158.8
[bounds]
x = [-10000.0, 10000.0]
y = [-10000.0, 10000.0]
z = [-4000.0, 0.0]
[terrain]
file = "{file}"
method = "linear"
{extra}
[mission]
start = [-5000.0, -5000.0, -2000.0]
goal = [5000.0, 5000.0, -2000.0]
"""


def _exit2(tmp_path, capsys, file, *words, extra=""):
    s = tmp_path / "s.toml"
    s.write_text(SCENARIO.replace("{file}", file).replace("{extra}", extra))
    assert cli.main(["validate", str(s)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    for w in words:
        assert w in err, (w, err)


def test_good_files_validate_and_malformed_ones_exit_2(tmp_path, capsys):
    import rioxarray  # noqa: F401

    good = xr.Dataset({"elevation": (("lat", "lon"), grid())}, coords={"lat": LAT, "lon": LON})
    write(tmp_path, "good.nc", good)
    s = tmp_path / "s.toml"
    s.write_text(SCENARIO.replace("{file}", "good.nc").replace("{extra}", ""))
    assert cli.main(["validate", str(s)]) == 0
    capsys.readouterr()
    # a GeoTIFF without a CRS
    da = xr.DataArray(grid().astype("float32"), dims=("y", "x"), coords={"y": LAT, "x": LON})
    da.rio.to_raster(tmp_path / "nocrs.tif")
    _exit2(tmp_path, capsys, "nocrs.tif", "nocrs.tif", "crs", "no coordinate reference system")
    # three bands
    da3 = xr.DataArray(np.stack([grid()] * 3).astype("float32"), dims=("band", "y", "x"),
                       coords={"band": [1, 2, 3], "y": LAT, "x": LON}).rio.write_crs("EPSG:4326")
    da3.rio.to_raster(tmp_path / "rgb.tif")
    _exit2(tmp_path, capsys, "rgb.tif", "rgb.tif", "band", "3 bands")
    # an elevation with a time axis of several steps
    ds = xr.Dataset({"elevation": (("time", "lat", "lon"), np.stack([grid()] * 2))},
                    coords={"time": [0.0, 1.0], "lat": LAT, "lon": LON})
    write(tmp_path, "timed.nc", ds)
    _exit2(tmp_path, capsys, "timed.nc", "timed.nc", "'elevation'", "dimension 'time' has 2 values")
    # coordinate-less dimensions and nothing to say where they are
    ds = xr.Dataset({"elevation": (("a", "b"), grid())})
    write(tmp_path, "bare.nc", ds)
    _exit2(tmp_path, capsys, "bare.nc", "bare.nc", "'elevation'", "cannot find latitude/longitude")
    # missing values with the default policy
    z = grid()
    z[3, 4] = np.nan
    write(tmp_path, "nan.nc", xr.Dataset({"elevation": (("lat", "lon"), z)}, coords={"lat": LAT, "lon": LON}))
    _exit2(tmp_path, capsys, "nan.nc", "nan.nc", "elevation", "1 missing", "nan_policy")
    # non-monotonic latitude
    lat = LAT.copy()
    lat[5], lat[6] = lat[6], lat[5]
    write(tmp_path, "mono.nc", xr.Dataset({"elevation": (("lat", "lon"), grid())}, coords={"lat": lat, "lon": LON}))
    _exit2(tmp_path, capsys, "mono.nc", "mono.nc", "'elevation'", "strictly monotonic")
    # a box the data do not reach, and bounds the data do not cover
    _exit2(tmp_path, capsys, "good.nc", "good.nc", "does not overlap", extra="box = [40.0, 41.0, 10.0, 11.0]")
    s.write_text(SCENARIO.replace("{file}", "good.nc").replace("{extra}", "").replace(
        "x = [-10000.0, 10000.0]", "x = [-10000.0, 90000.0]"))
    assert cli.main(["validate", str(s)]) == 2
    assert "uncovered on the east side" in capsys.readouterr().err
    # grid_mapping pointing at nothing
    ds = xr.Dataset({"elevation": (("y", "x"), grid(), {"grid_mapping": "utm"})},
                    coords={"y": ("y", np.arange(LAT.size) * 1000.0, {"units": "m"}),
                            "x": ("x", np.arange(LON.size) * 1000.0, {"units": "m"})})
    write(tmp_path, "gm.nc", ds)
    _exit2(tmp_path, capsys, "gm.nc", "gm.nc", "'elevation'", "grid_mapping variable 'utm' not found")


def test_data_inspect_reports_what_was_detected(tmp_path, capsys):
    ds = xr.Dataset({
        "depth": (("y", "x"), -grid(), {"positive": "down", "units": "m"}),
        "latitude": (("y",), LAT, {"units": "degrees_north"}),
        "longitude": (("x",), LON, {"units": "degrees_east"}),
    })
    p = write(tmp_path, "ferret.nc", ds)
    assert cli.main(["data", "inspect", str(p)]) == 0
    out = capsys.readouterr().out
    for w in ("NetCDF", "as bathymetry: variable 'depth'", "1-D variable 'latitude' on coordinate-less dimension 'y'",
              "positive down (attribute positive)", "0 missing"):
        assert w in out, (w, out)
    import rioxarray  # noqa: F401

    da = xr.DataArray(grid()[::-1].astype("float32"), dims=("y", "x"),
                      coords={"y": np.arange(LAT.size)[::-1] * 500.0 + 1.67e6, "x": np.arange(LON.size) * 500.0 + 3e5})
    da.rio.write_crs("EPSG:32657").rio.to_raster(tmp_path / "utm.tif")
    assert cli.main(["data", "inspect", str(tmp_path / "utm.tif")]) == 0
    out = capsys.readouterr().out
    assert "GeoTIFF" in out and "projected grid" in out and "UTM zone 57N" in out
    assert cli.main(["data", "inspect", str(tmp_path / "none.nc")]) == 2
    assert "none.nc: file not found" in capsys.readouterr().err
    # a folder (or a FIFO) exists: not "file not found" (docwalk20: a FIFO read "file not found")
    assert cli.main(["data", "inspect", str(tmp_path)]) == 2
    assert f"{tmp_path}: not a regular file (a FIFO, a device or a folder)" in capsys.readouterr().err
