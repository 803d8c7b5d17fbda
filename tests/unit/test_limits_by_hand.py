"""The planners' limit check and repair by hand (issue 49's mutation run of ``vehicle-limits``): each value
below is worked out on paper, at and either side of each threshold, so that a changed comparison, sign or
index in ``check_limits``, ``merge_close``, ``vertex_floors`` or ``repair_pitch`` fails."""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.path.flyable import (
    PITCH_SLACK_DEG,
    VehicleLimits,
    check_limits,
    flyby_arcs,
    leg_pitch_deg,
    leg_turn_radius,
    merge_close,
)
from auvplan.planners.core.vehicle_limits import repair_pitch, vertex_floors
from helpers import RIDGE, build_toml

# legs: 0 climbs 20 m down over 100 m (11.31°), 1 level, 2 level after a 90° turn, 3 after another 90° turn
# dives 470 m over 100 m (77.99°) to 500 m; fly-by radii: leg 1 100 / (0 + tan 45°) = 100, leg 2
# 100 / (tan 45° + tan 45°) = 50, leg 3 100 / (tan 45° + 0) = 100, leg 0 straight at both ends (inf)
P = np.array([[0.0, 0.0, -10.0], [100.0, 0.0, -30.0], [200.0, 0.0, -30.0], [200.0, 100.0, -30.0],
              [300.0, 100.0, -500.0]])


def test_check_limits_names_each_leg_and_limit_and_the_worst() -> None:
    r = check_limits(P, VehicleLimits(15.0, 60.0, 400.0))
    got = [(v.leg, v.limit, round(v.value, 3), v.allowed) for v in r.violations]
    assert got == [(2, "turn_radius_m", 50.0, 60.0), (3, "max_pitch_deg", round(math.degrees(math.atan(4.7)), 3), 15.0),
                   (3, "max_depth_m", 500.0, 400.0)]
    assert (r.max_pitch_leg, r.tightest_turn_leg) == (3, 2)
    assert r.max_pitch_deg == pytest.approx(math.degrees(math.atan(4.7)))
    assert r.tightest_turn_m == pytest.approx(50.0) and r.max_depth_m == 500.0
    assert not r.ok


def test_check_limits_at_exactly_each_limit_passes() -> None:
    """A leg at exactly the pitch limit, a turn at exactly the radius, a leg at exactly the rating: no violation;
    a hair beyond each (1e-6 relative): one each, on the right leg."""
    q = np.vstack([P[:4], [[300.0, 100.0, -30.0]]])  # P with a level last leg: radii inf, 100, 50, 100
    pitch = math.degrees(math.atan(0.2))
    at = check_limits(q, VehicleLimits(pitch, 50.0, 30.0))
    assert at.ok, at.violations
    beyond = check_limits(q, VehicleLimits(pitch * (1 - 1e-6), 50.0 * (1 + 1e-6), 30.0 * (1 - 1e-6)))
    assert sorted((v.leg, v.limit) for v in beyond.violations) == [
        (0, "max_depth_m"), (0, "max_pitch_deg"), (1, "max_depth_m"), (2, "max_depth_m"), (2, "turn_radius_m"),
        (3, "max_depth_m")]
    # the deeper end of a leg counts (a descent's last point): 30 m on leg 0 although it starts at 10 m
    assert check_limits(q[:2], VehicleLimits(90.0, 0.0, 29.0)).violations[0].value == 30.0
    one = check_limits(q[:1], VehicleLimits())  # a single point: its depth, no legs
    assert (one.max_depth_m, one.max_pitch_leg, one.tightest_turn_leg, one.violations) == (10.0, -1, -1, ())
    assert (one.max_pitch_deg, one.tightest_turn_m) == (0.0, math.inf)
    # a leg's depth is its deeper end, whatever the first waypoint's: 50 m on legs 0 and 1
    v = check_limits([[0.0, 0.0, -10.0], [100.0, 0.0, -50.0], [200.0, 0.0, -20.0]], VehicleLimits(90.0, 0.0, 40.0))
    assert [(x.leg, x.value) for x in v.violations] == [(0, 50.0), (1, 50.0)]


