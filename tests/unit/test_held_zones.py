"""A survey's route under held depth (MOOS-IvP) was re-checked for the seabed and the obstacles, not the no-go zones'
depth bands (:func:`auvplan.survey.held.held_safe`): a leg whose depth change carried the executor through a zone's
band (its straight 3D line above it) was reported safe, and its ``mission.moos`` failed ``mission check``.  Now a
leg whose held envelope enters a band is split along its 3D line until it clears, and what cannot clear (a level leg
whose held depth lies in the band) is said, naming the zone.  A band that does not hold the depth (a cable zone
``above_seabed_m`` below the held depth) is no obstacle.

Oracle: the zone's band and the legs' depth ranges by hand (a flat 100 m seabed, the zone the strip
900 <= x <= 1100), and ``held_zone_entries``, the exact test of ``mission check``."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.guidance.mission.zone_legs import held_zone_entries
from auvplan.io.scenario.build import build
from auvplan.io.scenario.loader import loads
from auvplan.survey.held import held_safe

SCENE = """
name = "zoned"
[bounds]
x = [0.0, 2000.0]
y = [0.0, 1000.0]
z = [-120.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 100.0
cell_m = 50.0
[mission]
start = [100.0, 500.0, -50.0]
goal = [1900.0, 500.0, -50.0]
min_altitude_m = 10.0
[[zones]]
name = "band"
polygon = [[900.0, 0.0], [1100.0, 0.0], [1100.0, 1000.0], [900.0, 1000.0]]
{band}
"""
LEVEL = np.array([[100.0, 500.0, -50.0], [1900.0, 500.0, -50.0]])  # a survey line held 50 m deep
DIVE = np.array([[100.0, 500.0, -10.0], [1900.0, 500.0, -88.0]])  # a join diving from 10 m to 88 m deep


def _world(band: str):
    return build(loads(SCENE.format(band=band), "z.toml"))[0]


def test_a_level_line_in_a_band_holding_its_depth_is_refused_naming_the_zone():
    route, _, msg = held_safe(_world("top_m = 40.0\nbottom_m = 60.0"), LEVEL, np.zeros(2, dtype=np.int64), 15.0, 5.0)
    assert "leg 0 (line 0" in msg and "enters no-go zone 'band'" in msg, msg


@pytest.mark.parametrize("band", ["above_seabed_m = 20.0", "top_m = 70.0\nbottom_m = 90.0"])
def test_a_band_that_does_not_hold_the_held_depth_is_no_obstacle(band):
    """A seabed cable zone 20 m high (80-100 m deep) or a band 70-90 m deep, under a line held 50 m deep."""
    route, _, msg = held_safe(_world(band), LEVEL, np.zeros(2, dtype=np.int64), 15.0, 5.0)
    assert msg == "" and np.array_equal(route, LEVEL)


def test_a_depth_change_through_a_band_is_split_until_it_clears():
    world = _world("top_m = 70.0\nbottom_m = 90.0")
    straight, _ = world.zones.exact.entries(np.stack([DIVE[:-1], DIVE[1:]], axis=1))
    assert straight.size == 0 and held_zone_entries(world.zones.exact, DIVE, 15.0)[0].size  # the case: held only
    route, labels, msg = held_safe(world, DIVE, np.array([-1, -1], dtype=np.int64), 15.0, 5.0, {-1: "a turn"})
    assert msg == "", msg
    a, b = route[:-1], route[1:]
    over = (np.maximum(a[:, 0], b[:, 0]) >= 900.0) & (np.minimum(a[:, 0], b[:, 0]) <= 1100.0)
    deep, shallow = -np.minimum(a[:, 2], b[:, 2]), -np.maximum(a[:, 2], b[:, 2])
    assert over.any() and ((deep[over] < 70.0) | (shallow[over] > 90.0)).all()  # by hand: no range meets 70-90 m
    assert held_zone_entries(world.zones.exact, route, 15.0)[0].size == 0  # and mission check's own test
    t = (route[:, 0] - DIVE[0, 0]) / (DIVE[1, 0] - DIVE[0, 0])  # every inserted point on the 3D line
    assert np.allclose(route, DIVE[0] + t[:, None] * (DIVE[1] - DIVE[0]))
