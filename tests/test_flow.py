"""Potential-flow streamline planner (document 000): analytic oracles and the many-start claims."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.io import scenario as sc
from auvplan.planners import plan
from auvplan.planners.flow import (
    FlowField,
    FlowParams,
    blend_weights,
    design_rankine_body,
    integrate_streamlines,
    rankine_indicator,
    rankine_radius,
    rankine_stagnation_points,
    rankine_velocity,
    sphere_document_potential,
    sphere_document_velocity,
    sphere_exact_velocity,
    uniform_dipole_velocity,
)
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
    """METHODS.md §1.1: the document's potential has spurious sources (its Laplacian is not zero)."""
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


def test_rankine_body_contains_the_real_ellipsoid():
    e = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0), yaw=0.4)
    m, a2, basis = design_rankine_body(e, (30.0, 0.0, 0.0), 1.0, margin=0.5)
    th, ph = np.meshgrid(np.linspace(0, np.pi, 30), np.linspace(0, 2 * np.pi, 60))
    local = np.stack([8 * np.sin(th) * np.cos(ph), 4 * np.sin(th) * np.sin(ph), 3 * np.cos(th)], -1).reshape(-1, 3)
    pts = local @ e._rot.T
    a1 = 30.0
    assert np.all(rankine_indicator(pts @ basis, m, a2, 1.0, a1) < 0)


def test_uniform_dipole_cannot_reach_a_fixed_goal():
    """Reference [15]'s field flows past: no streamline converges on the goal."""
    p = np.array([[-30.0, 1.0, 0.5]])
    u = uniform_dipole_velocity(p, C * 0, 4.0, (1.0, 0.0, 0.0))
    assert u[0, 0] > 0.9
    far = uniform_dipole_velocity(np.array([[30.0, 0.0, 0.0]]), C * 0, 4.0, (1.0, 0.0, 0.0))
    assert far[0, 0] > 0.99  # the flow keeps going past x = 30: there is no sink to stop at


def _starts(field, box, n, seed):
    rng = np.random.default_rng(seed)
    p = rng.uniform(box[0], box[1], (4 * n, 3))
    p = p[(field.distances(p).min(axis=1) > 0.2) & (np.linalg.norm(p - field.target, axis=1) > 2.0)]
    return p[~field.inside_body(p)][:n]


def _check_scene(world, goal, n=500, min_arrival=1.0):
    field = FlowField(world.obstacles, goal, FlowParams(), world.margins.obstacle)
    starts = _starts(field, (-15, 25), n, 0)
    assert len(starts) == n
    sl = integrate_streamlines(field, starts)
    assert sl.arrived.mean() >= min_arrival
    margin = world.margins.obstacle
    for path, ok in zip(sl.paths, sl.arrived):
        seg = np.stack([path[:-1], path[1:]], axis=1)
        # no penetration of any real obstacle on the dense polyline; clearance ≥ the margin on arrival
        for ob in world.obstacles:
            assert not ob.segments_hit(seg, 0.0).any()
            if ok:
                assert not ob.segments_hit(seg, margin).any()
    return sl


def test_flow_spheres_500_starts():
    world, mission = sc.build(sc.load("flow-spheres"))
    _check_scene(world, np.asarray(mission.goal))


@pytest.mark.parametrize("goal", [(30.0, 0.0, 0.0), (28.0, 28.0, 0.0)])
def test_flow_ellipsoid_500_starts(goal):
    world, _ = sc.build(sc.load("flow-ellipsoid"))
    _check_scene(world, np.asarray(goal))


def test_flow_ellipsoid_plus_spheres():
    """Blending a Rankine body with spheres: the blended field is not tangent to the body, so a few
    streamlines (3 of 500 here) stall against the rear of the ellipsoid; none enters any obstacle."""
    from dataclasses import replace

    world, _ = sc.build(sc.load("flow-ellipsoid"))
    world = replace(world, obstacles=world.obstacles + (Sphere((15.0, 5.0, 0.0), 3.0), Sphere((-12.0, -6.0, 2.0), 2.5)))
    sl = _check_scene(world, np.array([30.0, 0.0, 0.0]), min_arrival=0.99)
    assert set(sl.status[~sl.arrived]) <= {"contact"}


def test_collinear_start_is_nudged_and_arrives():
    world, _ = sc.build(sc.load("flow-ellipsoid"))
    field = FlowField((Sphere((0.0, 0.0, 0.0), 5.0),), (30.0, 0.0, 0.0), FlowParams(), 0.5)
    sl = integrate_streamlines(field, np.array([[-30.0, 0.0, 0.0]]))
    assert sl.arrived.all()


@pytest.mark.parametrize("name", ["flow-spheres", "flow-ellipsoid"])
def test_plan_flow_status(name):
    world, mission = sc.build(sc.load(name))
    r = plan(planning_problem(world, mission), mission.planner)
    assert r.status is Status.EXACT and r.planner == "flow"
    assert r.cost_terms["min_clearance_m"] >= world.margins.obstacle - 1e-9
    assert np.allclose(r.path[0], mission.start) and np.allclose(r.path[-1], mission.goal)


def test_flow_reports_the_seabed():
    """The flow knows only the obstacles: a streamline through the seabed is INFEASIBLE, not hidden."""
    from auvplan.planners import PlannerSpec, PlanningProblem
    from helpers import flat_world

    world = flat_world(depth=100.0, size=1000.0, min_altitude=5.0)
    r = plan(PlanningProblem(world, [100.0, 100.0, -50.0], [900.0, 900.0, -50.0], 1.5), PlannerSpec(name="flow"))
    assert r.status is Status.EXACT  # open water: straight to the sink
    x = np.arange(0.0, 1001.0, 50.0)
    from auvplan.world import Terrain, World

    z = np.where(np.abs(x - 500.0)[None, :] < 60, -20.0, -100.0) * np.ones((x.size, 1))
    ridge = World(world.bounds, Terrain(x, x, z), margins=world.margins)
    r = plan(PlanningProblem(ridge, [100.0, 100.0, -50.0], [900.0, 900.0, -50.0], 1.5), PlannerSpec(name="flow"))
    assert r.status is Status.INFEASIBLE and "seabed" in r.message
