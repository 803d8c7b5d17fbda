"""The seabed model is never deeper than its data (issue 30, point 1).

Oracle: the data's own bilinear surface, evaluated independently (scipy's RegularGridInterpolator on
the data's axes, through pyproj for geographic data) at dense random points of the model's extent and
at every sounding; the reported excess against the same independent computation.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator

from auvplan.io.data.bathymetry import TerrainSpec, terrain_from_lonlat, terrain_from_xy
from auvplan.io.data.geo import LocalFrame

STEP = 1000.0
XS = np.arange(0.0, 12_001.0, STEP)
YS = np.arange(0.0, 10_001.0, STEP)


def _peak_and_pit() -> np.ndarray:
    """A sloping coarse grid with a one-node spike (a pinnacle 900 m high) and a one-node pit (600 m deep)."""
    gy, gx = np.meshgrid(YS, XS, indexing="ij")
    z = -2000.0 + 0.05 * gx - 0.03 * gy + 40.0 * np.sin(gx / 1700.0) * np.cos(gy / 2300.0)
    z[4, 5] += 900.0  # the pinnacle: a single sounding
    z[7, 9] -= 600.0  # the pit
    return z


def _data_surface(x, y, z):
    return RegularGridInterpolator((YS, XS), z)(np.column_stack([y, x]))


def _dense(terrain, n=200_000, seed=1):
    """Random points of the terrain's extent plus every sounding inside it (where the extremes often are)."""
    rng = np.random.default_rng(seed)
    x0, x1, y0, y1 = terrain.extent
    gy, gx = np.meshgrid(YS, XS, indexing="ij")
    on = (gx >= x0) & (gx <= x1) & (gy >= y0) & (gy <= y1)
    return np.r_[rng.uniform(x0, x1, n), gx[on]], np.r_[rng.uniform(y0, y1, n), gy[on]]


@pytest.mark.parametrize("cell", [370.0, 2300.0, 1000.0 / 3.0 * 7.0])
def test_conservative_model_is_never_below_the_bilinear_data(cell):
    """Finer (370 m) and coarser (2.3 km, 2.33 km) than the 1 km data: at or above the data at dense points
    and at every sounding; the reported excess equals the independent computation."""
    z = _peak_and_pit()
    t = terrain_from_xy(XS, YS, z, resample_m=cell)
    x, y = _dense(t)
    below = _data_surface(x, y, z) - t.elevation(x, y)
    assert below.max() <= 1e-9
    gy, gx = np.meshgrid(YS, XS, indexing="ij")
    on = (gx <= t.x[-1]) & (gy <= t.y[-1])
    assert np.all(t.elevation(gx[on], gy[on]) >= z[on] - 1e-9)  # every sounding, the pinnacle included
    # the reported excess: mean at the model's nodes, max anywhere (dense sampling comes close from below)
    nx, ny = np.meshgrid(t.x, t.y)
    excess_nodes = t.z - _data_surface(nx.ravel(), ny.ravel(), z).reshape(t.z.shape)
    assert t.fit.method == "conservative"
    assert t.fit.excess_mean_m == pytest.approx(excess_nodes.mean(), rel=1e-9, abs=1e-9)
    assert t.fit.deficit_max_m <= 1e-9
    dense_max = float((-below).max())
    assert dense_max <= t.fit.excess_max_m + 1e-9
    assert dense_max >= 0.97 * t.fit.excess_max_m
    assert t.fit.excess_max_m >= 0.0


def test_the_pinnacle_is_kept_and_costs_what_is_reported():
    """At a cell coarser than the data the whole footprint of the pinnacle is lifted to its top (the upper
    envelope); at a finer one only the cells around it."""
    z = _peak_and_pit()
    coarse = terrain_from_xy(XS, YS, z, resample_m=2300.0)
    fine = terrain_from_xy(XS, YS, z, resample_m=250.0)
    top = z[4, 5]
    assert coarse.elevation(5000.0, 4000.0) >= top and fine.elevation(5000.0, 4000.0) >= top
    assert fine.fit.excess_mean_m < coarse.fit.excess_mean_m


def test_cubic_and_linear_lie_below_the_data_and_the_report_says_so():
    """The methods that stay selectable are measured with the same yardstick: cubic overshoots into the data
    and linear shaves the pinnacle; the reported deficit matches dense sampling."""
    z = _peak_and_pit()
    for method in ("cubic", "linear"):
        t = terrain_from_xy(XS, YS, z, resample_m=700.0, method=method)
        x, y = _dense(t)
        below = float((_data_surface(x, y, z) - t.elevation(x, y)).max())
        assert below > 50.0  # tens of metres deeper than the data somewhere
        assert t.fit.deficit_max_m >= below - 1e-9
        assert below >= 0.97 * t.fit.deficit_max_m
        assert "DEEPER" in t.fit.describe()


