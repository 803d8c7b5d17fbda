"""The ``.csv`` time column and the ``mission.yaml`` stamps are the mission's times as flown through the current, the
navigation plan's (``fixes.csv``'s), not still-water times (helper export2, wave 17).

The exporters timed each leg at the planned speed through still water while the navigation plan (and ``fixes.csv``)
times the mission through the World's current (:func:`auvplan.sim.navigation.timed_navigation`): across 0.6 m/s
east and 0.3 m/s north at 1.5 m/s, the 18 km mission below arrived at 12 240 s in the ``.csv`` (still water, two
120 s waits) and at 8 961 s in the plan, its fixes 1 000 s apart between the files.

Oracle: the closed form of a leg flown along its own line through a uniform current: the ground speed along the
unit direction ``u`` at through-water speed ``V`` in the current ``c`` is ``u·c + sqrt((u·c)² − |c|² + V²)``; the
arrivals add each leg's length over it and the waits at the fixes.
"""

from __future__ import annotations

import csv

import numpy as np
import yaml

from auvplan.io.missions import export
from auvplan.io.scenario import loader
from auvplan.sim.navigation import navigation_plan
from auvplan.sim.result import RunRecord

CURRENT = np.array([0.6, 0.3, 0.0])
SPEED = 1.5
SCENARIO = f"""name = "fixes-in-a-current"
[origin]
lat = 10.0
lon = 20.0
[bounds]
x = [-1000.0, 20000.0]
y = [-1000.0, 1000.0]
z = [-500.0, 0.0]
[currents]
uniform = [{CURRENT[0]}, {CURRENT[1]}, 0.0]
[mission]
start = [0.0, 0.0, -50.0]
goal = [18000.0, 0.0, -50.0]
route = [[0.0, 0.0, -50.0], [18000.0, 0.0, -50.0]]
min_depth_m = 0.0
[vehicle]
speed = {SPEED}
max_pitch_deg = 20.0
[navigation]
drift_pct_no_lock = 1.0
max_error_m = 100.0
confidence = 2.0
fixes = "plan"
surface_s = 120.0
"""


def test_the_csv_and_yaml_times_are_the_flight_through_the_current(tmp_path):
    (tmp_path / "s.toml").write_text(SCENARIO)
    world, mission = loader.build(loader.load(tmp_path / "s.toml"))
    nav = navigation_plan(world, mission, np.array([[0.0, 0.0, -50.0], [18000.0, 0.0, -50.0]]))
    assert nav is not None and nav.ok and nav.kinds.count("gps") >= 1
    record = RunRecord("fixes-in-a-current", 1, None, nav.points, np.empty((0, 3)), None, nav=nav)
    export.write_exports(tmp_path, record, world.origin, SPEED, ("csv", "yaml"))
    rows = list(csv.DictReader((tmp_path / "mission.csv").open()))
    t = np.array([float(r["time"]) for r in rows])
    poses = yaml.safe_load((tmp_path / "mission.yaml").read_text())["poses"]
    stamps = np.array([p["header"]["stamp"]["sec"] + 1e-9 * p["header"]["stamp"]["nanosec"] for p in poses])
    # the closed form, leg by leg
    d = np.diff(nav.points, axis=0)
    length = np.linalg.norm(d, axis=1)
    uc = (d / length[:, None]) @ CURRENT
    ground = uc + np.sqrt(uc**2 - CURRENT @ CURRENT + SPEED**2)
    flown = np.r_[0.0, np.cumsum(length / ground + nav.dwell_s[:-1])]
    np.testing.assert_allclose(t, flown, atol=0.006)  # the file's 2 decimals
    np.testing.assert_allclose(stamps, flown, atol=1e-6)
    # the files agree with the plan's own times (fixes.csv's)
    fixes = [i for i, k in enumerate(nav.kinds) if k]
    np.testing.assert_allclose(t[fixes], nav.times_s, atol=0.006)
    still = length.sum() / SPEED + nav.dwell_s.sum()
    assert flown[-1] < still - 2000.0  # a current that matters: the still-water times are far off
