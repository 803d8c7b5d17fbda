"""Audit 12: what the last wave's fixtures never varied (each test failed on the code before its fix)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from auvplan.world import Zone, Zones
from helpers import flat_world


@pytest.mark.parametrize(("depth", "h", "pad"), [(0.5, 0.2, 1.0), (0.5, 0.15, 1.0), (1.0, 0.3, 3.0),
                                                  (3.0, 0.1, 1.0), (0.5, 0.35, 1.0)])
def test_the_derived_exact_set_s_seabed_band_is_the_zone_s_own_height(depth, h, pad):
    """Oracle: a set built from the footprints alone.  ``Zones.exact`` took a seabed band's height as
    ``(h + pad) - pad`` (an ulp off: 0.2 -> 0.19999999999999996), so a leg level on the band's top face (the closed
    prism: touching is entering) was passed by ``mission check``'s exact set, or one an ulp above it refused."""
    w = flat_world(depth=depth)
    zone = Zone("cable", shapely.box(400.0, 400.0, 600.0, 600.0), above_seabed=h)
    derived, alone = Zones((zone,), w.terrain, pad=pad).exact, Zones((zone,), w.terrain)
    z = [-depth + h]
    for _ in range(3):
        z = [np.nextafter(z[0], -np.inf), *z, np.nextafter(z[-1], np.inf)]
    seg = np.array([[[300.0, 500.0, v], [700.0, 500.0, v]] for v in z])
    np.testing.assert_array_equal(derived.segments_enter(seg), alone.segments_enter(seg))
    np.testing.assert_array_equal(derived.polyline_slack(seg), alone.polyline_slack(seg))


def test_a_zone_file_with_no_feature_in_the_area_is_kept_too(tmp_path, monkeypatch):
    """Oracle: the reader runs once.  An empty result (no feature reaches the operating area) failed to unpack
    (``zip(strict=True)`` of no names with one start): every warm run read the file again."""
    from auvplan.io.data.vector.kept import kept_geometries

    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path / "cache"))
    path = tmp_path / "zones.geojson"
    path.write_text('{"type": "FeatureCollection", "features": []}')
    calls = []
    for _ in range(2):
        assert kept_geometries("zones", ("empty",), path, lambda: calls.append(1) or []) == []
    assert len(calls) == 1
    one = [("a", shapely.box(0.0, 0.0, 1.0, 1.0))]
    for _ in range(2):
        got = kept_geometries("zones", ("one",), path, lambda: calls.append(1) or one)
        assert got[0][0] == "a" and shapely.equals_exact(got[0][1], one[0][1], 0.0)
    assert len(calls) == 2
