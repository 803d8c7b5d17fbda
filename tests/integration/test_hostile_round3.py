"""Issue #48, the command line: every new key bounded by the one estimator, readers that never raise, one
results folder per job, ``--port`` checked.

Oracles: each hostile case is refused with the exception the contract names (``ScenarioError`` /
``DataError`` / exit 2 with one line) whose message holds the file or table, the key and the value; the
accepted neighbours of each bound are accepted (the bound is where it is stated).
"""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from auvplan import cli
from auvplan.errors import DataError, ScenarioError
from auvplan.io.files import limits
from auvplan.io.files.manifest import MANIFEST, written_by
from auvplan.io.files.outdir import OutputError, release_all
from auvplan.io.files.safeio import atomic_write, prepare_out
from auvplan.io.missions.formats import read_mission
from auvplan.io.missions.tail import read_tail
from auvplan.io.scenario import loader
from auvplan.io.scenario.builtins import resolve

ORIGIN = (14.76, 158.40)


def _doc(name: str = "flow-spheres") -> dict:
    return tomllib.loads(resolve(name).read_text(encoding="utf-8"))


def _toml(doc: dict) -> str:
    from auvplan.app.page.tomlout import dumps

    return dumps(doc)


# ---------------------------------------------------------------- the estimator's new entries
@pytest.mark.parametrize("length, legs, ds, named", [
    (1e5, 1, 1e-9, "ds_m = 1e-09"), (1e5, 1, 0.0, "ds_m = 0"), (1e5, 1, -1.0, "ds_m = -1"),
    (1e5, 1, math.nan, "ds_m = nan"), (1.4e9, 1, 100.0, "1.4e+09 m"), (math.inf, 1, 100.0, "inf m"),
    (math.nan, 1, 100.0, "nan m"), (2.1e8, 1, 100.0, "2.1e+08 m"), (1e3, 3_000_000, 100.0, "3000000 legs"),
])
def test_the_energy_integration_is_bounded_before_it_runs(length, legs, ds, named):
    with pytest.raises(ScenarioError, match=r"^w: \[endurance\] ds_m = .*integration steps") as e:
        limits.check_endurance(limits.DEFAULT, "w: [endurance]", length, legs, ds)
    assert named in str(e.value)


@pytest.mark.parametrize("length, ds", [(1e5, 0.1), (1.9e8, 100.0), (0.0, 1e-3)])
def test_the_energy_bound_accepts_its_neighbours(length, ds):
    limits.check_endurance(limits.DEFAULT, "w:", length, 1, ds)


@pytest.mark.parametrize("counts, ok", [([1000], True), ([500, 500], True), ([1000] * 20, False), ([999, 2], False),
                                        ([1] * 1001, False), ([], True)])
def test_ensemble_members_are_counted_in_total(counts, ok):
    if ok:
        limits.check_members("s.toml: [currents] members", counts)
        return
    with pytest.raises(ScenarioError, match=rf"\[currents\] members: {len(counts)} entries stand for "
                                            rf"{sum(counts):,} members in total; at most 1,000"):
        limits.check_members("s.toml: [currents] members", counts)


@pytest.mark.parametrize("spacing, station, step, named", [
    (0.0, 10.0, 1.0, "inf lines"), (1e-3, 10.0, 1.0, "lines allowed"), (math.nan, 10.0, 1.0, "spacing of ~nan m"),
    (50.0, 1e-6, 1.0, "station_m = 1e-06"), (50.0, 10.0, 1e-9, "step_m = 1e-09"), (50.0, 0.0, 1.0, "station_m = 0"),
])
def test_survey_sizes_are_bounded_before_planning(spacing, station, step, named):
    with pytest.raises(ScenarioError, match=r"^s: \[survey\] the area") as e:
        limits.check_survey(limits.DEFAULT, "s: [survey]", 10_000.0, 10_000.0, spacing, station, step, 200.0)
    assert named in str(e.value)


