"""Audit 17: a leg speed carried by a mission file over 100 m/s is refused (hostile input round 4) — an infinite
one too.  ``Infinity`` in a ``.plan``'s ``MAV_CMD_DO_CHANGE_SPEED`` (Python's JSON reads it) or ``inf`` in a CSV
``speed`` column made every carried speed be dropped silently (the file 'carries none'), the check then flying the
vehicle's own speed on every leg, the finite ones the file gives included.  Oracle: the bound's own rule."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.errors import DataError
from auvplan.io.missions.readback.speeds import read_leg_speeds

_PLAN = ('{"mission": {"cruiseSpeed": 1.5, "plannedHomePosition": [0, 0, 0], "items": ['
         '{"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, null, 0.001, 0.001, -5]},'
         '{"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, SPEED, -1, 0, 0, 0, 0]},'
         '{"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, null, 0.002, 0.002, -5]}]}}')


@pytest.mark.parametrize(("name", "text"), [
    ("m.plan", _PLAN.replace("SPEED", "Infinity")),
    ("m.csv", "x,y,z,speed\n0,0,-5,1.5\n100,0,-5,2.0\n200,0,-5,inf\n"),
])
def test_an_infinite_leg_speed_is_refused_naming_the_leg(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(DataError, match=r"speed inf m/s \(carried by the file\) is over 100 m/s"):
        read_leg_speeds(path, 2)


@pytest.mark.parametrize(("speed", "want"), [("2.5", [np.nan, 2.5]), ("-1", None), ("NaN", None)])
def test_a_plan_s_finite_or_unchanged_speed_reads_as_before(tmp_path, speed, want):
    """The leg before the speed command is not in the file (NaN; cruiseSpeed 1.5 is never uploaded to the vehicle);
    an unchanged speed (-1, NaN) leaves every leg so: the file carries none (None)."""
    path = tmp_path / "m.plan"
    path.write_text(_PLAN.replace("SPEED", speed))
    got = read_leg_speeds(path, 2)
    assert got is None if want is None else np.array_equal(got, want, equal_nan=True)
