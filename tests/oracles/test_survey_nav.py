"""Survey line spacing under the relative navigation error of adjacent lines (issue 52 item 5).

Oracle: an independent computation from the planned route itself.  For every pair of adjacent lines and
every station, the path flown between the two passes is measured along the route (its horizontal
length between the route points nearest the station on each line); the relative error there is
confidence × drift rate × that length (the same bias on both lines between fixes).  Displaced by it, the
two swaths must still overlap by the floor; on the plan made without ``[navigation]`` they do not.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan.io.results.survey import survey_params
from auvplan.io.scenario import loader
from auvplan.survey.mission import plan_survey


@pytest.fixture(scope="module")
def planned():
    sc = loader.load("shelf-survey-nav")
    world, mission = loader.build(sc)
    params = survey_params(sc.survey, world, mission.vehicle, sc.base_dir, "shelf-survey-nav: [survey]")
    return mission, {nav: plan_survey(world, replace(mission, navigation=mission.navigation if nav else None),
                                      params, 1) for nav in (True, False)}


def _displaced_overlap(plan, rel_per_m):
    """Per adjacent pair: (least overlap with the second line displaced by the relative error, least margin
    the planner used minus the error measured on the route)."""
    lines, route, lab = plan.lines, plan.route, plan.labels
    cum = np.r_[0.0, np.cumsum(np.hypot(*np.diff(route[:, :2], axis=0).T))]
    s_route = lines.geom.to_sn(route[:, 0], route[:, 1])[0]
    worst, slack = [], []
    for i, (a, b) in enumerate(zip(lines.lines[:-1], lines.lines[1:], strict=True)):
        ks = np.arange(max(a.first, b.first), min(a.last, b.last) + 1)
        ja, jb = np.flatnonzero(lab == i), np.flatnonzero(lab == i + 1)
        s = lines.stations[ks]
        pa = ja[np.argmin(np.abs(s_route[ja][None, :] - s[:, None]), axis=1)]  # the pass of each line
        pb = jb[np.argmin(np.abs(s_route[jb][None, :] - s[:, None]), axis=1)]
        r = rel_per_m * np.abs(cum[pb] - cum[pa])  # the drift grown between the two passes
        ea, eb = a.c[ks] + a.right[ks], b.c[ks] - b.left[ks]
        keep = (eb < lines.area_hi[ks]) & (ea > lines.area_lo[ks])  # the seam inside the area
        w = np.minimum(a.left + a.right, b.left + b.right)[ks]
        worst.append(float(((ea - eb - r) / w)[keep].min()))
        if b.nav_margin is not None:
            slack.append(float((b.nav_margin[ks] - r).min()))
    return np.array(worst), np.array(slack)


def test_spacing_keeps_the_overlap_floor_under_the_relative_error_measured_on_the_route(planned):
    mission, plans = planned
    nav = mission.navigation
    rel = nav.confidence * nav.drift_pct / 100.0  # 30 m above the seabed: bottom lock on the lines
    floor = 0.10  # the scenario's overlap floor
    with_nav, slack = _displaced_overlap(plans[True], rel)
    assert with_nav.min() >= floor - 1e-3  # displaced by the measured error, every seam keeps the floor
    assert slack.size == len(plans[True].lines.lines) - 1 and slack.min() >= 0.0  # the planner's bound holds
    without, _ = _displaced_overlap(plans[False], rel)
    assert without.min() < floor - 0.05  # it matters: the plan without [navigation] loses the floor
    assert len(plans[True].lines.lines) > len(plans[False].lines.lines)  # at the price of more lines
