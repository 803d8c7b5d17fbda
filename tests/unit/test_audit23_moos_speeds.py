"""The speed of each leg of a MOOS-IvP file read as the helm flies it (audit 23).

``BHV_Waypoint`` takes parameter updates only from the variable its ``updates`` names, and an update sets the
parameter for good: MOOS-IvP's ``IvPBehavior::checkUpdates`` calls ``setParam`` with each ``param=value`` of the
posted string (ivp/src/lib_behaviors/IvPBehavior.cpp).  The export writes ``updates = WPT_UPDATE`` and a
``runflag = WPT_UPDATE = speed=v_i`` on every leg's depth behaviour, so every leg said its speed.  A file edited by
hand (a leg slowed in a constant-speed export, one leg's runflag removed) was read otherwise: a runflag the waypoint
behaviour never takes was read as that leg's speed, and a leg without one as the behaviour's first ``speed``, where
the helm keeps the last update.  ``mission check`` then judged time and energy at speeds the vehicle does not fly.

Oracle: those semantics by hand, leg by leg; the exporter's own files read back as written.
"""

from __future__ import annotations

import numpy as np

from auvplan.io.missions import formats
from auvplan.io.missions.readback.speeds import read_leg_speeds

POINTS = np.array([[0.0, 0.0, -10.0], [500.0, 0.0, -10.0], [1000.0, 0.0, -10.0], [1500.0, 0.0, -10.0],
                   [2000.0, 0.0, -10.0]])


def _depth_block(text: str, leg: int) -> tuple[int, int]:
    start = text.index(f"name      = auvplan_depth_{leg}")
    return start, text.index("}", start)


def test_an_exported_file_is_read_as_written(tmp_path):
    for speed in (1.5, [1.0, 2.0, 2.0, 1.2]):
        (tmp_path / "m.moos").write_text(formats.to_moos(POINTS, speed))
        np.testing.assert_array_equal(read_leg_speeds(tmp_path / "m.moos", 4), np.broadcast_to(speed, (4,)))


def test_an_update_the_waypoint_behaviour_does_not_take_changes_no_speed(tmp_path):
    """A constant-speed export (no ``updates`` line) with a runflag added to leg 1: the helm never reads it."""
    text = formats.to_moos(POINTS, 1.5)
    assert "updates" not in text
    a, b = _depth_block(text, 1)
    text = text[:b] + "  runflag   = WPT_UPDATE = speed=0.8\n" + text[b:]
    (tmp_path / "m.moos").write_text(text)
    np.testing.assert_array_equal(read_leg_speeds(tmp_path / "m.moos", 4), [1.5, 1.5, 1.5, 1.5])
    # with the waypoint behaviour taking the updates, leg 1 is slowed, and so is every leg after it
    text = text.replace("  points         =", "  updates        = WPT_UPDATE\n  points         =")
    (tmp_path / "m.moos").write_text(text)
    np.testing.assert_array_equal(read_leg_speeds(tmp_path / "m.moos", 4), [1.5, 0.8, 0.8, 0.8])


def test_a_leg_without_its_update_keeps_the_last_one(tmp_path):
    """Per-leg speeds 1.0, 2.0, 0.7, 1.2 with leg 2's runflag removed: leg 2 is flown at leg 1's 2.0 m/s."""
    text = formats.to_moos(POINTS, [1.0, 2.0, 0.7, 1.2])
    a, b = _depth_block(text, 2)
    line = "  runflag   = WPT_UPDATE = speed=0.7\n"
    assert text[a:b].count(line) == 1
    text = text[:a] + text[a:b].replace(line, "") + text[b:]
    (tmp_path / "m.moos").write_text(text)
    np.testing.assert_array_equal(read_leg_speeds(tmp_path / "m.moos", 4), [1.0, 2.0, 2.0, 1.2])


def test_a_waypoint_behaviour_without_a_speed_carries_none(tmp_path):
    """No ``speed`` in the waypoint behaviour: the file carries no speed (judged at the vehicle's), whatever its
    depth behaviours' updates say."""
    text = formats.to_moos(POINTS, [1.0, 2.0, 0.7, 1.2])
    text = "\n".join(line for line in text.splitlines() if not line.startswith("  speed "))
    (tmp_path / "m.moos").write_text(text)
    assert read_leg_speeds(tmp_path / "m.moos", 4) is None
