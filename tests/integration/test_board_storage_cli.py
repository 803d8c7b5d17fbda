"""``--board-storage`` on ``mission check``, ``export`` and ``report`` (helper storage, wave 18).

A ``.plan`` between 655 and 4 368 commands is what only a board with enough storage holds (16 KiB: 655, 32 KiB of
FRAM: 1 312, ``BRD_SD_MISSION = 64``: 4 368; ``(storage − 4) // 15``, the home included): ``mission check`` passed it
and ``export`` wrote it without a word.  Now the check names the storage the file needs (informative), and with the
board named a file it cannot hold fails (exit 1) and is not exported (exit 2, one line; nothing written).

Oracle: ``.plan`` files written by hand here (three waypoints and ``MAV_CMD_DO_CHANGE_SPEED`` items up to the count,
a ``survey`` ComplexItem's generated items counted one by one), their commands counted by hand, the capacities
worked out from the bytes (``tests/unit/test_mission_storage.py``).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.data.geo import LocalFrame
from auvplan.io.results.records import write_run
from auvplan.sim.result import RunRecord
from helpers import HOLDS

ORIGIN = (-7.0, 70.8)  # HOLDS' [origin]
SPEED = {"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, 1.5, -1, 0, 0, 0, 0]}


def _waypoint(x: float) -> dict[str, object]:
    lon, lat = LocalFrame(*ORIGIN).inverse(x, 1000.0)
    return {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, None, float(lat), float(lon), -15.0]}


def _plan(tmp_path, commands: int, survey: int = 0):
    """A ``.plan`` of ``commands`` commands with the home: 3 waypoints, ``survey`` generated waypoints in one
    ComplexItem (one item of the file, ``survey`` commands), and speed commands for the rest."""
    items = [_waypoint(500.0)]
    if survey:
        generated = [_waypoint(x) for x in np.linspace(600.0, 1400.0, survey)]
        items.append({"type": "ComplexItem", "complexItemType": "survey",
                      "TransectStyleComplexItem": {"Items": generated}})
    items += [_waypoint(1500.0), _waypoint(2500.0)]
    speeds = commands - 1 - 3 - survey  # the home, the three waypoints, the generated ones
    assert speeds >= 0
    items[1:1] = [dict(SPEED) for _ in range(speeds)]
    lon, lat = LocalFrame(*ORIGIN).inverse(500.0, 1000.0)
    path = tmp_path / f"m{commands}.plan"
    path.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS)
    return path, scen


def _check(capsys, path, scen, *extra):
    code = main(["mission", "check", str(path), "--scenario", str(scen), *extra])
    out = capsys.readouterr().out
    lines = [ln for ln in out.splitlines() if "mission storage" in ln]
    assert len(lines) == 1, out
    return code, lines[0]


@pytest.mark.parametrize(("commands", "needs"), [
    (655, "fits a 16 KiB-storage board (655 commands)"),
    (656, "needs 32 KiB of storage (FRAM: 1312 commands"),
    (1313, "needs BRD_SD_MISSION ≥ 20 (KiB"),  # 4 + 15·1313 = 19 699 bytes
])
def test_mission_check_names_the_storage_the_plan_needs(tmp_path, capsys, commands, needs):
    path, scen = _plan(tmp_path, commands)
    code, line = _check(capsys, path, scen)
    assert code == 0  # informative without the board
    assert line == (f"{path}: mission storage: {commands} commands ({commands - 1} items + the home, "
                    f"{4 + 15 * commands} bytes): " + line.split("bytes): ", 1)[1])
    assert needs in line


@pytest.mark.parametrize(("commands", "board", "code"), [
    (655, "16k", 0), (656, "16k", 1),
    (1312, "32k", 0), (1313, "32k", 1),
    (1313, "sd:19", 1),  # (19 456 − 4) // 15 = 1 296
    (1313, "sd:20", 0),  # (20 480 − 4) // 15 = 1 365
])
def test_mission_check_fails_a_plan_the_board_cannot_hold(tmp_path, capsys, commands, board, code):
    path, scen = _plan(tmp_path, commands)
    got, line = _check(capsys, path, scen, "--board-storage", board)
    assert got == code, line
    assert (" mission storage FAIL — " if code else " mission storage OK — ") in line
    assert f"(--board-storage {board})" in line
    main(["mission", "check", str(path), "--scenario", str(scen), "--board-storage", board, "--json"])
    rec = json.loads(capsys.readouterr().out)
    ms = rec["deploy"]["mission_storage"]
    hand = {"16k": 655, "32k": 1312, "sd:19": 1296, "sd:20": 1365}[board]
    assert (ms["commands"], ms["bytes"], ms["board"], ms["board_commands"]) == (commands, 4 + 15 * commands, board,
                                                                               hand)
    assert ms["ok"] is (code == 0) and rec["ok"] is (code == 0) and rec["deploy"]["ok"] is (code == 0)


def test_a_survey_s_generated_items_are_commands(tmp_path, capsys):
    """QGroundControl uploads a ComplexItem's generated items: each is a command (40 here, one item of the file)."""
    path, scen = _plan(tmp_path, 656, survey=40)
    assert len(json.loads(path.read_text())["mission"]["items"]) == 656 - 1 - 40 + 1
    code, line = _check(capsys, path, scen, "--board-storage", "16k")
    assert code == 1 and "656 commands (655 items + the home" in line


