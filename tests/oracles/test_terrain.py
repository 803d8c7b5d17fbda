"""Terrain: bilinear interpolation, exact segment test, document 004's stepping test."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from auvplan.errors import DataError
from auvplan.world import Terrain


def plane_terrain(a=-100.0, b=0.02, c=-0.03):
    x = np.linspace(0.0, 1000.0, 11)
    y = np.linspace(-500.0, 700.0, 13)
    gx, gy = np.meshgrid(x, y)
    return Terrain(x, y, a + b * gx + c * gy), (a, b, c)


def test_bilinear_matches_nodes(marcus):
    _, world, _ = marcus
    t = world.terrain
    gx, gy = np.meshgrid(t.x, t.y)
    assert np.abs(t.elevation(gx, gy) - t.z).max() < 1e-9


@given(st.floats(0, 1000), st.floats(-500, 700))
def test_bilinear_exact_for_planes(x, y):
    t, (a, b, c) = plane_terrain()
    assert t.elevation(x, y) == pytest.approx(a + b * x + c * y, abs=1e-9)
    gx, gy = t.gradient(x, y)
    assert gx == pytest.approx(b, abs=1e-12) and gy == pytest.approx(c, abs=1e-12)


def test_gradient_matches_finite_differences(marcus):
    _, world, _ = marcus
    t = world.terrain
    rng = np.random.default_rng(3)
    # points away from cell edges, where the bilinear surface is smooth
    i = rng.integers(0, t.x.size - 1, 200)
    j = rng.integers(0, t.y.size - 1, 200)
    x = t.x[i] + rng.uniform(0.2, 0.8, 200) * t.dx
    y = t.y[j] + rng.uniform(0.2, 0.8, 200) * t.dy
    h = 1e-3
    gx, gy = t.gradient(x, y)
    fx = (t.elevation(x + h, y) - t.elevation(x - h, y)) / (2 * h)
    fy = (t.elevation(x, y + h) - t.elevation(x, y - h)) / (2 * h)
    assert np.allclose(gx, fx, atol=1e-6) and np.allclose(gy, fy, atol=1e-6)
    assert t.max_slope >= np.hypot(gx, gy).max()


def test_exact_segment_test_agrees_with_dense_sampling(marcus):
    """≥ 10 000 random segments over the real terrain vs sampling at 1/100 of a cell."""
    _, world, _ = marcus
    t = world.terrain
    rng = np.random.default_rng(2024)
    n = 10_000
    a_xy = rng.uniform([0, 0], [100_000, 100_000], (n, 2))
    length = rng.uniform(0.0, 10 * t.dx, n)  # up to 10 cells long
    ang = rng.uniform(0, 2 * np.pi, n)
    b_xy = np.clip(a_xy + length[:, None] * np.c_[np.cos(ang), np.sin(ang)], 0, 100_000)
    za = t.elevation(a_xy[:, 0], a_xy[:, 1]) + rng.uniform(-100, 300, n)
    zb = t.elevation(b_xy[:, 0], b_xy[:, 1]) + rng.uniform(-100, 300, n)
    seg = np.stack([np.c_[a_xy, za], np.c_[b_xy, zb]], axis=1)
    exact = t.segment_min_altitude(seg)
    # brute force: samples every dx/100 along each segment
    dense = np.empty(n)
    steps = np.maximum(np.ceil(np.linalg.norm(b_xy - a_xy, axis=1) / (t.dx / 100)), 1).astype(int)
    for k0 in range(0, n, 500):
        k = np.arange(k0, min(k0 + 500, n))
        m = steps[k].max() + 1
        s = np.minimum(np.arange(m)[None, :] / steps[k][:, None], 1.0)
        pts = seg[k, 0][:, None] + s[..., None] * (seg[k, 1] - seg[k, 0])[:, None]
        dense[k] = t.altitude(pts).min(axis=1)
    crossing_dense = dense < 0
    crossing_exact = exact < 0
    assert crossing_dense.sum() > 1000 and (~crossing_dense).sum() > 1000  # both kinds are well represented
    assert not np.any(crossing_dense & ~crossing_exact), "the exact test missed a crossing found by sampling"
    assert np.all(exact <= dense + 1e-6)
    # where they disagree, the crossing is shallower than the sampling resolution can see
    disagree = crossing_exact & ~crossing_dense
    assert disagree.mean() < 0.005
    assert np.all(exact[disagree] > -0.5)
    # the bounded variant is exact below its threshold and a valid lower bound above it
    bounded = t.segment_min_altitude(seg, threshold=50.0)
    below = exact < 50.0
    assert np.allclose(bounded[below], exact[below])
    assert np.all(bounded[~below] >= 50.0) and np.all(bounded <= exact + 1e-9)


def thin_ridge():
    """Flat seabed at -100 m with a one-node ridge rising to -60 m at x = 100 (10 m cells)."""
    x = np.arange(0.0, 301.0, 10.0)
    y = np.arange(0.0, 101.0, 10.0)
    z = np.full((y.size, x.size), -100.0)
    z[:, x == 100.0] = -60.0
    return Terrain(x, y, z, name="thin ridge")


def test_stepping_misses_thin_ridge_exact_catches_it():
    t = thin_ridge()
    # crosses the ridge at x = 100 at z = -70: 10 m below the crest
    seg = np.array([[[55.0, 50.0, -70.0], [155.0, 50.0, -70.0]]])
    assert not t.segments_below_stepping(seg, altitude=0.0, step=25.0)[0]  # probes at 55, 80, 105, 130, 155
    assert t.segments_below(seg, altitude=0.0)[0]
    assert t.segment_min_altitude(seg)[0] == pytest.approx(-10.0, abs=1e-9)
    # the stepping test catches it with a fine enough step
    assert t.segments_below_stepping(seg, altitude=0.0, step=1.0)[0]


def test_stepping_miss_rate_against_exact():
    """Random crossings of the thin ridge: the 004 test with c1 = 2.5 cells misses many, the exact test none."""
    t = thin_ridge()
    rng = np.random.default_rng(5)
    n = 2000
    xa = rng.uniform(0, 95, n)
    xb = rng.uniform(105, 300, n)
    z = rng.uniform(-95, -65, n)
    seg = np.stack([np.c_[xa, np.full(n, 50.0), z], np.c_[xb, np.full(n, 50.0), z]], axis=1)
    truth = np.ones(n, dtype=bool)  # every segment at z < -60 crosses the crest
    exact = t.segments_below(seg)
    stepping = t.segments_below_stepping(seg, step=25.0)
    assert np.array_equal(exact, truth)
    assert (~stepping).sum() > 0.2 * n


def test_segment_outside_extent_uses_clamped_surface():
    t, _ = plane_terrain()
    seg = np.array([[[-200.0, 0.0, 50.0], [1200.0, 0.0, 50.0]]])
    dense = t.altitude(np.linspace(seg[0, 0], seg[0, 1], 20001)).min()
    assert t.segment_min_altitude(seg)[0] == pytest.approx(dense, abs=1e-6)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1000, 1000), min_size=6, max_size=6))
def test_exact_min_is_a_lower_bound_of_samples(coords):
    t, _ = plane_terrain()
    rng = np.random.default_rng(0)
    t = Terrain(t.x, t.y, t.z + rng.normal(0, 20, t.z.shape))
    seg = np.array(coords, dtype=float).reshape(1, 2, 3)
    samples = t.altitude(np.linspace(seg[0, 0], seg[0, 1], 4001)).min()
    exact = t.segment_min_altitude(seg)[0]
    assert exact <= samples + 1e-6
    assert exact >= samples - 5.0  # the samples are 0.5 m apart at most: the gap is bounded by the slope


@pytest.mark.parametrize(
    "x, y, z, match",
    [
        (np.arange(3.0), np.arange(1.0), np.zeros((1, 3)), "at least 2 x 2"),
        (np.arange(3.0), np.arange(2.0), np.zeros((3, 2)), "does not match"),
        (np.array([0.0, 1.0, 3.0]), np.arange(2.0), np.zeros((2, 3)), "uniformly spaced"),
        (np.arange(3.0), np.arange(2.0), np.array([[0.0, np.nan, 0.0], [0.0, 0.0, 0.0]]), "non-finite"),
    ],
)
def test_terrain_rejects_bad_grids(x, y, z, match):
    with pytest.raises(DataError, match=match):
        Terrain(x, y, z, name="bad")
