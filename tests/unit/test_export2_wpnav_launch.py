"""A ``.plan``'s vertical legs are judged at AC_WPNav's default vertical speed with or without a speed command in
force (helper export2, wave 17; ``docs/missions.md`` "A ``.plan`` as ArduSub flies it").

ArduSub's ``Sub::do_change_speed`` sets the horizontal speed only (``wp_nav.set_speed_xy``) and ``kinematic_limit``
flies a vertical leg at the vertical limit, ``WPNAV_SPEED_DN`` 1.5 m/s down (``WPNAV_SPEED_UP`` 2.5 up), a parameter
no speed command changes.  ``mission check`` judged the launch (home to the first item) at 1.5 m/s after a speed
command but at the scenario vehicle's speed without one (2.4 m/s below: the 300 m dive 125 s instead of 200 s).

Oracle: the same mission with and without a leading speed command: the vertical legs' speeds 1.5 down and 2.5 up
in both, their times ``|Δz| / v_z``; the legs with a horizontal run at the command's speed (level, audit 20) or,
without one, at the vehicle's (named), as before.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.io.missions.formats import read_mission, to_qgc_plan
from auvplan.io.missions.readback.speeds import WPNAV_SPEED_DN_MPS, WPNAV_SPEED_UP_MPS, judged_leg_speeds

ORIGIN = (-20.0, 150.0)
VEHICLE = 2.4  # the scenario vehicle's speed: not the vertical limit
# a dive of 300 m from the home (the launch), a level leg, a vertical climb of 100 m, a level leg
POINTS = np.array([[0.0, 0.0, -300.0], [2000.0, 0.0, -300.0], [2000.0, 0.0, -200.0], [3000.0, 0.0, -200.0]])


def _judged(tmp_path, with_command: bool):
    doc = to_qgc_plan(POINTS, ORIGIN, 1.2)
    if not with_command:
        doc["mission"]["items"] = [it for it in doc["mission"]["items"] if it["command"] != 178]
    path = tmp_path / f"m{int(with_command)}.plan"
    path.write_text(json.dumps(doc))
    pts = read_mission(path, ORIGIN)[0]  # home first: the launch is leg 0
    assert pts.shape[0] == POINTS.shape[0] + 1
    return judged_leg_speeds(path, pts.shape[0] - 1, VEHICLE, pts), pts


@pytest.mark.parametrize("with_command", [True, False])
def test_vertical_legs_fly_at_the_vertical_limit_with_or_without_a_speed_command(tmp_path, with_command):
    judged, pts = _judged(tmp_path, with_command)
    v = judged.speeds
    assert v[0] == pytest.approx(WPNAV_SPEED_DN_MPS) and WPNAV_SPEED_DN_MPS == 1.5  # the launch: 300 m down
    assert v[2] == pytest.approx(WPNAV_SPEED_UP_MPS) and WPNAV_SPEED_UP_MPS == 2.5  # the vertical climb
    rise = np.abs(np.diff(pts[:, 2]))
    assert rise[0] / v[0] == pytest.approx(200.0, abs=0.01) and rise[2] / v[2] == pytest.approx(40.0, abs=0.01)
    level = [1, 3]
    if with_command:
        assert judged.assumed_legs == () and v[level] == pytest.approx(1.2, abs=1e-4)
    else:  # the legs with a horizontal run: ArduSub's WPNAV_SPEED, judged at the vehicle's speed and named
        assert judged.assumed_legs == (1, 3) and v[level] == pytest.approx(VEHICLE)
        assert judged.line.endswith(f"judged at {VEHICLE:g} m/s (legs 1, 3)"), judged.line
