"""A ``.plan``'s geofence fits ArduPilot's fence storage (``AC_PolyFence_loader``): 672 bytes on a 16 KiB board
(``StorageManager.cpp``'s ``StorageFence`` areas 160 + 256 + 256 for every vehicle but Copter), 4 of header, 2 + 8 n
per polygon of n vertices and 1 end-of-storage byte (``fence_storage_space_required``, ``write_fence``: "Fence
exceeds storage size").  The export wrote every land exclusion whatever its size: ``admiralty-inlet``'s fence took
1 165 bytes and could not be uploaded.  Now exclusions that do not fit are shrunk and simplified inside the land they
stand for (the inclusion, the operating region, is never cut); an inclusion too long is refused in one line."""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely

from auvplan.errors import DataError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.deploy import DeployInfo, Envelope
from auvplan.io.missions.deploy_formats import FENCE_STORAGE_BYTES, fence_bytes, qgc_geofence

ORIGIN = (48.1, -122.7)
FRAME = LocalFrame(*ORIGIN)
BOX = ((0.0, 0.0), (20000.0, 0.0), (20000.0, 12000.0), (0.0, 12000.0))  # 4 edges x 8 = 32 fence vertices


def _island(n: int, cx: float = 9000.0, cy: float = 6000.0) -> tuple[tuple[float, float], ...]:
    """A star-shaped island of n vertices (not convex: simplifying it changes it)."""
    a = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    r = 1500.0 + 400.0 * np.cos(5.0 * a) + 150.0 * np.sin(11.0 * a)
    return tuple((float(cx + ri * np.cos(t)), float(cy + ri * np.sin(t))) for ri, t in zip(r, a))


def _fence(polygon, exclusions) -> list[dict]:
    env = Envelope(polygon, 100.0, 10.0, 3600.0, 3000.0, exclusions=tuple(exclusions))
    doc = qgc_geofence(DeployInfo(ORIGIN, env), FRAME)
    return json.loads(json.dumps(doc))["polygons"]  # as written


def _local(poly: dict) -> shapely.Polygon:
    lat, lon = np.array(poly["polygon"]).T
    x, y = FRAME.forward(lon, lat)
    return shapely.Polygon(np.column_stack([x, y]))


def test_at_the_limit_the_fence_is_written_as_it_is():
    """32 + 50 vertices: 4 + (2 + 256) + (2 + 400) + 1 = 665 bytes, the most two polygons can take of 672."""
    island = _island(50)
    fence = _fence(BOX, [island])
    assert [len(p["polygon"]) for p in fence] == [32, 50]
    assert fence_bytes([32, 50]) == 665 <= FENCE_STORAGE_BYTES < fence_bytes([32, 51])
    assert shapely.equals_exact(_local(fence[1]), shapely.Polygon(island), tolerance=1e-3)


def test_one_vertex_over_the_exclusion_is_simplified_inside_its_land():
    island = _island(51)
    fence = _fence(BOX, [island])
    counts = [len(p["polygon"]) for p in fence]
    assert fence_bytes(counts) <= FENCE_STORAGE_BYTES  # ArduPilot takes it
    assert fence[0]["inclusion"] and counts[0] == 32  # the operating region as it was
    assert shapely.covers(_local(fence[0]).buffer(1e-3), shapely.Polygon(BOX))
    assert all(not p["inclusion"] for p in fence[1:]) and len(fence) >= 2
    land = shapely.Polygon(island)
    for p in fence[1:]:
        assert shapely.covers(land.buffer(1e-3), _local(p))  # never on the water the mission may use
    assert sum(_local(p).area for p in fence[1:]) > 0.8 * land.area  # still most of the island


def test_many_exclusions_keep_the_largest_within_the_storage():
    """admiralty-inlet's shape of problem: several land pieces of 600 vertices in all."""
    islands = [_island(120, 3000.0 + 4500.0 * k, 6000.0) for k in range(4)] + [_island(40, 9000.0, 1500.0)]
    fence = _fence(BOX, islands)
    assert fence_bytes([len(p["polygon"]) for p in fence]) <= FENCE_STORAGE_BYTES
    land = shapely.union_all([shapely.Polygon(i) for i in islands])
    kept = [_local(p) for p in fence[1:]]
    assert kept and all(shapely.covers(land.buffer(1e-3), k) for k in kept)


def test_an_inclusion_over_the_storage_is_refused_in_one_line():
    """The operating region is never cut (the fence would fire inside it): 10 edges x 8 = 80 vertices fit (4 + 642
    + 1 = 647 bytes), 11 x 8 = 88 do not."""
    def ring(k: int):
        a = np.linspace(0.0, 2.0 * np.pi, k, endpoint=False)
        return tuple((float(10000.0 + 9000.0 * np.cos(t)), float(6000.0 + 5000.0 * np.sin(t))) for t in a)

    assert [len(p["polygon"]) for p in _fence(ring(10), [])] == [80]
    with pytest.raises(DataError) as info:
        _fence(ring(11), [])
    msg = str(info.value)
    assert "\n" not in msg and "88 vertices (711 bytes)" in msg and "holds 672 bytes" in msg and "83 vertices" in msg