# ---------------------------------------------------------------- scenario keys at load and build
_DS = [1e-9, 0.0, -1.0, 1e300, "nan", "inf", 0.05, 1e6, '"fine"', "true"]


@pytest.mark.parametrize("ds", _DS, ids=[str(d) for d in _DS])
def test_endurance_ds_m_has_a_floor_and_a_ceiling(tmp_path, ds):
    text = resolve("flow-spheres").read_text(encoding="utf-8") + f"\n[endurance]\nds_m = {ds}\n"
    p = tmp_path / "s.toml"
    p.write_text(text)
    with pytest.raises(ScenarioError) as e:
        loader.build(loader.load(p))
    assert str(e.value).startswith(f"{p}: [endurance]") and "ds_m" in str(e.value), e.value


@pytest.mark.parametrize("ds", [0.1, 100.0, 100_000.0])
def test_endurance_ds_m_bounds_accept_their_ends(tmp_path, ds):
    text = resolve("flow-spheres").read_text(encoding="utf-8") + f"\n[endurance]\nds_m = {ds}\n"
    assert loader.loads(text, "s.toml").endurance.ds_m == ds


def test_a_long_route_at_a_fine_step_is_refused_before_any_data_is_read(tmp_path):
    doc = _doc("marcus-wake")
    xs = np.linspace(5_000.0, 95_000.0, 40)
    route = [[float(x), 5_000.0 if i % 2 else 95_000.0, -1500.0] for i, x in enumerate(xs)]
    doc["mission"].update(route=route, start=route[0], goal=route[-1])
    doc.setdefault("endurance", {})["ds_m"] = 0.5
    doc["terrain"] = {"file": "missing-but-never-read.nc"}
    p = tmp_path / "long.toml"
    p.write_text(_toml(doc))
    with pytest.raises(ScenarioError, match=rf"^{p}: \[endurance\] ds_m = 0.5 m over a .* m mission of 41 legs "
                                            r"\(.* integration steps\): over the 2,000,000 steps allowed"):
        loader.build(loader.load(p))


@pytest.mark.parametrize("counts", [[1000, 1000], [600, 401], [1000] * 21])
def test_perturbation_members_over_1000_in_total_are_refused_at_load(tmp_path, counts):
    doc = _doc("flow-spheres")
    doc.setdefault("currents", {})["uniform"] = [0.1, 0.0, 0.0]
    doc["currents"]["members"] = [{"perturbation": {"count": c, "spread_mps": 0.1, "correlation_m": 50.0}}
                                  for c in counts]
    with pytest.raises(ScenarioError, match=rf"\[currents\] members: {len(counts)} entries stand for "
                                            rf"{sum(counts):,} members in total"):
        loader.loads(_toml(doc), "s.toml")


@pytest.fixture(scope="module")
def shelf():
    sc = loader.load("shelf-survey")
    world, mission = loader.build(sc)
    return sc, world, mission


_SURVEY = [
    ({"station_m": 1e-6}, "station_m = 1e-06"), ({"step_m": 1e-9}, "step_m = 1e-09"),
    ({"opening_deg": 1e-4}, "lines"), ({"mounting": "auv", "altitude_m": 1e-6}, "lines"),
    ({"sensor": "sidescan", "range_m": 1e-3, "mounting": "surface"}, "lines"),
    ({"overlap": (0.0, 0.99999)}, "lines"), ({"station_m": 1e-3, "step_m": 1e-3}, "station_m = 0.001"),
]


@pytest.mark.parametrize("change, named", _SURVEY, ids=[next(iter(c)) + str(i) for i, (c, _) in enumerate(_SURVEY)])
def test_survey_settings_that_would_allocate_gigabytes_are_refused_naming_them(shelf, change, named):
    from auvplan.io.results.survey import survey_params

    sc, world, mission = shelf
    spec = dataclasses.replace(sc.survey, **change)
    with pytest.raises(ScenarioError, match=r"^s.toml: \[survey\] ") as e:
        survey_params(spec, world, mission.vehicle, sc.base_dir, "s.toml: [survey]")
    assert named in str(e.value), e.value


