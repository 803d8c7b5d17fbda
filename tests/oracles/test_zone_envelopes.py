"""The zones a held-depth leg may enter (``Zones.envelope_entries``, ``held_zone_entries``) against shapely and
dense sampling.

A leg's vertical envelope (its horizontal trace times every depth between its ends) meets a flat band where the
trace meets the footprint (shapely, boundary included: a closed prism) and the depth ranges overlap (touching
counts); it meets a seabed band where the envelope's lowest edge comes within the band's height of the seabed
over the footprint (sampled every ~0.5 m along the clipped trace on a random bilinear seabed).  The held
executor's track (``held_track``) is sampled the same way and each sample charged to the leg whose horizontal
stretch it lies on.  Zones: boxes, a multipolygon with a hole, flat bands from the surface and at depth, seabed
bands; legs level, climbing and diving, some ending exactly on a band's face.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from auvplan.guidance.mission.flycheck import held_track
from auvplan.guidance.mission.zone_legs import held_zone_entries
from auvplan.world import Zone, Zones
from auvplan.world.terrain import Terrain


def _world(seed: int) -> tuple[Terrain, tuple[Zone, ...]]:
    rng = np.random.default_rng(seed)
    x, y = np.linspace(0.0, 2000.0, 9), np.linspace(0.0, 1200.0, 7)  # non-square cells
    t = Terrain(x, y, rng.uniform(-260.0, -140.0, (7, 9)))
    ring = shapely.box(1200.0, 100.0, 1700.0, 600.0).difference(shapely.box(1350.0, 250.0, 1550.0, 450.0))
    zones = (Zone("surface box", shapely.box(300.0, 300.0, 700.0, 900.0), top=0.0, bottom=40.0),
             Zone("deep band", shapely.box(900.0, 200.0, 1300.0, 1000.0), top=80.0, bottom=120.0),
             Zone("ring and box", shapely.MultiPolygon([ring, shapely.box(100.0, 1000.0, 400.0, 1150.0)]),
                  top=20.0, bottom=60.0),
             Zone("cable", shapely.box(1500.0, 700.0, 1900.0, 1100.0), above_seabed=25.0),
             Zone("wreck", shapely.Polygon([(600.0, 100.0), (900.0, 150.0), (700.0, 350.0)]), above_seabed=100.0))
    return t, zones


def _envelope_oracle(t: Terrain, zones, a, b) -> set[tuple[int, int]] | None:
    """(leg, zone) pairs by shapely and sampling; None when a seabed band is within 0.05 m of the decision."""
    out = set()
    for k, (p, q) in enumerate(zip(a, b, strict=True)):
        trace = shapely.LineString([p[:2], q[:2]]) if np.any(p[:2] != q[:2]) else shapely.Point(p[:2])
        lo, hi = min(p[2], q[2]), max(p[2], q[2])
        for j, z in enumerate(zones):
            if not shapely.intersects(trace, z.footprint):
                continue
            if z.above_seabed is None:
                if lo <= -z.top and hi >= -z.bottom:
                    out.add((k, j))
                continue
            s = np.linspace(0.0, 1.0, int(np.hypot(*(q[:2] - p[:2])) / 0.5) + 2)
            xy = p[:2] + s[:, None] * (q[:2] - p[:2])
            inside = shapely.intersects_xy(z.footprint, xy[:, 0], xy[:, 1])
            if not inside.any():
                return None  # a graze between samples
            alt = float((lo - t.elevation(xy[inside, 0], xy[inside, 1])).min())
            if abs(alt - z.above_seabed) < 0.05:
                return None
            if alt <= z.above_seabed:
                out.add((k, j))
    return out


def _legs(seed: int, n: int) -> np.ndarray:
    rng = np.random.default_rng(100 + seed)
    w = np.column_stack([rng.uniform(50.0, 1950.0, n), rng.uniform(50.0, 1150.0, n),
                         -rng.choice([0.0, 20.0, 40.0, 60.0, 80.0, 120.0, 150.0], n) - rng.uniform(0.0, 30.0, n)
                         * rng.integers(0, 2, n)])
    return w


@pytest.mark.parametrize("seed", range(3))
def test_envelope_entries_are_shapely_and_the_sampled_seabed(seed):
    t, zones = _world(seed)
    zs = Zones(zones, t)
    w = _legs(seed, 41)
    a, b = w[:-1], w[1:]
    want = _envelope_oracle(t, zones, a, b)
    assert want is not None
    leg, zi = zs.envelope_entries(a, b)
    got = list(zip(leg.tolist(), zi.tolist(), strict=True))
    assert got == sorted(want)  # each pair once, by leg then zone
    assert leg.dtype == np.intp and zi.dtype == np.intp
    entered = {j for _, j in got}
    assert len(got) >= 20 and {0, 1, 2} <= entered and {3, 4} & entered  # flat and seabed bands entered
    np.testing.assert_array_equal(zs.envelopes_enter(a, b), np.isin(np.arange(len(a)), leg))


def _track_oracle(t: Terrain, zones, w: np.ndarray, pitch: float) -> set[tuple[int, int]]:
    """(leg, zone) pairs of the held track sampled every ~0.5 m, each sample charged to the leg whose horizontal
    stretch holds it (the track follows the waypoints' horizontal path; samples within 1 mm of a waypoint are left
    out)."""
    trk = held_track(w, pitch)
    ends = np.r_[0.0, np.cumsum(np.hypot(*np.diff(w[:, :2], axis=0).T))]
    at = np.r_[0.0, np.cumsum(np.hypot(*np.diff(trk[:, :2], axis=0).T))]
    pts, arc = [], []
    for i in range(trk.shape[0] - 1):
        s = np.linspace(0.0, 1.0, int(np.linalg.norm(trk[i + 1] - trk[i]) / 0.5) + 2)
        pts.append(trk[i] + s[:, None] * (trk[i + 1] - trk[i]))
        arc.append(at[i] + s * (at[i + 1] - at[i]))
    p, arc = np.vstack(pts), np.concatenate(arc)
    keep = np.min(np.abs(arc[:, None] - ends[None, :]), axis=1) > 1e-3
    p, leg = p[keep], np.searchsorted(ends, arc[keep]) - 1
    out = set()
    for j, z in enumerate(zones):
        inside = shapely.intersects_xy(z.footprint, p[:, 0], p[:, 1])
        if z.above_seabed is None:
            inside &= (p[:, 2] <= -z.top) & (p[:, 2] >= -z.bottom)
        else:
            inside &= p[:, 2] - t.elevation(p[:, 0], p[:, 1]) <= z.above_seabed
        out |= {(int(k), j) for k in np.unique(leg[inside])}
    return out


@pytest.mark.parametrize(("seed", "pitch"), [(0, 8.0), (3, 60.0)])
def test_held_zone_entries_are_the_envelopes_and_the_sampled_executor_track(seed, pitch):
    """Oracle: shapely and dense sampling, as above, over 12 legs; the track's lag carries a depth change into
    the next leg, outside that leg's envelope."""
    t, zones = _world(seed)
    zs = Zones(zones, t)
    # a 5 m leg asking for a 55 m descent, then a leg held 60 m deep across the 0-40 m box: the descent carries
    # on into it and passes through the band, which neither leg's envelope meets
    # (after a first leg 20 m deep out of the same box: the legs are counted from the mission's first)
    w = np.vstack([[[350.0, 650.0, -20.0], [290.0, 600.0, -5.0], [295.0, 600.0, -60.0], [800.0, 600.0, -60.0]],
                   _legs(seed, 12)])
    env = _envelope_oracle(t, zones, w[:-1], w[1:])
    assert env is not None
    trk = _track_oracle(t, zones, w, pitch)
    leg, zi = held_zone_entries(zs, w, pitch)
    got = list(zip(leg.tolist(), zi.tolist(), strict=True))
    assert got == sorted(env | trk) and leg.dtype == np.intp and zi.dtype == np.intp
    assert (0, 0) in env and (1, 0) not in env | trk and (2, 0) in trk - env  # the track enters where no envelope does


