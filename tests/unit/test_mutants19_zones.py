"""Round 6 of docs/mutants.md: the zone reader's repair of an invalid polygon (``_repaired``: the rings' structure,
not the even-odd rebuild), worked by hand.

* A single polygon whose hole crosses its shell (box 0-10 with a hole 5-15): the shell's 100 m^2 less the hole's
  part inside it, 25 m^2: 75 m^2 (the even-odd rebuild made it 150 m^2: the hole's outer part a zone).
* A part that has collapsed to a line (three collinear points) is dropped, not kept as a line: the footprint is
  the one box, a polygon.
"""

from __future__ import annotations

import shapely

from auvplan.io.data.vector.zones import _repaired


def test_a_polygon_whose_hole_crosses_its_shell_keeps_the_shell_less_the_hole():
    p = shapely.Polygon(shapely.box(0.0, 0.0, 10.0, 10.0).exterior.coords,
                        [shapely.box(5.0, 5.0, 15.0, 15.0).exterior.coords])
    assert not p.is_valid
    out = _repaired(p)
    assert out.area == 75.0
    assert out.equals(shapely.box(0.0, 0.0, 10.0, 10.0).difference(shapely.box(5.0, 5.0, 10.0, 10.0)))


def test_a_part_collapsed_to_a_line_is_dropped():
    mp = shapely.MultiPolygon([shapely.box(0.0, 0.0, 10.0, 10.0), shapely.Polygon([(20, 20), (25, 20), (22, 20)])])
    out = _repaired(mp)
    assert out.geom_type == "Polygon" and out.equals(shapely.box(0.0, 0.0, 10.0, 10.0))
