"""Audit 22 of this session's merges (``git diff 6bd4b09``).

1. ``mission check`` flew a ``.plan``'s speed command at ``v / cos γ`` along every leg (audit 20) with no vertical
   limit, so a leg that drops almost straight down was judged at thousands of m/s: a waypoint 2 cm beside the one
   above it, 90 m deeper (one MAVLink position quantum from a plumb dive, which a hand-made or QGroundControl
   plan easily has), was flown at 4 500 m/s for 2.9 × 10⁶ Wh, RESERVE_BROKEN, where the plumb dive next to it is
   judged at the command's speed (6.3 Wh).  ArduPilot's ``kinematic_limit`` (``AP_Math/control.cpp``) bounds the
   speed along a leg by the vertical limit too (``max_z / |dir.z|``); the file does not hold
   ``WPNAV_SPEED_UP``/``_DN``: AC_WPNav's defaults (2.5/1.5 m/s) or the command, whichever is faster, are taken (a
   leg of our own export steeper than 45° is flown at the planned speed with the defaults); a vertical leg is still
   judged at the command's speed (audit 20).  Oracle: ``kinematic_limit`` transcribed from ArduPilot below.
2. A hold on station sampled the current at 16 instants however long it was (up to 65 535 s): a hold of 16 periods
   of a current ``1 + sin`` (4 000 s) sampled it once a period, always at sin = 0, so a current that passes the
   vehicle's 1.8 m/s top speed every period was 'EXACT' at P(1 m/s) for the whole 64 000 s.  Oracle: the
   current's peak by hand against the top speed, and the mean of P(1 + sin) over whole periods by fine quadrature.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.endurance import EnergyModel
from auvplan.endurance.budget import mission_budget
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.energy import mission_file_energy
from auvplan.io.scenario import loader
from auvplan.world.currents.fields import CurrentField
from helpers import HOLDS


def kinematic_limit(direction, max_xy: float, max_z_pos: float, max_z_neg: float) -> float:
    """ArduPilot's ``kinematic_limit`` (AP_Math/control.cpp), line for line: the largest speed along
    ``direction`` (x, y, z up) within the horizontal and vertical limits."""
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    xy = math.hypot(d[0], d[1])
    if xy == 0.0:
        return max_z_pos if d[2] > 0 else max_z_neg
    if d[2] == 0.0:
        return max_xy
    slope = d[2] / xy
    if slope > 0:
        return max_xy / xy if abs(slope) < max_z_pos / max_xy else abs(max_z_pos / d[2])
    return max_xy / xy if abs(slope) < max_z_neg / max_xy else abs(max_z_neg / d[2])


def _plan(tmp_path, frame: LocalFrame, items, speed: float):
    its = [{"type": "SimpleItem", "command": 178, "frame": 2, "params": [1, speed, -1, 0, 0, 0, 0]}]
    for x, y, z in items:
        lon, lat = frame.inverse(x, y)
        its.append({"type": "SimpleItem", "command": 16, "frame": 3,
                    "params": [0, 0, 0, None, float(lat), float(lon), float(z)]})
    lon, lat = frame.inverse(*items[0][:2])
    path = tmp_path / "m.plan"
    path.write_text(json.dumps({"mission": {"plannedHomePosition": [float(lat), float(lon), 0], "items": its}}))
    return path


@pytest.mark.parametrize(("offset", "dz"), [(0.0, -90.0), (0.02, -90.0), (0.5, -90.0), (40.0, -90.0),
                                            (90.0, -90.0), (300.0, -90.0), (0.3, 60.0), (20.0, 60.0), (60.0, 60.0)])
def test_a_near_vertical_leg_is_flown_within_the_vertical_limit(tmp_path, offset, dz):
    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS, encoding="utf-8")
    world, mission = loader.build(loader.load(str(scen)))
    speed = 1.2
    items = [[500.0, 1000.0, -100.0], [500.0 + offset, 1000.0, -100.0 + dz], [1500.0, 1000.0, -100.0 + dz]]
    rec = mission_file_energy(world, mission, _plan(tmp_path, LocalFrame(*world.origin), items, speed))[0]
    p = np.array([[500.0, 1000.0, 0.0], *items])  # the launch from the home above item 0
    want = [kinematic_limit(b - a, speed, 2.5, 1.5) for a, b in zip(p[:-1], p[1:])]  # export22: AC_WPNav's defaults
    assert rec["leg_speeds_mps"] == pytest.approx(want, rel=1e-5)  # offset 2 cm: 5 400 m/s before
    assert offset == 0.0 or max(want) > speed  # the oracle is not the command itself
    legs = np.linalg.norm(np.diff(p, axis=0), axis=1)
    assert rec["duration_s"] == pytest.approx(float(np.sum(legs / np.array(want))), rel=1e-5)
    assert rec["energy_status"] == "EXACT"  # RESERVE_BROKEN by 10⁶ Wh before


PERIOD = 4000.0


class _Surge(CurrentField):
    """``(1 + sin(2π t / PERIOD), 0, 0)`` m/s everywhere."""

    def velocity(self, points, t=0.0):
        out = np.zeros(np.asarray(points, dtype=float).shape)
        out[..., 0] = 1.0 + math.sin(2.0 * math.pi * t / PERIOD)
        return out

    @property
    def steady(self) -> bool:
        return False

    @property
    def max_speed(self) -> float:
        return 2.0


@pytest.mark.parametrize("periods", [16, 8])
def test_a_long_hold_samples_the_current_often_enough_to_see_its_peaks(tmp_path, periods):
    from dataclasses import replace

    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS, encoding="utf-8")
    world = replace(loader.build(loader.load(str(scen)))[0], currents=_Surge())
    route = np.array([[0.0, 0.0, -15.0], [1000.0, 0.0, -15.0], [2000.0, 0.0, -15.0]])
    hold = periods * PERIOD  # 64 000 s: within a .plan's 65 535 s

    def budget(max_speed):
        dwell = np.array([0.0, hold, 0.0])
        return mission_budget(world, route, EnergyModel(max_speed=max_speed), 1.2, 0.0, 50.0, None, dwell, dwell > 0)

    blocked = budget(1.8)  # 1 + sin passes 1.8 m/s for 819 s of every period
    assert blocked.status is Status.INFEASIBLE and "the hold at waypoint 1" in blocked.message
    b = budget(2.05)
    model = EnergyModel(max_speed=2.05)
    t = np.linspace(0.0, PERIOD, 200001)
    mean_power = float(np.mean(model.power(1.0 + np.sin(2.0 * math.pi * t[:-1] / PERIOD))))  # whole periods
    moving = float(b.t_end[1] - b.t_start[1]) - hold
    held_wh = float(b.energy_leg_wh[1]) - float(model.power(b.speed_water[1])) * moving / 3600.0
    assert b.status is Status.EXACT and held_wh == pytest.approx(mean_power * hold / 3600.0, rel=1e-3)


def test_our_export_of_a_leg_steeper_than_45_degrees_checks_at_the_planned_speed(tmp_path):
    """The export commands v cos γ (audit 20); with AC_WPNav's default descent limit (1.5 m/s ≥ v sin γ) ArduSub
    flies v along the leg, and so does the check (bounded by the command alone it judged v cot γ: 0.58 v at 60°)."""
    from auvplan.io.missions.formats import to_qgc_plan

    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS, encoding="utf-8")
    world, mission = loader.build(loader.load(str(scen)))
    pts = np.array([[500.0, 1000.0, -5.0], [552.0, 1000.0, -95.0], [1500.0, 1000.0, -95.0]])  # 60° then level
    path = tmp_path / "e.plan"
    path.write_text(json.dumps(to_qgc_plan(pts, world.origin, 1.1)))
    rec = mission_file_energy(world, mission, path)[0]
    assert rec["leg_speeds_mps"][1:] == pytest.approx([1.1, 1.1], abs=2e-4)
    assert rec["leg_speeds_mps"][0] == pytest.approx(kinematic_limit([0, 0, -1], 1.1, 2.5, 1.5))  # launch: v_z (1.5)
    assert not rec["speed_assumed_line"]  # 1.1 sin 60° = 0.95 m/s < 1.5: the default does not bind


@pytest.mark.parametrize(("speed", "dz", "run"), [(2.0, -90.0, 52.0), (3.4, 90.0, 52.0), (1.1, -90.0, 52.0),
                                                  (3.0, -90.0, 107.26), (4.5, 90.0, 107.26)])
def test_a_speed_command_does_not_raise_the_vertical_limit(tmp_path, speed, dz, run):
    """export22: ArduSub's ``do_change_speed`` is ``wp_nav.set_speed_xy`` only (``ArduSub/commands_logic.cpp``), so a
    60° leg of our export commanded fast enough is held to AC_WPNav's default ``WPNAV_SPEED_DN`` 1.5 m/s
    (``WPNAV_SPEED_UP`` 2.5 climbing): the leg's time is max(horizontal / v cos γ, |rise| / v_z).  Before, the
    command raised the vertical limit (judged at 2 m/s along the leg, flown at 1.73).  Oracle: ``kinematic_limit``."""
    from auvplan.io.missions.formats import to_qgc_plan

    scen = tmp_path / "s.toml"
    scen.write_text(HOLDS, encoding="utf-8")
    world, mission = loader.build(loader.load(str(scen)))
    z0 = -5.0 if dz < 0 else -100.0
    pts = np.array([[500.0, 1000.0, z0], [500.0 + run, 1000.0, z0 + dz], [1500.0, 1000.0, z0 + dz]])  # 60°/40°
    path = tmp_path / "e.plan"
    path.write_text(json.dumps(to_qgc_plan(pts, world.origin, speed)))
    rec = mission_file_energy(world, mission, path)[0]
    d = pts[1] - pts[0]
    command = speed * math.cos(math.atan2(abs(dz), run))  # the export's; 40°: 2.3 > 1.5 m/s
    want = kinematic_limit(d, command, 2.5, 1.5)
    assert rec["leg_speeds_mps"][1] == pytest.approx(want, rel=1e-4)
    vz = 2.5 if dz > 0 else 1.5
    binds = speed * abs(d[2]) / np.linalg.norm(d) > vz
    assert (want < speed - 1e-3) == binds  # the oracle differs from the planned speed exactly when v_z binds
    assert ("legs 1)" in rec["speed_assumed_line"] and "WPNAV_SPEED_DN 1.5" in rec["speed_assumed_line"]) == binds
    legs = np.linalg.norm(np.diff(np.array([[500.0, 1000.0, 0.0], *pts]), axis=0), axis=1)
    flat = np.hypot(d[0], d[1])
    assert legs[1] / rec["leg_speeds_mps"][1] == pytest.approx(max(flat / command, abs(dz) / vz), rel=1e-4)
