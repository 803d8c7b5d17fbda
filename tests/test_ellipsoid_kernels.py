"""The compiled ellipsoid foot point is bit-identical to the numpy bisection it replaced (#35.3)."""

from __future__ import annotations

import numpy as np

from auvplan.world.ellipsoid_kernels import foot_point_kernel
from auvplan.world.obstacles import Ellipsoid


def _numpy_foot_point(a: np.ndarray, pb: np.ndarray) -> np.ndarray:
    """The numpy version of ``Ellipsoid._foot_point`` before it was compiled (the reference)."""
    sign = np.where(pb < 0, -1.0, 1.0)
    p = np.maximum(np.abs(pb), 1e-10 * a)
    outside = ((p / a) ** 2).sum(axis=-1) >= 1.0
    lo = np.where(outside, 0.0, -(a.min() ** 2))
    hi = np.where(outside, a.max() * np.linalg.norm(p, axis=-1), 0.0)
    a2 = a * a
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        pos = (((a * p) / (a2 + mid[:, None])) ** 2).sum(axis=-1) - 1.0 > 0
        lo = np.where(pos, mid, lo)
        hi = np.where(pos, hi, mid)
    t = 0.5 * (lo + hi)
    out: np.ndarray = sign * (a2 * p / (a2 + t[:, None]))
    return out


def test_foot_point_kernel_matches_numpy_bit_for_bit() -> None:
    rng = np.random.default_rng(7)
    a = np.array([8.0, 4.0, 3.0])
    pts = np.concatenate([
        rng.normal(scale=10.0, size=(400, 3)),          # inside and outside
        rng.normal(scale=2.0, size=(100, 3)),           # deep inside
        [[0.0, 0.0, 0.0], [0.0, 0.0, 5.0], [9.0, 0.0, 0.0], [-0.0, -4.0, 0.0], [8.0, 0.0, 0.0]],
    ])
    got = foot_point_kernel(a, pts)
    want = _numpy_foot_point(a, pts)
    assert np.array_equal(got, want)
    # the foot lies on the surface, and a surface point is its own foot (independent oracle)
    assert np.allclose(((got / a) ** 2).sum(axis=-1), 1.0, atol=1e-12)
    on = want[:50]
    assert np.allclose(foot_point_kernel(a, on), on, atol=1e-12)


def test_ellipsoid_distance_uses_the_kernel_on_a_turned_body() -> None:
    e = Ellipsoid((1.0, -2.0, 3.0), (8.0, 4.0, 3.0), yaw=0.7, pitch=0.2)
    pts = np.random.default_rng(3).normal(scale=9.0, size=(200, 3)) + np.array([1.0, -2.0, 3.0])
    pb = e.to_body(pts)
    foot = _numpy_foot_point(np.array(e.semi_axes), pb)
    want = np.linalg.norm(pb - foot, axis=-1) * np.where(((pb / np.array(e.semi_axes)) ** 2).sum(-1) < 1, -1, 1)
    assert np.array_equal(e.distance(pts), want)
    # analytic: a point on the long axis at x = 12 (body frame) is 4 m from the surface
    tip = np.array([1.0, -2.0, 3.0]) + 12.0 * e._rot[:, 0]
    assert abs(float(e.distance(tip)) - 4.0) < 1e-12
