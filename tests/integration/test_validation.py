"""The validation layer (issue #20), one test per input class: each names the file, the key and
the value; resource budgets are refused before anything is allocated; data-file faults are told
apart. And the resource estimates are upper bounds of measured peaks (tracemalloc)."""

from __future__ import annotations

import math
import tracemalloc

import numpy as np
import pytest
import xarray as xr

from auvplan import cli
from auvplan.errors import DataError, ScenarioError
from auvplan.io.data.bathymetry import read_bathymetry
from auvplan.io.data.geo import LocalFrame
from auvplan.io.files import limits
from auvplan.io.scenario import build as bld
from auvplan.io.scenario import loader as sc
from auvplan.world import RandomWalkMotion

BASE = """
[bounds]
x = [0.0, 1000.0]
y = [0.0, 1000.0]
z = [-100.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 90.0
[mission]
start = [100.0, 100.0, -40.0]
goal = [900.0, 900.0, -40.0]
"""


def load(extra: str = "", base: str = BASE, source: str = "s.toml"):
    return sc.loads(base + extra, source)


def rejects(text: str, *needles: str, base: str = BASE) -> str:
    with pytest.raises(ScenarioError) as info:
        sc.build(sc.loads(base + text, "s.toml"))
    msg = str(info.value)
    assert msg.startswith("s.toml"), msg
    for n in needles:
        assert n in msg, msg
    return msg


def test_the_base_scenario_is_valid():
    world, mission = sc.build(load())
    assert mission.goal == (900.0, 900.0, -40.0) and world.terrain is not None


@pytest.mark.parametrize("value", ["inf", "-inf", "nan", "1e300"])
@pytest.mark.parametrize("table, key", [("vehicle", "speed"), ("sim", "dt"), ("planner", "w_length"),
                                        ("avoidance", "radius")])
def test_non_finite_and_huge_numbers_are_refused(table, key, value):
    why = {"inf": "must be finite", "-inf": "must be finite", "nan": "NaN", "1e300": "out of range"}[value]
    rejects(f"[{table}]\n{key} = {value}\n", f"[{table}]", key, why)


def test_an_infinite_bound_or_velocity_or_vortex_core_is_refused():
    rejects("", "x", base=BASE.replace("x = [0.0, 1000.0]", "x = [0.0, inf]"))
    rejects('[[moving]]\nradius = 5.0\nmotion = "linear"\nstart = [0.0, 0.0, -50.0]\nvelocity = [inf, 0.0, 0.0]\n',
            "[[moving]] #1", "velocity")
    rejects("[currents]\nvortices = [{ x = 1.0, y = 1.0, gamma = 10.0, delta = inf }]\n", "delta")
    rejects('[[moving]]\nradius = 5.0\nmotion = "linear"\nstart = [0.0, 0.0, -50.0]\nvelocity = [1.0, 0.0, 0.0]\n'
            "disappears = inf\n", "disappears")


def test_union_typed_keys_name_the_key_instead_of_raising_a_string():
    msg = rejects("[currents]\nfile = 3\n", "[currents]", "file", "3")
    assert "expected a string or a table" in msg  # file = "x.nc" or file = { path = ... }


@pytest.mark.parametrize("text, needles", [
    ("", ("goal", "nothing to plan")),
])
def test_start_on_the_goal_is_refused(text, needles):
    rejects(text, *needles, base=BASE.replace("goal = [900.0, 900.0, -40.0]", "goal = [100.0, 100.0, -40.0]"))


def test_zero_length_route_legs_and_one_point_routes_are_refused():
    rejects("", "route[1]", "no horizontal distance",
            base=BASE.replace("[mission]", "[mission]\nroute = [[100.0, 100.0, -40.0], [100.0, 100.0, -40.0]]"))
    rejects("", "route", "at least two points", base=BASE.replace("[mission]", "[mission]\nroute = [[1.0, 1.0, -4.0]]"))


