"""Potential-flow streamline planner (document 000): analytic oracles and the many-start claims."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.io.scenario import loader as sc
from auvplan.planners import PlannerSpec, PlanningProblem, plan
from auvplan.planners.core.params import FlowParams
from auvplan.planners.flow.elements import (
    rankine_indicator,
    rankine_radius,
    rankine_stagnation_points,
    rankine_velocity,
    sphere_document_potential,
    sphere_document_velocity,
    sphere_exact_velocity,
    uniform_dipole_velocity,
)
from auvplan.planners.flow.field import (
    FlowField,
    blend_weights,
)
from auvplan.planners.flow.stream import integrate_streamlines
from auvplan.sim import planning_problem
from auvplan.world import Ellipsoid, Sphere

C = np.array([1.0, 2.0, 3.0])
A = 4.0
T = np.array([20.0, 25.0, 30.0])


def _surface(n=2000, seed=0):
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    return C + A * v, v


def _outside(n=300, seed=1):
    rng = np.random.default_rng(seed)
    p = C + rng.normal(size=(n, 3)) * 8
    return p[(np.linalg.norm(p - C, axis=1) > A + 0.3) & (np.linalg.norm(p - T, axis=1) > 0.3)]


@pytest.mark.parametrize("target", [T, np.array([1.0, 2.0, 8.0]), np.array([-30.0, 2.0, 3.0])])
def test_exact_field_no_penetration(target):
    p, n = _surface()
    u = sphere_exact_velocity(p, C, A, target)
    assert np.max(np.abs((u * n).sum(axis=1)) / np.linalg.norm(u, axis=1)) <= 1e-9


def test_exact_field_is_divergence_free():
    p = _outside()
    h = 1e-5
    div = sum((sphere_exact_velocity(p + h * e, C, A, T) - sphere_exact_velocity(p - h * e, C, A, T))[:, i] / (2 * h)
              for i, e in enumerate(np.eye(3)))
    scale = np.linalg.norm(sphere_exact_velocity(p, C, A, T), axis=1) / np.linalg.norm(p - C, axis=1)
    assert np.all(np.abs(div) <= 1e-6 * scale + 1e-12)


def test_exact_field_points_to_the_goal_far_away():
    far = np.array([[500.0, -300.0, 100.0]])
    u = sphere_exact_velocity(far, C, A, T)[0]
    assert np.dot(u, T - far[0]) / (np.linalg.norm(u) * np.linalg.norm(T - far[0])) > 0.999


def test_document_field_is_the_gradient_of_its_potential():
    p = _outside()
    h = 1e-5
    fd = np.stack([(sphere_document_potential(p + h * e, C, A, T) - sphere_document_potential(p - h * e, C, A, T))
                   / (2 * h) for e in np.eye(3)], axis=1)
    u = sphere_document_velocity(p, C, A, T)
    assert np.allclose(u, fd, rtol=1e-6, atol=1e-12)
    s, n = _surface()
    ud = sphere_document_velocity(s, C, A, T)
    assert np.max(np.abs((ud * n).sum(axis=1)) / np.linalg.norm(ud, axis=1)) <= 1e-9  # zero normal flux too


def test_document_field_is_not_harmonic():
    """docs/methods.md §1.1: the document's potential has spurious sources (its Laplacian is not zero)."""
    p = _outside()[:50]
    h = 1e-3
    lap = sum(sphere_document_potential(p + h * e, C, A, T) + sphere_document_potential(p - h * e, C, A, T)
              - 2 * sphere_document_potential(p, C, A, T) for e in np.eye(3)) / h**2
    assert np.abs(lap).max() > 1e-4 * np.abs(sphere_document_potential(p, C, A, T)).max()


def test_weights():
    rng = np.random.default_rng(0)
    d = rng.uniform(0.1, 10, (100, 4))
    assert np.allclose(blend_weights(d).sum(axis=1), 1.0)
    w3 = blend_weights(np.full((1, 3), 2.0), "document")
    assert np.allclose(w3.sum(), 3 / 2**2)  # n / 2^(n-1): the document's weights do not sum to 1
    touching = blend_weights(np.array([[1e-9, 3.0, 5.0]]), "document")
    assert touching[0, 0] == pytest.approx(1.0, abs=1e-6)


