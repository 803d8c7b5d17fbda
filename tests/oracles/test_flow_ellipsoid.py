"""The exact flow past a triaxial ellipsoid (docs/flow.md): oracles from Lamb's solution and Carlson's R_D."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import elliprd

from auvplan.planners.core.params import FlowParams
from auvplan.planners.flow.design import offset_surface
from auvplan.planners.flow.ellipsoid import (
    EllipsoidBody,
    carlson_rd,
    design_ellipsoid_body,
    ellipsoid_coefficients,
    ellipsoid_disturbance,
)
from auvplan.planners.flow.field import FlowField
from auvplan.planners.flow.stream import integrate_streamlines
from auvplan.world import Ellipsoid

AXES = np.array([8.5, 4.5, 3.5])


def _surface(rng: np.random.Generator, a: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    q = v * a
    nrm = q / a**2
    return q, nrm / np.linalg.norm(nrm, axis=1, keepdims=True)


def test_carlson_rd_matches_scipy():
    """The compiled R_D equals scipy.special.elliprd to 1e-14 relative over six decades of arguments."""
    rng = np.random.default_rng(0)
    for x, y, z in 10.0 ** rng.uniform(-3, 3, (200, 3)):
        assert carlson_rd(x, y, z) == pytest.approx(elliprd(x, y, z), rel=1e-14)


def test_depolarisation_factors_sum_to_two():
    """α₁ + α₂ + α₃ = 2 (Lamb §114), α = abc (2/3) R_D: from K = abc/(2 − α)."""
    abc = float(np.prod(AXES))
    alpha = 2.0 - abc / ellipsoid_coefficients(AXES)
    assert alpha.sum() == pytest.approx(2.0, abs=1e-13)


def test_normal_velocity_vanishes_on_the_surface_for_random_streams():
    """U + ∇φ_d has no normal component on the ellipsoid (λ = 0), to 1e-9 of |U|, for 2 000 random streams."""
    rng = np.random.default_rng(1)
    q, n = _surface(rng, AXES, 2000)
    U = rng.normal(size=(2000, 3))
    u = U + ellipsoid_disturbance(q * (1.0 + 1e-14), U, AXES)
    assert np.max(np.abs((u * n).sum(axis=1)) / np.linalg.norm(U, axis=1)) < 1e-9


def test_sphere_limit_is_the_doublet():
    """Equal semi-axes R: the disturbance is the sphere doublet ∇(U·x R³ / (2 r³))."""
    rng = np.random.default_rng(2)
    R = 2.0
    p = rng.normal(size=(300, 3)) * 6.0
    p = p[np.linalg.norm(p, axis=1) > R]
    U = rng.normal(size=3)
    r = np.linalg.norm(p, axis=1, keepdims=True)
    exact = R**3 / 2.0 * (U / r**3 - 3.0 * (p @ U)[:, None] * p / r**5)
    np.testing.assert_allclose(ellipsoid_disturbance(p, U, [R, R, R]), exact, atol=1e-13)


def test_far_field_decays_as_the_cube():
    """Along any ray the disturbance falls as r⁻³: doubling r far away divides it by 8 (to 1 %)."""
    rng = np.random.default_rng(3)
    d = rng.normal(size=(20, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    U = np.array([0.3, -1.0, 0.4])
    near = np.linalg.norm(ellipsoid_disturbance(400.0 * d, U, AXES), axis=1)
    far = np.linalg.norm(ellipsoid_disturbance(800.0 * d, U, AXES), axis=1)
    np.testing.assert_allclose(near / far, 8.0, rtol=0.01)


def test_disturbance_is_the_gradient_of_the_potential():
    """∇φ_d against central differences of φ_d = Σ Uᵢ Kᵢ xᵢ (2/3) R_D(...+λ) (λ from the cubic, scipy R_D)."""
    rng = np.random.default_rng(4)
    K = ellipsoid_coefficients(AXES)
    U = np.array([0.7, -0.2, 0.5])

    def phi(x: np.ndarray) -> float:
        from scipy.optimize import brentq

        lam = brentq(lambda s: float(np.sum(x**2 / (AXES**2 + s))) - 1.0, 0.0, float(x @ x))
        d = AXES**2 + lam
        integ = [2.0 / 3.0 * elliprd(d[(i + 1) % 3], d[(i + 2) % 3], d[i]) for i in range(3)]
        return float(np.sum(U * K * x * integ))

    for _ in range(20):
        x = rng.normal(size=3) * 8.0
        if np.sum((x / AXES) ** 2) < 1.5:
            continue
        h = 1e-5
        num = np.array([(phi(x + h * e) - phi(x - h * e)) / (2 * h) for e in np.eye(3)])
        np.testing.assert_allclose(ellipsoid_disturbance(x[None], U, AXES)[0], num, atol=1e-8)


@pytest.mark.parametrize("goal", [(28.0, 28.0, 0.0), (0.0, 0.0, 35.0), (-20.0, 20.0, -20.0)])
def test_body_contains_the_inflated_obstacle_and_flow_is_tangent(goal):
    """The designed body holds all 18 240 points of the 0.5 m offset surface, its volume is 1.04× the
    inflated ellipsoid (8.5, 4.5, 3.5) for every goal, and the sink + disturbance flow is tangent to it."""
    ob = Ellipsoid((1.0, -2.0, 0.5), (8.0, 4.0, 3.0), yaw=0.3, pitch=0.2, roll=-0.1)
    body = design_ellipsoid_body(ob, np.array(goal), 1.0, 0.5, 0.016)
    assert body.inside(offset_surface(ob, 0.5, 95)).all()
    assert body.volume / (4.0 / 3.0 * np.pi * np.prod(AXES)) == pytest.approx(1.045, abs=0.005)
    rng = np.random.default_rng(5)
    q, n = _surface(rng, np.asarray(body.shape.semi_axes), 500)
    rot = body.shape._rot
    p = q @ rot.T + np.asarray(ob.center)
    u = body.velocity(p)
    assert np.max(np.abs((u * (n @ rot.T)).sum(axis=1)) / np.linalg.norm(u, axis=1)) < 1e-9


def test_front_point_is_a_stagnation_point():
    """The front point's flow vanishes (relative to the sink's speed there) and lies on the surface."""
    ob = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0))
    body = design_ellipsoid_body(ob, np.array([28.0, 28.0, 0.0]), 1.0, 0.5)
    f, n = body.front
    assert body.distance(f) == pytest.approx(0.0, abs=1e-9)
    us = 1.0 / (4.0 * np.pi * np.sum((f - [28.0, 28.0, 0.0]) ** 2))
    assert np.linalg.norm(body.velocity(f[None])[0]) < 1e-8 * us
    assert isinstance(body, EllipsoidBody) and n @ (np.array([28.0, 28.0, 0.0]) - f) < 0


def test_on_the_stagnation_line_the_rule_steps_aside_and_arrives():
    """A start exactly on the front stagnation streamline (long axis at the goal: the axis) arrives."""
    ob = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0), yaw=np.pi / 4)
    field = FlowField((ob,), np.array([28.0, 28.0, 0.0]), FlowParams(), 0.5)
    sl = integrate_streamlines(field, np.array([[-21.0, -21.0, 0.0]]))
    assert sl.status[0] == "arrived" and sl.deflections[0] >= 1
