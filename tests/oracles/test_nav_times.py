"""The planned time of each fix (``fixes.csv`` ``t_s``, the report's error against time) through the current
at the legs' own speeds (audit of issue 52).

Oracle, independent of the code: in a uniform steady current ``c`` a leg of length ``L`` and unit tangent ``e``
held at the through-water speed ``v`` is flown at the ground speed ``g = c·e + √(v² − |c|² + (c·e)²)``, so the
arrival at each waypoint is ``Σ L / g`` plus the dwells (``surface_s``) at the fixes before it.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from auvplan.io.scenario import loader
from auvplan.nav.band import profile_times
from auvplan.nav.budget import error_profile
from auvplan.sim.navigation import navigation_plan, timed_navigation

CURRENT = np.array([0.3, -0.2, 0.0])
SCENARIO = """name = "fix-times"
[bounds]
x = [0.0, 15000.0]
y = [0.0, 12000.0]
z = [-3000.0, 0.0]
[currents]
uniform = [0.3, -0.2, 0.0]
[mission]
start = [500.0, 500.0, -400.0]
goal = [12500.0, 10000.0, -400.0]
route = [[500.0, 500.0, -400.0], [7500.0, 1500.0, -400.0], [6000.0, 7000.0, -400.0], [12500.0, 10000.0, -400.0]]
min_depth_m = 0.0
[vehicle]
speed = 1.5
max_pitch_deg = 20.0
[navigation]
drift_pct_no_lock = 1.0
max_error_m = 100.0
confidence = 2.0
surface_s = 300.0
"""


def _arrivals(points: np.ndarray, speeds: np.ndarray, dwell: np.ndarray) -> np.ndarray:
    """The oracle (module notes)."""
    d = np.diff(points, axis=0)
    length = np.linalg.norm(d, axis=1)
    e = d / length[:, None]
    along = e @ CURRENT
    g = along + np.sqrt(speeds**2 - CURRENT @ CURRENT + along**2)
    return np.r_[0.0, np.cumsum(length / g + dwell[:-1])]


def test_fix_times_are_flown_through_the_current_at_the_legs_speeds():
    """The fixes' times at the cruise speed through the current, and again at per-leg speeds (0.8–2.0 m/s, as
    ``[endurance] speeds`` chooses them), equal the closed form to a microsecond per hour; the report's time
    axis passes through them.  Before: the cruise speed in still water, 449 s late at the first fix here (16 %) and
    hours off at other leg speeds."""
    world, mission = loader.build(loader.loads(SCENARIO, "fix-times.toml"))
    nav = navigation_plan(world, mission, np.array(mission.route))
    assert nav is not None and nav.ok, nav and nav.message
    fixes = [i for i, k in enumerate(nav.kinds) if k]
    assert len(fixes) >= 2
    legs = nav.points.shape[0] - 1
    cruise = _arrivals(nav.points, np.full(legs, 1.5), nav.dwell_s)
    np.testing.assert_allclose(nav.times_s, cruise[fixes], rtol=1e-9)
    speeds = 0.8 + 1.2 * (np.arange(legs) % 4) / 3.0
    timed = timed_navigation(world, replace(mission, leg_speeds=tuple(speeds)), nav)
    np.testing.assert_allclose(timed.times_s, _arrivals(nav.points, speeds, nav.dwell_s)[fixes], rtol=1e-9)
    prof = error_profile(world, timed.points, timed.kinds, mission.navigation)
    t = profile_times(prof, 1.5, timed.dwell_s[fixes], timed.points, timed.vertex_times_s)
    np.testing.assert_allclose(t[prof.fix], timed.times_s, rtol=1e-9)
    assert np.all(np.diff(t) >= 0.0)
