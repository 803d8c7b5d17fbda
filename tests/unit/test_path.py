"""B-spline paths: the corrected uniform basis, clamped ends, derivatives, population sampling."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.path import (
    BSplinePath,
    arc_length,
    basis_matrix,
    densify,
    polyline_length,
    sample_population,
    uniform_cubic_basis,
)


def test_uniform_basis_partition_of_unity_and_symmetry():
    u = np.linspace(0, 1, 101)
    B = uniform_cubic_basis(u)
    assert np.allclose(B.sum(axis=1), 1.0)
    assert np.all(B >= 0)
    assert np.allclose(B[:, 0], B[::-1, 3]) and np.allclose(B[:, 1], B[::-1, 2])
    assert np.allclose(B[0], [1 / 6, 4 / 6, 1 / 6, 0])  # does not interpolate its end control point


def test_clamped_basis_interior_span_is_the_uniform_basis():
    """Where all four overlapping basis functions have uniform knots, the clamped spline is eq. 6."""
    k = 10  # knots 0,0,0,0,1/7,...,6/7,1,1,1,1: the span [3/7, 4/7] uses N3..N6, all uniform
    n = 701
    B = basis_matrix(k, n)
    u = np.linspace(0, 1, n)
    mid = (u > 3 / 7 + 1e-9) & (u < 4 / 7 - 1e-9)
    local = (u[mid] - 3 / 7) * 7
    assert mid.sum() > 50
    assert np.allclose(B[mid][:, 3:7], uniform_cubic_basis(local))


@pytest.mark.parametrize("k", [4, 5, 8, 12])
def test_partition_of_unity_and_end_interpolation(k):
    B = basis_matrix(k, 257)
    assert np.allclose(B.sum(axis=1), 1.0) and np.all(B >= -1e-15)
    assert np.allclose(B[0], np.eye(k)[0]) and np.allclose(B[-1], np.eye(k)[-1])
    ctrl = np.random.default_rng(k).normal(size=(3, k, 3))
    pts = sample_population(ctrl, 257)
    assert np.allclose(pts[:, 0], ctrl[:, 0]) and np.allclose(pts[:, -1], ctrl[:, -1])


def test_derivatives_match_finite_differences():
    ctrl = np.random.default_rng(1).normal(size=(8, 3)) * 100
    path = BSplinePath(ctrl)
    u = np.linspace(0.05, 0.95, 37)
    h = 1e-6
    fd1 = (path(u + h) - path(u - h)) / (2 * h)
    assert np.allclose(path(u, 1), fd1, rtol=1e-5, atol=1e-4)
    fd2 = (path(u + 1e-7, 1) - path(u - 1e-7, 1)) / 2e-7
    assert np.allclose(path(u, 2), fd2, rtol=1e-4, atol=1.0)
    d1 = sample_population(ctrl[None], 37, order=1)[0]
    assert np.allclose(d1, path(np.linspace(0, 1, 37), 1))


def test_geometry_of_a_straight_and_a_circular_path():
    line = BSplinePath(np.linspace([0, 0, 0], [300, 400, -100], 6))
    assert line.length() == pytest.approx(np.linalg.norm([300, 400, -100]), rel=1e-9)
    assert np.allclose(line.curvature(np.linspace(0, 1, 11)), 0.0, atol=1e-12)
    assert np.allclose(line.pitch([0.5]), np.arctan2(-100, 500))
    assert np.allclose(line.tangent([0.3]), np.array([300, 400, -100]) / np.linalg.norm([300, 400, -100]))
    # a dense control polygon on a circle gives a curve of curvature close to 1/R
    th = np.linspace(0, np.pi, 60)
    arc = BSplinePath(np.c_[100 * np.cos(th), 100 * np.sin(th), np.zeros_like(th)])
    assert np.allclose(arc.curvature(np.linspace(0.2, 0.8, 9)), 0.01, rtol=0.01)


def test_arc_length_of_a_three_four_five_polyline():
    """Arc length at each vertex: 0, then the 3-4-5 legs' sums; its last value is polyline_length."""
    p = np.array([[0.0, 0.0, 0.0], [3.0, 4.0, 0.0], [3.0, 4.0, 12.0], [3.0, 4.0, 12.0]])
    np.testing.assert_array_equal(arc_length(p), [0.0, 5.0, 17.0, 17.0])
    assert arc_length(p)[-1] == polyline_length(p) == 17.0
    assert arc_length(p[:1]).tolist() == [0.0]


def test_densify_keeps_every_vertex_and_caps_the_step():
    p = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 3.0, 0.0]])
    d = densify(p, 4.0)
    assert len(d) == 3 + 1 + 1 + 0 and np.all(np.diff(arc_length(d)) <= 4.0 + 1e-12)
    assert all(any(np.array_equal(v, q) for q in d) for v in p)
    assert arc_length(d)[-1] == pytest.approx(13.0)

