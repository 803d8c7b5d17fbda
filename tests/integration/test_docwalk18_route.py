"""``auvplan run marcus-terrain-follow`` (docs/missions.md) sat at the end of its flight bar for 45 s (docwalk 18):
the flight's distance to the route (``SimResult.route_error``, the cross-track RMS and max of every run) measured
every one of the 343 400 samples against every one of the 1 593 legs.  Now the nearest leg of each sample comes
from an R-tree of the legs (2.7 s for the same sizes).  Oracles: the distances by the brute force written here,
and the memory: no samples x legs array is made."""

from __future__ import annotations

import tracemalloc

import numpy as np

from auvplan.guidance.following.route import RouteTracker


def _brute(w: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Each point's least distance to every segment, horizontally (clamped projection)."""
    out = np.full(len(pts), np.inf)
    for a, b in zip(w[:-1, :2], w[1:, :2], strict=True):
        d = b - a
        t = np.clip(((pts[:, :2] - a) @ d) / max(float(d @ d), 1e-300), 0.0, 1.0)
        out = np.minimum(out, np.hypot(*(pts[:, :2] - (a + t[:, None] * d)).T))
    return out


def test_the_distance_to_the_route_is_the_least_over_its_legs() -> None:
    rng = np.random.default_rng(18)
    w = np.cumsum(rng.normal(size=(120, 3)) * 40.0, axis=0)
    w = np.vstack([w, w[-1] + [0.0, 0.0, -30.0], w[:1]])  # a vertical leg (no horizontal length) and a closing loop
    pts = np.vstack([rng.uniform(w.min(0) - 50.0, w.max(0) + 50.0, size=(3000, 3)), w])  # and the vertices: 0
    got = RouteTracker(w, 10.0).cross_track(pts)
    np.testing.assert_allclose(got, _brute(w, pts), rtol=0.0, atol=1e-9)
    assert np.all(got[-len(w):] <= 1e-9)


def test_no_samples_by_legs_array_is_made() -> None:
    rng = np.random.default_rng(7)
    w = np.cumsum(rng.normal(size=(2001, 3)) * 30.0, axis=0)  # 2 000 legs
    pts = np.repeat(w[:-1], 10, axis=0) + rng.normal(size=(20_000, 3))
    tracker = RouteTracker(w, 10.0)
    tracemalloc.start()
    try:
        tracker.cross_track(pts)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 8e6  # was 1 000 x 2 000 x 2 float64 a chunk (32 MB, several at once): O(N M) work


def test_a_point_at_no_finite_place_has_no_distance() -> None:
    """As the brute force: NaN for a NaN sample, inf for an infinite one (never a value left from np.empty)."""
    w = np.array([[0.0, 0.0, -1.0], [100.0, 0.0, -1.0], [100.0, 100.0, -1.0]])
    got = RouteTracker(w, 10.0).cross_track(np.array([[50.0, 5.0, 0.0], [np.nan, 0.0, 0.0], [np.inf, 0.0, 0.0]]))
    assert got[0] == 5.0 and np.isnan(got[1]) and got[2] == np.inf