def test_the_builtin_survey_passes_its_estimate(shelf):
    from auvplan.io.results.survey import survey_params

    sc, world, mission = shelf
    survey_params(sc.survey, world, mission.vehicle, sc.base_dir, "s.toml: [survey]")


def test_validate_exits_2_on_what_plan_would_refuse(tmp_path, capsys):
    text = resolve("flow-spheres").read_text(encoding="utf-8")
    cases = {"ds.toml": text + "\n[endurance]\nds_m = 1e-9\n",
             "members.toml": text.replace("[mission]", "[currents]\nuniform = [0.1, 0, 0]\nmembers = ["
                                          + ", ".join(["{perturbation = {count = 1000, spread_mps = 0.1, "
                                                       "correlation_m = 50}}"] * 20) + "]\n\n[mission]", 1)}
    for name, body in cases.items():
        p = tmp_path / name
        p.write_text(body)
        assert cli.main(["validate", str(p)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith(f"auvplan: error: {p}: ") and "Traceback" not in err, err


# ---------------------------------------------------------------- mission readers: what real tools write
def _geojson(tmp_path, geometry, props=None) -> Path:
    p = tmp_path / "m.geojson"
    p.write_text(json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "mission", **(props or {})}, "geometry": geometry}]}))
    return p


_GEO = [
    ({"type": "LineString", "coordinates": [[158.4, 14.76], [158.45, 14.78]]}, "without an altitude"),
    ({"type": "Point", "coordinates": [158.4, 14.76, -10]}, "one point"),
    ({"type": "Point", "coordinates": [158.4, 14.76]}, "one point"),
    ({"type": "LineString", "coordinates": [158.4, 14.76, -10, 158.5, 14.7, -10]}, "one point"),
    ({"type": "Polygon", "coordinates": [[[158.4, 14.76, 0], [158.5, 14.7, 0], [158.4, 14.7, 0]]]}, "polygon"),
    ({"type": "LineString", "coordinates": [[158.4, 14.76, -10, 5], [158.5, 14.7, -10, 5]]}, "4 values per point"),
    ({"type": "LineString", "coordinates": [[158.4, 14.76, -10], [158.5, 14.7]]}, "not a readable"),
    ({"type": "LineString", "coordinates": [[158.4, 95.0, -10], [158.5, 14.7, -10]]}, "not a lon, lat"),
    ({"type": "LineString", "coordinates": [["a", 1, 2], [1, 2, 3]]}, "not a readable"),
    ({"type": "LineString", "coordinates": None}, "not a list of points"),
    ({"type": "LineString"}, "no geometry coordinates"),
    (None, "no geometry coordinates"),
    ({"type": "LineString", "coordinates": "158.4,14.76"}, "not a readable"),
    ({"type": "LineString", "coordinates": [[1e400, 14.7, 0], [158.5, 14.7, 0]]}, "not a lon, lat"),
    ({"type": "LineString", "coordinates": [[]]}, "0 values per point"),
]


@pytest.mark.parametrize("geometry, named", _GEO, ids=[f"g{i}" for i in range(len(_GEO))])
def test_odd_geojson_missions_are_refused_naming_the_file(tmp_path, geometry, named):
    p = _geojson(tmp_path, geometry)
    p.write_text(p.read_text().replace("Infinity", "1e400"))  # json writes inf as Infinity: the file says 1e400
    with pytest.raises(DataError, match=rf"^{p}: ") as e:
        read_mission(p, ORIGIN)
    assert named in str(e.value), e.value


