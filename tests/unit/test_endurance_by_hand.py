"""The energy budget's input checks and edge cases by hand (issue 49's mutation run of ``endurance``)."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.endurance.budget import traverse
from auvplan.world import Bounds, World

WORLD = World(Bounds(-1000, 1000, -1000, 1000, -200, 0))
PTS = np.array([[0.0, 0.0, -50.0], [100.0, 0.0, -50.0], [200.0, 0.0, -50.0]])


@pytest.mark.parametrize("speeds", [[1.0, 0.0], [0.0, 1.0], [1.0, -1.0], [1.0, np.nan], [1.0, np.inf]])
def test_traverse_refuses_any_leg_speed_that_is_not_positive_and_finite(speeds) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match="leg speeds and ds must be positive"):
        traverse(WORLD, PTS, speeds, 0.0, 10.0)


def test_traverse_in_still_water_takes_length_over_speed_per_leg() -> None:
    tr = traverse(WORLD, PTS, [1.0, 2.0], 100.0, 10.0)
    assert tr.ok and tr.times.tolist() == pytest.approx([100.0, 200.0, 250.0])
