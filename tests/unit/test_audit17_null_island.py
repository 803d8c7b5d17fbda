"""Audit 17: an item of a ``.plan`` at latitude 0, longitude 0.  ArduSub stores positions in 1e-7 degrees and reads
both 0 as "no position given: the current one" (``Sub::do_nav_wp``, ``do_loiter_unlimited``: ``if (lat == 0 &&
lng == 0)``), as it reads altitude 0 as "the current altitude" (the centimetre rule of wave 13): the vehicle goes
to the item's depth where it is, not to the point.  ``mission check`` judged the leg to (0°, 0°) (the Gulf of
Guinea, 5 km deep: a real place to work), and the export wrote such an item.  Oracle: ArduSub's
commands_logic.cpp; the export's item read back 1.1 cm north, the distance 1e-7° is."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.errors import DataError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.formats import to_qgc_plan
from auvplan.io.missions.readback.readers import parse_qgc_plan


def _doc(lat: float, lon: float) -> dict:
    items = [{"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, None, 0.01, 0.01, -20.0]},
             {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, None, lat, lon, -20.0]}]
    return {"mission": {"plannedHomePosition": [0.01, 0.01, 0], "items": items}}


@pytest.mark.parametrize(("lat", "lon"), [(0.0, 0.0), (4e-8, -6e-8), (-0.0, 9.9e-8)])
def test_an_item_at_null_island_is_refused_naming_it(lat, lon):
    with pytest.raises(DataError, match=r"mission\.items\[1\]: at latitude .* ArduSub reads \(0, 0\)"):
        parse_qgc_plan(_doc(lat, lon), LocalFrame(0.0, 0.0))


@pytest.mark.parametrize(("lat", "lon"), [(0.0, 2e-7), (-3e-7, 0.0), (0.5, -0.5)])
def test_an_item_near_it_reads_as_before(lat, lon):
    w = parse_qgc_plan(_doc(lat, lon), LocalFrame(0.0, 0.0))
    x, y = LocalFrame(0.0, 0.0).forward(lon, lat)
    assert np.allclose(w[2], [x, y, -20.0])


def test_the_export_of_a_waypoint_at_0_0_moves_it_a_centimetre_north_and_reads_back():
    frame = LocalFrame(0.0, 0.0)
    pts = np.array([[-500.0, 300.0, -20.0], [0.0, 0.0, -20.0], [400.0, -200.0, -20.0]])
    doc = to_qgc_plan(pts, (0.0, 0.0), 1.5)
    w = parse_qgc_plan(doc, frame)
    lat, lon = doc["mission"]["items"][2]["params"][4:6]  # after the leading DO_CHANGE_SPEED and the first point
    assert lat == 1e-7 and abs(lon) < 1e-7
    assert np.allclose(w[1:], pts, atol=0.02) and 0.005 < w[2, 1] < 0.02  # 1.1 cm north