def test_rankine_body_closed_forms():
    m, a2, Q, a1 = 0.5, 2.0, 1.0, 30.0
    xf, xr = rankine_stagnation_points(m, a2, Q, a1)
    assert xf < -a2 and a2 < xr < a1
    u = rankine_velocity(np.array([[xf, 0, 0], [xr, 0, 0]]), m, a2, Q, a1)
    assert np.abs(u).max() < 1e-12
    # the front equation's spurious root in (-a2, 0) is not a stagnation point of the flow
    R0 = rankine_radius(m, a2, Q, a1)
    assert rankine_indicator(np.array([[0.0, R0, 0.0]]), m, a2, Q, a1)[0] == pytest.approx(0.0, abs=1e-12)
    assert rankine_indicator(np.array([[0.0, 0.99 * R0, 0.0]]), m, a2, Q, a1)[0] < 0  # inside
    assert rankine_indicator(np.array([[0.0, 1.01 * R0, 0.0]]), m, a2, Q, a1)[0] > 0  # outside
    # the indicator is the Stokes stream function: the flow runs along its level sets (u · ∇F = 0)
    rng = np.random.default_rng(2)
    p = rng.uniform(-10, 10, (200, 3))
    p = p[np.abs(p[:, 1]) + np.abs(p[:, 2]) > 0.5]
    h = 1e-6
    grad = np.stack([(rankine_indicator(p + h * e, m, a2, Q, a1) - rankine_indicator(p - h * e, m, a2, Q, a1))
                     / (2 * h) for e in np.eye(3)], axis=1)
    uu = rankine_velocity(p, m, a2, Q, a1)
    cos = np.abs((uu * grad).sum(axis=1)) / (np.linalg.norm(uu, axis=1) * np.linalg.norm(grad, axis=1))
    assert cos.max() < 1e-6


def test_uniform_dipole_cannot_reach_a_fixed_goal():
    """Reference [15]'s field flows past: no streamline converges on the goal."""
    p = np.array([[-30.0, 1.0, 0.5]])
    u = uniform_dipole_velocity(p, C * 0, 4.0, (1.0, 0.0, 0.0))
    assert u[0, 0] > 0.9
    far = uniform_dipole_velocity(np.array([[30.0, 0.0, 0.0]]), C * 0, 4.0, (1.0, 0.0, 0.0))
    assert far[0, 0] > 0.99  # the flow keeps going past x = 30: there is no sink to stop at


ELLIPSOID = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0))
SPHERES = (Sphere((15.0, 5.0, 0.0), 3.0), Sphere((-12.0, -6.0, 2.0), 2.5))
GOAL = np.array([30.0, 0.0, 0.0])


def _starts(field, n, seed, box=(-15.0, 25.0)):
    """``n`` uniform starts in the box outside every inflated obstacle and 2 m from the goal (none dropped later)."""
    rng = np.random.default_rng(seed)
    p = rng.uniform(box[0], box[1], (6 * n, 3))
    p = p[(field.clearance(p) > 0) & (np.linalg.norm(p - field.target, axis=1) > 2.0)][:n]
    assert len(p) == n
    return p


def _penetrations(obstacles, paths, margin):
    """Streamlines that come closer than ``margin`` to a real obstacle (exact segment tests)."""
    bad = 0
    for path in paths:
        seg = np.stack([path[:-1], path[1:]], axis=1)
        bad += any(ob.segments_hit(seg, margin).any() for ob in obstacles)
    return bad


def _scene(obstacles, goal, n, min_arrival=1.0, seed=0):
    field = FlowField(obstacles, goal, FlowParams(), 0.5)
    sl = integrate_streamlines(field, _starts(field, n, seed))
    assert len(sl.paths) == n and sl.arrived.mean() >= min_arrival, dict(zip(*np.unique(sl.status, return_counts=True)))
    assert _penetrations(obstacles, sl.paths, 0.5) == 0
    return sl


def test_flow_spheres_500_starts():
    world, mission = sc.build(sc.load("flow-spheres"))
    _scene(world.obstacles, np.asarray(mission.goal), 500)


def test_flow_ellipsoid_500_starts():
    """The issue's claim: 500 starts outside the inflated ellipsoid, none dropped, ≥ 99.5 % arrive, 0 penetrate."""
    _scene((ELLIPSOID,), GOAL, 500, min_arrival=0.995)


