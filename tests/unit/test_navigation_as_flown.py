"""``mission check``'s navigation of a ``.plan`` whose legs follow the seabed (``app.check._navigation_as_flown``)
against independent computations, the cases wave 13's tests left open (found by mutation, docs/mutants.md
section 5): with no leg following, the track is the waypoints and the verdict is ``check_navigation``'s on them,
field for field; with legs following, each leg's figures are its track segments' gathered by hand (the largest
error, the least altitude, all clear, the bottom lock weighted by length); the error over the budget and a leg not
clear named as the straight check names them."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.app.check import _navigation_as_flown
from auvplan.guidance.mission.terrain_legs import terrain_track
from auvplan.nav import NavParams, check_navigation, surface_kinds
from auvplan.world import Bounds, Margins, Terrain, World


def _ridge(min_altitude: float = 10.0) -> World:
    """A ridge 40 m high across x = 500 m over a seabed 100 m deep (25 m cells)."""
    x, y = np.arange(0.0, 1001.0, 25.0), np.arange(0.0, 401.0, 25.0)
    z = np.broadcast_to(-100.0 + 40.0 * np.exp(-(((x - 500.0) / 80.0) ** 2)), (y.size, x.size)).copy()
    return World(Bounds(0.0, 1000.0, 0.0, 400.0, -150.0, 0.0), Terrain(x, y, z, name="ridge"),
                 margins=Margins(min_altitude=min_altitude))


# home on the surface (a fix), then items 20 m and 60 m above the seabed across the ridge, off the grid lines (the
# followed legs' first and last segments shorter than the 25 m between crossings; the straight leg 5 m
# under its crest), back down to 20 m
POINTS = np.array([[100.0, 200.0, 0.0], [210.0, 200.0, -80.0], [790.0, 200.0, -40.0], [905.0, 220.0, -80.0]])
NAV = NavParams(drift_pct=0.5, drift_pct_no_lock=1.5, dvl_range_m=30.0, fix_error_m=3.0, max_error_m=60.0)


def _same(got, want) -> None:
    assert np.array_equal(got.budget.error_m, want.budget.error_m)
    assert np.array_equal(got.budget.leg_error_m, want.budget.leg_error_m)
    assert np.array_equal(got.budget.leg_lock, want.budget.leg_lock)
    assert np.array_equal(got.leg_uncertain_altitude_m, want.leg_uncertain_altitude_m)
    assert np.array_equal(got.leg_clear, want.leg_clear)
    assert (got.ok, got.message) == (want.ok, want.message)


@pytest.mark.parametrize("max_error", [60.0, 8.0])
def test_no_leg_following_is_the_straight_check_field_for_field(max_error):
    """The straight leg 1 through the crest, the others clear: 'leg 2: within its predicted error the seabed ...
    comes within'; with a budget of 8 m broken first: 'leg k: predicted error ... exceeds max_error_m 8 m'."""
    world = _ridge()
    nav = NavParams(drift_pct=0.5, drift_pct_no_lock=1.5, dvl_range_m=30.0, fix_error_m=3.0, max_error_m=max_error)
    kinds = surface_kinds(POINTS)
    got = _navigation_as_flown(world, nav, POINTS, kinds, np.zeros(3, dtype=bool))
    want = check_navigation(world, POINTS, kinds, nav, nav.usbl_xy)
    _same(got, want)
    assert got.leg_clear.tolist() == [True, False, True] and not got.ok
    if max_error == 8.0:
        assert "exceeds max_error_m 8 m" in got.message
    else:
        assert got.message.startswith("leg 2: within its predicted error")


def test_following_legs_gather_their_track_segments_figures():
    """Legs 1 and 2 follow the seabed (20 m up, then 60 m: out of the DVL's 30 m range part of the way): each
    leg's error is the largest of its segments', its altitude the least, clear only if all are, its bottom lock
    the segments' weighted by their horizontal lengths; the waypoints' errors are the track's at their vertices."""
    world = _ridge()
    follow = np.array([False, True, True])
    kinds = surface_kinds(POINTS)
    got = _navigation_as_flown(world, NAV, POINTS, kinds, follow)
    track, seg = terrain_track(world.terrain, POINTS, follow)
    at = [0] + [int(np.flatnonzero(seg == k)[-1]) + 1 for k in range(3)]  # each waypoint's vertex
    on_track = [""] * len(track)
    for j, kind in zip(at, kinds):
        on_track[j] = kind
    c = check_navigation(world, track, tuple(on_track), NAV, NAV.usbl_xy)
    length = np.hypot(*np.diff(track[:, :2], axis=0).T)
    lock = c.budget.leg_lock
    assert lock[seg == 1].min() < 1.0 == lock[seg == 1].max()  # part of the way out of the DVL's range
    for k in range(3):
        on = seg == k
        assert got.budget.leg_error_m[k] == c.budget.leg_error_m[on].max()
        assert got.leg_uncertain_altitude_m[k] == c.leg_uncertain_altitude_m[on].min()
        assert got.leg_clear[k] == c.leg_clear[on].all()
        assert got.budget.leg_lock[k] == pytest.approx((lock[on] * length[on]).sum() / length[on].sum(), rel=1e-12)
    assert np.array_equal(got.budget.error_m, c.budget.error_m[at])
    assert got.ok and got.message == ""
