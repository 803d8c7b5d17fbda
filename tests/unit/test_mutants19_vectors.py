"""Round 6 of docs/mutants.md: what hostile 17's tests of the vector guard and the dense zone files missed.

* ``lean`` of a straight-edged square drawn with 10 400 vertices: the simplification keeps its 4 corners, the growth
  by 2 x 0.1 m with 2 chords a quarter circle gives 4 x 3 + 1 coordinates and the area L^2 + 4 L r + 2 sqrt(2) r^2
  (the corners' 8 chords inscribed in the circle of radius r = 0.2 m: a regular octagon's area);
* a part smaller than the tolerance is kept (topology preserved), so the lean footprint still contains it;
* the bounds themselves: LEAN_FROM coordinates kept exactly, MAX_ZONE_VERTICES accepted, one more refused;
* a character device is named a device.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely

from auvplan.io.data.vector import dense
from auvplan.io.data.vector.dense import LEAN_FROM, LEAN_TOL_M, check_zone_vertices, lean
from auvplan.io.data.vector.guard import check_source


def _dense_square(side: float, per_edge: int, x0: float = 0.0) -> shapely.Polygon:
    t = np.linspace(0.0, side, per_edge, endpoint=False)
    z = np.zeros_like(t)
    ring = np.concatenate([np.c_[t, z], np.c_[z + side, t], np.c_[side - t, z + side], np.c_[z, side - t]])
    return shapely.Polygon(ring + [x0, 0.0])


def test_a_dense_square_is_lean_with_the_corners_grown_by_two_tolerances():
    sq = _dense_square(100.0, 2600)
    assert shapely.get_num_coordinates(sq) == 10_401
    out = lean(sq)
    r = 2.0 * LEAN_TOL_M
    assert shapely.get_num_coordinates(out) == 4 * 3 + 1
    assert out.area == pytest.approx(100.0**2 + 4 * 100.0 * r + 2.0 * math.sqrt(2.0) * r**2, rel=1e-12)
    assert out.contains(sq)


def test_a_part_smaller_than_the_tolerance_is_kept_inside_the_lean_footprint():
    tiny = shapely.box(500.0, 0.0, 500.05, 0.05)  # 5 cm: Douglas-Peucker without topology drops it
    parts = shapely.MultiPolygon([_dense_square(100.0, 2600), tiny])
    out = lean(parts)
    assert out.contains(tiny) and out.contains(parts)


def test_the_lean_bound_itself_is_kept_exactly():
    per = LEAN_FROM // 4  # 4 x 2500 + the closing vertex = LEAN_FROM + 1
    at = shapely.Polygon(_dense_square(100.0, per).exterior.coords[:-2])  # one vertex fewer: LEAN_FROM in all
    assert shapely.get_num_coordinates(at) == LEAN_FROM
    assert lean(at) is at
    over = _dense_square(100.0, per)
    assert shapely.get_num_coordinates(over) == LEAN_FROM + 1 and lean(over) is not over


def test_the_vertex_bound_itself_is_accepted_and_one_more_refused(monkeypatch):
    monkeypatch.setattr(dense, "MAX_ZONE_VERTICES", 10)
    box = shapely.box(0.0, 0.0, 1.0, 1.0)  # 5 coordinates
    check_zone_vertices([box, box], "s.toml", ValueError)
    with pytest.raises(ValueError, match=r"^s.toml: \[\[zones\]\] footprints of 11 vertices in all, over the 10 "):
        check_zone_vertices([box, box, shapely.Point(0.0, 0.0)], "s.toml", ValueError)


@pytest.mark.skipif(not Path("/dev/null").exists(), reason="no /dev/null")
def test_a_character_device_is_named_a_device():
    with pytest.raises(ValueError, match=r"^z: is a device, not a file of features"):
        check_source(Path("/dev/null"), "z", ValueError)
