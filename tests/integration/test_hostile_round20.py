"""Hostile input, round 20: the command-line flags, the names a scenario gives, the page's small endpoints.

Each case is one an earlier round had not tried, with what it did before (docs/hostile-input.md, "Round 20"):
exit 2 (or ``AuvplanError``/``ScenarioError``, HTTP 400) with one line naming the flag, key or file and its
value, at once; the neighbour of each bound accepted.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.errors import AuvplanError, ScenarioError


def _one_error_line(capsys, *needles):
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.count("\n") == 1, err
    for needle in needles:
        assert needle in err, err
    return err


# ---------------------------------------------------------------- bench: how many runs a sweep may hold
def test_a_billion_seeds_is_refused_before_any_task_is_listed(tmp_path, capsys, monkeypatch):
    """``bench --seeds 1000000000`` built its task list for minutes, filling the memory (> 60 s, killed)."""
    from auvplan.app.bench.sweep import SweepSpec

    monkeypatch.setattr(SweepSpec, "tasks", lambda self: pytest.fail("tasks were listed"))
    assert main(["bench", "--scenarios", "track-single", "--seeds", "1000000000", "--out", str(tmp_path / "b")]) == 2
    _one_error_line(capsys, "auvplan: error: --seeds 1000000000: over the 100,000 runs a sweep may hold")
    assert not (tmp_path / "b").exists()


def test_the_runs_are_counted_over_every_axis_and_the_bound_itself_is_listed_quickly():
    """Over the variants: 2 planners × 60 000 seeds refused before a cell is built.  At the bound, 10 000
    chunks of 10 seeds are listed (the duplicate check scanned the list once per chunk: quadratic)."""
    from auvplan.app.bench.sweep import MAX_RUNS, SweepSpec

    with pytest.raises(AuvplanError, match=r"^the sweep holds 120,000 runs \(scenarios × members × planners"):
        SweepSpec(("track-single",), ("iabc", "ga"), seeds=60_000).tasks()
    tasks = SweepSpec(("track-single",), ("iabc",), seeds=MAX_RUNS, chunk=10).tasks()
    assert len(tasks) == MAX_RUNS // 10
    assert tasks[-1] == ("track-single", "route", "hybrid", tuple(range(MAX_RUNS - 10, MAX_RUNS)))
    # a repeated cell (a scenario flying a fixed route: every planner is 'route') is still listed once
    assert SweepSpec(("track-single",), ("scenario", "iabc"), seeds=3, chunk=2).tasks() == [
        ("track-single", "route", "hybrid", (0, 1)), ("track-single", "route", "hybrid", (2,))]


@pytest.mark.parametrize(("value", "ok"), [("101", False), ("1000000000", False), ("100", True), ("0", True)])
def test_retries_are_bounded(capsys, value, ok):
    """``--retries 1000000000`` re-ran a task that fails for good a billion times."""
    from auvplan.cli.parser import _parser

    if ok:
        assert _parser().parse_args(["bench", "--retries", value]).retries == int(value)
        return
    with pytest.raises(SystemExit):
        _parser().parse_args(["survey", "shelf-survey", "--retries", value])
    assert f"argument --retries: {value} must be <= 100" in capsys.readouterr().err


# ---------------------------------------------------------------- what is there, but is not a file
@pytest.mark.parametrize("kind", ["folder", "fifo", "empty"])
def test_a_scenario_that_is_not_a_file_is_named_for_what_it_is(tmp_path, capsys, kind):
    """A folder, a FIFO or ``''`` was 'no such scenario file, and not a built-in scenario (<35 names>)'."""
    target = {"folder": tmp_path, "fifo": tmp_path / "s.toml", "empty": ""}[kind]
    if kind == "fifo":
        os.mkfifo(target)
    assert main(["validate", str(target)]) == 2
    want = {"folder": "a folder, not a scenario file", "fifo": "not a regular file (a FIFO, a device or a socket)",
            "empty": "'': an empty scenario name"}[kind]
    err = _one_error_line(capsys, want)
    assert "no such scenario file" not in err


@pytest.mark.parametrize("kind", ["folder", "fifo"])
def test_data_inspect_of_what_is_not_a_file_says_so(tmp_path, capsys, kind):
    """``data inspect`` of a folder or a FIFO said 'file not found'."""
    target = tmp_path / "x.nc"
    os.mkfifo(target) if kind == "fifo" else target.mkdir()
    assert main(["data", "inspect", str(target)]) == 2
    _one_error_line(capsys, f"{target}: not a regular file (a FIFO, a device or a folder)")


# ---------------------------------------------------------------- ensemble member names
_TWO = """
name = "m"
[origin]
lat = 68.0
lon = 13.0
[bounds]
x = [0.0, 1000.0]
y = [0.0, 1000.0]
z = [-100.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 80.0
[currents]
uniform = [0.1, 0.0, 0.0]
members = [{{ name = {a}, uniform = [0.1, 0.0, 0.0] }}, {{ name = {b}, uniform = [0.0, 0.1, 0.0] }}]
[mission]
start = [100.0, 100.0, -10.0]
goal = [900.0, 900.0, -10.0]
"""


@pytest.mark.parametrize(("a", "b", "needle"), [
    ('"a@b"', '"c"', "name = 'a@b': a member's name"),  # bench's label s@a@b read back as member 'b'
    ('"x~3"', '"c"', "name = 'x~3': a member's name"),  # read back as member 'x', perturbation seed 3
    ('"a\\u202eb"', '"c"', "name = 'a\\u202eb': a member's name"),  # reversed every message naming it
    ('"a\\nb"', '"c"', "name = 'a\\nb': a member's name"),
    ('"' + "x" * 65 + '"', '"c"', "a member's name is 1-64 characters"),
    ('"same"', '"same"', "[currents] members: two members are named 'same'"),  # bench --members same: the first
])
def test_a_member_name_that_breaks_labels_or_lines_is_refused(a, b, needle):
    from auvplan.io.scenario import loader

    with pytest.raises(ScenarioError) as err:
        loader.loads(_TWO.format(a=a, b=b), "s.toml")
    assert needle in str(err.value) and "\n" not in str(err.value) and str(err.value).startswith("s.toml: ")


def test_plain_member_names_and_unnamed_members_load():
    from auvplan.io.scenario import loader

    sc = loader.loads(_TWO.format(a='"arctic-20km_v2.1"', b='""'), "s.toml")
    assert [m.name for m in sc.currents.members] == ["arctic-20km_v2.1", ""]


# ---------------------------------------------------------------- a flight of too many time steps
def test_a_flight_of_1e306_steps_is_refused_naming_speed_and_dt():
    """A survey (start = goal: the load-time estimate saw a 0 m mission) at ``[vehicle] speed = 1e-300``:
    ``validate`` OK, then ``survey`` died on 'ValueError: Maximum allowed dimension exceeded'."""
    from dataclasses import replace

    import numpy as np

    from auvplan.io.scenario import loader
    from auvplan.io.scenario.build import build
    from auvplan.sim import simulate

    sc = loader.loads(_TWO.format(a='"a"', b='"b"'), "s.toml")
    world, mission = build(sc)
    slow = replace(mission, vehicle=replace(mission.vehicle, speed=1e-300))
    route = np.array([[100.0, 100.0, -10.0], [900.0, 100.0, -10.0], [900.0, 900.0, -10.0]])
    with pytest.raises(AuvplanError, match=r"^\[sim\] dt = 0.1 s over a time limit of 4.8e\+303 s \(3 × the 1600 m "
                                           r"route at \[vehicle\] speed = 1e-300 m/s\): 4.8e\+304 time steps, over the "
                                           r"20,000,000"):
        simulate(world, slow, route=route, avoidance="none", keys=np.empty((0, 3)))


def test_the_step_bound_accepts_its_end():
    from auvplan.sim.loop import MAX_SIM_STEPS, _check_steps

    _check_steps(MAX_SIM_STEPS * 0.1, 0.1, 1.0, 1.0, True)  # at the bound (dt 0.1 s: 23 days)
    with pytest.raises(AuvplanError, match=r"\[sim\] max_time\): 2e\+07 time steps"):
        _check_steps(MAX_SIM_STEPS * 0.1 * 1.000001, 0.1, 1.0, 1.0, True)


# ---------------------------------------------------------------- the page's small endpoints
@pytest.fixture(scope="module")
def served(tmp_path_factory):
    pytest.importorskip("starlette")
    from starlette.testclient import TestClient

    from auvplan.cli.serve import make_session
    from auvplan.serve.app import LOCAL_HOSTS, make_app

    session = make_session("track-single", [str(tmp_path_factory.mktemp("served20"))])
    return session, TestClient(make_app(session, (*LOCAL_HOSTS, "testserver")))


@pytest.mark.parametrize("name", [{"a": 1}, [1], 5, "a\nb", "\u202e", "\x00"])
def test_a_candidate_name_that_is_not_plain_text_is_400(served, name):
    """Kept as ``str(value)`` ("{'a': 1}") or with a newline / U+202E in the candidates' table."""
    session, client = served
    before = len(session.candidates)
    r = client.post("/api/keep", json={"name": name})
    assert r.status_code == 400 and r.json()["error"].startswith("auvplan: error: keep name = ")
    assert len(session.candidates) == before
    assert client.post("/api/keep", json={"name": "mine 2"}).status_code == 200  # the neighbour
    assert session.candidates[-1].name == "mine 2"


@pytest.mark.parametrize(("body", "needle"), [
    ({"semantics": "HELD", "pitch": 15}, "check semantics = 'HELD': choose one of held, ramp"),  # was '--pitch 15: …'
    ({"semantics": "held", "pitch": "x"}, "check pitch = 'x': expected a number of degrees"),
    ({"semantics": "held", "pitch": True}, "check pitch = 'True': expected a number"),  # was read as 1°
    ({"semantics": "held", "pitch": 0}, "check pitch = 0.0: must be a finite angle in (0, 90]"),
])
def test_each_check_setting_is_named_by_its_own_error(served, body, needle):
    session, client = served
    r = client.post("/api/check", json=body)
    assert r.status_code == 400 and needle in r.json()["error"] and "--pitch" not in r.json()["error"], r.json()
    assert client.post("/api/check", json={"semantics": "ramp", "pitch": 90}).status_code == 200


def test_an_error_line_quoting_a_megabyte_is_cut(served):
    """``/api/plan`` with a planner name of 10⁶ characters answered an error line of a megabyte."""
    session, client = served
    r = client.post("/api/plan", json={"planner": "x" * 1_000_000})
    error = r.json()["error"]
    assert r.status_code == 400 and error.startswith("auvplan: error: --planner 'xxx")
    assert len(error) < 2100 and error.endswith("… (1,000,071 characters)"), error[-80:]


# ---------------------------------------------------------------- --out
@pytest.mark.parametrize("command", [("plan", "track-single"), ("simulate", "track-single"), ("run", "track-single"),
                                     ("survey", "shelf-survey"), ("bench",), ("demo",)])
@pytest.mark.parametrize(("out", "needle"), [("", "'': an empty folder name"), ("  ", "'  ': an empty folder name"),
                                             ("a\nb", "'a\\nb': a control or formatting character")])
def test_an_empty_or_control_character_out_is_a_usage_error(capsys, command, out, needle):
    """``plan --out ''`` (an unset shell variable) wrote its files into the current folder; ``--out 'a<LF>b'`` made
    a folder every one-line message named 'a b'."""
    from auvplan.cli.parser import _parser

    with pytest.raises(SystemExit):
        _parser().parse_args([*command, "--out", out])
    assert f"argument --out: {needle}" in capsys.readouterr().err
    assert _parser().parse_args([*command, "--out", "résultats 2"]).out == "résultats 2"  # the neighbour


# ---------------------------------------------------------------- tidal station files
def _set(path, value):
    def change(doc):
        *head, last = path
        for p in head:
            doc = doc[p]
        if value is _DEL:
            del doc[last]
        else:
            doc[last] = value
    return change


_DEL = object()
_ST = "stations[0] (Rosario Strait (Depth 155.1ft), Washington Current harmonics)"
_TIDE_CASES = [  # each was a traceback (TypeError, IndexError, AttributeError, OverflowError, KeyError) or read as is
    (("first_year",), None, "first_year = None: expected a year in 1678..2261"),  # TypeError: int() argument
    (("first_year",), float("inf"), "first_year = inf: expected a year"),  # OverflowError
    (("constituents",), 5, "constituents: expected a list of 1 to 400 entries (got int)"),  # TypeError: not iterable
    (("equilibrium_deg",), 0, "equilibrium_deg: expected a list of 29 entries (got int)"),  # IndexError
    (("node_factor", 6, 5), {}, "node_factor[6][5] (M3, 2025) = {}: expected a finite number in [0, 10]"),
    (("speed_deg_per_hour", 5), 1e308, "speed_deg_per_hour[5] (M2) = 1e+308: expected a finite number in [0, 360]"),
    (("stations", 0, "amplitude_m_s"), 3, f"{_ST} amplitude_m_s: expected an object"),  # AttributeError: .get
    (("stations", 0, "amplitude_m_s", "M2"), float("nan"), f"{_ST} amplitude_m_s['M2'] = nan: expected a finite"),
    (("stations", 0, "phase_deg", "M2"), None, f"{_ST} phase_deg['M2'] = None: expected a finite number"),  # read NaN
    (("stations", 0, "amplitude_m_s", "m2"), 1.0, f"{_ST} amplitude_m_s: 'm2' is not one of the file's constituents"),
    (("stations", 0, "lat"), True, f"{_ST} lat = True: expected a finite number in [-90, 90]"),  # read as 1°
    (("stations", 0, "lon"), float("inf"), f"{_ST} lon = inf: expected a finite number"),  # numpy warnings, then NaN
    (("stations", 0, "zone_hours"), float("nan"), f"{_ST} zone_hours = nan"),
    (("stations", 0, "name"), _DEL, "stations[0] name = 'None': expected the station's name"),  # KeyError: 'name'
    (("stations", 0, "depth_m"), _DEL, f"{_ST}: no depth_m"),
    (("stations",), [], "stations: expected a list of 1 to 10,000 entries (got a list of 0)"),
    (("stations", 0), "x", "stations[0]: expected a station object (got str)"),
]


@pytest.mark.parametrize(("path", "value", "needle"), _TIDE_CASES,
                         ids=[".".join(map(str, p)) for p, _, _ in _TIDE_CASES])
def test_a_tide_file_value_of_the_wrong_kind_is_refused_naming_it(tmp_path, path, value, needle):
    import json
    from importlib import resources

    from auvplan.errors import DataError
    from auvplan.io.data.ocean.tides import read_tide_file

    doc = json.loads(resources.files("auvplan.data").joinpath("tides_rotary.json").read_text(encoding="utf-8"))
    _set(path, value)(doc)
    f = tmp_path / "t.json"
    f.write_text(json.dumps(doc), encoding="utf-8")
    with pytest.raises(DataError) as err:
        read_tide_file(str(f))
    assert str(err.value).startswith(f"{f}: ") and needle in str(err.value) and "\n" not in str(err.value), err.value


@pytest.mark.parametrize("name", ["juan-de-fuca", "rotary"])
def test_the_built_in_station_files_pass_the_check(name):
    from auvplan.io.data.ocean.tides import BUILTIN_TIDES, read_tide_file

    doc = read_tide_file(name if name in BUILTIN_TIDES else str(_data("tides_rotary.json")))
    assert len(doc["stations"]) == {"juan-de-fuca": 78, "rotary": 2}[name] and doc["first_year"] == 2020


def _data(name):
    from importlib import resources

    return resources.files("auvplan.data").joinpath(name)


# ---------------------------------------------------------------- moving obstacles' names
@pytest.mark.parametrize(("name", "ok"), [("a\u202eb", False), ("a\nb", False), ("x" * 129, False), ("", True),
                                          ("ferry «Ærø» 2", True)])
def test_a_moving_obstacle_name_with_control_characters_is_refused(name, ok):
    """Accepted before: a collision message naming 'a<U+202E>b' printed the rest of its line reversed."""
    import json

    from auvplan.io.scenario import loader

    text = _TWO.format(a='"a"', b='"b"') + (
        f"[[moving]]\nname = {json.dumps(name)}\ntype = \"sphere\"\nradius = 10.0\nmotion = \"linear\"\n"
        "start = [500.0, 200.0, -10.0]\nvelocity = [0.0, 1.0, 0.0]\n")
    if ok:
        assert loader.loads(text, "s.toml").moving[0].name == name
        return
    with pytest.raises(ScenarioError, match=r"^s.toml: \[\[moving\]\] #1 name = .*: a moving obstacle's name is up to "
                                            r"128 characters without control"):
        loader.loads(text, "s.toml")


# ---------------------------------------------------------------- serve --host / --port
@pytest.mark.parametrize(("host", "needle"), [
    ("garbage.invalid", "--host 'garbage.invalid': cannot serve on this address"),  # was: uvicorn's ERROR, exit 3
    ("999.1.1.1", "--host '999.1.1.1': cannot serve on this address"),
    ("", "--host '': an empty address; --host 0.0.0.0 serves on every interface"),  # was: served on every interface
])
def test_an_address_the_machine_cannot_serve_on_names_host(monkeypatch, capsys, host, needle):
    """``--port 0`` skipped the check: 'serving on http://garbage.invalid:0/', then uvicorn's 'ERROR: [Errno -2]',
    exit 3; with a port the fault was blamed on ``--port``."""
    import uvicorn

    monkeypatch.setattr(uvicorn.Server, "run", lambda self: pytest.fail("the server was started"))
    monkeypatch.setattr("auvplan.cli.serve.make_session", lambda *a: pytest.fail("the scenario was loaded"))
    assert main(["serve", "track-single", "--no-browser", "--port", "0", "--host", host]) == 2
    err = _one_error_line(capsys, f"auvplan: error: {needle}")
    assert "warning" not in err and "--port" not in err


def test_port_0_prints_the_real_address_and_loopback_gets_no_warning(monkeypatch, capsys):
    """The page's address was printed as 'http://127.0.0.1:0/' (the port the kernel had not chosen yet); ``::1``
    was warned about as reachable by anyone and printed without brackets."""
    import uvicorn

    seen = {}
    monkeypatch.setattr(uvicorn.Server, "run", lambda self: seen.update(port=self.config.port, host=self.config.host))
    assert main(["serve", "track-single", "--no-browser", "--port", "0", "--host", "localhost"]) == 0
    err = capsys.readouterr().err
    assert seen["port"] > 0 and f"on http://localhost:{seen['port']}/ (folders:" in err and "warning" not in err


# ---------------------------------------------------------------- a tampered run.npz
def _results(folder, **change):
    import json

    import numpy as np

    n = 5
    arrays = {"route": np.array([[0.0, 0.0, -20.0], [600.0, 0.0, -20.0]]), "keys": np.array([[0.0, 0.0, -20.0]]),
              "sim_t": np.arange(n) * 0.1, "sim_position": np.column_stack([np.arange(n), np.zeros(n), -np.ones(n)]),
              "sim_obstacle_distance": np.zeros((n, 0))}
    arrays.update({f"sim_{k}": np.zeros(n) for k in ("heading", "speed", "rudder", "cross_track", "route_error",
                                                      "progress", "altitude")})
    arrays.update(change)
    folder.mkdir()
    np.savez(folder / "run.npz", **arrays)
    sim = {"status": "EXACT", "arrived": True, "guidance": "los", "events": [[0.4, "arrival", "x"]]}
    (folder / "run.json").write_text(json.dumps({"scenario": "s", "seed": 1, "plan": None, "simulation": sim}))
    return folder


_NAN3 = [[0.0, 0.0, -20.0], [float("nan"), 0.0, -20.0]]
_NPZ_CASES = [  # report: each was a traceback (IndexError) or a ValueError naming no file
    ({"route": _NAN3}, "member 'route' holds a value that is not finite (row 1)"),  # cannot convert float NaN to int
    ({"route": [[0.0, 0.0], [1.0, 1.0]]}, "member 'route' has the shape (2, 2), not (N, 3)"),
    ({"sim_t": [0.0, 0.1, 0.2]}, "member 'sim_position' has the shape (5, 3), not (3, 3)"),  # IndexError
    ({"sim_t": [0.4, 0.3, 0.2, 0.1, 0.0]}, "member 'sim_t' ((5,)) is not a finite, non-decreasing time series"),
    ({"sim_position": [[0.0, 0.0]] * 5}, "member 'sim_position' has the shape (5, 2), not (5, 3)"),  # IndexError
    ({"sim_position": [[math.inf, 0.0, 0.0]] * 5}, "member 'sim_position' holds a value that is not finite (row 0)"),
    ({"sim_heading": [0.0] * 4}, "member 'sim_heading' has 4 rows, 'sim_t' 5"),  # IndexError: boolean index
]


@pytest.mark.parametrize(("change", "needle"), _NPZ_CASES, ids=[next(iter(c)) + str(i) for i, (c, _) in
                                                                 enumerate(_NPZ_CASES)])
def test_a_tampered_run_npz_is_blamed_on_its_member(tmp_path, change, needle):
    import numpy as np

    from auvplan.errors import DataError
    from auvplan.io.results.readback import read_run

    folder = _results(tmp_path / "r", **{k: np.asarray(v, dtype=float) for k, v in change.items()})
    with pytest.raises(DataError) as err:
        read_run(folder)
    assert str(err.value) == f"{folder / 'run.npz'}: {needle}"
    record, _ = read_run(_results(tmp_path / "ok"))  # the untampered neighbour reads
    assert record.sim is not None and record.sim.position.shape == (5, 3) and record.route.shape == (2, 3)


# ---------------------------------------------------------------- current files: magnitudes
def _current_file(path, u, units="m s-1"):
    import numpy as np
    import xarray as xr

    lat, lon = np.linspace(47.9, 48.2, 6), np.linspace(-125.9, -125.4, 7)
    field = np.full((1, lat.size, lon.size), 0.3)
    uo = field.copy()
    uo[0, 2, 3] = u
    dims = ("time", "latitude", "longitude")
    ds = xr.Dataset({"uo": (dims, uo, {"units": units, "standard_name": "eastward_sea_water_velocity"}),
                     "vo": (dims, field, {"units": units, "standard_name": "northward_sea_water_velocity"})},
                    coords={"time": np.array(["2024-03-01T00:00"], dtype="datetime64[ns]"),
                            "latitude": ("latitude", lat, {"units": "degrees_north"}),
                            "longitude": ("longitude", lon, {"units": "degrees_east"})})
    ds.to_netcdf(path)
    return path


@pytest.mark.parametrize(("u", "units", "needle"), [
    (1e30, "m s-1", "variable 'uo' holds 1e+30 m/s (at lat 48.0200, lon -125.6500, level 0, time 0; 1 such values): "
                    "over the 50 m/s"),  # an undeclared fill value: validate OK, flown as a current of 1e30 m/s
    (6000.0, "cm s-1", "variable 'uo' holds 60 m/s"),  # over the bound after the units
    (math.inf, "m s-1", "variable 'uo' holds an infinite value (1 of them)"),
])
def test_a_current_no_ocean_has_is_refused_naming_the_variable(tmp_path, u, units, needle):
    from auvplan.errors import DataError
    from auvplan.io.data.geo import LocalFrame
    from auvplan.io.data.ocean.currents import CurrentsFileSpec, read_currents

    frame, box = LocalFrame(48.05, -125.65), (-5000.0, 5000.0, -5000.0, 5000.0)
    with pytest.raises(DataError) as err:
        read_currents(CurrentsFileSpec(str(_current_file(tmp_path / "c.nc", u, units))), frame, extent_m=box)
    assert needle in str(err.value) and "\n" not in str(err.value), err.value
    ok = read_currents(CurrentsFileSpec(str(_current_file(tmp_path / "ok.nc", 4900.0, "cm s-1"))), frame,
                       extent_m=box)  # the neighbour: 49 m/s at a node, under the bound, is read (regridded)
    assert 10.0 < np.nanmax(np.abs(ok.u)) <= 49.0


# ---------------------------------------------------------------- bench --resume of an edited rows.csv
def _rows_csv(path, *rows):
    from auvplan.app.bench.rows import COLUMNS

    def line(seed, status="EXACT", guidance="hybrid"):
        values = {k: "" for k in COLUMNS} | {"scenario": "track-single", "planner": "route", "guidance": guidance,
                                             "seed": seed, "status": status, "wall_s": "0.5"}
        return ",".join(values[k] for k in COLUMNS) + "\r\n"

    path.write_text(",".join(COLUMNS) + "\r\n" + "".join(line(*r) for r in rows), encoding="utf-8", newline="")
    return path


@pytest.mark.parametrize(("rows", "kept"), [
    ([("0",), ("x",)], ["0"]),  # the resumed sweep ended in 'ValueError: invalid literal for int()'
    ([("0",), ("1e400",)], ["0"]),
    ([("0",), ("1", "EXACT", "hy\x00brid")], ["0"]),  # a NUL reached the figures' labels
    ([("0",), ("1",)], ["0", "1"]),  # the neighbour: both count
])
def test_a_row_whose_seed_or_text_is_not_a_rows_is_run_again(tmp_path, rows, kept):
    from auvplan.app.bench.rows import read_rows

    assert [r["seed"] for r in read_rows(_rows_csv(tmp_path / "rows.csv", *rows))] == kept


@pytest.mark.parametrize(("text", "needle"), [
    ("a,b,c\r\n1,2,3\r\n", "its first line is not the header `auvplan bench` writes ('a,b,c'…)"),  # rows appended
    ("\x89PNG\r\n\x1a\n" * 3, "its first line is not the header"),
    (None, "line 2 is not a row of `auvplan bench` (field larger than field limit (131072))"),  # a traceback
])
def test_a_rows_csv_bench_did_not_write_is_not_resumed(tmp_path, text, needle):
    from auvplan.app.bench.sweep import SweepSpec, _todo

    path = tmp_path / "rows.csv"
    if text is None:
        _rows_csv(path, ("0",))
        path.write_text(path.read_text() + "a" * 200_000 + "\r\n")
    else:
        path.write_text(text, encoding="latin-1")
    before = path.read_bytes()
    with pytest.raises(AuvplanError) as err:
        _todo(SweepSpec(("track-single",), seeds=2), path, resume=True)
    assert str(err.value).startswith(f"{path}: {needle}") and "\n" not in str(err.value), err.value
    assert path.read_bytes() == before  # nothing appended under another header


@pytest.mark.parametrize("name", ["results", "m.plan"])
def test_mission_check_of_a_folder_says_it_is_a_folder(tmp_path, capsys, name):
    """Was "unknown mission format ''" for a folder (and for a folder named m.plan, whatever the reader said)."""
    folder = tmp_path / name
    folder.mkdir()
    assert main(["mission", "check", str(folder), "--scenario", "track-single"]) == 2
    _one_error_line(capsys, f"auvplan: error: {folder}: a folder, not a mission file")


# ---------------------------------------------------------------- [endurance] return_speed
@pytest.mark.parametrize(("value", "ok"), [(100.0, False), (1e-300, False), (0.49, False), (0.5, True), (2.5, True),
                                           (0.0, True)])
def test_a_return_speed_the_vehicle_cannot_fly_is_refused(value, ok):
    """``return_speed = 100`` (max_speed 2.5) costed the return at 100 m/s ('699.6 Wh back'); ``1e-300`` printed
    'turn back by 0.00 km: 0.0 Wh out, 0.0 Wh back'.  Both validated OK."""
    from auvplan.io.scenario import loader

    tables = f"[vehicle]\nmin_speed = 0.5\nmax_speed = 2.5\n[endurance]\nreturn_speed = {value!r}\n"
    text = _TWO.format(a='"a"', b='"b"') + tables
    if ok:
        assert loader.loads(text, "s.toml").endurance.return_speed == value
        return
    with pytest.raises(ScenarioError, match=rf"^s.toml: \[endurance\] return_speed = {value!r}: outside the vehicle's "
                                            r"speeds \[min_speed 0.5, max_speed 2.5\] m/s"):
        loader.loads(text, "s.toml")
