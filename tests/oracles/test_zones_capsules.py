"""The capsules of the zones' exact flat-band test (:func:`auvplan.world.zones.parts.capsules`): what they settle
against shapely, on long thin corridors (where the discs settle nothing), concave, holed, multi-part and round
footprints."""

from __future__ import annotations

import numpy as np
import shapely

from auvplan.world.zones.exact import flat_hits_kernel
from auvplan.world.zones.parts import capsules, rings


def _footprints() -> np.ndarray:
    cable = shapely.buffer(shapely.linestrings([[1000.0, 2000.0], [2700.0, 1300.0]]), 35.0)
    bent = shapely.buffer(shapely.linestrings([[200.0, 300.0], [900.0, 500.0], [1100.0, 1200.0]]), 50.0)
    holed = shapely.Polygon([(2000, 2000), (2900, 2100), (2800, 2900), (2100, 2800)],
                            [[(2300, 2300), (2600, 2350), (2550, 2600), (2350, 2550)]])
    parts = shapely.MultiPolygon([shapely.box(100, 2200, 300, 2900), shapely.box(400, 2200, 500, 2900)])
    thin = shapely.affinity.rotate(shapely.box(1500, 400, 2900, 430), 27.0)
    return np.array([cable, bent, holed, parts, thin, shapely.buffer(shapely.points(600.0, 1600.0), 120.0)])


def test_a_capsule_holds_inside_what_it_says_and_the_footprint_within_its_outer_radius():
    geoms = _footprints()
    cap = capsules(geoms)
    rng = np.random.default_rng(5)
    for g, (ax, ay, bx, by, c_in, c_out) in zip(geoms, cap, strict=True):
        axis = shapely.linestrings([[ax, ay], [bx, by]])
        assert shapely.distance(shapely.points(shapely.get_coordinates(g)), axis).max() <= c_out
        if c_in == 0.0:  # settles nothing inside (the kernel's test is strict)
            continue
        t = rng.uniform(0.0, 1.0, 4000)
        ang, r = rng.uniform(0.0, 2 * np.pi, t.size), c_in * np.sqrt(rng.uniform(0.0, 1.0, t.size))
        q = np.column_stack([ax + t * (bx - ax) + r * np.cos(ang), ay + t * (by - ay) + r * np.sin(ang)])
        assert shapely.covers(g, shapely.points(q)).all()
    # the straight corridors are settled by their own line: nearly the buffer's half-width inside
    assert cap[0, 4] > 0.95 * 35.0 and cap[0, 5] < 1.05 * 35.0
    assert cap[4, 4] > 0.8 * 15.0 and cap[4, 5] < 2.0 * 15.0
    assert cap[1, 4] == 0.0  # the bent cable's axis leaves it: nothing is settled inside
    assert cap[5, 4] == 0.0 and abs(cap[5, 5] - 120.0) < 0.01  # a round wreck: not thin, left to its disc


def test_the_flat_test_with_capsules_answers_as_shapely_does():
    geoms = _footprints()
    xy, ring, rs, disc = rings(geoms)
    rng = np.random.default_rng(11)
    a = rng.uniform(0.0, 3000.0, (6000, 2))
    b = a + rng.normal(0.0, 150.0, (6000, 2))
    b[:500] = a[:500]  # points
    seg = np.zeros((a.shape[0], 2, 3))
    seg[:, 0, :2], seg[:, 1, :2] = a, b
    si = np.repeat(np.arange(a.shape[0]), geoms.size)
    zi = np.tile(np.arange(geoms.size), a.shape[0])
    out = np.empty(si.size, dtype=bool)
    band = np.full(geoms.size, np.inf)
    flat_hits_kernel(seg, si, zi, -band, band, xy, ring, rs, disc, out)
    traces = shapely.linestrings(np.stack([a, b], axis=1)[si])
    theirs = shapely.intersects(geoms[zi], np.where((a == b).all(axis=1)[si], shapely.points(a[si]), traces))
    assert theirs.sum() > 600 and (~theirs).sum() > 20000
    np.testing.assert_array_equal(out, theirs)
