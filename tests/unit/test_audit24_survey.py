"""Audit 24 of the survey code: bugs the fixtures never reached because they never varied what the bug depends on
(a thin strip of an area, ...). Each test has an independent oracle worked out by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from auvplan.survey.coverage import lawnmower
from auvplan.survey.lines.swath import Sensor


def _flat(depth: float):  # noqa: ANN202
    return lambda x, y: np.full(np.broadcast(np.asarray(x), np.asarray(y)).shape, -depth)


@pytest.mark.parametrize(("width", "heading_deg"), [(12.0, 90.0), (30.0, 90.0), (39.0, 90.0), (30.0, 0.0)])
def test_the_lawnmower_of_a_strip_narrower_than_its_sampling_grid(width, heading_deg):
    """A 4 km x ``width`` strip over a flat 50 m seabed: its shallowest depth is 50 m.  The lawnmower sampled the
    seabed on a grid of a hundredth of the area's longer side (40 m) and read no sample inside a strip narrower than
    that: ``np.max`` of nothing, a ValueError out of ``auvplan survey`` (exit 2, 'zero-size array') on a valid strip.
    By hand: a 120° fan over 50 m reaches 50 tan 60° either side, the lanes 0.9 x 2 x 86.6 = 155.9 m apart; along
    the strip (90°) one lane of 4 km + 2 x 60 m run-in; across it (0°) a lane every 155.9 m or less over the 4 km
    less the swath, each the strip's width + 2 x 60 m long."""
    area = shapely.box(0.0, 0.0, 4000.0, width)
    mower = lawnmower(_flat(50.0), area, Sensor(), math.radians(heading_deg), 0.1, 0.0, 60.0)
    reach = 50.0 * math.tan(math.radians(60.0))
    assert mower.shallowest_m == pytest.approx(50.0)
    assert mower.spacing_m == pytest.approx(0.9 * 2.0 * reach)
    if heading_deg == 90.0:
        assert mower.lines == 1 and mower.line_length_m == pytest.approx(4000.0 + 120.0, abs=2.5)
    else:
        count = math.ceil((4000.0 - 2.0 * reach) / (0.9 * 2.0 * reach)) + 1
        assert mower.lines == count and mower.line_length_m == pytest.approx(count * (width + 120.0), rel=1e-6)
