"""A ``.plan`` whose mission starts at the surface is not read as a GPS fix at its start (audit 23).

A ``.plan`` starts from its home, on the surface above the mission's first waypoint, so ``mission check`` reads its
points home first: the mission's start is the file's point 1.  Read as "a surface waypoint after the first is a GPS
fix", a mission launched at the surface got one fix more in its ``.plan`` than in any other format — and, since the
export writes no wait at the start (the plan's fixes come later), ``navigation: FAIL — waypoint 1: waits 0 s at the
surface, less than surface_s`` for a mission its ``.moos`` and ``.csv`` pass (measured on ``mariana-nav`` started at
the surface: 7 surface fixes in the ``.plan``, 6 in the others).

Oracle: the same mission written in three formats by the exporters: every file counts the one surfacing the mission
makes as its only fix and passes; the ``.plan`` with that surfacing's wait removed fails naming it (home first: its
point 4), so the wait check still holds where a fix is.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.app.check import check_missions
from auvplan.io.missions import formats

ORIGIN = (-20.0, 150.0)
SCENARIO = f"""name = "launch-at-surface"
[origin]
lat = {ORIGIN[0]}
lon = {ORIGIN[1]}
[bounds]
x = [-1000.0, 6000.0]
y = [-1000.0, 1000.0]
z = [-500.0, 0.0]
[mission]
start = [0.0, 0.0, 0.0]
goal = [4000.0, 0.0, -50.0]
min_depth_m = 0.0
[vehicle]
speed = 1.5
max_pitch_deg = 20.0
[navigation]
drift_pct_no_lock = 1.0
max_error_m = 200.0
confidence = 2.0
surface_s = 120.0
"""
# launched at the surface, a dive, a surfacing for a fix (its wait), a dive, the end at depth
POINTS = np.array([[0.0, 0.0, 0.0], [300.0, 0.0, -50.0], [2000.0, 0.0, -50.0], [2300.0, 0.0, 0.0],
                   [2600.0, 0.0, -50.0], [4000.0, 0.0, -50.0]])
DWELL = np.array([0.0, 0.0, 0.0, 120.0, 0.0, 0.0])


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("launch")
    (d / "s.toml").write_text(SCENARIO)
    (d / "m.plan").write_text(json.dumps(formats.to_qgc_plan(POINTS, ORIGIN, 1.5, dwell=DWELL)))
    (d / "m.moos").write_text(formats.to_moos(POINTS, 1.5, dwell=DWELL))
    (d / "m.csv").write_text(formats.mission_csv(POINTS, ORIGIN, 1.5))
    return d


def test_a_mission_launched_at_the_surface_has_the_same_fixes_in_every_format(files):
    _, checks = check_missions(str(files / "s.toml"), [str(files / n) for n in ("m.plan", "m.moos", "m.csv")], 15.0)
    for c in checks:
        nav = c.record["navigation"]
        assert nav["fixes"] == 1 and nav["ok"], (c.record["file"], nav["message"])
    plan = checks[0].record["navigation"]
    # the .plan's legs numbered from its home (leg 0 the launch): the same budget, one leg more
    assert [leg["nav_error_m"] for leg in plan["legs"][1:]] == [leg["nav_error_m"] for leg in
                                                                 checks[1].record["navigation"]["legs"]]


def test_the_wait_at_a_real_surfacing_is_still_required(files, tmp_path):
    doc = json.loads((files / "m.plan").read_text())
    for it in doc["mission"]["items"]:
        if it["command"] == 16:
            it["params"][0] = 0
    bare = tmp_path / "bare.plan"
    bare.write_text(json.dumps(doc))
    _, (c,) = check_missions(str(files / "s.toml"), [str(bare)], 15.0)
    nav = c.record["navigation"]
    assert not nav["ok"] and nav["message"].startswith("waypoint 4: waits 0 s at the surface"), nav["message"]
    assert nav["fixes"] == 1


@pytest.mark.parametrize(("hold", "depth", "ok"), [(120, 0.0, True), (119, 0.0, False), (0, -0.5, False),
                                                   (120, -0.5, True), (0, -0.51, True)])
def test_a_surfacing_waits_its_surface_s_to_the_second(files, tmp_path, hold, depth, ok):
    """The surfacing's hold against surface_s = 120 s (whole seconds, as ArduSub counts them): 119 s fails; a
    waypoint 0.5 m deep is at the surface (a fix that must wait), 0.51 m is not (no fix, no wait)."""
    doc = json.loads((files / "m.plan").read_text())
    wps = [it for it in doc["mission"]["items"] if it["command"] == 16]
    wps[3]["params"][0] = hold
    if depth:
        wps[3]["params"][6] = wps[3]["Altitude"] = depth
    path = tmp_path / "h.plan"
    path.write_text(json.dumps(doc))
    _, (c,) = check_missions(str(files / "s.toml"), [str(path)], 15.0)
    nav = c.record["navigation"]
    assert nav["ok"] is ok and nav["fixes"] == (0 if depth < -0.5 else 1), nav["message"]


def test_a_mission_that_ends_at_the_surface_needs_no_wait_there(files, tmp_path):
    """Recovered at the surface: the last waypoint is a fix of no leg (the mission is over), the exporters write no
    wait there (its wait is after the mission) and the energy check counts none; the check asked its surface_s, so
    the run's own .plan and .moos of such a mission failed (`mariana-nav` ending at the surface: 'waypoint 775: waits
    0 s at the surface') while its .csv passed.  Oracle: all three formats pass with the mid-mission wait held; that
    surfacing without its wait still fails in the .plan and the .moos."""
    pts = np.vstack([POINTS[:-1], [[4300.0, 0.0, 0.0]]])
    dwell = np.array([0.0, 0.0, 0.0, 120.0, 0.0, 120.0])  # the plan's fix at the end: not written (after the mission)
    for waits, ok in ((dwell, True), (np.zeros(6), False)):
        (tmp_path / "e.plan").write_text(json.dumps(formats.to_qgc_plan(pts, ORIGIN, 1.5, dwell=waits)))
        (tmp_path / "e.moos").write_text(formats.to_moos(pts, 1.5, dwell=waits))
        (tmp_path / "e.csv").write_text(formats.mission_csv(pts, ORIGIN, 1.5))
        _, checks = check_missions(str(files / "s.toml"), [str(tmp_path / n) for n in ("e.plan", "e.moos", "e.csv")],
                                   15.0)
        for c in checks:
            nav = c.record["navigation"]
            want = ok or c.record["format"] == "csv"  # the csv carries no wait: the scenario's surface_s
            assert nav["ok"] is want and nav["fixes"] == 2, (c.record["file"], nav["message"])
            if not want:
                point = 4 if c.record["format"] == "qgc" else 3  # its home first
                assert nav["message"].startswith(f"waypoint {point}: waits 0 s"), nav["message"]


def test_a_surfacing_just_before_the_end_still_waits(files, tmp_path):
    """The surfacing is the waypoint before the last (then a surface leg to the recovery point): its fix serves that
    leg, so its wait is still asked (only the last waypoint's is not)."""
    pts = np.array([[0.0, 0.0, 0.0], [300.0, 0.0, -50.0], [2000.0, 0.0, -50.0], [2300.0, 0.0, 0.0],
                    [2400.0, 0.0, 0.0]])
    (tmp_path / "b.plan").write_text(json.dumps(formats.to_qgc_plan(pts, ORIGIN, 1.5)))
    (tmp_path / "b.moos").write_text(formats.to_moos(pts, 1.5, dwell=np.zeros(5)))
    _, checks = check_missions(str(files / "s.toml"), [str(tmp_path / "b.plan"), str(tmp_path / "b.moos")], 15.0)
    for c, point in zip(checks, (4, 3), strict=True):
        nav = c.record["navigation"]
        assert not nav["ok"] and nav["message"].startswith(f"waypoint {point}: waits 0 s"), nav["message"]
