"""What a newcomer following the README and docs/missions.md met (docwalk 18), each pinned.

* ``-q``/``-v`` after the command (``auvplan run X --out D -q``): the README's "``-q`` or ``--json`` silence
  them" was refused (``unrecognized arguments: -q``, exit 2) unless written before the command.
* ``auvplan scenarios | head -1``: the reader going away was reported as ``auvplan: error: BrokenPipeError``,
  exit 2 (bad input); now silent, 141 (128 + SIGPIPE, as 130 is 128 + SIGINT).
* A ``.plan`` edited by hand (one item's ``frame``, a ``null`` coordinate): the line wrapped the item's own message
  in ``missing or malformed key (QGC plan: …)``, printed ``frame = "3"`` as ``frame = 3: expected 3``, and a null
  altitude as a bare ``float() argument must be …`` naming no item (main's ``_param`` names it now, audit 18).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from auvplan.cli.parser import _parser
from auvplan.errors import DataError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.readback.readers import parse_qgc_plan


@pytest.mark.parametrize(("argv", "quiet", "verbose"), [
    (["run", "s.toml", "--out", "d", "-q"], True, False),   # after the command (refused before)
    (["-q", "run", "s.toml", "--out", "d"], True, False),   # before it: not reset by the command's parser
    (["run", "s.toml", "--out", "d"], False, False),
    (["mission", "check", "m.csv", "--scenario", "s", "--verbose"], False, True),
    (["-v", "scenario", "new", "x.toml"], False, True),
])
def test_quiet_and_verbose_are_read_on_either_side_of_the_command(argv: list[str], quiet: bool,
                                                                  verbose: bool) -> None:
    args = _parser().parse_args(argv)
    assert (args.quiet, args.verbose) == (quiet, verbose)


def test_a_reader_gone_away_is_no_error() -> None:
    read, write = os.pipe()
    os.close(read)  # `| head -0`: the pipe is closed before the first line (before the command starts: no race)
    try:
        p = subprocess.Popen([sys.executable, "-m", "auvplan", "scenarios"], stdout=write, stderr=subprocess.PIPE)
    finally:
        os.close(write)
    assert p.stderr is not None
    err = p.stderr.read().decode()
    assert p.wait(timeout=60) == 141
    assert err == ""  # was "auvplan: error: BrokenPipeError: [Errno 32] Broken pipe", exit 2


def _plan(**change: object) -> dict[str, object]:
    """A two-waypoint ``.plan`` (a leading 178, as the export writes) with item 1's keys changed."""
    items: list[dict[str, object]] = [
        {"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, 1.5, -1, 0, 0, 0, 0]},
        {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, None, 48.001, -125.0, -20.0]},
        {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, None, 48.002, -125.0, -30.0]},
    ]
    items[1].update(change)
    return {"mission": {"items": items, "plannedHomePosition": [48.001, -125.0, 0]}}


FRAME = LocalFrame(48.0, -125.0)


def test_a_hand_edited_plan_reads_back_and_its_refusals_name_the_item_once() -> None:
    w = parse_qgc_plan(_plan(), FRAME)  # the oracle of the reading: 3 points, the home on the surface
    assert w.shape == (3, 3) and w[0, 2] == 0.0 and list(w[1:, 2]) == [-20.0, -30.0]
    with pytest.raises(DataError) as exc:
        parse_qgc_plan(_plan(frame=0), FRAME)  # MAV_FRAME_GLOBAL: altitudes above mean sea level
    assert str(exc.value) == ("QGC plan: mission.items[1].frame = 0: expected 3 (relative alt), or 10 (terrain alt) "
                              "with a seabed")  # was wrapped in "missing or malformed key (QGC plan: …)"
    with pytest.raises(DataError, match=r"mission\.items\[1\]\.frame = '3': expected 3 "):
        parse_qgc_plan(_plan(frame="3"), FRAME)  # a string: read "frame = 3: expected 3"
    with pytest.raises(DataError) as exc:
        parse_qgc_plan(_plan(params=[0, 0, 0, None, 48.001, -125.0, None]), FRAME)
    assert str(exc.value) == "QGC plan: mission.items[1].params[6] = null: expected a number (altitude)"
    doc = _plan()
    doc["mission"]["plannedHomePosition"] = [None, -125.0, 0]  # type: ignore[index]
    with pytest.raises(DataError, match=r"^QGC plan: mission\.plannedHomePosition = \[None, -125\.0, 0\]: "):
        parse_qgc_plan(json.loads(json.dumps(doc)), FRAME)


