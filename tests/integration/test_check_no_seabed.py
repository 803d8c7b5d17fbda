"""``mission check`` of a mission over a scenario with no seabed said "least altitude inf m (leg -1)": it now says
plainly that no seabed was checked, and what was (the sea surface, the depth band, the bounds); with a seabed the
least altitude is printed as before."""

from __future__ import annotations

import pytest

from auvplan import cli
from helpers import HOLDS, RIDGE

CSV = "x,y,z\n500,1000,-15\n1500,1000,-15\n2500,1000,-15\n"  # along the HOLDS mission, 15 m deep
MOOS = """// start: 500.000, 1000.000, 15.000
Behavior = BHV_Waypoint
{
  speed  = 1.5
  points = 2500.000,1000.000
}
Behavior = BHV_ConstantDepth
{
  condition = WPT_INDEX = 0
  depth     = 15.000
}
"""  # the same mission for a depth-holding executor (MOOS-IvP), flown at --pitch
RIDGE_CSV = "x,y,z\n100,200,-80\n1900,200,-80\n"  # across the ridge (40 m high on a 100 m deep seabed) at 80 m


def _check(tmp_path, capsys, scenario: str, text: str, name: str = "m.csv") -> tuple[int, str]:
    (tmp_path / "s.toml").write_text(scenario)
    (tmp_path / name).write_text(text)
    code = cli.main(["mission", "check", str(tmp_path / name), "--scenario", str(tmp_path / "s.toml")])
    return code, capsys.readouterr().out


@pytest.mark.parametrize(("name", "text"), [("m.csv", CSV), ("m.moos", MOOS)])
def test_no_seabed_is_said_plainly_not_as_an_infinite_altitude(tmp_path, capsys, name, text):
    code, out = _check(tmp_path, capsys, HOLDS, text, name)
    line = out.splitlines()[0]
    assert code == 0, out
    assert "inf" not in line and "leg -1" not in line, line
    assert "no seabed in the scenario: altitude not checked (the sea surface, depth band and bounds were)" in line


def test_no_seabed_still_checks_the_depth_band(tmp_path, capsys):
    """What the line says was checked is checked: a waypoint below [mission] max_depth_m fails."""
    code, out = _check(tmp_path, capsys, HOLDS.replace('goal = [', 'max_depth_m = 50.0\ngoal = ['),
                       CSV.replace("1500,1000,-15", "1500,1000,-60"))
    assert code == 1 and "FAIL" in out.splitlines()[0] and "no seabed in the scenario" in out, out


def test_with_a_seabed_the_least_altitude_is_printed(tmp_path, capsys):
    """Oracle: the ridge's crest is 100 - 40 = 60 m deep, the mission 80 m deep: least altitude -20 m, on leg 0."""
    code, out = _check(tmp_path, capsys, RIDGE, RIDGE_CSV)
    line = out.splitlines()[0]
    assert code == 1 and "least altitude -20.00 m (required 10 m, leg 0)" in line, line
    assert "no seabed" not in line