def test_geographic_grid_through_the_projection():
    """A lat/lon grid projected about a frame off its centre (cells not aligned with the model's): the
    model stays at or above the data's bilinear surface in lat/lon at dense points."""
    lat = np.arange(47.0, 47.2001, 0.02)
    lon = np.arange(-125.0, -124.7499, 0.025)
    la, lo = np.meshgrid(lat, lon, indexing="ij")
    z = -800.0 + 300.0 * np.sin(la * 90.0) * np.cos(lo * 70.0)
    z[5, 5] += 500.0
    z[3, 7] -= 400.0
    frame = LocalFrame(46.5, -126.0)  # far enough for the grid to be visibly rotated and sheared
    t = terrain_from_lonlat(lon, lat, z, frame=frame, resample_m=600.0)
    x, y = _dense(t, n=100_000)
    lon_p, lat_p = frame.inverse(x, y)
    data = RegularGridInterpolator((lat, lon), z)(np.column_stack([lat_p, lon_p]))
    assert (data - t.elevation(x, y)).max() <= 1e-6
    assert t.fit.deficit_max_m <= 1e-6 and t.fit.excess_max_m >= float((t.elevation(x, y) - data).max()) - 1e-6


def test_conservative_is_the_default():
    assert TerrainSpec(builtin="etopo1-chagos").method == "conservative"


def test_validate_inspect_and_plan_json_report_the_excess(tmp_path, capsys):
    """The figures reach the user: ``validate`` and ``plan --json`` give the terrain's own fit, ``data inspect``
    the cost at several cells (each equal to building that model directly)."""
    import json

    import xarray as xr

    from auvplan.cli import main
    from auvplan.io.data.bathymetry import read_bathymetry
    from auvplan.io.scenario import loader as scenario_io

    sc = scenario_io.load("admiralty-inlet")
    fit = scenario_io.build(sc)[0].terrain.fit
    assert main(["validate", "admiralty-inlet"]) == 0
    out = capsys.readouterr().out
    assert f"shallower by up to {fit.excess_max_m:.1f} m" in out and "never deeper than the data" in out
    assert main(["plan", "admiralty-inlet", "--planner", "grid", "--json"]) in (0, 1)
    rec = json.loads(capsys.readouterr().out)
    assert rec["terrain_method"] == "conservative"
    assert rec["terrain_excess_max_m"] == pytest.approx(fit.excess_max_m, abs=1e-3)
    # data inspect on a lat/lon file: the line for the data's own cell matches read_bathymetry at that cell
    lat, lon = np.arange(10.0, 10.31, 0.03), np.arange(20.0, 20.31, 0.03)
    la, lo = np.meshgrid(lat, lon, indexing="ij")
    z = -1000.0 + 400.0 * np.sin(la * 40.0) * np.cos(lo * 30.0)
    ds = xr.Dataset({"elevation": (("lat", "lon"), z, {"units": "m"})},
                    coords={"lat": ("lat", lat, {"units": "degrees_north"}),
                            "lon": ("lon", lon, {"units": "degrees_east"})})
    path = tmp_path / "g.nc"
    ds.to_netcdf(path)
    assert main(["data", "inspect", str(path)]) == 0
    text = capsys.readouterr().out
    t = read_bathymetry(path)  # frame at the data's centre, the data's own cell: as inspect does
    import re

    found = re.findall(r"cell (\d+) m: up to ([\d.]+) m, mean ([\d.]+) m", text)
    rows = {int(c): (float(a), float(b)) for c, a, b in found}
    assert len(rows) >= 4
    cell = min(rows, key=lambda c: abs(c - t.dx))
    assert abs(cell - t.dx) < 2.0  # the data's own spacing (read_bathymetry rounds it to whole cells)
    assert rows[cell][0] == pytest.approx(t.fit.excess_max_m, abs=0.06)
    assert rows[cell][1] == pytest.approx(t.fit.excess_mean_m, abs=0.006)


def test_results_folder_keeps_the_fit(tmp_path):
    """A results folder's terrain carries its fit, so a re-rendered report states the same excess."""
    from auvplan.io.results import folder as results
    from auvplan.io.results import records

    t = terrain_from_xy(XS, YS, _peak_and_pit(), resample_m=700.0)
    results.save_terrain(tmp_path, t)
    back = results.load_terrain(tmp_path)
    assert back.fit == t.fit
    m = records.fit_metrics(back.fit)
    assert m["terrain_method"] == "conservative" and m["terrain_excess_max_m"] == round(t.fit.excess_max_m, 3)
