"""A results folder's ``scenario.toml`` keeps the user's text, relative data paths and all: loaded as the
``--scenario`` of ``mission check`` (README, "Hand it to the vehicle"), those paths resolve against the original
scenario's folder recorded in ``source.json``, not against the results folder (``chagos-reefs``' reef file,
``../ne_10m_reefs_chagos.geojson``, was 'not found', exit 2)."""

from __future__ import annotations

import json

import pytest

from auvplan.cli import main
from auvplan.errors import ScenarioError
from auvplan.io.scenario import loader

ZONES = """{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"name": "box"},
 "geometry": {"type": "Polygon", "coordinates": [[[-124.990, 48.008], [-124.986, 48.008], [-124.986, 48.012],
 [-124.990, 48.012], [-124.990, 48.008]]]}}]}"""

SCENARIO = """name = "rel-zone"
seed = 1
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 2000.0]
y = [0.0, 2000.0]
z = [-100.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 80.0
cell_m = 50.0
[[zones]]
name = "area"
file = "zones.geojson"     # relative to this file's folder
[mission]
start = [200.0, 1000.0, -30.0]
goal = [1800.0, 1000.0, -30.0]
min_altitude_m = 5.0
[vehicle]
speed = 1.5
[planner]
name = "grid"
"""


def test_mission_check_against_the_results_folder_scenario_finds_its_relative_zone_file(tmp_path, capsys):
    src = tmp_path / "src"
    src.mkdir()
    (src / "zones.geojson").write_text(ZONES)
    (src / "s.toml").write_text(SCENARIO)
    out = tmp_path / "out"
    assert main(["-q", "plan", str(src / "s.toml"), "--out", str(out)]) == 0
    assert main(["-q", "export", str(out), "--format", "csv"]) == 0
    capsys.readouterr()
    # the straight line y = 1000 crosses the box (x 745-1043 m, y 890-1334 m): the plan goes round it, 1 m off
    assert main(["mission", "check", str(out / "mission.csv"), "--scenario", str(out / "scenario.toml")]) == 0
    cap = capsys.readouterr()
    assert "zone 'area: box': OK — closest approach" in cap.out, cap.err
    assert loader.load(out / "scenario.toml").base_dir == src

    again = tmp_path / "again"  # a results folder of a run of that folder's scenario.toml: followed to the source
    again.mkdir()
    (again / "scenario.toml").write_text((out / "scenario.toml").read_text())
    (again / "source.json").write_text(json.dumps({"scenario_source": str(out / "scenario.toml")}))
    assert loader.load(again / "scenario.toml").base_dir == src

    (again / "source.json").write_text("[1, 2]")
    with pytest.raises(ScenarioError, match=r"source.json: malformed .*scenario_source"):
        loader.load(again / "scenario.toml")


def test_report_and_serve_follow_source_json_through_re_runs_as_the_loader_does(tmp_path, monkeypatch):
    """``report``/``export``/``serve`` read a results folder's scenario against
    :func:`~auvplan.io.results.folder.scenario_base`: one hop only, so a re-run's folder resolved against the
    first results folder (audit 16: its ``zones.geojson`` 'not found' there, or a stale copy read).  Oracle:
    the same folder as the loader; a relative ``scenario_source`` from its ``source.json``'s folder, not the
    working directory."""
    from auvplan.io.files.jsonfile import source_base
    from auvplan.io.results import folder

    src, out, again = (tmp_path / n for n in ("src", "out", "again"))
    for d in (src, out, again):
        d.mkdir()
    (src / "s.toml").write_text(SCENARIO)
    (out / "scenario.toml").write_text(SCENARIO)
    (out / "source.json").write_text(json.dumps({"scenario_source": str(src / "s.toml")}))
    (again / "scenario.toml").write_text(SCENARIO)
    (again / "source.json").write_text(json.dumps({"scenario_source": str(out / "scenario.toml")}))
    assert folder.scenario_base(again) == src == source_base(again / "scenario.toml")
    (again / "source.json").write_text(json.dumps({"scenario_source": "../out/scenario.toml"}))
    monkeypatch.chdir(src)  # from the working directory, '../out' would be tmp_path/out too: go deeper
    (src / "deep").mkdir()
    monkeypatch.chdir(src / "deep")
    assert folder.scenario_base(again) == src
    (again / "source.json").write_text(json.dumps({"scenario_source": str(again / "scenario.toml")}))  # a cycle
    assert folder.scenario_base(again) == again


def test_a_results_folder_run_again_into_itself_keeps_its_original_source(tmp_path):
    """``plan DIR/scenario.toml --out DIR --force`` recorded DIR/scenario.toml as its own source (audit 16):
    the original folder was lost and the next load said '[[zones]] #1 file = 'DIR/zones.geojson': not found'.
    Oracle: ``source.json`` names the original file; the folder's scenario still loads against it."""
    from auvplan.app.results import save_context

    src, out = tmp_path / "src", tmp_path / "out"
    src.mkdir()
    out.mkdir()
    (src / "zones.geojson").write_text(ZONES)
    (src / "s.toml").write_text(SCENARIO)
    world, _ = loader.build(loader.load(src / "s.toml"))
    save_context(out, str(src / "s.toml"), world)  # the first run's folder
    (out / "scenario.toml").write_text(SCENARIO)
    sc = loader.load(out / "scenario.toml")
    save_context(out, sc.source, world)  # what the second run writes last, into the same folder
    assert json.loads((out / "source.json").read_text()) == {"scenario_source": str((src / "s.toml").resolve())}
    assert loader.load(out / "scenario.toml").base_dir == src


def test_force_never_removes_the_scenario_the_command_reads(tmp_path, capsys):
    """``run DIR/scenario.toml --out DIR --force`` on a folder ``plan`` wrote removed the plan's files, the
    scenario among them, then said 'no such scenario file' (audit 16: the folder emptied, nothing written).
    Oracle: refused naming the file, exit 2, every file still there."""
    from auvplan.io.files.outdir import session
    from auvplan.io.files.safeio import atomic_write, prepare_out

    out = tmp_path / "out"
    with session():  # the folder as `plan` left it
        prepare_out(out, job="plan")
    atomic_write(out / "scenario.toml", SCENARIO)
    atomic_write(out / "run.json", "{}")
    before = sorted(p.name for p in out.iterdir())
    assert main(["run", str(out / "scenario.toml"), "--out", str(out), "--force"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{out / 'scenario.toml'}: the file this `auvplan run` reads; --force" in err
    assert sorted(p.name for p in out.iterdir()) == before
