"""Land given as parts drawn one inside another ("Nested shells": an island's outline and a smaller part of it,
or a chart's land area and a sub-area) is all land: never a hole that a plan could cross.

``shapely.make_valid``'s default rebuilds a polygon from its edges by the even-odd rule, which turns the inner
part into a hole; the land keeps the union of its parts (the rings' structure).  Oracle: the union of the parts
(shapely's ``union_all``), the area by hand.
"""

from __future__ import annotations

import numpy as np
import shapely

from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.vector.coast import LandSpec, read_land
from auvplan.world.land import Land

OUTER, INNER = shapely.box(0.0, 0.0, 1600.0, 1600.0), shapely.box(600.0, 600.0, 1000.0, 1000.0)


def test_nested_parts_are_all_land():
    nested = shapely.MultiPolygon([OUTER, INNER])
    assert not shapely.is_valid(nested)  # GEOS: "Nested shells"
    land = Land(nested, name="nested")
    assert land.geometry.area == 1600.0 * 1600.0  # the union of the parts, by hand
    assert shapely.equals(land.geometry, shapely.union_all([OUTER, INNER]))
    assert land.contains(np.array([[800.0, 800.0], [300.0, 300.0]])).all()


def test_a_land_file_with_nested_parts_is_all_land(tmp_path):
    import pyogrio

    frame = LocalFrame(-33.9, 151.3)  # southern hemisphere, east of Greenwich
    lonlat = [shapely.transform(g, lambda xy: np.column_stack(frame.inverse(xy[:, 0], xy[:, 1])))
              for g in (OUTER, INNER)]
    p = tmp_path / "coast.gpkg"
    pyogrio.raw.write(p, geometry=shapely.to_wkb(np.asarray([shapely.MultiPolygon(lonlat)], dtype=object)),
                      field_data=[], fields=[], crs="EPSG:4326", geometry_type="MultiPolygon", driver="GPKG",
                      layer="land")
    land = read_land(LandSpec(file=p.name), frame, (-2000.0, 3000.0, -2000.0, 3000.0), base_dir=tmp_path)
    assert land.contains(np.array([[800.0, 800.0], [300.0, 300.0]])).all()
    assert abs(land.geometry.area - 1600.0 * 1600.0) < 1.0  # m², the projection's round trip