@pytest.mark.parametrize("body", ["{}", '{"features": 3}', '{"features": [3, "x"]}', "[]", '{"features": null}'])
def test_geojson_without_a_mission_feature_is_named(tmp_path, body):
    p = tmp_path / "m.geojson"
    p.write_text(body)
    with pytest.raises(DataError, match=rf"^{p}: "):
        read_mission(p, ORIGIN)


_KML = [
    ("158.40,14.76 158.45,14.78", "without an altitude"), ("158.40,14.76,-5 158.45,14.78", "mixes points"),
    ("", "no LineString coordinates"), ("a,b,c d,e,f", "not a readable"), ("158.4,14.76,-5,1 1,2,3,4", "4 values"),
    ("158.4,95,-5 158.5,14.7,-5", "not a lon, lat"), ("158.4", "1 values per point"),
]


@pytest.mark.parametrize("coords, named", _KML, ids=[f"k{i}" for i in range(len(_KML))])
def test_odd_kml_missions_are_refused_naming_the_file(tmp_path, coords, named):
    p = tmp_path / "m.kml"
    p.write_text('<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document><Placemark>'
                 f"<name>mission</name><LineString><coordinates>{coords}</coordinates></LineString></Placemark>"
                 "</Document></kml>")
    with pytest.raises(DataError, match=rf"^{p}: ") as e:
        read_mission(p, ORIGIN)
    assert named in str(e.value), e.value


def test_a_3d_kml_and_geojson_still_read(tmp_path):
    p = _geojson(tmp_path, {"type": "LineString", "coordinates": [[158.4, 14.76, -10], [158.45, 14.78, -20]]})
    w, sem, fmt = read_mission(p, ORIGIN)
    assert w.shape == (2, 3) and fmt == "geojson" and w[1, 2] == -20.0 and abs(w[0, 0]) < 1.0


_TAILS = ["[1e400]", '["a"]', "[null]", '{"a": 1}', "[-1]", "[1e20]", "3", '"0"', "[[0]]", "[0.5]"]


def _tail_geojson(tmp_path, tail):
    p = tmp_path / "m.geojson"
    p.write_text('{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"name": "mission", '
                 f'"tail_first_legs": {tail}}}, "geometry": {{"type": "LineString", "coordinates": '
                 '[[158.4, 14.76, -10], [158.45, 14.78, -20], [158.5, 14.78, -20]]}}]}')
    return p


@pytest.mark.parametrize("tail", _TAILS + ["[2]", "[0, true]"])
def test_odd_tail_first_legs_are_refused_naming_file_key_and_value(tmp_path, tail):
    p = _tail_geojson(tmp_path, tail)  # (a string "0" or a number 0.5 was once read as leg 0)
    with pytest.raises(DataError, match=rf"^{p}: tail_first_legs = ") as e:
        read_tail(p, 2)
    shown = str(e.value).split("tail_first_legs = ")[1]
    assert shown.startswith(tail.replace("1e400", "Infinity")[:3]) and "\n" not in str(e.value), e.value


