"""Tail-first legs in the energy check: the budget times a leg flown tail-first with the far root.

Oracles: in a steady uniform current stronger than the vehicle the leg times are ``L / (c·ŝ ∓ √(V² −
|c⊥|²))`` (analytic) and the energy ``P(V) T``; on ``rotary-tide`` leaving at +18 h (no forward path
exists, the plan flies tail-first legs) the budget of the mission route, with the follower's flags, is
feasible and takes the plan's own time (the planner's integrator, an independent one) within 0.5 %.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.endurance import EnergyModel, assess, ground_speed, mission_budget
from auvplan.io.scenario import loader as scenario
from auvplan.sim import planned_route
from auvplan.sim.pipeline import route_tail
from auvplan.world import GriddedCurrent

V = 1.5


def _uniform(u: float, v: float):
    world, mission = scenario.build(scenario.load("rotary-tide"))
    field = GriddedCurrent([-1e5, 1e5], [-1e5, 1e5], [0.0], np.full((2, 2, 1), u), np.full((2, 2, 1), v))
    return replace(world, currents=field), mission


def test_both_roots_of_the_ground_speed():
    c, e = np.array([2.0, 0.3, 0.0]), np.array([1.0, 0.0, 0.0])
    root = math.sqrt(V * V - 0.09)
    assert ground_speed(c, e, V) == pytest.approx(2.0 + root, rel=1e-12)
    assert ground_speed(c, e, V, tail=True) == pytest.approx(2.0 - root, rel=1e-12)
    assert math.isnan(ground_speed(np.array([0.5, 0.0, 0.0]), e, V, tail=True))  # carried backwards


def test_budget_times_a_tail_first_leg_with_the_far_root():
    """A 1 km leg east tail-first, then 1 km forward, in (2.0, 0.3) m/s: analytic times and energies."""
    world, mission = _uniform(2.0, 0.3)
    model = EnergyModel.from_vehicle(mission.vehicle)
    root = math.sqrt(V * V - 0.09)
    route = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0], [2000.0, 0.0, -50.0]])
    b = mission_budget(world, route, model, V, 0.0, 100.0, tail=[True, False])
    legs = np.array([1000.0 / (2.0 - root), 1000.0 / (2.0 + root)])
    assert b.status is Status.EXACT
    np.testing.assert_allclose(b.t_end - b.t_start, legs, rtol=1e-9)
    np.testing.assert_allclose(b.energy_leg_wh, float(model.power(V)) * legs / 3600.0, rtol=1e-9)
    forward = mission_budget(world, route, model, V, 0.0, 100.0)  # no flags: both forward, as before
    np.testing.assert_allclose(forward.t_end - forward.t_start, 1000.0 / (2.0 + root), rtol=1e-9)


def test_tail_first_where_the_current_cannot_carry_the_vehicle_is_infeasible():
    world, mission = _uniform(0.5, 0.0)
    model = EnergyModel.from_vehicle(mission.vehicle)
    route = np.array([[0.0, 0.0, -50.0], [1000.0, 0.0, -50.0]])
    b = mission_budget(world, route, model, V, tail=[True])
    assert b.status is Status.INFEASIBLE and "too weak to carry the vehicle tail-first" in b.message
    with pytest.raises(ValueError, match="one flag per leg"):
        mission_budget(world, route, model, V, tail=[True, False])


def test_rotary_tide_tail_first_mission_is_budgeted_as_planned():
    """+18 h: forward legs only, the budget said INFEASIBLE (leg 8: the current beats the vehicle)."""
    sc = scenario.load("rotary-tide")
    assert sc.mission.start_time == "2026-06-15T21:00:00Z"
    world, mission = scenario.build(replace(sc, mission=replace(sc.mission, start_time="2026-06-16T15:00:00Z")))
    t = replace(mission.planner.timeopt, tail_first=True, method="lattice")
    mission = replace(mission, planner=replace(mission.planner, timeopt=t))
    planned, route = planned_route(world, mission, mission.seed)
    assert planned is not None and route is not None and planned.tail is not None and planned.tail.any()
    tail = route_tail(route, planned.path, planned.tail)
    assert tail is not None and tail.any()
    e = assess(world, route, mission.vehicle, mission.endurance, tail=tail)
    assert e.status is Status.EXACT
    assert e.budget.duration_s == pytest.approx(float(planned.cost_terms["duration_s"]), rel=0.005)
    assert assess(world, route, mission.vehicle, mission.endurance).status is Status.INFEASIBLE
