"""A terrain-following ``.plan`` read back within the millimetre its file carries (docwalk20).

``auvplan run mariana-nav`` then ``mission check results/nav/mission.plan`` failed (exit 1) on a mission the
export had judged flyable: its surface fixes, written in the terrain frame (altitude 1 869.1 m over the seabed),
read back 0.3 mm above the surface; a waypoint at exactly ``max_depth_m`` read back 0.5 mm below it; and a leg the
export placed on a grid line read back 0.03 mm off it, the 26 µm sliver of the next cell lending the whole leg that
cell's slope (24.8° for the 19.98° it flies).  Oracles: the depth band's edges by hand; the pitch of a leg
following a seabed of two known slopes (the cell it flies over, in closed form).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_deploy_terrain_cases import _band_world

from auvplan.guidance.mission.terrain_legs import END_MERGE_M, flown_track
from auvplan.io.missions.deploy import ROUNDED_RISE_M, _terrain_items
from auvplan.world import Terrain


def test_waypoints_on_the_depth_bands_edges_keep_their_depth() -> None:
    """Band 5-50 m over a flat 100 m seabed: the waypoints at 5 m (``min_depth_m``, a surface fix's edge) and at
    50 m (``max_depth_m``) and within ``ROUNDED_RISE_M`` of them are written at their depth; 1 cm inside the band
    they follow the seabed."""
    world = _band_world()
    z = [-20.0, -5.0, -20.0, -50.0, -20.0, -50.0 + 0.5 * ROUNDED_RISE_M, -49.99, -5.01, -20.0]
    w = np.column_stack([np.linspace(100.0, 900.0, len(z)), np.full(len(z), 500.0), z])
    items = _terrain_items(world, w, 20.0)
    assert items.tolist() == [True, False, True, False, True, False, True, True, True]


def _two_slopes(y_line: float) -> Terrain:
    """A seabed rising northward at 1 in 10 below ``y_line`` and 1 in 2 above it (a grid line there)."""
    x = np.array([0.0, 100.0, 200.0])
    y = np.array([0.0, y_line, y_line + 100.0])
    z = np.array([-200.0, -200.0 + 0.1 * y_line, -200.0 + 0.1 * y_line + 50.0])
    return Terrain(x, y, np.repeat(z[:, None], 3, axis=1), name="two slopes")


@pytest.mark.parametrize("offset", [-2.6e-5, 0.0, 2.6e-5, -0.9 * END_MERGE_M])
def test_a_leg_starting_within_the_files_precision_of_a_grid_line_flies_the_cell_it_crosses(offset: float) -> None:
    """A 62.5 m leg north from the grid line at y = 100 m (or a fraction of a millimetre to either side of it),
    held 50 m above the seabed: its steepest tangent is the upper cell's, atan(1/2) = 26.57°, not the lower
    cell's 1 in 10 (5.71°) — nor, had the slopes been the other way, the lower cell's steeper one (below)."""
    ter = _two_slopes(100.0)
    a = np.array([100.0, 100.0 + offset, float(ter.elevation(100.0, 100.0 + offset)) + 50.0])
    b = np.array([100.0, 162.5, float(ter.elevation(100.0, 162.5)) + 50.0])
    pitch = flown_track(ter, np.stack([a, b]), np.ones(1, dtype=bool)).pitch[0]
    assert pitch == pytest.approx(math.degrees(math.atan(0.5)), abs=1e-6)
    # the slopes the other way: a steep cell below, a gentle one above; the sliver below is not the leg's pitch
    flat = Terrain(ter.x, ter.y, np.repeat(np.array([-200.0, -150.0, -140.0])[:, None], 3, axis=1), name="steep below")
    a2 = np.array([100.0, 100.0 + offset, float(flat.elevation(100.0, 100.0 + offset)) + 50.0])
    b2 = np.array([100.0, 162.5, float(flat.elevation(100.0, 162.5)) + 50.0])
    pitch2 = flown_track(flat, np.stack([a2, b2]), np.ones(1, dtype=bool)).pitch[0]
    assert pitch2 == pytest.approx(math.degrees(math.atan(0.1)), abs=1e-3)
