"""Issue #32, readers and arguments: bounded nesting and size, a linear MOOS scan, out-of-range numbers
in ``run.json``, a ``run.npz`` fault blamed on ``run.npz``, CLI numbers checked by argparse types, a
start time the nanosecond clock cannot hold, a depth offset outside the world, and an axis fault that
names the axis."""

from __future__ import annotations

import io
import time
import tomllib
import zipfile
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from auvplan import cli
from auvplan.errors import DataError, ScenarioError
from auvplan.io.data.elevation import read_elevation
from auvplan.io.files.jsonfile import read_json
from auvplan.io.missions.formats import read_mission
from auvplan.io.missions.readback.parsers import _moos_blocks
from auvplan.io.scenario import loader as scenario_io

_BUILTINS = Path(__file__).parents[2] / "src" / "auvplan" / "data" / "scenarios"


def run_cli(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("name, text", [
    ("deep.plan", "[" * 100_000 + "]" * 100_000),
    ("deep.yaml", "poses: " + "[" * 100_000 + "]" * 100_000),
    ("deep.geojson", '{"a":' * 100_000 + "1" + "}" * 100_000),
])
def test_deeply_nested_mission_files_are_named_not_a_recursion_error(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    with pytest.raises(DataError, match=rf"^{p}: nested too deeply"):
        read_mission(p, (14.0, 158.0))


def test_a_deep_or_out_of_range_run_json_is_named(tmp_path):
    p = tmp_path / "run.json"
    p.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(DataError, match=rf"^{p}: nested too deeply"):
        read_json(p)
    p.write_text('{"seed": 1e400}')
    with pytest.raises(DataError, match=rf"^{p}: not valid JSON \(number 1e400 is out of range"):
        read_json(p)
    p.write_text('{"seed": NaN}')
    with pytest.raises(DataError, match="NaN is not a number JSON allows"):
        read_json(p)
    assert read_json(_write(p, '{"seed": 12, "x": [1.5, -2e300]}')) == {"seed": 12, "x": [1.5, -2e300]}


def _write(p: Path, text: str) -> Path:
    p.write_text(text)
    return p


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = tmp_path_factory.mktemp("r") / "r"
    assert cli.main(["-q", "plan", "flow-spheres", "--out", str(out)]) == 0
    return out


def test_report_blames_run_json_and_run_npz_for_their_own_faults(results, tmp_path, capsys):
    import shutil

    out = tmp_path / "r"
    shutil.copytree(results, out)
    good = (out / "run.json").read_text()
    (out / "run.json").write_text(good.replace('"seed": ', '"seed": 1e400, "x": ', 1))
    code, _, err = run_cli(capsys, "report", out)
    assert code == 2 and err.count("\n") == 1 and f"{out / 'run.json'}: not valid JSON" in err
    (out / "run.json").write_text(good)
    arrays = dict(np.load(out / "run.npz"))
    arrays["plan_path"] = np.array(["not", "numbers"])
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    (out / "run.npz").write_bytes(buf.getvalue())
    code, _, err = run_cli(capsys, "report", out)
    assert code == 2 and err.count("\n") == 1, err
    assert f"{out / 'run.npz'}: member 'plan_path' is not a numeric array" in err and "run.json" not in err
    with zipfile.ZipFile(out / "run.npz", "w") as zf:
        zf.writestr("route.npy", b"\x93NUMPY garbage")
    code, _, err = run_cli(capsys, "report", out)
    assert code == 2 and f"{out / 'run.npz'}: not a readable .npz archive" in err


def _hostile_moos(n: int) -> str:
    return "Behavior = BHV_Waypoint {\n points = 0,0\n" * n  # n blocks that never close


def _cost(n: int) -> float:
    best = float("inf")
    text = _hostile_moos(n)
    for _ in range(5):
        t0 = time.thread_time()  # this thread's CPU: not another thread's of the process (a server's, dask's)
        assert _moos_blocks(text) == []
        best = min(best, time.thread_time() - t0)
    return best


def test_the_moos_scan_is_linear_in_the_file_size():
    """Size scaling, not a wall-clock limit: 8× the (hostile, never-closed) blocks may cost at most 24×
    (linear: ~8×; the former regex that rescanned from every brace: ~64×), with 5 ms of slack for timer noise."""
    small, large = _cost(2_000), _cost(16_000)
    assert large <= 24.0 * small + 0.005, (small, large)


def test_mission_check_of_a_hostile_moos_file_exits_2_naming_it(tmp_path, capsys):
    p = tmp_path / "m.moos"
    p.write_text(_hostile_moos(50_000))
    code, _, err = run_cli(capsys, "mission", "check", p, "--scenario", "flow-spheres")
    assert code == 2 and err.count("\n") == 1 and f"{p}: no BHV_Waypoint block" in err


def test_moos_blocks_still_read_every_closed_block():
    text = "// start: 1, 2, 3\nBehavior = A {\n a = 1 // c\n}\nBehavior=B{b=2}\nBehavior = C {\n c = 3\n"
    assert _moos_blocks(text) == [("A", [("a", "1")]), ("B", [("b", "2")])]


@pytest.mark.parametrize("argv, needle", [
    (("--depart-between", "+0h", "+6h", "--step", "inf"), "argument --step: 'inf': a step must lie in (0 s, 366 d]"),
    (("--depart-between", "+0h", "+6h", "--step", "nan"), "argument --step: 'nan'"),
    (("--depart-between", "+0h", "+6h", "--step=-15min"), "argument --step: '-15min'"),
    (("--depart-between", "+1e12h", "+1e12h"), "argument --depart-between: '+1e12h': an offset must lie within 366 d"),
    (("--depart-between", "0001-01-01T00:00:00Z", "+1h"), "'0001-01-01T00:00:00Z': year 1 is outside 1678..2261"),
    (("--depart-between", "+0h", "+1e400h"), "argument --depart-between: '+1e400h'"),
])
def test_sweep_numbers_are_argparse_errors_before_any_work(capsys, argv, needle):
    code, _, err = run_cli(capsys, "plan", "juan-de-fuca-tides", *argv)
    assert code == 2 and needle in err, err


def test_start_time_in_year_1_is_refused_naming_the_key():
    data = tomllib.loads((_BUILTINS / "juan-de-fuca-tides.toml").read_text())
    data["mission"]["start_time"] = "0001-06-01T00:00:00Z"
    with pytest.raises(ScenarioError, match=r"t.toml: \[mission\] start_time = '0001-06-01T00:00:00Z'.*year 1 is "
                                            r"outside 1678..2261"):
        scenario_io.from_dict(data, "t.toml")


def test_a_depth_offset_outside_the_world_is_refused_not_ignored():
    data = tomllib.loads((_BUILTINS / "chagos-formation.toml").read_text())
    data["vehicles"][1]["depth_offset_m"] = 1e6
    with pytest.raises(ScenarioError, match=r"f.toml: \[\[vehicles\]\] 'port' depth_offset_m = 1000000.0: puts the "
                                            r"vehicle outside the world's"):
        scenario_io.build(scenario_io.from_dict(data, "f.toml"))


@pytest.mark.parametrize("axis, fix, needle", [
    ("lat", lambda v: np.r_[v[:3], v[2], v[4:]], "the latitude axis 'lat' repeats the value"),
    ("lon", lambda v: np.r_[v[:3], v[4], v[3], v[5:]], "the longitude axis 'lon' is not monotonic"),
    ("lat", lambda v: np.r_[v[:3], np.nan, v[4:]], "the latitude axis 'lat' has 1 non-finite value(s)"),
])
def test_an_axis_fault_names_the_axis(tmp_path, axis, fix, needle):
    lat, lon = np.linspace(14.0, 15.0, 12), np.linspace(158.0, 159.0, 10)
    coords = {"lat": lat, "lon": lon}
    coords[axis] = fix(coords[axis])
    ds = xr.Dataset({"elevation": (("lat", "lon"), np.full((12, 10), -100.0), {"units": "m"})},
                    coords={"lat": ("lat", coords["lat"], {"units": "degrees_north"}),
                            "lon": ("lon", coords["lon"], {"units": "degrees_east"})})
    p = tmp_path / "g.nc"
    ds.to_netcdf(p)
    with pytest.raises(DataError) as exc:
        read_elevation(p)
    assert str(exc.value).startswith(f"{p}: variable 'elevation': ") and needle in str(exc.value)
