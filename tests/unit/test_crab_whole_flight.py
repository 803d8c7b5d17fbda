"""The survey's crab-angle margin read the current over the first 12 h only: a survey flying longer (strait-corridor
flies 12.5 h) never saw a current that sets in later, and its lines were placed for a current of zero.  The margin
now reads the current over the flight's estimated span (:func:`auvplan.survey.mission._lines_for_flight`).

Oracle: a current that is zero for 13 h and then a cross-current ``c`` gives the margin of the steady current ``c``
(the largest crab angle over the flight is the late one): ``1 - cos(asin(c / U))``.  On the built-in
strait-corridor (12.5 h): tests/heavy/test_survey_corridor_flown.py (make survey-flown)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from auvplan.io.results.survey import survey_params
from auvplan.io.scenario.build import build
from auvplan.io.scenario.loader import loads
from auvplan.survey.mission import _lines_for_flight
from auvplan.world.currents.fields import CurrentField

SLOW = """
name = "slow-survey"
[bounds]
x = [0.0, 3000.0]
y = [0.0, 3000.0]
z = [-120.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 100.0
cell_m = 50.0
[mission]
start = [900.0, 900.0, -5.0]
goal = [900.0, 900.0, -5.0]
min_altitude_m = 10.0
[vehicle]
speed = 0.1
[survey]
polygon_xy = [[1000.0, 1000.0], [2000.0, 1000.0], [2000.0, 2000.0], [1000.0, 2000.0]]
sensor = "multibeam"
opening_deg = 120.0
mounting = "surface"
overlap = [0.10, 0.20]
heading_deg = 0.0
"""


class LateCurrent(CurrentField):
    """Zero until ``after_s``, then ``(east, 0, 0)`` everywhere (a cross-current to north-south lines)."""

    def __init__(self, east: float, after_s: float) -> None:
        self.east, self.after_s = east, after_s

    def velocity(self, points, t=0.0):
        v = np.zeros_like(np.asarray(points, dtype=float).reshape(-1, 3))
        v[:, 0] = self.east if t > self.after_s else 0.0
        return v


@pytest.fixture(scope="module")
def slow():
    sc = loads(SLOW, "slow.toml")
    world, mission = build(sc)
    return world, mission, survey_params(sc.survey, world, mission.vehicle, None, "slow.toml: [survey]")


def test_a_current_that_sets_in_after_12_h_is_seen(slow):
    world, mission, params = slow
    late = dataclasses.replace(world, currents=LateCurrent(0.05, 13 * 3600.0))
    margin, _, _, route, _, _ = _lines_for_flight(late, mission, params, world.seabed, 0.0)
    hours = np.linalg.norm(np.diff(route, axis=0), axis=1).sum() / mission.vehicle.speed / 3600.0
    assert hours > 13.0  # the lines alone fly past the current's onset
    assert margin == pytest.approx(1.0 - math.cos(math.asin(0.05 / 0.1)), rel=1e-9)


def test_a_current_after_the_flight_is_not_read(slow):
    """The span read is the flight's (times the slack), not any time: a current setting in at 1000 h is not seen."""
    world, mission, params = slow
    margin = _lines_for_flight(dataclasses.replace(world, currents=LateCurrent(0.05, 1000 * 3600.0)), mission,
                               params, world.seabed, 0.0)[0]
    assert margin == 0.0


class DeepCurrent(CurrentField):
    """``(east, 0, 0)`` below ``z_below`` and none above it: an undercurrent (an estuary's inflow at depth)."""

    def __init__(self, east: float, z_below: float) -> None:
        self.east, self.z_below = east, z_below

    def velocity(self, points, t=0.0):
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        v = np.zeros_like(p)
        v[:, 0] = np.where(p[:, 2] < self.z_below, self.east, 0.0)
        return v


@pytest.mark.parametrize("mounting", ["auv", "surface"])
def test_the_crab_margin_reads_the_current_where_the_vehicle_flies(mounting):
    """Audit 24: the margin read the current at the surface (``-min_depth_m``) whatever the mounting; an AUV-mounted
    sensor flies at its altitude above the seabed (20 m over 100 m: at 80 m), here in a 0.05 m/s cross-current
    under 50 m that the surface never feels, and its lines were placed with no margin for it.  Oracle: the margin of
    the current at the vehicle's depth, ``1 - cos(asin(c / U))`` (AUV) and 0 (surface: the vessel feels none)."""
    sc = loads(SLOW.replace('mounting = "surface"', f'mounting = "{mounting}"\naltitude_m = 20.0'
                            if mounting == "auv" else 'mounting = "surface"'), "slow.toml")
    world, mission = build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, None, "slow.toml: [survey]")
    deep = dataclasses.replace(world, currents=DeepCurrent(0.05, -50.0))
    margin = _lines_for_flight(deep, mission, params, world.seabed, 0.0)[0]
    want = 1.0 - math.cos(math.asin(0.05 / 0.1)) if mounting == "auv" else 0.0
    assert margin == pytest.approx(want, rel=1e-9, abs=1e-12)