@pytest.mark.parametrize("x0", [0.0, 5.0e5])
def test_a_depth_change_ending_on_the_last_waypoint_is_charged_to_the_last_leg(x0):
    """By hand: the last leg's descent ends within a rounding of its waypoint (``held_track`` then places its corner
    on the waypoint itself, 500 km from the origin): the zone round the end is entered by the last leg (1, from 0)
    only, never by a leg 2 the mission does not have (it was: legs [1, 2])."""
    slope = np.tan(np.radians(15.0))
    need = 100.0 * (1.0 - 1e-14)
    w = np.array([[x0 - 200.0, 0.0, -10.0], [x0, 0.0, -10.0], [x0 + 100.0, 0.0, -10.0 - need * slope]])
    zs = Zones((Zone("end", shapely.box(x0 + 50.0, -10.0, x0 + 150.0, 10.0)),), None)
    leg, zi = held_zone_entries(zs, w, 15.0)
    assert leg.tolist() == [1] and zi.tolist() == [0]


def test_one_leg_one_waypoint_and_no_zones():
    """By hand: a single leg through the surface box is entered (its envelope and its track); one waypoint, no
    legs or no zones: nothing, as empty integer arrays."""
    t, zones = _world(0)
    zs = Zones(zones, t)
    one = np.array([[100.0, 600.0, -20.0], [500.0, 600.0, -20.0]])
    for leg, zi in (zs.envelope_entries(one[:1], one[1:]), held_zone_entries(zs, one, 15.0)):
        assert leg.tolist() == [0] and zi.tolist() == [0]
    empty = Zones((), t)
    for leg, zi in (held_zone_entries(zs, one[:1], 15.0), held_zone_entries(empty, one, 15.0),
                    zs.envelope_entries(one[:0], one[:0]), empty.envelope_entries(one[:1], one[1:])):
        assert leg.size == 0 and zi.size == 0 and leg.dtype == np.intp and zi.dtype == np.intp
