"""Round 9's survivors of the waits a mission file carries (docs/mutants.md section 9): the MOOS read-back of a
``BHV_StationKeep`` (a file without its ``// start:`` line, a station keep of the operator's own, a wait at the start,
its ``duration`` at the edges), the export's rounding at ArduPilot's 16-bit limit and the pause of the waypoint and
depth behaviours while a wait runs.

Oracle: the MOOS-IvP semantics ``to_moos`` writes (``WPT_INDEX = j``: heading on from the file's point j after
waiting there; the waypoint and depth behaviours run only while ``DWELL = false``, the surface held while it is
true) and ArduPilot's 16-bit hold (65 535 s), by hand.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from auvplan.errors import DataError
from auvplan.io.missions import formats
from auvplan.io.missions.readback.dwell import moos_dwells
from auvplan.io.missions.readback.parsers import _moos_blocks, parse_moos

POINTS = np.array([[0.0, 0.0, -20.0], [400.0, 0.0, -20.0], [800.0, 0.0, 0.0], [1200.0, 0.0, -20.0],
                   [1600.0, 0.0, -20.0]])


def _station(j: int, duration: str, extra: str = "") -> str:
    return (f"\nBehavior = BHV_StationKeep\n{{\n  name = mine_{j}\n  condition = DEPLOY = true\n{extra}"
            f"  condition = WPT_INDEX = {j}\n  duration = {duration}\n}}\n")


def test_waits_read_back_where_written_with_and_without_the_start_line():
    dwell = np.array([30.0, 0.0, 120.0, 0.0, 0.0])  # at the start (before the first leg) and at the surfacing
    text = formats.to_moos(POINTS, 1.5, dwell=dwell)
    np.testing.assert_array_equal(moos_dwells(text, len(POINTS)), dwell)
    # without its '// start:' line the file's points are the waypoints after the start: WPT_INDEX = j waits at
    # the file's point j - 1, and a wait at the start names a point the file does not hold
    bare = re.sub(r"//[^\n]*start:[^\n]*\n", "", text)
    assert len(parse_moos(bare)) == len(POINTS) - 1
    with pytest.raises(DataError, match="WPT_INDEX = 0: no such waypoint"):
        moos_dwells(bare, len(POINTS) - 1)
    bare = re.sub(r"Behavior = BHV_StationKeep\n\{\n  name                = auvplan_dwell_0\n[^}]*\}\n", "", bare)
    np.testing.assert_array_equal(moos_dwells(bare, len(POINTS) - 1), dwell[1:])


def test_a_station_keep_of_the_operators_own_is_skipped_and_the_waits_after_it_read():
    text = formats.to_moos(POINTS, 1.5, dwell=[0.0, 0.0, 120.0, 0.0, 0.0])
    head, tail = text.split("Behavior = BHV_StationKeep", 1)
    own = "\nBehavior = BHV_StationKeep\n{\n  name = loiter_on_return\n  condition = RETURN = true\n}\n"
    np.testing.assert_array_equal(moos_dwells(head + own + "Behavior = BHV_StationKeep" + tail, 5), [0, 0, 120, 0, 0])


@pytest.mark.parametrize(("duration", "wait"), [("0", 0.0), ("0.5", 0.5), ("1e3", 1000.0)])
def test_a_duration_of_zero_or_above_is_the_wait(duration, wait):
    text = formats.to_moos(POINTS, 1.5) + _station(2, duration)
    np.testing.assert_array_equal(moos_dwells(text, 5), [0.0, 0.0, wait, 0.0, 0.0])


@pytest.mark.parametrize("duration", ["-5", "-0.5", "nan", "inf", "soon"])
def test_a_duration_that_is_not_seconds_is_refused_naming_it(duration):
    with pytest.raises(DataError, match=rf"mine_2: duration = '{duration}': expected seconds"):
        moos_dwells(formats.to_moos(POINTS, 1.5) + _station(2, duration), 5)


@pytest.mark.parametrize("j", [5, 6])
def test_a_wait_past_the_last_waypoint_is_refused_naming_it(j):
    with pytest.raises(DataError, match=rf"WPT_INDEX = {j}: no such waypoint \(5 in the file\)"):
        moos_dwells(formats.to_moos(POINTS, 1.5) + _station(j, "10"), 5)


def test_the_waypoint_and_depth_behaviours_pause_while_a_wait_runs():
    """Every behaviour that steers (the waypoints, each leg's depth) runs only while DWELL = false; the station keep
    raises DWELL while it runs, and a depth behaviour holds the surface meanwhile.  Without a wait nothing is paused."""
    for dwell in ([0.0, 0.0, 120.0, 0.0, 0.0], [10.0, 0.0, 0.0, 0.0, 0.0]):
        blocks = _moos_blocks(formats.to_moos(POINTS, [1.0, 1.2, 1.5, 1.1], dwell=dwell))
        steer = [p for k, p in blocks if k == "BHV_Waypoint" or (k == "BHV_ConstantDepth"
                                                                  and ("condition", "DWELL = true") not in p)]
        assert len(steer) == 1 + 4 and all(("condition", "DWELL = false") in p for p in steer)
        keep = [dict(p) for k, p in blocks if k == "BHV_StationKeep"]
        assert [(d["runflag"], d["endflag"]) for d in keep] == [("DWELL = true", "DWELL = false")]
        surface = [dict(p) for k, p in blocks if k == "BHV_ConstantDepth" and ("condition", "DWELL = true") in p]
        assert len(surface) == 1 and float(surface[0]["depth"]) == 0.0
    plain = formats.to_moos(POINTS, 1.5, dwell=np.zeros(5))
    assert "DWELL" not in plain and plain == formats.to_moos(POINTS, 1.5)


def test_the_export_holds_up_to_arduPilots_16_bits_and_names_the_first_wait_over():
    """65 535 s is the longest hold ArduPilot stores: written as is; 65 535.2 s rounds up past it and is refused, the
    message naming that waypoint even when an exact 65 535 comes before it."""
    doc = formats.to_qgc_plan(POINTS, (10.0, 20.0), 1.5, dwell=[0.0, 65535.0, 120.0000000001, 0.0, 0.0])
    holds = [it["params"][0] for it in doc["mission"]["items"] if it["command"] == 16]
    assert holds == [0, 65535, 120, 0, 0]
    with pytest.raises(DataError, match=r"waypoint 2 waits 65535\.2 s"):
        formats.to_qgc_plan(POINTS, (10.0, 20.0), 1.5, dwell=[0.0, 65535.0, 65535.2, 0.0, 0.0])


@pytest.mark.parametrize("dwell", [[0.0, math.nan, 0, 0, 0], [0.0, -1.0, 0, 0, 0], [0.0, 1.0, 0, 0],
                                   [0.0, math.inf, 0, 0, 0]])
def test_a_wait_that_is_not_seconds_is_refused(dwell):
    with pytest.raises(ValueError, match="dwell: one finite wait"):
        formats.to_moos(POINTS, 1.5, dwell=dwell)