def test_a_file_of_another_format_has_no_storage_line(tmp_path, capsys):
    path, scen = _plan(tmp_path, 10)
    gpx = tmp_path / "m.gpx"
    lon, lat = LocalFrame(*ORIGIN).inverse(np.array([500.0, 2500.0]), np.array([1000.0, 1000.0]))
    gpx.write_text('<?xml version="1.0"?><gpx version="1.1" creator="t" xmlns="http://www.topografix.com/GPX/1/1">'
                   + "<rte>" + "".join(f'<rtept lat="{a}" lon="{b}"><ele>-15</ele></rtept>' for a, b in zip(lat, lon))
                   + "</rte></gpx>")
    assert main(["mission", "check", str(gpx), "--scenario", str(scen), "--board-storage", "16k", "--json"]) == 0
    assert "mission_storage" not in json.loads(capsys.readouterr().out)["deploy"]


def _results(tmp_path, waypoints: int):
    out = tmp_path / "r"
    out.mkdir()
    route = np.column_stack([np.linspace(500.0, 2500.0, waypoints), np.full(waypoints, 1000.0),
                             np.full(waypoints, -15.0)])
    write_run(out, RunRecord("holds", 1, None, route, route[[0, -1]], None), HOLDS, origin=ORIGIN)
    return out


def test_export_refuses_a_plan_the_board_cannot_hold_and_writes_nothing(tmp_path, capsys):
    out = _results(tmp_path, 654)  # 654 waypoints + the launch's speed command + the home = 656 commands
    code = main(["export", str(out), "--format", "csv", "plan", "--board-storage", "16k"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err
    assert f"{out / 'mission.plan'}: 655 items + the home = 656 commands > the 655 that a 16 KiB-storage board " \
           "holds (--board-storage 16k)" in err
    assert not (out / "mission.plan").exists() and not (out / "mission.csv").exists()  # nothing written
    (out / "mission.plan").write_text("mine")  # the user's own file: never overwritten, even with --force
    assert main(["export", str(out), "--format", "plan", "--board-storage", "16k", "--force"]) == 2
    assert (out / "mission.plan").read_text() == "mine"
    (out / "mission.plan").unlink()
    assert main(["export", str(out), "--format", "csv", "plan", "--board-storage", "32k"]) == 0
    assert len(json.loads((out / "mission.plan").read_text())["mission"]["items"]) == 655


@pytest.fixture
def no_page(monkeypatch):
    """The report's page left empty: these tests are about the exports beside it (seconds of plotly saved)."""
    import auvplan.viz.report

    monkeypatch.setattr(auvplan.viz.report, "build_report", lambda *a, **k: "<html></html>")


def test_report_leaves_out_a_plan_the_board_cannot_hold(tmp_path, capsys, no_page):
    """``report`` (as ``run``, through the same writer) keeps every other export and says why the .plan is not."""
    out = _results(tmp_path, 654)
    assert main(["report", str(out), "--board-storage", "16k"]) == 0
    err = capsys.readouterr().err
    assert "mission.plan left out: " in err and "656 commands > the 655" in err
    assert not (out / "mission.plan").exists() and (out / "mission.moos").exists()


@pytest.mark.parametrize("argv", [
    ["mission", "check", "m.plan", "--scenario", "s.toml"],
    ["export", "DIR"],
    ["report", "DIR"],
    ["run", "s.toml"],
    ["survey", "s.toml"],
])
@pytest.mark.parametrize("value", ["sd:0", "sd:65", "48k", "SD:4"])
def test_bad_board_storage_values_exit_2_naming_them(capsys, argv, value):
    code = main([*argv, "--board-storage", value])
    err = capsys.readouterr().err
    errors = [ln for ln in err.splitlines() if "error:" in ln]
    assert code == 2 and len(errors) == 1
    assert f"argument --board-storage: '{value}': not 16k, 32k or sd:N" in errors[0]


def test_run_hands_the_board_to_the_writer_of_its_results(tmp_path, monkeypatch):
    """``run --board-storage`` reaches :func:`auvplan.app.run.run_scenario` (which hands it to ``write_results``, the
    writer ``report`` uses above)."""
    import auvplan.app.run as app_run
    from auvplan.errors import AuvplanError

    seen = {}

    def fake(*args, **kwargs):
        seen.update(kwargs)
        raise AuvplanError("stopped before the mission")

    monkeypatch.setattr(app_run, "run_scenario", fake)
    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS)
    assert main(["run", str(scen), "--board-storage", "sd:24"]) == 2
    assert seen["board"].name == "sd:24" and seen["board"].commands == 1638  # (24576 - 4) // 15


def test_survey_leaves_out_a_plan_the_board_cannot_hold(tmp_path, capsys, no_page):
    """``survey`` writes its other exports and says why the .plan is not written, as ``run`` does (a refused .plan,
    over 4 368 commands or a fence across ±180°, stopped it with exit 2 part-way through its exports)."""
    from test_survey_mission import _write

    out = tmp_path / "out"
    assert main(["-q", "survey", str(_write(tmp_path)), "--out", str(out), "--json", "--board-storage", "sd:1"]) == 0
    notes = json.loads(capsys.readouterr().out)["notes"]
    assert len(notes) == 1 and notes[0].startswith(f"mission.plan left out: {out / 'mission.plan'}: ")
    assert "commands > the 68 that BRD_SD_MISSION = 1 holds (--board-storage sd:1)" in notes[0]  # (1024 - 4) // 15
    assert not (out / "mission.plan").exists() and (out / "mission.moos").exists() and (out / "report.html").exists()