@pytest.mark.parametrize("extra, needles", [
    ("[planner]\npopulation = 1000000\nsamples = 100000\n", ("population × samples", "memory_mb")),
    ("[sim]\ndt = 1e-9\n", ("[sim]", "dt", "memory_mb")),
    ('[[moving]]\nradius = 5.0\nmotion = "random-walk"\nstart = [0.0, 0.0, -50.0]\nspeed = 1.0\n'
     "duration = 1e12\n", ("[[moving]] #1", "duration / dt", "memory_mb")),
    ("[planner.grid]\ncell = 0.01\nmax_nodes = 100000000000\n", ("[planner.grid]", "lattice", "memory_mb")),
])
def test_resource_bombs_are_refused_with_the_estimate_and_the_key_to_raise(extra, needles):
    msg = rejects(extra, *needles)
    assert "MiB" in msg and "limit of 2048 MiB" in msg


def test_a_tiny_synthetic_cell_is_refused_before_allocating(monkeypatch):
    monkeypatch.setattr(bld, "_synthetic_terrain", lambda *a: pytest.fail("allocated before the budget check"))
    rejects("", "[terrain.synthetic]", "cell_m", base=BASE.replace('kind = "flat"', 'kind = "flat"\ncell_m = 0.001'))


def test_a_tiny_resample_is_refused_before_reading_the_data(monkeypatch):
    monkeypatch.setattr(bld, "load_terrain", lambda *a, **k: pytest.fail("read the data before the budget check"))
    text = sc.resolve("marcus-wake").read_text()
    assert "resample_m" in text
    lines = [ln if not ln.startswith("resample_m") else "resample_m = 0.01" for ln in text.splitlines()]
    with pytest.raises(ScenarioError, match=r"\[terrain\] resample_m = 0.01 .* raise \[limits\] memory_mb"):
        sc.build(sc.loads("\n".join(lines), "mw.toml"))


def test_raising_the_limit_lets_a_large_scenario_through():
    rejects("[planner]\npopulation = 20000\nsamples = 1000\n", "population")
    sc.loads(BASE + "[planner]\npopulation = 20000\nsamples = 1000\n[limits]\nmemory_mb = 8000.0\n")


def test_non_utf8_and_deeply_nested_toml_are_named_errors(tmp_path):
    p = tmp_path / "latin1.toml"
    p.write_bytes(BASE.encode() + b'description = "Nordsee \xfcber"\n')
    with pytest.raises(ScenarioError, match=r"latin1.toml: line 1[0-9]: not UTF-8 .*0xfc"):
        sc.load(p)
    deep = BASE + "seed = " + "[" * 20000 + "]" * 20000 + "\n"
    with pytest.raises(ScenarioError, match="s.toml: invalid TOML"):
        sc.loads(deep, "s.toml")
    nested = "x = " + "{a = " * 300 + "1" + "}" * 300 + "\n"
    with pytest.raises(ScenarioError, match="s.toml"):
        sc.loads(BASE + nested, "s.toml")


# ------------------------------------------------------------------ data files
@pytest.fixture()
def grid(tmp_path):
    lat, lon = np.linspace(14.2, 16.3, 60), np.linspace(157.9, 160.0, 60)
    z = -4000.0 + 100.0 * np.sin(lat)[:, None] * np.cos(lon)[None, :]
    ds = xr.Dataset({"elevation": (("lat", "lon"), z)}, coords={"lat": lat, "lon": lon})
    return ds


FRAME = LocalFrame(15.0, 159.0)


@pytest.mark.parametrize("engine, fmt", [("scipy", "NETCDF3_64BIT"), ("netcdf4", "NETCDF4")])
@pytest.mark.parametrize("keep", [0.3, 0.9, 0.999])
def test_a_truncated_file_is_reported_as_truncated(tmp_path, grid, engine, fmt, keep):
    whole = tmp_path / "whole.nc"
    grid.to_netcdf(whole, engine=engine, format=fmt)
    read_bathymetry(whole, frame=FRAME, box=(14.5, 16.0, 158.2, 159.7))  # the whole file reads
    cut = tmp_path / "cut.nc"
    data = whole.read_bytes()
    cut.write_bytes(data[: int(len(data) * keep)])
    with pytest.raises(DataError, match=r"cut.nc: truncated"):
        read_bathymetry(cut, frame=FRAME)


