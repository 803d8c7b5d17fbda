"""An earlier run's mission files are never left beside this run's (wave 18).

A results folder written again (``run --out D`` of another mission, ``report D --board-storage …``) overwrote the
exports it wrote and kept every other ``mission.*`` auvplan had written there before: a ``.plan`` left out (the
board cannot hold it, a fence across ±180°) or the geographic files of a mission without ``[origin]`` stayed, files
of *another* mission beside this one's, ready to be uploaded in its place.  Now the writer of a folder's exports
removes its own earlier files it did not write again (:func:`auvplan.io.files.manifest.disown`) and says so; a
user's file is left alone.

Oracle: the files on disk and the manifest, read back; the route each remaining export carries, counted in
``mission.csv``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.files.manifest import MANIFEST, disown, written
from auvplan.io.results.records import write_run
from auvplan.sim.result import RunRecord
from helpers import HOLDS

ORIGIN = (-7.0, 70.8)  # HOLDS' [origin]
NO_ORIGIN = HOLDS.replace("[origin]\nlat = -7.0\nlon = 70.8\n", "")


@pytest.fixture
def no_page(monkeypatch):
    """The report's page left empty: these tests are about the exports beside it."""
    import auvplan.viz.report

    monkeypatch.setattr(auvplan.viz.report, "build_report", lambda *a, **k: "<html></html>")


def _run(out, waypoints: int, scenario: str = HOLDS, origin=ORIGIN) -> None:
    route = np.column_stack([np.linspace(500.0, 2500.0, waypoints), np.full(waypoints, 1000.0),
                             np.full(waypoints, -15.0)])
    write_run(out, RunRecord("holds", 1, None, route, route[[0, -1]], None), scenario, origin=origin)


def _rows(path) -> int:
    return sum(1 for ln in path.read_text().splitlines()[1:] if ln.strip())


def test_a_plan_left_out_takes_the_earlier_runs_plan_with_it(tmp_path, capsys, no_page):
    out = tmp_path / "r"
    out.mkdir()
    _run(out, 5)
    assert main(["report", str(out)]) == 0
    assert len(json.loads((out / "mission.plan").read_text())["mission"]["items"]) == 6  # 5 + the speed command
    _run(out, 654)  # another mission into the same folder: 656 commands, more than a 16 KiB board holds
    assert main(["report", str(out), "--board-storage", "16k"]) == 0
    err = capsys.readouterr().err
    assert "mission.plan left out: " in err
    assert f"mission.plan of an earlier run removed from {out}" in err
    assert not (out / "mission.plan").exists() and "mission.plan" not in written(out)
    assert _rows(out / "mission.csv") == 654  # the other exports are this mission's


def test_a_mission_without_origin_leaves_no_geographic_file_of_the_last(tmp_path, capsys, no_page):
    out = tmp_path / "r"
    out.mkdir()
    _run(out, 5)
    assert main(["report", str(out)]) == 0
    geo = ["mission.geojson", "mission.kml", "mission.plan", "mission.gpx"]
    assert all((out / n).is_file() for n in geo)
    _run(out, 7, NO_ORIGIN, origin=None)
    assert main(["report", str(out)]) == 0
    assert not any((out / n).exists() for n in geo) and not set(geo) & written(out)
    err = capsys.readouterr().err
    assert "mission.geojson, mission.kml, mission.plan, mission.gpx of an earlier run removed" in err
    assert _rows(out / "mission.csv") == 7


def test_disown_removes_only_auvplans_own_regular_files(tmp_path):
    (tmp_path / "a.plan").write_text("auvplan's")
    (tmp_path / "target").write_text("kept")
    (tmp_path / "b.plan").symlink_to(tmp_path / "target")
    (tmp_path / "c.plan").write_text("the user's")
    (tmp_path / MANIFEST).write_text(json.dumps({"files": ["a.plan", "b.plan", "gone.plan"], "job": "run"}))
    assert disown(tmp_path, ["c.plan", "b.plan", "a.plan", "gone.plan"]) == ["a.plan"]
    assert not (tmp_path / "a.plan").exists() and (tmp_path / "target").read_text() == "kept"
    assert (tmp_path / "b.plan").is_symlink() and (tmp_path / "c.plan").read_text() == "the user's"
    doc = json.loads((tmp_path / MANIFEST).read_text())
    assert doc == {"files": ["b.plan"], "job": "run"}  # the link still there, listed; the two gone, dropped
