"""The compiled ellipsoid foot point is bit-identical to the numpy bisection it replaced (#35.3), which
runs instead when compiling is off (``NUMBA_DISABLE_JIT=1``)."""

from __future__ import annotations

import os
from collections.abc import Callable

import numpy as np
import pytest

from auvplan.runtime import jit as _jit
from auvplan.world.kernels import ellipsoid as ellipsoid_kernels
from auvplan.world.kernels.ellipsoid import foot_point, foot_point_kernel, foot_point_numpy
from auvplan.world.obstacles import Ellipsoid


def test_foot_point_kernel_matches_numpy_bit_for_bit() -> None:
    rng = np.random.default_rng(7)
    a = np.array([8.0, 4.0, 3.0])
    pts = np.concatenate([
        rng.normal(scale=10.0, size=(400, 3)),          # inside and outside
        rng.normal(scale=2.0, size=(100, 3)),           # deep inside
        [[0.0, 0.0, 0.0], [0.0, 0.0, 5.0], [9.0, 0.0, 0.0], [-0.0, -4.0, 0.0], [8.0, 0.0, 0.0]],
    ])
    got = foot_point_kernel(a, pts)
    want = foot_point_numpy(a, pts)
    assert np.array_equal(got, want)
    # the foot lies on the surface, and a surface point is its own foot (independent oracle)
    assert np.allclose(((got / a) ** 2).sum(axis=-1), 1.0, atol=1e-12)
    on = want[:50]
    assert np.allclose(foot_point_kernel(a, on), on, atol=1e-12)


def test_ellipsoid_distance_uses_the_kernel_on_a_turned_body() -> None:
    e = Ellipsoid((1.0, -2.0, 3.0), (8.0, 4.0, 3.0), yaw=0.7, pitch=0.2)
    pts = np.random.default_rng(3).normal(scale=9.0, size=(200, 3)) + np.array([1.0, -2.0, 3.0])
    pb = e.to_body(pts)
    foot = foot_point_numpy(np.array(e.semi_axes), pb)
    want = np.linalg.norm(pb - foot, axis=-1) * np.where(((pb / np.array(e.semi_axes)) ** 2).sum(-1) < 1, -1, 1)
    assert np.array_equal(e.distance(pts), want)
    # analytic: a point on the long axis at x = 12 (body frame) is 4 m from the surface
    tip = np.array([1.0, -2.0, 3.0]) + 12.0 * e._rot[:, 0]
    assert abs(float(e.distance(tip)) - 4.0) < 1e-12


def test_numpy_path_matches_the_kernel_on_awkward_points() -> None:
    # flattened and elongated bodies, points on the axes, on the surface, at the centre, far away, NaN
    rng = np.random.default_rng(11)
    for a in (np.array([50.0, 2.0, 0.5]), np.array([1.0, 1.0, 1.0]), np.array([3.0, 30.0, 7.0])):
        pts = np.concatenate([
            rng.normal(scale=float(a.max()), size=(300, 3)),
            rng.normal(scale=1e4, size=(20, 3)),
            np.diag(a), -np.diag(a) * 0.5, np.zeros((1, 3)), [[np.nan, 1.0, 0.0]],
        ])
        got, want = foot_point_numpy(a, pts), foot_point_kernel(a, pts)
        assert np.array_equal(got, want, equal_nan=True)


def test_foot_point_takes_the_numpy_path_when_compiling_is_off(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[str] = []

    def spy(name: str) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
        def run(a: np.ndarray, p: np.ndarray) -> np.ndarray:
            calls.append(name)
            return p
        return run

    monkeypatch.setattr(ellipsoid_kernels, "foot_point_numpy", spy("numpy"))
    monkeypatch.setattr(ellipsoid_kernels, "foot_point_kernel", spy("kernel"))
    pts = np.ones((2, 3))
    monkeypatch.setattr(ellipsoid_kernels, "jit_enabled", lambda: False)
    foot_point(np.ones(3), pts)
    monkeypatch.setattr(ellipsoid_kernels, "jit_enabled", lambda: True)
    foot_point(np.ones(3), pts)
    assert calls == ["numpy", "kernel"]
    # and _jit knows numba's switch
    assert _jit.jit_enabled() is (os.environ.get("NUMBA_DISABLE_JIT", "0") != "1")