def test_wrong_dimensionality_names_the_variable(tmp_path, grid):
    p = tmp_path / "3d.nc"
    grid["elevation"].expand_dims(time=[0.0, 1.0]).to_dataset().to_netcdf(p)
    with pytest.raises(DataError, match=r"3d.nc: variable 'elevation' must be 2-D; dimension 'time' has 2 values"):
        read_bathymetry(p, frame=FRAME)
    p1 = tmp_path / "1d.nc"
    xr.Dataset({"elevation": ("n", np.arange(10.0))}).to_netcdf(p1)
    with pytest.raises(DataError, match=r"1d.nc: variable 'elevation' has 1 dimension\(s\) \(n = 10\)"):
        read_bathymetry(p1, frame=FRAME)


def test_missing_coordinate_values_name_the_dimension(tmp_path, grid):
    p = tmp_path / "nocoords.nc"
    grid.drop_vars(["lat", "lon"]).to_netcdf(p)
    with pytest.raises(DataError, match=r"nocoords.nc: variable 'elevation' has dimensions "
                                        r"\('lat', 'lon'\) without coordinate values"):
        read_bathymetry(p, frame=FRAME)


def test_not_a_netcdf_file(tmp_path):
    p = tmp_path / "notes.nc"
    p.write_text("hello")
    with pytest.raises(DataError, match=r"notes.nc: cannot read the bathymetry file: not a NetCDF file \(it starts "
                                        r"with b'hello'"):
        read_bathymetry(p, frame=FRAME)


def test_the_cli_names_the_table_and_file_for_a_bad_data_file(tmp_path, capsys):
    (tmp_path / "grid.nc").write_bytes(b"CDF\x01" + b"\x00" * 10)
    text = sc.resolve("marcus-wake").read_text().replace('builtin = "etopo1-marcus-wake"', 'file = "grid.nc"')
    assert 'file = "grid.nc"' in text
    (tmp_path / "s.toml").write_text(text)
    assert cli.main(["validate", str(tmp_path / "s.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "[terrain]" in err and "grid.nc" in err and "truncated" in err


# ------------------------------------------------------------------ the estimates are upper bounds
def _peak(fn) -> int:
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_the_terrain_estimate_bounds_the_measured_peak():
    s = load(base=BASE.replace('kind = "flat"', 'kind = "hills"\nhills = [[500.0, 500.0, 20.0, 100.0]]\ncell_m = 2.0'))
    nodes = limits.grid_nodes(1000.0, 1000.0, 2.0)
    peak = _peak(lambda: sc.build(s))
    assert 0.3 * nodes * limits.BYTES_PER_TERRAIN_NODE < peak <= nodes * limits.BYTES_PER_TERRAIN_NODE


def test_the_random_walk_estimate_bounds_the_measured_peak():
    steps = 200_000
    peak = _peak(lambda: RandomWalkMotion((0.0, 0.0, 0.0), 1.0, duration=float(steps), dt=1.0,
                                          bounds=(0.0, 10.0, 0.0, 10.0)))
    assert 0.3 * steps * limits.BYTES_PER_WALK_STEP < peak <= steps * limits.BYTES_PER_WALK_STEP


def test_check_refuses_nan_and_inf_estimates():
    for v in (math.inf, math.nan):
        with pytest.raises(ScenarioError, match="unbounded memory|MiB"):
            limits.check(limits.Limits(), "s.toml: [x]", "k", v)


def test_currents_that_do_not_cover_the_bounds_name_the_table_and_file(tmp_path):
    x = np.linspace(0.0, 500.0, 6)
    y = np.linspace(0.0, 500.0, 6)
    ds = xr.Dataset({"u": (("y", "x"), np.full((6, 6), 0.1)), "v": (("y", "x"), np.zeros((6, 6)))},
                    coords={"x": ("x", x, {"units": "m", "axis": "X"}), "y": ("y", y, {"units": "m", "axis": "Y"})})
    ds.to_netcdf(tmp_path / "cur.nc")
    with pytest.raises(DataError, match=r"s.toml: \[currents\] the current file 'cur.nc' does not cover the bounds"):
        sc.build(sc.loads(BASE + '[currents]\nfile = { path = "cur.nc" }\n', "s.toml", base_dir=tmp_path))


def test_a_waypoint_track_with_a_repeated_point_is_refused():
    rejects('[[moving]]\nradius = 5.0\nmotion = "waypoints"\npoints = [[0.0, 0.0, -50.0], [0.0, 0.0, -50.0]]\n'
            "speed = 1.0\n", "[[moving]] #1", "points[1]", "zero-length")
