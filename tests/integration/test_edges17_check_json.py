"""``mission check --json`` said ``"min_altitude_leg": -1`` over a scenario without a seabed (and
``"tightest_turn_leg": -1`` for a straight mission): a leg number that is not there is ``null`` now, as the
figure beside it (``min_altitude_m``, ``tightest_turn_m``: ``null``); a leg that is there is still its number."""

from __future__ import annotations

import json

from auvplan import cli
from helpers import HOLDS, RIDGE

CSV = "x,y,z\n500,1000,-15\n1500,1000,-15\n2500,1000,-15\n"  # straight, 15 m deep, along HOLDS' mission
RIDGE_CSV = "x,y,z\n100,200,-80\n1000,260,-80\n1900,200,-80\n"  # over the ridge's crest (60 m deep) at 80 m


def _json(tmp_path, capsys, scenario: str, text: str) -> tuple[int, dict]:
    (tmp_path / "s.toml").write_text(scenario)
    (tmp_path / "m.csv").write_text(text)
    code = cli.main(["mission", "check", str(tmp_path / "m.csv"), "--scenario", str(tmp_path / "s.toml"), "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_no_seabed_no_turn_gives_null_legs(tmp_path, capsys):
    code, rec = _json(tmp_path, capsys, HOLDS, CSV)
    assert code == 0, rec
    assert rec["min_altitude_m"] is None and rec["min_altitude_leg"] is None
    assert rec["vehicle"]["tightest_turn_m"] is None and rec["vehicle"]["tightest_turn_leg"] is None
    assert rec["vehicle"]["max_pitch_leg"] == 0  # a leg that is there keeps its number


def test_with_a_seabed_and_a_turn_the_legs_are_numbers(tmp_path, capsys):
    """Oracle: the crest under x = 1000 is 60 m deep, the mission 80 m deep, so the least altitude (-20 m) is on a leg
    touching x = 1000 (leg 0 ends there, leg 1 starts there); the only turn is at waypoint 1, so on leg 0 or 1."""
    code, rec = _json(tmp_path, capsys, RIDGE, RIDGE_CSV)
    assert code == 1
    assert rec["min_altitude_leg"] in (0, 1) and rec["min_altitude_m"] < 0
    assert rec["vehicle"]["tightest_turn_leg"] in (0, 1) and rec["vehicle"]["tightest_turn_m"] > 0
