"""``Zones.traces_near``, the broad phase of the clearance under a horizontal error: exactly the (segment, zone)
pairs whose horizontal trace comes within the reach of the footprint, by shapely's distance of every pair (the
oracle); one reach for all and one per segment, the padded set's exact view (what the checks ask) included."""

from __future__ import annotations

import numpy as np
import shapely

from auvplan.world.zones import Zone, Zones


def _zones() -> Zones:
    rng = np.random.default_rng(5)
    zs = [Zone(f"z{i}", shapely.box(x, y, x + w, y + h), top=10.0 * i, bottom=10.0 * i + 50.0)
          for i, (x, y, w, h) in enumerate(zip(rng.uniform(0, 9000, 40), rng.uniform(0, 6000, 40),
                                               rng.uniform(50, 800, 40), rng.uniform(50, 300, 40), strict=True))]
    return Zones(tuple(zs), pad=25.0)


def test_traces_near_are_the_pairs_within_reach():
    zones = _zones().exact
    rng = np.random.default_rng(6)
    a = np.column_stack([rng.uniform(0, 9000, 300), rng.uniform(0, 6000, 300), -rng.uniform(0, 100, 300)])
    seg = np.stack([a, a + rng.normal(scale=600.0, size=(300, 3))], axis=1)
    traces = shapely.linestrings(seg[:, :, :2])
    dist = shapely.distance(traces[:, None], np.array([z.footprint for z in zones.zones])[None, :])
    for reach in (150.0, rng.uniform(0.0, 400.0, 300)):
        k, j = zones.traces_near(seg, reach)
        want = set(zip(*np.nonzero(dist <= np.broadcast_to(reach, (300,))[:, None]), strict=True))
        assert set(zip(k.tolist(), j.tolist(), strict=True)) == {(int(x), int(y)) for x, y in want} and want
    assert [x.size for x in zones.traces_near(np.zeros((0, 2, 3)), 1.0)] == [0, 0]