def test_turns_are_judged_on_the_horizontal_track() -> None:
    """A right-angle corner between two legs both climbing 20 %: still 90° (only x, y count), so each 100 m leg's
    fly-by fits R = 100 / tan 45°; a vertex 0.5 m off a 200 m chord is no corner at R = 60 m (the track is
    simplified to 6 m first: tightest turn inf), and the straight vertex before a corner keeps its fly-by there."""
    climb = np.array([[0.0, 0.0, 0.0], [100.0, 0.0, 20.0], [100.0, 100.0, 40.0]])
    assert leg_turn_radius(climb) == pytest.approx([100.0, 100.0])
    back = np.array([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [100.0 - 100.0 * math.cos(math.radians(30.0)),
                                                          100.0 * math.sin(math.radians(30.0)), 0.0]])
    assert leg_turn_radius(back) == pytest.approx(100.0 / math.tan(math.radians(75.0)))  # a 150° turn: 26.8 m
    nearly = np.array([[0.0, 0.0, -10.0], [100.0, 0.5, -10.0], [200.0, 0.0, -10.0]])
    straight = check_limits(nearly, VehicleLimits(turn_radius_m=60.0))
    assert (straight.tightest_turn_m, straight.tightest_turn_leg) == (math.inf, -1)
    entry, exit_, centre = flyby_arcs([[0, 0, 0], [100, 0, 0], [200, 0, 0], [200, 100, 0]], 10.0)
    assert entry[1].tolist() == exit_[1].tolist() == centre[1].tolist() == [100.0, 0.0]  # straight: the vertex
    assert entry[2] == pytest.approx([190.0, 0.0]) and exit_[2] == pytest.approx([200.0, 10.0])
    assert centre[2] == pytest.approx([190.0, 10.0])  # a left turn: the centre to the left of the first leg


def test_merge_close_keeps_the_ends_and_drops_only_what_is_closer_than_tol() -> None:
    assert merge_close([[0, 0, 0], [3, 4, 0], [6, 8, 0]], 5.0).tolist() == [0, 1, 2]  # exactly tol apart: kept
    assert merge_close([[0, 0, 0], [3, 4, 0], [6, 8, 0]], 5.0 + 1e-9).tolist() == [0, 2]
    assert merge_close([[0, 0, 0], [0.006, 0, 0.009]], 0.01).tolist() == [0, 1]  # 10.8 mm in 3D (6 mm flat)
    assert merge_close([[0, 0, 0], [0.006, 0, 0.009], [0.0061, 0, 0.009]], 0.01).tolist() == [0, 2]  # last wins
    assert merge_close([[0, 0, 0], [0.001, 0, 0]], 0.01).tolist() == [0, 1]  # both ends although close
    assert merge_close([[0, 0, 0], [0.001, 0, 0], [0.002, 0, 0], [9, 0, 0]], 0.01).tolist() == [0, 3]
    assert merge_close([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2.001, 0, 0]], 0.01).tolist() == [0, 1, 3]  # the end
    # replaces the last kept vertex, not another




def _highest(world, a, b) -> float:  # type: ignore[no-untyped-def]
    """The highest seabed under a leg along x, sampled every 1/32 m (exact binary steps: the grid's 5 m nodes,
    where a bilinear surface's maximum along a grid line lies, are among the samples)."""
    x = np.arange(a[0], b[0] + 1e-9, 1.0 / 32.0)
    return float(world.seabed(x, np.full_like(x, a[1])).max())


def test_vertex_floors_are_each_vertex_highest_adjacent_leg_floor() -> None:
    world, _ = build_toml(RIDGE)
    path = np.array([[100.0, 200.0, -80.0], [500.0, 200.0, -80.0], [1900.0, 200.0, -80.0]])
    legs = [_highest(world, path[k], path[k + 1]) + 10.0 for k in range(2)]  # dense samples, min altitude 10 m
    assert legs[0] == pytest.approx(-90.0, abs=1e-3) and legs[1] > -60.0
    assert vertex_floors(world, path) == pytest.approx([legs[0], max(legs), legs[1]], abs=1e-3)
    assert vertex_floors(world, path[:2]) == pytest.approx([legs[0], legs[0]], abs=1e-3)
    assert vertex_floors(world, path[:1]).tolist() == [-math.inf]


