"""A ``.plan``'s ``MAV_CMD_DO_CHANGE_SPEED`` (178) with a null speed (QGroundControl writes a NaN parameter as null)
was refused, 'speed None is not a number'.  ArduSub changes its speed only for a speed above 0
(``Sub::do_change_speed``, ArduSub/commands_logic.cpp: ``if (cmd.content.speed.target_ms > 0)``; ``AP_Mission``
copies param 2 unchecked): NaN > 0 is false, so a null speed changes nothing, as -1 and 0 do.

Oracle: the legs' speeds a .plan carries by hand: 1.5 m/s from the first command, unchanged by the null one."""

from __future__ import annotations

import json
import math

import pytest

from auvplan import cli
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.readback.speeds import read_leg_speeds
from helpers import HOLDS

_FRAME = LocalFrame(-7.0, 70.8)  # the HOLDS scene's origin


def _wp(x: float) -> dict:
    lon, lat = _FRAME.inverse(x, 1000.0)
    return {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, None, float(lat), float(lon), -15.0]}


def _speed(v) -> dict:
    return {"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, v, -1, 0, 0, 0, 0]}


def _plan(tmp_path, second) -> str:
    lon, lat = _FRAME.inverse(500.0, 1000.0)
    items = [_speed(1.5), _wp(1000.0), _speed(second), _wp(2000.0), _wp(2500.0)]
    path = tmp_path / "m.plan"
    path.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    return str(path)


@pytest.mark.parametrize("second", [None, -1, 0])
def test_a_null_speed_changes_nothing_as_minus_one_and_zero(tmp_path, second):
    assert read_leg_speeds(_plan(tmp_path, second), 3).tolist() == [1.5, 1.5, 1.5]


def test_a_speed_above_zero_changes_the_legs_after_it(tmp_path):
    assert read_leg_speeds(_plan(tmp_path, 0.75), 3).tolist() == [1.5, 0.75, 0.75]


def test_mission_check_of_a_null_speed_exits_0(tmp_path, capsys):
    (tmp_path / "s.toml").write_text(HOLDS)
    code = cli.main(["mission", "check", _plan(tmp_path, None), "--scenario", str(tmp_path / "s.toml"), "--json"])
    out = capsys.readouterr()
    assert code == 0, out.err
    rec = json.loads(out.out)
    assert rec["energy"]["leg_speeds_mps"] == pytest.approx([1.5, 1.5, 1.5], rel=1e-3)  # the file's, not assumed
    assert not rec["speed_assumed_legs"] and math.isfinite(rec["energy"]["energy_wh"])
