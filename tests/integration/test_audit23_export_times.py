"""The planned times a ``mission.csv`` and a ``mission.yaml`` carry count the waits at the surface fixes (audit 23).

The ``.plan`` holds each surface fix's ``surface_s`` and the ``.moos`` keeps station there (nav22), but the CSV's
``time`` column (planned arrival) and the ROS ``nav_msgs/Path`` stamps were the legs' times alone: every waypoint
after a fix was planned ``surface_s`` too early per fix before it (``mariana-nav``: the last waypoint 720 s early,
six fixes of 120 s; the fixes' own times in ``fixes.csv`` include them).

Oracle: the navigation plan's own times on a still-water mission with planned fixes: each waypoint's arrival as the
plan is timed (``NavPlan.vertex_times_s``, flown by the energy budget's traverse with the waits,
:func:`auvplan.sim.navigation.timed_navigation`) and each fix's (``NavPlan.times_s``); the legs' lengths over the
speed by hand between them.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest
import yaml

from auvplan.io.missions import export
from auvplan.io.scenario import loader
from auvplan.sim.navigation import navigation_plan
from auvplan.sim.result import RunRecord

SCENARIO = """name = "still-fixes"
[origin]
lat = 10.0
lon = 20.0
[bounds]
x = [-1000.0, 20000.0]
y = [-1000.0, 1000.0]
z = [-500.0, 0.0]
[mission]
start = [0.0, 0.0, -50.0]
goal = [18000.0, 0.0, -50.0]
route = [[0.0, 0.0, -50.0], [18000.0, 0.0, -50.0]]
min_depth_m = 0.0
[vehicle]
speed = 1.5
max_pitch_deg = 20.0
[navigation]
drift_pct_no_lock = 1.0
max_error_m = 100.0
confidence = 2.0
fixes = "plan"
surface_s = 120.0
"""


def test_the_csv_and_yaml_times_count_the_waits_at_the_fixes(tmp_path):
    (tmp_path / "s.toml").write_text(SCENARIO)
    world, mission = loader.build(loader.load(tmp_path / "s.toml"))
    route = np.array([[0.0, 0.0, -50.0], [18000.0, 0.0, -50.0]])
    nav = navigation_plan(world, mission, route)
    assert nav is not None and nav.kinds.count("gps") == 3 and nav.vertex_times_s is not None
    record = RunRecord("still-fixes", 1, None, nav.points, np.empty((0, 3)), None, nav=nav)
    export.write_exports(tmp_path, record, world.origin, 1.5, ("csv", "yaml"))
    rows = list(csv.DictReader((tmp_path / "mission.csv").open()))
    t = np.array([float(r["time"]) for r in rows])
    fixes = [i for i, k in enumerate(nav.kinds) if k]
    np.testing.assert_allclose(t, nav.vertex_times_s, atol=0.006)  # the file's 2 decimals
    np.testing.assert_allclose(t[fixes], nav.times_s, atol=0.006)
    # between fixes, each leg's time at 1.5 m/s; a fix's wait before the leg that leaves it
    legs = np.linalg.norm(np.diff(nav.points, axis=0), axis=1)
    np.testing.assert_allclose(np.diff(t), legs / 1.5 + nav.dwell_s[:-1], atol=0.011)
    assert nav.dwell_s[fixes].tolist() == [120.0] * len(fixes)
    poses = yaml.safe_load((tmp_path / "mission.yaml").read_text())["poses"]
    stamps = np.array([p["header"]["stamp"]["sec"] + 1e-9 * p["header"]["stamp"]["nanosec"] for p in poses])
    np.testing.assert_allclose(stamps, t, atol=0.006)
    assert stamps[-1] == pytest.approx(legs.sum() / 1.5 + 120.0 * len(fixes), abs=1e-6)
