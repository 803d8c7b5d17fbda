"""The fixed-lane lawnmower the survey is compared with (survey.coverage.lawnmower): every lane counted flies the
area's length.  Oracle: a rectangle over a flat seabed by hand — the swath 2 D tan(θ/2), the lane count
ceil((W - swath) / spacing) + 1, each lane the rectangle's length plus its two run-ins."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from auvplan.cli.survey import _versus_lawnmower
from auvplan.survey.coverage import lawnmower
from auvplan.survey.lines.swath import Sensor


@pytest.mark.parametrize("width", [700.0, 800.0, 300.0])
def test_every_lane_of_the_fixed_lawnmower_flies_the_area_s_length(width: float) -> None:
    """A 120° multibeam at the surface over 100 m of water: swath 346.4 m, spacing 311.8 m at 10 % overlap.  700 m
    wide: 3 lanes; stepping the spacing from the west edge put the third 97 m east of the area, counted with no
    length (2 lanes' length for 3: the corridor's "-28.5 km saved").  800 m: 3 lanes, all inside either way;
    300 m: one lane down the middle."""
    area = shapely.box(0.0, 0.0, width, 10000.0)
    swath = 2.0 * 100.0 * math.tan(math.radians(60.0))
    spacing = 0.9 * swath
    count = max(1, math.ceil(max(width - swath, 0.0) / spacing) + 1)
    m = lawnmower(lambda x, y: np.full(np.shape(x), -100.0), area, Sensor(), 0.0, 0.1, 0.0, 50.0)
    assert m.lines == count == {700.0: 3, 800.0: 3, 300.0: 1}[width]
    assert m.spacing_m == pytest.approx(spacing, rel=1e-9) and m.shallowest_m == pytest.approx(100.0)
    assert m.line_length_m == pytest.approx(count * (10000.0 + 2 * 50.0), rel=1e-9)


def test_the_comparison_is_said_only_where_the_survey_saves_something() -> None:
    saved = {"shallowest_m": 62.4, "lines": 22, "line_length_m": 60279.4, "lines_saved": 4,
             "line_length_saved_m": 13167.9}
    assert _versus_lawnmower(saved) == "; fixed lawnmower for 62 m: 22 lines, 4 lines and 13.2 km of line saved"
    corridor = {"shallowest_m": 174.3, "lines": 2, "line_length_m": 56200.0, "lines_saved": 0,
                "line_length_saved_m": -299.3}
    assert _versus_lawnmower(corridor) == ("; fixed lawnmower for 174 m: 2 lines, 56.2 km: the depth-adaptive "
                                           "spacing saves no line here")
