"""The turn-limited path along a flow (planners/flow/turning.py): analytic circle, the vehicle's turn per
step on the Fig. 8 scene, and the status where no flyable path exists (issue 36, point 1a)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.planners.core.params import FlowParams
from auvplan.planners.flow.field import FlowField
from auvplan.planners.flow.stream import integrate_streamlines
from auvplan.planners.flow.turning import turn_limited_path
from auvplan.sim import planning_problem
from auvplan.world import Sphere


def _turns(path):
    d = np.diff(path, axis=0)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.arccos(np.clip((d[:-1] * d[1:]).sum(axis=1), -1.0, 1.0))


def _free(a, b):
    return True


def test_a_right_angle_is_flown_on_the_turn_circle():
    """Flow due south, heading east: the vehicle turns at full rate, so its nodes are a regular polygon of
    side h and exterior angle h/R - on the circle of radius R_h = h / (2 sin(h / 2R)) through the start, its
    centre R_h cos(h/2R) to the right of the first leg's midpoint - then it flies south."""
    R, h = 10.0, 0.25
    out = turn_limited_path(lambda x: np.array([0.0, -1.0, 0.0]), [0.0, 0.0, 0.0], [0.0, -1e3, 0.0], R, h, 0.5,
                            _free, max_steps=200, heading=[1.0, 0.0, 0.0])
    a = h / R  # the first leg is already turned by a from the initial heading
    rh = h / (2.0 * np.sin(a / 2.0))
    p = out.path[: int(np.pi / 2 / a)]
    mid = 0.5 * h * np.array([np.cos(a), -np.sin(a), 0.0])
    centre = mid + rh * np.cos(a / 2.0) * np.array([-np.sin(a), -np.cos(a), 0.0])
    np.testing.assert_allclose(np.linalg.norm(p - centre, axis=1), rh, rtol=1e-9)
    assert np.allclose(np.diff(out.path[-5:], axis=0) / h, [0.0, -1.0, 0.0])
    assert _turns(out.path).max() <= a + 1e-12


def test_fig8_flyable_plan_turns_within_the_vehicle():
    """The built-in's plan (default ``path = "flyable"``): every turn between steps at most step / R (the
    vehicle's turn over that step, R = 10 m), passes the exact test, arrives; the pure streamline
    (``path = "streamline"``) is still there: the integrator's own polyline."""
    world, mission = sc.build(sc.load("flow-fig8"))
    problem = planning_problem(world, mission)
    R = problem.limits.turn_radius_m
    r = plan(problem, mission.planner)
    assert r.status is Status.EXACT and world.path_free(r.path)
    steps = np.linalg.norm(np.diff(r.path, axis=0), axis=1)
    assert _turns(r.path[:-1]).max() <= steps[0] / R + 1e-9
    pure = plan(problem, replace(mission.planner, flow=replace(mission.planner.flow, path="streamline")))
    field = FlowField(world.obstacles, mission.goal, mission.planner.flow, world.margins.obstacle)
    np.testing.assert_allclose(pure.path, integrate_streamlines(field, problem.start[None]).paths[0])
    assert len(pure.path) != len(r.path)


def test_a_start_facing_a_surface_is_reported_unflyable():
    """A start 0.5 m outside the margin of a 3 m sphere, the goal straight through it: the flow turns at the
    surface, a vehicle with R = 10 m cannot: the plan is INFEASIBLE and says so (no silent corner); the
    streamline itself arrives (planned without the vehicle's limits, which would reject its corner)."""
    world, mission = sc.build(sc.load("flow-fig8"))
    ball = Sphere((0.0, 0.0, 0.0), 3.0)
    world = replace(world, obstacles=(ball,))
    problem = replace(planning_problem(world, mission), start=np.array([-4.0, 0.0, 0.0]),
                      goal=np.array([30.0, 0.0, 0.0]))
    r = plan(problem, mission.planner)
    assert r.status is Status.INFEASIBLE and "cannot follow" in r.message
    pure = plan(replace(problem, limits=None), replace(mission.planner, flow=replace(mission.planner.flow,
                                                                                     path="streamline")))
    assert pure.status is Status.EXACT and np.degrees(_turns(pure.path).max()) > 45.0


def test_path_must_be_named():
    with pytest.raises(ValueError, match="path"):
        FlowParams(path="smooth")
