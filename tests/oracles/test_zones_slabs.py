"""The zones' fine field per depth slab (:mod:`auvplan.world.zones.bound`): each slab's plane never above the
distance to the footprints of the zones whose prism reaches into the slab (shapely and dense seabed samples, the
independent oracle), and the compiled passes that use it exact on both sides of every slab edge and band face."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from benchmarks.zones import independent_entries, random_world

from auvplan.world import Terrain, Zone, Zones
from auvplan.world.zones.bound import _far, _slab


def _slab_range(field: tuple, s: int) -> tuple[float, float]:
    """The depths (z up) of slab ``s``, the first and the last open."""
    z0, zinv, top = field[6:]
    lo = -np.inf if s == 0 else z0 + s / zinv
    hi = np.inf if s == top else z0 + (s + 1) / zinv
    return lo, hi


def _reaches(world, zone: Zone, pad: float, lo: float, hi: float) -> bool:
    """Whether the zone's prism (grown by ``pad``) has a point with ``lo <= z <= hi``: a flat band by its faces,
    a seabed band by the seabed sampled every 5 m over the footprint (at most its true top)."""
    if zone.above_seabed is None:
        return -zone.bottom - pad <= hi and -zone.top + pad >= lo
    fp = shapely.buffer(zone.footprint, pad)
    x0, y0, x1, y1 = fp.bounds
    gx, gy = np.meshgrid(np.arange(x0, x1 + 5.0, 5.0), np.arange(y0, y1 + 5.0, 5.0))
    inside = shapely.contains_xy(fp, gx, gy)
    xs = np.r_[gx[inside], shapely.get_coordinates(fp)[:, 0]]
    ys = np.r_[gy[inside], shapely.get_coordinates(fp)[:, 1]]
    return float(world.seabed(xs, ys).max()) + zone.above_seabed + pad >= lo


@pytest.mark.parametrize("seed", [2, 9])
def test_each_slab_plane_never_exceeds_the_distance_to_the_zones_reaching_into_the_slab(seed):
    rng = np.random.default_rng(seed)
    world = random_world(rng, 40)
    zones = world.zones
    field = zones._field
    x0, y0, f, fnx, fny, bound, z0, zinv, top = field
    assert top == 3 and bound.shape == (5, fny, fnx)
    pts = np.column_stack([rng.uniform(-300, 3300, 3000), rng.uniform(-300, 3300, 3000)])
    geoms = shapely.buffer(np.array([z.footprint for z in zones.zones]), zones.pad, join_style="mitre")
    pruned = 0
    for s in range(top + 1):
        lo, hi = _slab_range(field, s)
        member = np.array([_reaches(world, z, zones.pad, lo, hi) for z in zones.zones])
        assert 0 < member.sum() < len(zones)  # each slab drops some zones and keeps some
        true = shapely.distance(shapely.union_all(geoms[member]), shapely.points(pts))
        lb = np.array([_far.py_func(x, y, s, s, x0, y0, f, fnx, fny, bound) for x, y in pts])
        assert np.all(lb <= true)
        every = np.array([_far.py_func(x, y, top + 1, top + 1, x0, y0, f, fnx, fny, bound) for x, y in pts])
        assert np.all(lb >= every)  # a slab's plane is never below the plane of every zone
        pruned += int((lb > every + f).sum())
    assert pruned > 1000  # and well above it where the zones left out are near


def test_the_slab_of_a_depth_is_monotone_and_its_edges_are_where_the_planes_say():
    z0, zinv, top = -300.0, 4 / 300.0, 3
    z = np.sort(np.r_[np.linspace(-400, 100, 5001), z0 + np.arange(5) / zinv, -np.inf, np.inf])
    s = np.array([_slab.py_func(v, z0, zinv, top) for v in z])
    assert np.all(np.diff(s) >= 0) and s[0] == 0 and s[-1] == top
    edges = z0 + np.arange(1, 4) / zinv
    below = np.array([_slab.py_func(np.nextafter(e, -np.inf), z0, zinv, top) for e in edges])
    above = np.array([_slab.py_func(np.nextafter(e, np.inf), z0, zinv, top) for e in edges])
    assert np.all(above - below <= 1) and np.all(above >= [1, 2, 3]) and np.all(below <= [0, 1, 2])
    assert _slab.py_func(np.nan, z0, zinv, top) == 0


def _band_world(pad: float) -> tuple:
    """A flat seabed at -1000 m under an area banded 200-400 m deep, a wreck 30 m high and a cable to the seabed,
    side by side along y = 0."""
    x = np.linspace(-2000.0, 6000.0, 81)
    terrain = Terrain(x, x, np.full((81, 81), -1000.0), name="flat")
    zones = (Zone("area", shapely.box(0, -150, 300, 150), top=200.0, bottom=400.0),
             Zone("wreck", shapely.buffer(shapely.points(1500.0, 0.0), 100.0), above_seabed=30.0),
             Zone("cable", shapely.buffer(shapely.linestrings([[3000, -800], [3000, 800]]), 40.0), top=0.0,
                  bottom=900.0))
    return Zones(zones, terrain, pad=pad), terrain


@pytest.mark.parametrize("pad", [0.0, 1.0])
def test_legs_on_both_sides_of_every_slab_edge_and_band_face_enter_exactly_where_shapely_says(pad):
    zones, terrain = _band_world(pad)
    field = zones._field
    z0, zinv, top = field[6:]
    faces = [-400.0 - pad, -200.0 + pad, -970.0 - pad, -970.0 + pad, -900.0 - pad, -1000.0 + 1.0]
    edges = [z0 + k / zinv for k in range(1, top + 1)]
    levels = []
    for z in faces + edges:
        levels += [z, np.nextafter(z, -np.inf), np.nextafter(z, np.inf), z - 0.01, z + 0.01]
    # level legs across each zone, legs sloping across a slab edge beside them, legs passing just outside
    legs = []
    for z in levels:
        for xa, xb in ((-500.0, 800.0), (1000.0, 2000.0), (2500.0, 3500.0), (-500.0, 4000.0)):
            for rise in (0.0, 30.0, 300.0):  # level, gently sloping, steep across slab edges
                legs.append([[xa, 0.0, max(z - rise, -1000.0)], [xb, 0.0, z + rise]])
            legs.append([[xa, 160.0 + pad, z], [xb, 160.0 + pad, z]])  # beside the area, over nothing else
    for x, z in ((150.0, -300.0), (1500.0, -985.0), (3000.0, -850.0)):  # from inside each prism up and down
        for zb in (-990.0, -700.0, -450.0, -100.0):  # across the slab edges, out of the band or not
            legs.append([[x, 0.0, z], [x + 1200.0, 0.0, zb]])
            legs.append([[x + 1200.0, 0.0, zb], [x, 0.0, z]])
    seg = np.asarray(legs)
    # the legs as one polyline, each followed by a detour 5 km north (joins crossing no zone's footprint, so no
    # join grazes a face): the legs are its legs 1, 5, 9, ...
    off = seg[:, ::-1].copy()
    off[:, :, 1] = 5000.0
    path = np.concatenate([seg, off], axis=1).reshape(-1, 3)
    world = type("W", (), {"zones": zones, "seabed": terrain.elevation})()
    expect = {k for k, _ in independent_entries(world, path)}
    if pad:  # independent_entries tests the unpadded zones: the padded set's own prisms, as exact zones
        grown = Zones(tuple(Zone(z.name, shapely.buffer(z.footprint, pad, join_style="mitre"),
                                 top=max(z.top - pad, 0.0), bottom=z.bottom + pad,
                                 above_seabed=None if z.above_seabed is None else z.above_seabed + pad)
                            for z in zones.zones), terrain)
        expect = {k for k, _ in independent_entries(type("W", (), {"zones": grown, "seabed": terrain.elevation})(),
                                                    path)}
    got_path = set(np.flatnonzero(zones.polyline_inside_lengths(path[None])[0] > 0) + 1)
    got_segments = set(np.flatnonzero(zones.segments_enter(np.stack([path[:-1], path[1:]], axis=1))) + 1)
    assert got_path == expect and got_segments == expect
    own = {k for k in expect if k % 4 == 1}  # the legs themselves, not the joins
    assert 100 < len(own) < len(seg) - 100  # plenty in and plenty out