def test_validate_prints_the_derived_start_and_goal_to_the_centimetre(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """README's "Your own area": positions in degrees were printed as [-5375.523770336695, -13277.39385155641, …]."""
    from auvplan.cli import main

    scen = tmp_path / "geo.toml"
    scen.write_text('name = "geo"\n[origin]\nlat = 48.0\nlon = -125.0\n[bounds]\nx = [-3000.0, 3000.0]\n'
                    'y = [-3000.0, 3000.0]\nz = [-300.0, 0.0]\n[terrain.synthetic]\nkind = "plane"\ndepth = 100.0\n'
                    'cell_m = 100.0\n[mission]\nstart = { lat = 47.99, lon = -125.01, depth = 20.0 }\n'
                    'goal = { lat = 48.01, lon = -124.99, depth = 30.0 }\n')
    assert main(["validate", str(scen)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("  start "))
    (sx, sy), (gx, gy) = (FRAME.forward([lon], [lat]) for lat, lon in ((47.99, -125.01), (48.01, -124.99)))
    want = f"  start [{sx[0]:.2f}, {sy[0]:.2f}, -20.00] goal [{gx[0]:.2f}, {gy[0]:.2f}, -30.00] m; "  # pyproj's
    assert line.startswith(want), line


def test_the_template_s_zone_example_uncommented_is_a_zone(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """README: ``scenario new`` writes "every key"; it had no [[zones]] (nor a word on [survey], [navigation] …)."""
    from auvplan.cli import main
    from auvplan.io.scenario.schema import template

    text = template("t")
    start = text.index("# [[zones]]")
    block = text[start:text.index("\n\n", start)]
    assert "[survey]" in text and "[navigation]" in text and "[land]" in text  # named, with their docs
    path = tmp_path / "t.toml"
    path.write_text(text.replace(block, "\n".join(line[2:] for line in block.splitlines())))
    assert main(["validate", str(path)]) == 0
    assert "1 charted zone kept out of: 'wreck' (20 m above the seabed)" in capsys.readouterr().out


def test_one_violation_is_one(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """docs/missions.md's 4 mm leg (`leg 1: 0.004 m long < the shortest leg 0.1 m`) printed "1 violations"."""
    from auvplan.cli import main

    scen = tmp_path / "s.toml"
    scen.write_text('name = "s"\n[bounds]\nx = [0.0, 2000.0]\ny = [0.0, 2000.0]\nz = [-300.0, 0.0]\n'
                    '[terrain.synthetic]\nkind = "plane"\ndepth = 100.0\ncell_m = 100.0\n'
                    '[mission]\nstart = [100.0, 1000.0, -40.0]\ngoal = [1900.0, 1000.0, -40.0]\n')
    csv = tmp_path / "short.csv"
    csv.write_text("x,y,z\n100,1000,-40\n500,1000,-40\n500.004,1000,-40\n1900,1000,-40\n")
    assert main(["mission", "check", str(csv), "--scenario", str(scen)]) == 1
    line = next(x for x in capsys.readouterr().out.splitlines() if " vehicle: " in x)
    assert line.endswith("; 1 violation: leg 1: 0.004 m long < the shortest leg 0.1 m"), line


def test_a_results_folder_given_as_the_scenario_names_its_saved_scenario(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """README: `mission check DIR/mission.* --scenario DIR/scenario.toml`; `--scenario DIR` said "no such scenario
    file, and not a built-in scenario (35 names)"."""
    from auvplan.errors import ScenarioError
    from auvplan.io.scenario.builtins import resolve

    (tmp_path / "scenario.toml").write_text('name = "s"\n')
    with pytest.raises(ScenarioError, match=r"a folder, not a scenario file; the scenario its run saved is .*/"
                                            r"scenario\.toml$"):
        resolve(tmp_path)
    assert resolve(tmp_path / "scenario.toml") == tmp_path / "scenario.toml"


def test_a_refused_point_from_degrees_is_printed_to_the_centimetre(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """README's degrees example with a REMUS 100 (rated 100 m): `start = [-5375.523770336695, …]: not a free point`."""
    from auvplan.cli import main

    scen = tmp_path / "geo.toml"
    scen.write_text('name = "geo"\n[origin]\nlat = 48.0\nlon = -125.0\n[bounds]\nx = [-3000.0, 3000.0]\n'
                    'y = [-3000.0, 3000.0]\nz = [-300.0, 0.0]\n[terrain.synthetic]\nkind = "plane"\ndepth = 250.0\n'
                    'cell_m = 100.0\n[vehicle]\nmax_depth_m = 100.0\n[mission]\n'
                    'start = { lat = 47.99, lon = -125.01, depth = 200.0 }\ngoal = { lat = 48.01, lon = -124.99, '
                    'depth = 30.0 }\n')
    assert main(["validate", str(scen)]) == 2
    (sx, sy), = [FRAME.forward([-125.01], [47.99])]
    err = capsys.readouterr().err
    assert f"[mission] start = [{sx[0]:.2f}, {sy[0]:.2f}, -200.00] m: not a free point: deeper than" in err, err
