"""fix20: the launch leg of a ``.plan`` whose home is not above its first item.  ArduSub flies the launch as a
straight line from the vehicle (at home, on the surface) to the item's position and depth (``AC_WPNav::
set_wp_destination`` from the stopping point, ``calculate_straight_leg``): from a home 400 m away the vehicle runs
shallower than ``min_depth_m`` for 400 × 5 / 15 = 133 m.  ``mission check`` exempted the home from the depth band
whatever its position (a home above the item: a vertical descent, no horizontal run).

Oracle: the judgement by hand — home above the item (0 m, and 2 cm: MAVLink's rounding) passes, 0.1 m and 400 m
away fail naming waypoint 0 and the run; without a band (``min_depth_m = 0``) the 400 m home passes."""

from __future__ import annotations

import json

import pytest

from auvplan.cli import main
from auvplan.io.data.geo import LocalFrame
from helpers import HOLDS


def _files(tmp_path, home_x: float, min_depth: float):
    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS.replace('goal = [2500.0, 1000.0, -15.0]\n',
                                  f'goal = [2500.0, 1000.0, -15.0]\nmin_depth_m = {min_depth}\n'))
    frame = LocalFrame(-7.0, 70.8)
    items = []
    for x in (500.0, 1500.0, 2500.0):
        lon, lat = frame.inverse(x, 1000.0)
        items.append({"type": "SimpleItem", "command": 16, "frame": 3,
                      "params": [0, 0, 0, None, float(lat), float(lon), -15.0]})
    lon, lat = frame.inverse(home_x, 1000.0)
    plan = tmp_path / "m.plan"
    plan.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": items}}))
    return str(plan), str(scen)


@pytest.mark.parametrize(("home_x", "min_depth", "code"), [
    (500.0, 5.0, 0), (500.02, 5.0, 0), (500.1, 5.0, 1), (100.0, 5.0, 1), (100.0, 0.0, 0)])
def test_the_launch_point_is_exempt_from_the_depth_band_only_above_the_first_item(tmp_path, capsys, home_x,
                                                                                   min_depth, code):
    plan, scen = _files(tmp_path, home_x, min_depth)
    assert main(["mission", "check", plan, "--scenario", scen]) == code
    out = capsys.readouterr().out
    if code:
        run = f"{abs(500.0 - home_x):.1f}"
        assert ("1 waypoint outside the depth band (waypoint 0 at depth 0.00 m, shallower than min_depth_m = 5; "
                f"the launch point is {run} m from above waypoint 1: ArduSub dives the straight launch leg)") in out