def test_tail_first_legs_as_a_string_is_exit_2_in_one_line(tmp_path, capsys):
    p = _tail_geojson(tmp_path, '"0"')
    assert cli.main(["mission", "check", str(p), "--scenario", "marcus-wake"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f'{p}: tail_first_legs = "0" is not a list of leg indices' in err, err
    assert read_tail(_tail_geojson(tmp_path, "[1]"), 2).tolist() == [False, True]  # a good list still reads
    k = tmp_path / "m.kml"
    for value, ok in (("1", True), ("1 a", False), ("-1", False), ("0.5", False)):
        k.write_text('<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document><Placemark>'
                     f'<name>mission</name><ExtendedData><Data name="tail_first_legs"><value>{value}</value></Data>'
                     "</ExtendedData></Placemark></Document></kml>")
        if ok:
            assert read_tail(k, 2).tolist() == [False, True]
        else:
            with pytest.raises(DataError, match=rf"^{k}: tail_first_legs = '{value}' is not a list of leg"):
                read_tail(k, 2)


def test_mission_check_of_a_2d_geojson_exits_2_in_one_line(tmp_path, capsys):
    p = _geojson(tmp_path, {"type": "LineString", "coordinates": [[158.4, 14.76], [158.45, 14.78]]})
    assert cli.main(["mission", "check", str(p), "--scenario", "marcus-wake"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{p}: " in err and "without an altitude" in err, err
    far = tmp_path / "far.csv"  # a 10⁹ m leg: refused before the energy integration runs (since round 4 by the
    far.write_text("x,y,z\n0,0,-100\n1000000000,0,-100\n")  # reader, a waypoint beyond the Earth's circumference)
    assert cli.main(["mission", "check", str(far), "--scenario", "marcus-wake"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{far}: waypoint 1 = (1e+09, 0, -100) m lies over 4e+07 m" in err, err


# ---------------------------------------------------------------- --port
@pytest.mark.parametrize("port", ["99999", "65536", "-1", "abc", "1e3", "", "8080.5"])
def test_a_bad_port_is_a_usage_error(port, capsys):
    try:
        code = cli.main(["serve", "showcase", "--port", port, "--no-browser"])
    except SystemExit as e:
        code = e.code
    assert code == 2
    err = capsys.readouterr().err
    assert "--port" in err and "Traceback" not in err and (port in err or "integer" in err), err


# ---------------------------------------------------------------- one results folder = one job
@pytest.mark.parametrize("first, second, refused", [
    ("run", "survey", True), ("survey", "run", True), ("run", "plan", True), ("plan", "run", True),
    ("run", "bench", True), ("sweep", "plan", True), ("run formation", "run", True), ("run", "run", False),
    ("survey", "survey", False), ("run", "", False),
])
def test_a_folder_written_by_another_command_is_refused_by_name(tmp_path, first, second, refused):
    out = tmp_path / "D"
    try:
        prepare_out(out, ["metrics.json"], job=first)
        atomic_write(out / "metrics.json", "{}")
    finally:
        release_all()
    try:
        if refused:
            with pytest.raises(OutputError, match=rf"^{out}: holds the results of `auvplan {first}`"):
                prepare_out(out, ["metrics.json", "lines.csv"], job=second)
            assert (out / "metrics.json").exists()  # nothing removed without --force
        else:
            prepare_out(out, ["metrics.json"], job=second)
            assert written_by(out) == first
    finally:
        release_all()


def test_force_removes_the_other_jobs_files_and_keeps_the_users(tmp_path):
    out = tmp_path / "D"
    try:
        prepare_out(out, ["metrics.json", "track.csv"], job="run")
        atomic_write(out / "metrics.json", "{}")
        atomic_write(out / "track.csv", "t\n")
        (out / "notes.txt").write_text("mine")
    finally:
        release_all()
    try:
        prepare_out(out, ["metrics.json", "lines.csv"], job="survey", force=True)
    finally:
        release_all()
    assert not (out / "track.csv").exists() and not (out / "metrics.json").exists()
    assert (out / "notes.txt").read_text() == "mine" and written_by(out) == "survey"
    assert json.loads((out / MANIFEST).read_text())["job"] == "survey"


@pytest.mark.parametrize("planner, refused", [("iterations = 1000000000", True), ("budget = 1000000000000", True),
                                              ("iterations = 300000", True), ("iterations = 50000", False),
                                              ("budget = 10000", False)])
def test_a_plan_of_hours_is_refused_at_load_naming_the_keys(planner, refused):
    text = resolve("flow-spheres").read_text(encoding="utf-8").replace("[planner]", f"[planner]\n{planner}", 1)
    if not refused:
        loader.loads(text, "s.toml")
        return
    key = planner.split(" =")[0]
    with pytest.raises(ScenarioError, match=rf"^s.toml: \[planner\] .*{key}.* path samples to cost, over the"):
        loader.loads(text, "s.toml")
