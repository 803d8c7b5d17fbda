"""Survey areas and centre lines read from a vector file across the antimeridian (Fiji's Taveuni lies on it):
GeoJSON writers cut such a polygon or line in two at ±180° (RFC 7946 §3.1.9); the first reader kept the larger
half as "the largest polygon" and the first half of the line."""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely

from auvplan.io.data.geo import LocalFrame
from auvplan.io.data.vector.areas import read_area_lonlat, read_line_lonlat

FRAME = LocalFrame(-16.95, 180.0)


def _geojson(folder, name, geometry) -> object:
    path = folder / name
    feature = {"type": "Feature", "properties": {}, "geometry": geometry}
    path.write_text(json.dumps({"type": "FeatureCollection", "features": [feature]}), encoding="utf-8")
    return path


def _area_m2(lonlat) -> float:
    return float(shapely.Polygon(np.column_stack(FRAME.forward(lonlat[:, 0], lonlat[:, 1]))).area)


@pytest.mark.parametrize("west_deg", [0.05, 0.1, 0.15])
def test_an_area_cut_at_the_antimeridian_is_the_whole_area(tmp_path, west_deg):
    """Oracle: the same box written in one piece with longitudes past 180 (its area in the local frame).  The
    share of the box west of 180° varies (a half chosen by size would be right for one share only)."""
    lo, hi, s, n = 180.0 - west_deg, -179.9, -17.0, -16.9
    whole = _geojson(tmp_path, "whole.geojson", {"type": "Polygon", "coordinates": [
        [[lo, s], [hi + 360.0, s], [hi + 360.0, n], [lo, n], [lo, s]]]})
    cut = _geojson(tmp_path, "cut.geojson", {"type": "MultiPolygon", "coordinates": [
        [[[lo, s], [180.0, s], [180.0, n], [lo, n], [lo, s]]],
        [[[-180.0, s], [hi, s], [hi, n], [-180.0, n], [-180.0, s]]]]})
    want = _area_m2(read_area_lonlat(whole, "", "t.toml: [survey]"))
    assert want == pytest.approx((west_deg + 0.1) * 0.1 * 111e3 ** 2 * np.cos(np.radians(16.95)), rel=0.01)
    assert _area_m2(read_area_lonlat(cut, "", "t.toml: [survey]")) == pytest.approx(want, rel=1e-6)  # a vertex at 180


def test_separate_polygons_away_from_it_still_give_the_largest(tmp_path):
    path = _geojson(tmp_path, "two.geojson", {"type": "MultiPolygon", "coordinates": [
        [[[10.0, 0.0], [10.2, 0.0], [10.2, 0.1], [10.0, 0.1], [10.0, 0.0]]],
        [[[10.2, 0.0], [10.3, 0.0], [10.3, 0.1], [10.2, 0.1], [10.2, 0.0]]]]})  # touching, not merged
    ring = read_area_lonlat(path, "", "t.toml: [survey]")
    assert ring[:, 0].min() == 10.0 and ring[:, 0].max() == pytest.approx(10.2)


def test_a_centre_line_cut_at_the_antimeridian_is_one_line(tmp_path):
    """Oracle: the vertices written, the second half's longitudes past 180 (the frame normalises them)."""
    path = _geojson(tmp_path, "line.geojson", {"type": "MultiLineString", "coordinates": [
        [[179.8, -17.0], [180.0, -16.95]], [[-180.0, -16.95], [-179.9, -16.9]]]})
    line = read_line_lonlat(path, "", "t.toml: [survey]")
    assert np.allclose(line, [[179.8, -17.0], [180.0, -16.95], [180.1, -16.9]])
