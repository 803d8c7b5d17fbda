""":func:`auvplan.survey.joins.join_bridges` on two bridges that share a line vertex (a line crossing two
zones with one vertex kept between them): the second bridge's turn in must start from the heading the first
bridge's joined turn arrives with, not from the first bridge's original vertex (audit 13)."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.path.flyable import VehicleLimits
from auvplan.path.legs import helm_check
from auvplan.survey.joins import join_bridges
from auvplan.survey.mission import TRANSIT
from auvplan.world.terrain import Terrain
from auvplan.world.world import Bounds, World


def _tightest(route: np.ndarray, radius: float) -> float:
    return float(helm_check(route, VehicleLimits(90.0, radius), min_leg=0.0).tightest_turn_m)


@pytest.mark.parametrize("radius", [60.0, 100.0])
def test_two_bridges_sharing_a_vertex_fly_as_turns_of_the_radius(radius):
    x, y = np.linspace(-200.0, 1000.0, 7), np.linspace(-300.0, 300.0, 4)
    world = World(bounds=Bounds(-200.0, 1000.0, -300.0, 300.0, -200.0, 0.0),
                  terrain=Terrain(x, y, np.full((4, 7), -200.0)))
    xy = [(0, 0), (100, 0), (200, 0), (250, 60), (300, 60), (350, 0), (400, 60), (450, 60), (500, 0), (600, 0),
          (700, 0)]
    route = np.array([(a, b, -50.0) for a, b in xy], dtype=float)
    labels = np.array([0, 0, 0, TRANSIT, TRANSIT, 0, TRANSIT, TRANSIT, 0, 0, 0])
    before = _tightest(route, radius)
    assert before < radius  # the bridges' corners are too sharp: both are joined by turns
    joined, lab = join_bridges(world, route, labels, TRANSIT, radius)
    assert joined.shape[0] > route.shape[0] and lab.shape == joined.shape[:1]
    # the invariant of the docstring: every turn of a joined bridge fits the radius as a helm flies it
    # (before the fix: 13.9 m at 60 m, 22.6 m at 100 m, at the shared vertex (350, 0), sharper than the corners)
    assert _tightest(joined, radius) >= radius * (1.0 - 1e-9)
    assert np.isclose(joined[:, :2], [350.0, 0.0]).all(axis=1).sum() == 1  # the shared line vertex kept once
