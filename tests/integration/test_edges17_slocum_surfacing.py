"""The Slocum files surface the glider where the plan does: at the top of the last climb of a planned cycle, never
mid-dive.

With ``surface_every_s`` the planner and the flight surface at the first top at or after that long, the first dive
included (docs/gliders.md "Yos per cycle: one rule"), but ``surfac11.ma`` said ``start_when`` 12
(``BAW_NOCOMM_SECS``: no comms for ``when_secs``, wherever the glider is) with ``when_secs`` = ``surface_every_s``
and ``yo10.ma`` counted ``yos`` yos: the time elapsed before the first top after it, so every cycle was cut short
mid-dive. Now the yo file counts the planned cycle's yos (``surfac10.ma``, BAW_PITCH_IDLE, surfaces at its last top)
and the no-comms surfacing is a safety net a nominal cycle never reaches.

The oracle reads the files with its own parser (test_glider_exports') and times the cycle they describe with the
flight model's yo (:func:`auvplan.vehicles.glider.yo_timing`): a first dive from the surface, yos between the
file's ``c_target_depth`` and ``d_target_depth``, the last climb to the surface."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_glider_exports import _ma

from auvplan.io.missions.glider import slocum_files
from auvplan.planners.timeopt.glider import cycle
from auvplan.vehicles.glider import GliderParams, yo_timing

PTS = np.array([[0.0, 0.0], [6000.0, 2000.0], [12000.0, -1000.0]])

GLIDERS = [  # the time cap binding (7200 s is 1.8 yos of 4030 s), the yos cap binding, a time just past 1 yo
    # (2300 s: 1 yo, its top at 2309 s with the first dive; the planner said 2 before test_glider_yos_per_cycle),
    GliderParams(yos=4, dive_depth_m=350.0, climb_depth_m=15.0, surface_every_s=7200.0),  # shallow, many yos
    GliderParams(yos=3, surface_every_s=7200.0),
    GliderParams(yos=9, surface_every_s=2300.0),
    GliderParams(dive_depth_m=100.0, yos=50, surface_every_s=2500.0),
]


def _cycle_of_the_files(files: dict[str, str], g: GliderParams) -> tuple[int, float, float]:
    """(yos, seconds underwater, one yo's seconds) of the cycle the files make the glider fly."""
    _, yo, _ = _ma(files["yo10.ma"])
    half = int(yo["num_half_cycles_to_do"][1])
    top, bottom = yo["c_target_depth"][1], yo["d_target_depth"][1]
    t = yo_timing(g, top, bottom)
    yo_s = t.dive_s + t.climb_s
    assert half % 2 == 0
    n = half // 2
    return n, top / -t.w_dive + n * yo_s + top / t.w_climb, yo_s


@pytest.mark.parametrize("g", GLIDERS, ids=["time-cap-shallow", "yos-cap", "just-past-one-yo", "many-yos"])
def test_the_files_surface_at_the_planned_top_and_never_mid_dive(g):
    c = cycle(g)
    files = slocum_files(PTS, (67.25, 13.75), g, 12.0, yos=c.yos, underwater_s=c.underwater_s)
    n, under, yo_s = _cycle_of_the_files(files, g)
    first = g.climb_depth_m / -yo_timing(g, g.climb_depth_m, g.dive_depth_m).w_dive  # the dive from the surface
    # the first top at or after surface_every_s, the first dive included (test_glider_yos_per_cycle at the boundary)
    assert n == min(g.yos, max(1, math.ceil((g.surface_every_s - first) / yo_s)))
    assert under == pytest.approx(c.underwater_s, rel=1e-9)  # the cycle the plan flies
    _, surf, _ = _ma(files["surfac10.ma"])
    assert surf["start_when"][1] == 2  # BAW_PITCH_IDLE: at the top of the last climb
    _, every, _ = _ma(files["surfac11.ma"])
    assert every["start_when"][1] == 12  # BAW_NOCOMM_SECS: wherever the glider is when it fires
    when = every["when_secs"][1]
    assert under + yo_s < when <= under * (n + 1) / n + 1.0  # never in a nominal cycle, nor one a yo longer; at
    # most a cycle's time per yo late when the glider has not come up (a yo that stalls, an inflection missed)


def test_without_the_cycle_the_no_comms_file_is_not_guessed():
    g = GliderParams(yos=3, surface_every_s=7200.0)
    with pytest.raises(ValueError, match="underwater_s"):
        slocum_files(PTS, (67.25, 13.75), g, 12.0)
    assert "surfac11.ma" not in slocum_files(PTS, (67.25, 13.75), GliderParams(yos=3), 12.0)
