"""Every exported time-out is the mission's flown duration × the stated factor (1.5): the launch's dive from the
surface, each leg through the World's current at its own speed, every wait at a surface fix (helper timing, wave 18;
``docs/missions.md``, "Envelope").

Before, a results folder without a flight (``plan`` then ``export``) timed its time-out as the legs at the planned
speed in still water, without the waits and the dive: the hard case below, a 12 km transit at 1 000 m with planned
GPS fixes against a 0.7 m/s head current at 1.5 m/s (and across the antimeridian), wrote ``max_time`` 13 493.8 s in its
``mission.moos`` (1.5 × 8 995.8 s) while the vehicle takes 17 124.5 s (the dive 753.8 s, the legs 16 010.7 s, 3 × 120 s
at the surface): the helm's ``BHV_OpRegion`` would have posted ``ABORT = true`` at 79 % of the mission, and ``mission
check`` of the file failed its own envelope (``predicted duration 16371 s > max_time 13493.8 s``).  Now 25 686.8 s.

Oracle, the closed form of each leg flown along its own line through a uniform current ``c`` at through-water speed
``V``: the ground speed along the unit direction ``e`` is ``c·e + sqrt(V² − |c|² + (c·e)²)`` (the dive, ``e`` vertical:
``sqrt(V² − |c|²)``); the duration adds the dive, each leg's length over its ground speed, and ``surface_s`` at every
waypoint at the surface but the last.  With per-leg speeds, each leg at its own.
"""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import replace

import numpy as np
import pytest
import yaml

from auvplan.cli import main
from auvplan.io.missions import export
from auvplan.io.missions.deploy import TIMEOUT_FACTOR
from auvplan.io.scenario import loader
from auvplan.sim.navigation import navigation_plan
from auvplan.sim.result import RunRecord

CURRENT = np.array([-0.7, 0.0, 0.0])  # against the route (east)
SPEED, DIVE, SURFACE_S = 1.5, 1.5, 120.0
ROUTE = np.array([[1000.0, 3000.0, -1000.0], [13000.0, 3000.0, -1000.0]])
SCENARIO = f"""name = "head-current-fixes"
seed = 1
[origin]
lat = -12.0
lon = 179.95
[bounds]
x = [0.0, 16000.0]
y = [0.0, 6000.0]
z = [-4000.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 3000.0
cell_m = 1000.0
[currents]
uniform = [{CURRENT[0]}, {CURRENT[1]}, 0.0]
[mission]
start = [1000.0, 3000.0, -1000.0]
goal = [13000.0, 3000.0, -1000.0]
route = [[1000.0, 3000.0, -1000.0], [13000.0, 3000.0, -1000.0]]
min_depth_m = 0.0
[vehicle]
speed = {SPEED}
max_pitch_deg = 30.0
max_depth_m = 2000.0
[navigation]
drift_pct = 0.3
drift_pct_no_lock = 1.0
dvl_range_m = 100.0
fix_error_m = 5.0
max_error_m = 150.0
confidence = 2.0
fixes = "plan"
surface_s = {SURFACE_S}
[avoidance]
name = "none"
"""


def ground_speed(e: np.ndarray, v: float) -> float:
    """Ground speed along the unit direction ``e`` at through-water speed ``v`` in the uniform current (closed form)."""
    ce = float(CURRENT @ e)
    return ce + math.sqrt(v * v - float(CURRENT @ CURRENT) + ce * ce)


def flown_duration(points: np.ndarray, speeds: np.ndarray) -> tuple[float, float]:
    """The oracle: the launch's dive, each leg at its ground speed, ``surface_s`` at each surface waypoint but the
    last; and the still-water time of the legs alone (the old time-out's base)."""
    t = -points[0, 2] / ground_speed(np.array([0.0, 0.0, -1.0]), DIVE)
    still = 0.0
    for i in range(len(points) - 1):
        d = points[i + 1] - points[i]
        n = float(np.linalg.norm(d))
        if n > 0.0:
            t += n / ground_speed(d / n, float(speeds[i]))
            still += n / float(speeds[i])
        if i > 0 and points[i, 2] >= -1e-9:
            t += SURFACE_S
    return t, still


