"""Round 9's survivors of ``readback/speeds.py`` (docs/mutants.md section 9): a ``.plan``'s legs as WPNav flies them,
on the legs the suite never had — under a metre long (a waypoint a MAVLink quantum beside a plumb dive, a short
steep climb), plumb, and a leg asking exactly AC_WPNav's default vertical speed.

Oracle: ArduPilot's ``kinematic_limit`` transcribed line for line (``tests/unit/test_audit22.py``), with AC_WPNav's
default vertical limits; the along-track factor ``|d| / |d_xy|`` by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_audit22 import kinematic_limit

from auvplan.io.missions.readback import speeds
from auvplan.io.missions.readback.speeds import (
    WPNAV_SPEED_DN_MPS,
    WPNAV_SPEED_UP_MPS,
    along_track_factor,
    flown_speeds,
    vertical_bound_legs,
)

# legs: short and steep (0.5 m across, 0.5 m down), plumb down 90 m, plumb up 0.8 m, none (a duplicate), short and
# steep up (0.3 m across, 0.9 m up), level 100 m, 20° down over 200 m
STEPS = np.array([[0.3, 0.4, -0.5], [0.0, 0.0, -90.0], [0.0, 0.0, 0.8], [0.0, 0.0, 0.0], [0.3, 0.0, 0.9],
                  [100.0, 0.0, 0.0], [200.0, 0.0, -200.0 * math.tan(math.radians(20.0))]])
POINTS = np.vstack([[0.0, 0.0, -100.0], -100.0 * np.array([0, 0, 1.0]) + np.cumsum(STEPS, axis=0)])


def test_the_along_track_factor_of_short_plumb_and_empty_legs():
    want = [math.sqrt(2.0), 1.0, 1.0, 1.0, math.hypot(0.3, 0.9) / 0.3, 1.0, 1.0 / math.cos(math.radians(20.0))]
    np.testing.assert_allclose(along_track_factor(POINTS), want, rtol=1e-12)


@pytest.mark.parametrize("v", [0.6, 1.0, 2.0])
def test_flown_speeds_are_kinematic_limit_on_every_leg(v):
    got = flown_speeds(np.full(len(STEPS), v), POINTS)
    for k, d in enumerate(STEPS):
        if not d.any():  # no leg: no direction; flown 'at' the command (it takes no time at any speed)
            assert got[k] == v
            continue
        assert got[k] == pytest.approx(kinematic_limit(d, v, WPNAV_SPEED_UP_MPS, WPNAV_SPEED_DN_MPS), rel=1e-12), k


def test_the_legs_bound_by_the_vertical_default_are_those_kinematic_limit_slows():
    """A leg is named when the command would ask more than the default vertically (1 mm/s slack): the short steep
    climb (3 v up) at every speed, the short 45° dive (v down) above 1.5 m/s; the 20° dive at 5 m/s (1.82 m/s down)
    but not at 4.12 m/s (1.4996 m/s down)."""
    for v in (1.0, 4.12, 5.0):
        want = tuple(k for k, d in enumerate(STEPS) if np.hypot(*d[:2]) > 0 and d[2] != 0
                     and kinematic_limit(d, v, WPNAV_SPEED_UP_MPS, WPNAV_SPEED_DN_MPS) * np.hypot(*d[:2])
                     / np.linalg.norm(d) < v - 1e-9 and abs(v * d[2] / np.hypot(*d[:2]))
                     > (WPNAV_SPEED_UP_MPS if d[2] > 0 else WPNAV_SPEED_DN_MPS) + 1e-3)
        assert vertical_bound_legs(np.full(len(STEPS), v), POINTS) == want, v
    assert vertical_bound_legs(np.full(len(STEPS), 1.0), POINTS) == (4,)
    assert vertical_bound_legs(np.full(len(STEPS), 4.12), POINTS) == (0, 4)
    assert vertical_bound_legs(np.full(len(STEPS), 5.0), POINTS) == (0, 4, 6)
    # a leg asking exactly the default (45° down at 1.5 m/s horizontal: 1.5 m/s down) is flown as commanded
    square = np.array([[0.0, 0.0, -10.0], [100.0, 0.0, -110.0]])
    assert vertical_bound_legs(np.array([WPNAV_SPEED_DN_MPS]), square) == ()
    assert flown_speeds(np.array([WPNAV_SPEED_DN_MPS]), square)[0] == pytest.approx(WPNAV_SPEED_DN_MPS * math.sqrt(2))


def test_a_moos_file_with_a_depth_behaviour_past_its_legs_carries_no_speeds():
    text = ("Behavior = BHV_Waypoint\n{\n  speed = 1.5\n  updates = WPT_UPDATE\n  points = 10,0:20,0\n}\n"
            + "".join(f"Behavior = BHV_ConstantDepth\n{{\n  condition = WPT_INDEX = {i}\n  depth = 10\n"
                      f"  runflag = WPT_UPDATE = speed={1 + i}\n}}\n" for i in range(3)))
    assert speeds._moos(text, 3) == [1.0, 2.0, 3.0]
    assert speeds._moos(text, 2) is None  # WPT_INDEX = 2 of a file read as two legs: not this mission
