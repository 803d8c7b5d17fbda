"""The static shapes' public vertical extent ``z_range`` (what the simulator's depth bands use)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize
from scipy.spatial.transform import Rotation

from auvplan.sim.loop import _depth_band
from auvplan.world.obstacles import Ellipsoid, Sphere

N_SAMPLES = 100_000


def _surface(e: Ellipsoid, u: np.ndarray) -> np.ndarray:
    """World points of the surface for unit vectors ``u`` ``(N, 3)``, built with scipy's rotation (the
    shape's yaw/pitch/roll convention: intrinsic z-y-x, positive pitch lifting the body x axis)."""
    rot = Rotation.from_euler("ZYX", [e.yaw, -e.pitch, e.roll])
    out: np.ndarray = np.asarray(e.center) + rot.apply(u * np.asarray(e.semi_axes))
    return out


def _unit(angles: np.ndarray) -> np.ndarray:
    th, ph = angles[..., 0], angles[..., 1]
    return np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)


@pytest.mark.parametrize(("pitch", "roll", "half"), [
    (0.0, 0.0, 3.0),
    (math.pi / 2, 0.0, 8.0),
    (0.3, 0.0, math.hypot(8.0 * math.sin(0.3), 3.0 * math.cos(0.3))),
    (0.0, 0.9, math.hypot(4.0 * math.sin(0.9), 3.0 * math.cos(0.9))),
])
def test_analytic_vertical_extents(pitch: float, roll: float, half: float) -> None:
    # the yaw turns about the vertical: it never changes the extent
    for yaw in (0.0, 1.1, -2.5):
        e = Ellipsoid((5.0, -3.0, -40.0), (8.0, 4.0, 3.0), yaw=yaw, pitch=pitch, roll=roll)
        assert e.z_range == pytest.approx((-40.0 - half, -40.0 + half), rel=1e-14, abs=1e-12)
    assert Sphere((1.0, 2.0, -7.5), 2.5).z_range == (-10.0, -5.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_extent_against_sampled_surface_points(seed: int) -> None:
    rng = np.random.default_rng(seed)
    axes = tuple(rng.uniform(1.0, 30.0, 3))
    yaw, pitch, roll = rng.uniform(-math.pi, math.pi, 3)
    e = Ellipsoid(tuple(rng.normal(scale=100.0, size=3)), axes, yaw=yaw, pitch=pitch, roll=roll)
    lo, hi = e.z_range
    u = rng.normal(size=(N_SAMPLES, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    pts = _surface(e, u)
    # the independently built points are on the shape's surface
    assert np.abs(e.distance(pts[:2000])).max() < 1e-9 * max(axes)
    z = pts[:, 2]
    span = hi - lo
    # no surface point lies outside the extent, and the samples reach it (the gap of the best of 10^5
    # uniform samples is ~2e-5 of the half-extent)
    assert z.max() <= hi + 1e-12 * span and z.min() >= lo - 1e-12 * span
    assert hi - z.max() < 1e-3 * span and z.min() - lo < 1e-3 * span
    # refined from the best samples, the surface's true highest and lowest points are the extent (1e-6 relative)
    for sign, want, best in ((-1.0, hi, u[np.argmax(z)]), (1.0, lo, u[np.argmin(z)])):
        start = np.array([math.acos(np.clip(best[2], -1, 1)), math.atan2(best[1], best[0])])
        res = minimize(lambda ang, s=sign: s * float(_surface(e, _unit(ang)[None])[0, 2]), start,
                       method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-13, "maxiter": 4000})
        assert abs(sign * res.fun - want) <= 1e-6 * span


def test_depth_band_is_the_shape_extent() -> None:
    e = Ellipsoid((0.0, 0.0, -20.0), (10.0, 2.0, 1.5), yaw=0.4, pitch=0.25, roll=-0.6)
    assert _depth_band(e) == e.z_range
    s = Sphere((0.0, 0.0, -5.0), 2.0)
    assert _depth_band(s) == s.z_range == (-7.0, -3.0)