def time_outs(out) -> dict[str, float]:
    """The time-out of every format that carries one, each read with its own syntax."""
    moos = re.findall(r"^\s*max_time\s*=\s*([0-9.]+)", (out / "mission.moos").read_text(), re.M)
    doc = yaml.safe_load((out / "mission.yaml").read_text())
    gj = json.loads((out / "mission.geojson").read_text())
    (env,) = [f["properties"] for f in gj["features"] if f["properties"].get("name") == "envelope"]
    ns = "{http://www.opengis.net/kml/2.2}"
    kml = {d.get("name"): d.findtext(f"{ns}value") for pm in ET.parse(out / "mission.kml").getroot().iter(
        f"{ns}Placemark") if pm.findtext(f"{ns}name") == "envelope" for d in pm.iter(f"{ns}Data")}
    assert len(moos) == 1
    return {"moos": float(moos[0]), "yaml": float(doc["envelope"]["max_time_s"]), "geojson": float(env["max_time_s"]),
            "kml": float(kml["max_time_s"])}


@pytest.fixture(scope="module")
def hard_case(tmp_path_factory):
    """The plan folder's mission: the route with its planned fixes, no flight."""
    tmp = tmp_path_factory.mktemp("timeout")
    (tmp / "s.toml").write_text(SCENARIO)
    world, mission = loader.build(loader.load(tmp / "s.toml"))
    nav = navigation_plan(world, mission, ROUTE)
    assert nav is not None and nav.ok
    return tmp, world, mission, nav


def test_a_plan_folders_time_out_is_its_flown_duration(hard_case, capsys):
    tmp, world, mission, nav = hard_case
    out = tmp / "plan"
    out.mkdir()
    record = RunRecord("head-current-fixes", 1, None, nav.points, np.empty((0, 3)), None, nav=nav)
    deploy = export.deploy_for(world, mission, record, SPEED)
    # every format but the .plan, whose fence ArduPilot cannot hold across ±180° (it carries no time-out either)
    export.write_exports(out, record, world.origin, SPEED, [f for f in export.EXPORT_FORMATS if f != "plan"],
                         deploy=deploy)
    flown, still = flown_duration(nav.points, np.full(len(nav.points) - 1, SPEED))
    assert nav.kinds.count("gps") == 3  # the fixes the budget needs in this current
    assert 1.5 * still < flown  # the hard case: the old time-out (still water, no waits, no dive) fires mid-mission
    for fmt, limit in time_outs(out).items():
        assert limit == pytest.approx(TIMEOUT_FACTOR * flown, abs=0.1), fmt
    assert deploy.envelope is not None and deploy.envelope.predicted_s == pytest.approx(flown, abs=0.05)
    # the file's own check: its legs through the current and its station keeps within the time-out it carries
    code = main(["mission", "check", str(out / "mission.moos"), "--scenario", str(tmp / "s.toml"), "--json"])
    rec = json.loads(capsys.readouterr().out)
    rec = rec["files"][0] if "files" in rec else rec
    assert rec["deploy"]["ok"], rec["deploy"]
    assert code == 0


def test_per_leg_speeds_time_each_leg_at_its_own(hard_case, tmp_path):
    """The same mission with a speed per leg (1.2 to 1.9 m/s): the time-out follows each leg's own ground speed."""
    _, world, mission, nav = hard_case
    speeds = np.linspace(1.2, 1.9, len(nav.points) - 1)
    timed = replace(mission, leg_speeds=tuple(float(v) for v in speeds))
    record = RunRecord("head-current-fixes", 1, None, nav.points, np.empty((0, 3)), None, nav=nav)
    deploy = export.deploy_for(world, timed, record, speeds)
    export.write_exports(tmp_path, record, world.origin, speeds, ("moos", "yaml", "geojson", "kml"), deploy=deploy)
    flown, _ = flown_duration(nav.points, speeds)
    assert abs(flown - flown_duration(nav.points, np.full(len(speeds), SPEED))[0]) > 500.0  # the speeds matter
    for fmt, limit in time_outs(tmp_path).items():
        assert limit == pytest.approx(TIMEOUT_FACTOR * flown, abs=0.1), fmt


def test_a_longer_simulated_flight_still_sets_the_time_out(hard_case):
    """A run's flight longer than the prediction (guidance, regaining the route after a dwell) is kept: the longer."""
    _, world, mission, nav = hard_case
    flown, _ = flown_duration(nav.points, np.full(len(nav.points) - 1, SPEED))
    from auvplan.io.missions.deploy import deploy_info

    env = deploy_info(world, mission, nav.points, SPEED, flown + 1000.0, dwell=nav.dwell_s).envelope
    assert env is not None and env.max_time_s == pytest.approx(TIMEOUT_FACTOR * (flown + 1000.0), abs=0.1)
    env = deploy_info(world, mission, nav.points, SPEED, flown - 1000.0, dwell=nav.dwell_s).envelope
    assert env is not None and env.max_time_s == pytest.approx(TIMEOUT_FACTOR * flown, abs=0.1)
