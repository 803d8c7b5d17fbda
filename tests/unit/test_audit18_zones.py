"""audit18: a zone file's invalid polygon made valid keeps the area the chart draws, and every zone's name is its
own.

* ``shapely.make_valid``'s default ("linework") rebuilds a polygon from its edges with the even-odd rule: a
  MultiPolygon whose part lies inside another (GEOS: "Nested shells", a chart's area drawn with a sub-area as a
  second part) came out with the inner part a HOLE: a no-go zone open where the chart draws it closed.  Oracle:
  the union of the parts (shapely), and a point inside the inner part inside the zone.  Both paths: a feature near
  the area (``_made_valid``) and a chart-wide one cut to the area's window (``_clip_lonlat``).
* features sharing a name are numbered ``name #k`` by feature number: a third feature literally named ``"A #2"``
  took the same name as the first "A"'s second copy.
"""

from __future__ import annotations

import json

import numpy as np
import shapely

from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.vector.zones import ZoneSpec, read_zones

_FRAME = LocalFrame(48.0, -125.0)
_EXTENT = (0.0, 2000.0, 0.0, 2000.0)


def _ring(x0: float, y0: float, x1: float, y1: float) -> list[list[float]]:
    """A rectangle given in local metres, as a closed lon/lat ring."""
    xs, ys = [x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0]
    lon, lat = _FRAME.inverse(xs, ys)
    return [[float(a), float(b)] for a, b in zip(lon, lat, strict=True)]


def _zones(tmp_path, features: list[dict]):  # type: ignore[no-untyped-def]
    doc = {"type": "FeatureCollection", "features": features}
    (tmp_path / "chart.geojson").write_text(json.dumps(doc))
    spec = ZoneSpec(where_="s.toml: [[zones]] #1", name="chart", kind="file", file="chart.geojson")
    return read_zones((spec,), _FRAME, None, _EXTENT, base_dir=tmp_path).exact.zones


def _multi(name: str, *rings: list[list[float]]) -> dict:
    return {"type": "Feature", "properties": {"name": name},
            "geometry": {"type": "MultiPolygon", "coordinates": [[r] for r in rings]}}


def test_a_part_inside_another_part_stays_inside_the_zone(tmp_path) -> None:
    outer, inner = (200.0, 200.0, 1800.0, 1800.0), (800.0, 800.0, 1200.0, 1200.0)
    (z,) = _zones(tmp_path, [_multi("area", _ring(*outer), _ring(*inner))])
    truth = shapely.union_all([shapely.box(*outer), shapely.box(*inner)])  # what the chart draws
    assert abs(z.footprint.area - truth.area) < 1e-4 * truth.area, (z.footprint.area, truth.area)
    assert shapely.contains_xy(z.footprint, 1000.0, 1000.0)


def test_a_chart_wide_part_round_the_area_keeps_the_area_inside(tmp_path) -> None:
    """A part of ~100 km round a 2 km one, the operating area inside both: cut to the area's window first."""
    big, small = (-50_000.0, -50_000.0, 52_000.0, 52_000.0), (-500.0, -500.0, 2500.0, 2500.0)
    (z,) = _zones(tmp_path, [_multi("sea area", _ring(*big), _ring(*small))])
    xy = np.array([[1000.0, 1000.0], [100.0, 1900.0], [3000.0, 3000.0]])
    assert shapely.contains_xy(z.footprint, xy[:, 0], xy[:, 1]).all()


def test_numbered_names_never_take_a_feature_s_own_name(tmp_path) -> None:
    features = [_multi(n, _ring(100.0 + 300.0 * k, 100.0, 300.0 + 300.0 * k, 300.0))
                for k, n in enumerate(["A", "A", "A #2"])]
    names = [z.name for z in _zones(tmp_path, features)]
    assert names == ["chart: A #1", "chart: A #2", "chart: A #2 #3"], names  # the literal one numbered too
