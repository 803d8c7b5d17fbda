"""The fix planner judges each interval of a stretch at the error one piece (``step``) past its end, within its route
leg and the stretch (``auvplan.nav.fixes._clear``; helper timing, wave 18): ``mission check`` tests each piece of a
mission leg, at most ``step`` long, under the error at its end, and a surfacing cuts the route's legs so that those
pieces need not match the planner's intervals — a piece meeting interval k ends at most ``step`` past its end.

Oracle: that bound, by hand, on a route sampled every 30 m (step 50 m: a piece may reach two samples ahead) with the
error growing 1 m per sample; a safe radius of exactly the error there passes, 1 cm less fails; a leg's end caps it.
"""

from __future__ import annotations

import numpy as np

from auvplan.nav.fixes import RouteProfile, _clear


def _profile(r_safe: np.ndarray, leg: np.ndarray) -> RouteProfile:
    m = r_safe.size + 1
    s = np.arange(m) * 30.0
    xyz = np.column_stack([s, np.zeros(m), np.full(m, -100.0)])
    return RouteProfile(s, xyz, np.full(m, -1000.0), r_safe, s / 1.5, np.ones(m - 1), 0.3, leg=leg, step=50.0)


def test_each_interval_allows_the_error_a_step_past_its_end():
    err = 10.0 + np.arange(8.0)  # on arrival at samples 1..8 (intervals 0..7)
    ahead = err[np.minimum(np.arange(8) + 2, 7)]  # 30 m samples: s + 50 m is two samples on; the stretch caps it
    leg = np.zeros(8, dtype=np.intp)
    assert _clear(_profile(ahead.copy(), leg), 0, err)
    for k in range(6):  # one centimetre less anywhere a piece can reach: not clear (its own error would pass)
        r = ahead.copy()
        r[k] -= 0.01
        assert r[k] > err[k] and not _clear(_profile(r, leg), 0, err), k


def test_a_route_legs_end_caps_the_look_ahead():
    """The mission's legs lie within the route's: a piece never crosses a route vertex (at sample 4)."""
    err = 10.0 + np.arange(8.0)
    leg = np.r_[np.zeros(4), np.ones(4)].astype(np.intp)
    capped = err[np.minimum(np.minimum(np.arange(8) + 2, 7), np.r_[3, 3, 3, 3, 7, 7, 7, 7])]
    assert _clear(_profile(capped.copy(), leg), 0, err)
    assert capped[2] == err[3]  # interval 2 looks one sample ahead only, to its leg's end