@pytest.mark.parametrize("goal", [(28.0, 28.0, 0.0)])
def test_flow_ellipsoid_rotated_goal(goal):
    _scene((ELLIPSOID,), np.asarray(goal), 200, min_arrival=0.995, seed=1)


def test_flow_ellipsoid_plus_spheres():
    """Blending bodies with spheres (weights on the distance to the bodies): every start arrives."""
    sl = _scene((ELLIPSOID,) + SPHERES, GOAL, 300, min_arrival=0.995, seed=2)
    assert set(sl.status[~sl.arrived]) <= {"contact", "stagnation"}


def test_starts_inside_the_body_leave_it_and_arrive():
    """Starts between the inflated ellipsoid and its body: exit along the body's normal, then the streamline."""
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5)
    rng = np.random.default_rng(3)
    p = rng.uniform(-9.5, 9.5, (20000, 3)) * np.array([1.0, 0.55, 0.45])
    p = p[(field.clearance(p) > 0) & field.inside_body(p)][:40]
    assert len(p) == 40
    sl = integrate_streamlines(field, p)
    assert sl.exits.all() and sl.arrived.all()
    assert _penetrations((ELLIPSOID,), sl.paths, 0.5) == 0
    assert all(np.allclose(q[0], s) for q, s in zip(sl.paths, p))  # the path starts at the start


def test_fig8_case_arrives():
    """Document 000 Fig. 8: ellipsoid plus spheres, start (−30, 0, −5), goal (30, 0, 0)."""
    field = FlowField((ELLIPSOID,) + SPHERES, GOAL, FlowParams(), 0.5)
    sl = integrate_streamlines(field, np.array([[-30.0, 0.0, -5.0]]))
    assert sl.arrived[0] and sl.min_distance[0] > 0
    assert _penetrations((ELLIPSOID,) + SPHERES, sl.paths, 0.5) == 0


@pytest.mark.parametrize("start", [(-9.0, 0.0, 0.0), (-30.0, 0.0, 0.0), (-9.0, 1e-7, 0.0), (9.0, 0.0, 0.0),
                                   (-9.0, 0.0, -1.0), (-30.0, 0.0, 0.0)])
def test_tip_and_axis_starts_arrive(start):
    """1 m off the ellipsoid's tips and on the obstacle-goal axis: the front stagnation rule takes them round."""
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5)
    sl = integrate_streamlines(field, np.array([start]))
    assert sl.arrived[0] and _penetrations((ELLIPSOID,), sl.paths, 0.5) == 0


def test_on_axis_rule_goes_round_the_thin_side():
    """(8, 4, 3) with the axis along x: thinnest across the axis along z, so an on-axis start goes over (+z)."""
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5)
    sl = integrate_streamlines(field, np.array([[-30.0, 0.0, 0.0]]))
    path = sl.paths[0]
    assert sl.deflections[0] == 1
    assert path[:, 2].max() > 3.5 and np.abs(path[:, 1]).max() < 1e-6
    turned = FlowField((Ellipsoid((0.0, 0.0, 0.0), (8.0, 3.0, 4.0)),), GOAL, FlowParams(), 0.5)
    q = integrate_streamlines(turned, np.array([[-30.0, 0.0, 0.0]])).paths[0]
    assert np.abs(q[:, 1]).max() > 3.5 and np.abs(q[:, 2]).max() < 1e-6  # now round the side (y)


def test_on_axis_sphere_start_arrives():
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), GOAL, FlowParams(), 0.5)
    sl = integrate_streamlines(field, np.array([[-30.0, 0.0, 0.0]]))
    assert sl.arrived.all() and sl.deflections[0] == 1 and sl.min_distance[0] >= 0


def test_start_inside_the_inflated_obstacle_is_reported():
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5)
    sl = integrate_streamlines(field, np.array([[-8.2, 0.0, 0.0]]))
    assert sl.status[0] == "inside_obstacle"


