"""Where a surfacing splits the route, no leg is shorter than the exported mission's rule (helper export2, wave 17).

:func:`auvplan.nav.apply_fixes` lifts the route's depth schedule to ``max(z_route(s), −tanθ |s − s_f|)`` and breaks
it where a climb or dive meets a route leg; a fix or such a crossing a few centimetres from a route waypoint made a
leg of centimetres at the pitch limit (``mariana-nav`` launched at the surface: 0.255 m at 19.98°, read 20.14° once
its ends were rounded to the millimetre).  Properties over random routes (bends, climbs and dives within the limit,
legs of 2.5-80 m, a start at the surface or at depth) and fix positions clear of its ends (as the planner places
them), half of them within 3 m of a route waypoint:

* no leg is shorter than :data:`~auvplan.path.legs.FITTED_LEG_M` (3D);
* the pitch of every leg, its ends rounded to the millimetre (as ``.csv`` and ``.moos`` write them), is within the
  limit;
* the mission keeps the route's horizontal track (every route waypoint, every point on it) and is nowhere deeper
  than the route (sampled along each leg);
* each GPS fix is one waypoint at the surface, within 5 m of where it was asked (moved onto a waypoint or the
  rule away from it).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from auvplan.nav.fixes import route_profile
from auvplan.nav.params import NavParams
from auvplan.nav.surfacing import CLIMB_SLACK_DEG, SHORTEST_FIX_LEG_M, apply_fixes
from auvplan.path.flyable import PITCH_SLACK_DEG
from auvplan.path.legs import FITTED_LEG_M
from helpers import flat_world

FAST = settings(max_examples=60, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow])
LIMIT_DEG = 20.0


def _tan() -> float:
    """The planner's own climb slope for a 20° vehicle (``route_profile``)."""
    w = flat_world(depth=200.0, size=1000.0)
    prof = route_profile(w, np.array([[10.0, 10.0, -50.0], [500.0, 10.0, -50.0]]), NavParams(), LIMIT_DEG, 1.5)
    return prof.tan_pitch


TAN = _tan()
ROUTE_TAN = math.tan(math.radians(19.0))  # the routes' steepest legs
CLEAR_TAN = math.tan(math.radians(19.9))  # fixes placed clear of the ends for any climb this steep or steeper
ROUNDED_OVER = 36856
"""A case whose climb at 19.98° (``PITCH_SHARE`` of 20°, the slope before) reads 20.0008° once rounded to the mm."""


def _case(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """A random route and its fixes (None: a route too short for a fix clear of its ends)."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(4, 14))
    h = rng.uniform(2.5, 80.0, n)
    head = np.cumsum(rng.uniform(-1.0, 1.0, n))
    xy = np.vstack([[0.0, 0.0], np.cumsum(np.column_stack([np.cos(head), np.sin(head)]) * h[:, None], axis=0)])
    xy += rng.uniform(-1.0, 1.0, 2) * 1000.0
    z = [0.0 if rng.random() < 0.3 else -rng.uniform(5.0, 60.0)]
    for hk in h:  # each leg within 19°, diving where a climb would come within 1 m of the surface
        dz = rng.uniform(-1.0, 1.0) * ROUTE_TAN * hk
        z.append(z[-1] + dz if z[-1] + dz <= -1.0 else z[-1] - abs(dz))
    route = np.column_stack([xy, z])
    sv = np.r_[0.0, np.cumsum(h)]
    fixes = []
    for _ in range(int(rng.integers(1, 4))):
        if rng.random() < 0.5:  # near a waypoint (either side, within 3 m)
            fixes.append(sv[int(rng.integers(1, n))] + rng.uniform(-3.0, 3.0))
        else:
            fixes.append(rng.uniform(0.0, sv[-1]))
    lo, hi = -route[0, 2] / CLEAR_TAN, sv[-1] + route[-1, 2] / CLEAR_TAN  # clear of the ends, as planned
    if hi <= lo:
        return None
    f = np.sort(np.clip(fixes, lo, hi))
    keep = np.r_[True, np.diff(f) > 20.0]  # fixes apart
    return route, f[keep], sv


def _along(route: np.ndarray, sv: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each point's distance along the route's horizontal track, its distance off it, and the route's depth there."""
    s_out, off, zr = [], [], []
    for p in q:
        best = (math.inf, 0.0, 0.0)
        for i in range(route.shape[0] - 1):
            a, b = route[i, :2], route[i + 1, :2]
            L = sv[i + 1] - sv[i]
            t = float(np.clip(np.dot(p[:2] - a, b - a) / (L * L), 0.0, 1.0))
            d = float(np.hypot(*(a + t * (b - a) - p[:2])))
            if d < best[0] - 1e-9:
                best = (d, sv[i] + t * L, route[i, 2] + t * (route[i + 1, 2] - route[i, 2]))
        off.append(best[0]), s_out.append(best[1]), zr.append(best[2])
    return np.array(s_out), np.array(off), np.array(zr)


def test_the_rules_are_the_exported_missions():
    assert SHORTEST_FIX_LEG_M == FITTED_LEG_M
    assert CLIMB_SLACK_DEG == PITCH_SLACK_DEG
    assert math.degrees(math.atan(TAN)) == pytest.approx(LIMIT_DEG - PITCH_SLACK_DEG, abs=1e-12)


@FAST
@given(st.integers(0, 2**31 - 1))
@example(ROUNDED_OVER)
def test_a_fix_splits_the_route_into_legs_no_shorter_than_the_rule(seed):
    case = _case(seed)
    assume(case is not None)
    assert case is not None
    route, fixes, sv = case
    pts, kinds = apply_fixes(route, fixes, ("gps",) * fixes.size, TAN)
    legs = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert legs.min() >= FITTED_LEG_M - 1e-9, (int(legs.argmin()), float(legs.min()))
    d = np.diff(np.round(pts, 3), axis=0)  # the ends as the metric formats write them
    pitch = np.degrees(np.arctan2(np.abs(d[:, 2]), np.hypot(d[:, 0], d[:, 1])))
    assert pitch.max() <= LIMIT_DEG, (int(pitch.argmax()), float(pitch.max()))
    # the horizontal track kept: every route waypoint is one of the mission's, every point lies on the track
    for v in route[:, :2]:
        assert np.hypot(*(pts[:, :2] - v).T).min() < 1e-6
    t = np.linspace(0.0, 1.0, 9)[:, None, None]
    q = (pts[:-1] + t * (pts[1:] - pts[:-1])).reshape(-1, 3)
    s, off, zr = _along(route, sv, q)
    assert off.max() < 1e-6
    assert np.all(q[:, 2] >= zr - 1e-6), float((zr - q[:, 2]).max())  # nowhere deeper than the route
    # each fix a surface waypoint near where it was asked
    at = np.flatnonzero([k == "gps" for k in kinds])
    assert at.size == fixes.size and np.all(np.abs(pts[at, 2]) < 1e-9)
    s_fix, _, _ = _along(route, sv, pts[at])
    assert np.all(np.abs(s_fix - fixes) <= 2.0 * SHORTEST_FIX_LEG_M + 1e-9)  # moved off a waypoint at most
