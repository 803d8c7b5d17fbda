"""Audit 17: the least altitude of a ``.plan``'s terrain-frame leg is the altitude it holds.  ArduSub's target goes
linearly from one item's altitude above the seabed to the next one's, so a leg whose items are both 20 m above the
seabed is flown 20 m above it all the way; but it was measured on the track's chords, which over a crest stand up
to ``SAG_M`` (1 cm) under the curve they stand for: a leg held at exactly ``min_altitude_m`` read 19.99 m and
failed ``mission check`` (seabed check and terrain-following line).  Oracle: the analytic altitude (linear in the
leg's parameter) and a dense sampling of the flown curve over a bilinear crest."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.app.check import terrain_following_check
from auvplan.guidance.mission.terrain_legs import check_as_flown
from auvplan.world.terrain import Terrain
from auvplan.world.world import Bounds, Margins, World

# along the cell's diagonal the seabed is -100 + 80 t - 40 t^2: a crest the chords cut under
_CREST = Terrain(np.array([0.0, 100.0]), np.array([0.0, 100.0]), np.array([[-100.0, -60.0], [-60.0, -60.0]]))


def _world() -> World:
    return World(Bounds(0.0, 100.0, 0.0, 100.0, -200.0, 0.0), _CREST, margins=Margins(min_altitude=20.0))


def _flown_altitude(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The model's altitude along the leg, sampled densely: the track's depth less the seabed under it."""
    s = np.linspace(0.0, 1.0, 20_001)
    xy = a[:2] + s[:, None] * (b[:2] - a[:2])
    ha, hb = a[2] - _CREST.elevation(a[0], a[1]), b[2] - _CREST.elevation(b[0], b[1])
    return (_CREST.elevation(xy[:, 0], xy[:, 1]) + ha + s * (hb - ha)) - _CREST.elevation(xy[:, 0], xy[:, 1])


def test_a_leg_held_at_the_least_altitude_over_a_crest_passes():
    pts = np.array([[0.0, 0.0, -80.0], [100.0, 100.0, -40.0]])  # both items 20 m above the seabed
    assert _flown_altitude(pts[0], pts[1]).min() == pytest.approx(20.0, abs=1e-9)
    check = check_as_flown(_world(), pts, np.array([True]), launch=False)
    assert check.min_altitude_m == pytest.approx(20.0, abs=1e-9) and check.ok
    rec, ok, line = terrain_following_check(_world(), pts, np.array([True]))
    assert ok and rec["min_altitude_m"] == pytest.approx(20.0, abs=1e-9), line


@pytest.mark.parametrize(("ha", "hb"), [(25.0, 19.0), (19.5, 30.0)])
def test_a_leg_whose_item_is_under_the_least_altitude_still_fails_at_its_altitude(ha, hb):
    pts = np.array([[0.0, 0.0, -100.0 + ha], [100.0, 100.0, -60.0 + hb]])
    want = _flown_altitude(pts[0], pts[1]).min()
    assert want == pytest.approx(min(ha, hb), abs=1e-9)
    check = check_as_flown(_world(), pts, np.array([True]), launch=False)
    assert check.min_altitude_m == pytest.approx(want, abs=1e-9) and not check.ok
    rec, ok, _ = terrain_following_check(_world(), pts, np.array([True]))
    assert not ok and rec["min_altitude_m"] == pytest.approx(want, abs=1e-9)