def test_uniform_field_misses_a_fixed_goal():
    """Document 000 Fig. 5 baseline: uniform flow + dipoles passes the spheres but does not converge on the goal."""
    world, mission = sc.build(sc.load("flow-spheres"))
    goal = np.asarray(mission.goal)
    field = FlowField(world.obstacles, goal, FlowParams(field="uniform"), 0.5, direction=goal + 5.0)
    starts = _starts(field, 100, 4, box=(-15.0, 0.0))
    sl = integrate_streamlines(field, starts)
    assert sl.arrived.mean() < 0.1 and (sl.status == "missed").mean() > 0.8
    assert _penetrations(world.obstacles, sl.paths, 0.5) == 0
    r = plan(planning_problem(world, mission), PlannerSpec(name="flow", flow=FlowParams(field="uniform")))
    assert r.status is Status.INFEASIBLE and "uniform" in r.message


def test_document_sizing_lets_streamlines_into_the_ellipsoid():
    """The document's Rankine sizing: the ellipsoid sticks out of the body (docs/methods.md §1.4)."""
    field = FlowField((ELLIPSOID,), GOAL, FlowParams(rankine="document"), 0.5)
    body = field.bodies[0]
    from auvplan.planners.flow.design import offset_surface

    assert not body.inside(offset_surface(ELLIPSOID, 0.5)).all()
    near_axis = np.array([[-30.0, 0.2 * np.cos(a), 0.2 * np.sin(a)] for a in (0.0, 2.0, 4.0)])
    sl = integrate_streamlines(field, near_axis)
    # streamlines close to the dividing surface run into the part of the ellipsoid outside the body
    assert (~sl.arrived | (sl.corrections > 0)).all()
    assert integrate_streamlines(FlowField((ELLIPSOID,), GOAL, FlowParams(), 0.5), near_axis).arrived.all()


@pytest.mark.parametrize("name", ["flow-spheres", "flow-ellipsoid"])
def test_plan_flow_status(name):
    world, mission = sc.build(sc.load(name))
    r = plan(planning_problem(world, mission), mission.planner)
    assert r.status is Status.EXACT and r.planner == "flow"
    assert r.cost_terms["min_clearance_m"] >= world.margins.obstacle - 1e-9
    assert np.allclose(r.path[0], mission.start) and np.allclose(r.path[-1], mission.goal)


def test_flow_over_a_flat_seabed_and_a_ridge():
    """A flat seabed is a mirror plane (streamlines keep the minimum altitude); a ridge is named as the reason."""
    from auvplan.world import Terrain, World
    from helpers import flat_world

    world = flat_world(depth=100.0, size=1000.0, min_altitude=5.0, obstacles=(Sphere((500.0, 500.0, -84.0), 8.0),))
    bare = FlowField(world.obstacles, [900.0, 900.0, -93.0], FlowParams(), 0.0)
    below = integrate_streamlines(bare, np.array([[100.0, 100.0, -93.0]])).paths[0][:, 2].min()
    assert below < -95.0  # without the plane the flow round the sphere dips under the minimum altitude
    r = plan(PlanningProblem(world, [100.0, 100.0, -93.0], [900.0, 900.0, -93.0], 1.5), PlannerSpec(name="flow"))
    assert r.status is Status.EXACT and r.path[:, 2].min() >= -95.0
    mirrored = FlowField(world.obstacles, [900.0, 900.0, -93.0], FlowParams(), 0.0, plane=-95.0)
    rng = np.random.default_rng(0)
    p = np.column_stack([rng.uniform(0, 1000, (60, 2)), rng.uniform(-94.9, -20.0, 60)])
    sl = integrate_streamlines(mirrored, p[mirrored.clearance(p) > 0])
    assert sl.arrived.all() and min(q[:, 2].min() for q in sl.paths) >= -95.0
    x = np.arange(0.0, 1001.0, 50.0)
    z = np.where(np.abs(x - 500.0)[None, :] < 60, -20.0, -100.0) * np.ones((x.size, 1))
    ridge = World(world.bounds, Terrain(x, x, z), margins=world.margins)
    r = plan(PlanningProblem(ridge, [100.0, 100.0, -50.0], [900.0, 900.0, -50.0], 1.5), PlannerSpec(name="flow"))
    assert r.status is Status.INFEASIBLE and "seabed is not locally flat" in r.message


def test_cli_run_with_the_flow_planner(tmp_path, capsys):
    from auvplan.cli import main

    assert main(["run", "flow-ellipsoid", "--planner", "flow", "--json"]) == 0
    assert main(["run", "salish-shelf", "--planner", "flow", "--json"]) == 1
    assert "not locally flat" in capsys.readouterr().out
