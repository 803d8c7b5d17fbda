"""A near-duplicate waypoint is merged only where the leg that replaces the two passes the exact test the
export's check applies (guidance.mission.legs.merge_short_legs): a vertex moved by centimetres must not cut a
corner into the seabed over a crest or into a charted zone.  Oracles: the merged legs sampled every millimetre
against the bilinear seabed, and shapely against the zone's footprint."""

from __future__ import annotations

import numpy as np
import shapely

from auvplan.guidance.mission.legs import merge_short_legs
from auvplan.world import Bounds, Margins, Terrain, World
from auvplan.world.zones import Zone, Zones

MIN_ALT = 10.0


def _crest_world(zones: tuple[Zone, ...] = ()) -> World:
    """A seabed at -110 m with a knife-edge crest along x = 10.05 m rising to -99.95 m (5 m cells)."""
    x = np.arange(-4.95, 40.0, 5.0)
    y = np.arange(-10.0, 11.0, 5.0)
    z = np.full((y.size, x.size), -110.0)
    z[:, np.argmin(np.abs(x - 10.05))] = -99.95
    t = Terrain(x, y, z, name="crest")
    return World(Bounds(float(x[0]), float(x[-1]), -10.0, 10.0, -120.0, 0.0), t,
                 margins=Margins(min_altitude=MIN_ALT), zones=Zones(zones, t) if zones else None, name="crest")


def _sampled_min_altitude(world: World, w: np.ndarray) -> float:
    """Least altitude of the polyline ``w`` sampled every millimetre (the oracle)."""
    low = np.inf
    for a, b in zip(w[:-1], w[1:]):
        f = np.linspace(0.0, 1.0, max(int(np.linalg.norm(b - a) / 1e-3), 2))[:, None]
        p = a + f * (b - a)
        low = min(low, float((p[:, 2] - world.terrain.elevation(p[:, 0], p[:, 1])).min()))
    return low


def test_a_merge_that_would_cut_a_crest_keeps_the_short_leg() -> None:
    """A (a fixed corner) climbs 7 cm in 5 cm to V above the crest, then a long leg down to B: both legs clear
    10 m (V's altitude is 10.02 m), A's envelope does not (held at A's depth over the crest), and A -> B, V gone,
    passes 9.95 m over the crest."""
    world = _crest_world()
    w = np.array([[0.0, 0.0, -90.0], [10.0, 0.0, -90.0], [10.05, 0.0, -89.93], [20.0, 0.0, -90.0],
                  [30.0, 0.0, -90.0]])
    assert _sampled_min_altitude(world, w) >= MIN_ALT  # the mission as given is safe
    merged = np.delete(w, 2, axis=0)
    assert _sampled_min_altitude(world, merged) < MIN_ALT - 0.04  # the merge would cut the crest (9.95 m)
    keep = merge_short_legs(world, w, 0.1, fixed=[1], max_pitch_deg=90.0)
    assert keep.tolist() == [0, 1, 2, 3, 4]
    assert _sampled_min_altitude(world, w[keep]) >= MIN_ALT
    # the same short leg over a flat seabed goes (nothing to cut)
    flat = World(world.bounds, Terrain(world.terrain.x, world.terrain.y, np.full(world.terrain.z.shape, -110.0)),
                 margins=world.margins)
    assert merge_short_legs(flat, w, 0.1, fixed=[1], max_pitch_deg=90.0).tolist() == [0, 1, 3, 4]


def test_a_merge_that_would_cut_a_corner_into_a_zone_keeps_the_short_leg() -> None:
    """A horizontal corner: A (fixed) -> V 6 cm east -> B 10 m north; a thin zone reaching to the seabed lies
    inside the corner, across the chord A -> B but off both legs, and V's envelope meets the crest (not free)."""
    # the chord A (10, 0) -> B (10.06, 10) passes x = 10.03 at y = 5; the zone spans x 10.02..10.04 around y = 5
    zone = Zone("sliver wreck", shapely.box(10.02, 4.0, 10.04, 6.0))
    world = _crest_world((zone,))
    w = np.array([[0.0, 0.0, -90.0], [10.0, 0.0, -90.0], [10.06, 0.0, -89.93], [10.06, 10.0, -89.93],
                  [30.0, 10.0, -89.93]])
    legs = [shapely.LineString(w[i:i + 2, :2]) for i in range(len(w) - 1)]
    assert not any(leg.intersects(zone.footprint) for leg in legs)
    assert shapely.LineString(w[[1, 3], :2]).intersects(zone.footprint)  # the merged leg would enter the zone
    keep = merge_short_legs(world, w, 0.1, fixed=[1], max_pitch_deg=90.0)
    assert keep.tolist() == [0, 1, 2, 3, 4]
    assert not any(shapely.LineString(w[keep][i:i + 2, :2]).intersects(zone.footprint) for i in range(len(keep) - 1))