def test_repair_pitch_is_the_lowest_profile_within_the_limit() -> None:
    """Across the 40 m ridge at -80 m with a 12° limit: the repaired profile keeps the ends and the track, never
    passes under a vertex's floor + 0.05 m, and its steepest leg is exactly the limit less the slack (the lowest
    such profile: any slower climb would start earlier than needed)."""
    world, _ = build_toml(RIDGE)
    x = np.linspace(100.0, 1900.0, 91)
    path = np.column_stack([x, np.full_like(x, 200.0), np.full_like(x, -80.0)])
    fixed = repair_pitch(world, path, 12.0)
    assert fixed is not None
    assert np.array_equal(fixed[:, :2], path[:, :2]) and np.array_equal(fixed[[0, -1]], path[[0, -1]])
    floors = vertex_floors(world, path) + 0.05
    assert np.all(fixed[1:-1, 2] >= floors[1:-1] - 1e-9)
    assert np.abs(leg_pitch_deg(fixed)).max() == pytest.approx(12.0 - PITCH_SLACK_DEG, abs=1e-6)
    assert fixed[1:-1, 2].min() == pytest.approx(-80.0, abs=1e-9)  # away from the ridge it stays at -80 m
    assert repair_pitch(world, path, 0.5) is None  # 40 m up over the ridge's flanks is out of reach at 0.5°
    low = path.copy()  # start and goal pinned 8 m above the seabed, under min_altitude (10 m): kept where they are
    low[[0, -1], 2] = -92.0
    fixed = repair_pitch(world, low, 12.0)
    assert fixed is not None and fixed[0, 2] == fixed[-1, 2] == -92.0
    assert np.all(fixed[1:-1, 2] >= floors[1:-1] - 1e-9)
    assert np.abs(leg_pitch_deg(fixed)).max() == pytest.approx(12.0 - PITCH_SLACK_DEG, abs=1e-6)  # off the ends


def test_enforce_limits_repairs_only_what_it_can_and_says_why_not() -> None:
    """A 2-point plan climbing 30° (limit 20°) cannot be re-profiled (its ends are pinned): INFEASIBLE naming the
    vehicle; the same climb spread over 9 vertices is repaired within the limit; a timed plan is never repaired
    (its times would no longer hold): INFEASIBLE."""
    from dataclasses import replace

    from auvplan._types import Status
    from auvplan.planners import PlannerSpec
    from auvplan.planners.core.base import PlanResult
    from auvplan.planners.core.vehicle_limits import enforce_limits
    from auvplan.sim.pipeline import planning_problem

    world, mission = build_toml(RIDGE)
    problem = planning_problem(world, mission)
    assert problem.limits is not None and problem.limits.max_pitch_deg == 20.0
    rise = 100.0 * math.tan(math.radians(30.0))
    two = np.array([[100.0, 200.0, -80.0], [200.0, 200.0, -80.0 + rise]])
    plan = PlanResult(Status.EXACT, two, 1.0, {}, 0, 0, 0.0, np.empty(0), "straight")
    out = enforce_limits(problem, PlannerSpec(), plan)
    assert out.status is Status.INFEASIBLE and out.message.startswith("the vehicle cannot fly this plan"), out.message
    x = np.linspace(100.0, 500.0, 9)
    nine = np.column_stack([x, np.full(9, 200.0), np.interp(x, [100.0, 200.0, 500.0], [-80.0, -80.0 + rise,
                                                                                         -80.0 + rise])])
    fixed = enforce_limits(problem, PlannerSpec(), replace(plan, path=nine))
    assert fixed.status is Status.EXACT and "depth profile repaired" in fixed.message
    assert np.abs(leg_pitch_deg(fixed.path)).max() <= 20.0 and np.array_equal(fixed.path[[0, -1]], nine[[0, -1]])
    timed = enforce_limits(problem, PlannerSpec(), replace(plan, path=nine, times=np.arange(9.0)))
    assert timed.status is Status.INFEASIBLE
