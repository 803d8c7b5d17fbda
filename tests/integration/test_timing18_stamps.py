"""A mission without ``[navigation]`` is stamped as it is flown too: the ``.csv`` times and the ``.yaml`` stamps are
the arrivals through the World's current at each leg's speed (the energy budget's flight, ``legs.csv``'s), not the
planned speeds in still water (helper timing, wave 18; with ``[navigation]`` since wave 17,
``test_export2_flown_times``).

Before: across 0.6 m/s east and 0.3 m/s north, the 3-leg mission below (a climb, speeds 1.2 / 1.6 / 1.4 m/s) arrived
at 11 382.1 s in its files and at 7 932.1 s in its own energy budget; now the same.

Oracle: the closed form of a leg flown along its own line through a uniform current ``c`` at through-water speed
``V``: the ground speed along the unit direction ``e`` is ``c·e + sqrt(V² − |c|² + (c·e)²)``.
"""

from __future__ import annotations

import csv

import numpy as np
import yaml

from auvplan.endurance import EnergyModel, mission_budget
from auvplan.io.missions import export
from auvplan.io.scenario import loader
from auvplan.sim.result import RunRecord

CURRENT = np.array([0.6, 0.3, 0.0])
POINTS = np.array([[0.0, 0.0, -50.0], [6000.0, 0.0, -50.0], [9000.0, 1500.0, -20.0], [15000.0, 1500.0, -20.0]])
SPEEDS = np.array([1.2, 1.6, 1.4])
SCENARIO = f"""name = "stamps-in-a-current"
[origin]
lat = 10.0
lon = 20.0
[bounds]
x = [-1000.0, 16000.0]
y = [-1000.0, 3000.0]
z = [-500.0, 0.0]
[currents]
uniform = [{CURRENT[0]}, {CURRENT[1]}, 0.0]
[mission]
start = [0.0, 0.0, -50.0]
goal = [15000.0, 1500.0, -20.0]
[vehicle]
speed = 1.5
"""


def test_the_stamps_are_the_flight_through_the_current(tmp_path):
    (tmp_path / "s.toml").write_text(SCENARIO)
    world, mission = loader.build(loader.load(tmp_path / "s.toml"))
    record = RunRecord("stamps-in-a-current", 1, None, POINTS, np.empty((0, 3)), None)
    deploy = export.deploy_for(world, mission, record, SPEEDS)
    export.write_exports(tmp_path, record, world.origin, SPEEDS, ("csv", "yaml"), deploy=deploy)
    d = np.diff(POINTS, axis=0)
    n = np.linalg.norm(d, axis=1)
    ce = (d / n[:, None]) @ CURRENT
    expected = np.r_[0.0, np.cumsum(n / (ce + np.sqrt(SPEEDS**2 - CURRENT @ CURRENT + ce * ce)))]
    rows = list(csv.DictReader((tmp_path / "mission.csv").open()))
    np.testing.assert_allclose([float(r["time"]) for r in rows], expected, atol=0.006)
    poses = yaml.safe_load((tmp_path / "mission.yaml").read_text())["poses"]
    stamps = np.array([p["header"]["stamp"]["sec"] + 1e-9 * p["header"]["stamp"]["nanosec"] for p in poses])
    np.testing.assert_allclose(stamps, expected, atol=1e-6)
    budget = mission_budget(world, POINTS, EnergyModel.from_vehicle(mission.vehicle), SPEEDS)
    assert abs(budget.duration_s - expected[-1]) < 1e-6  # the energy budget's flight
    assert abs(float(np.sum(n / SPEEDS)) - expected[-1]) > 2000.0  # the hard case: still water is far off
