"""Round 6 of docs/mutants.md: ``merge_short_legs``'s choices worked by hand on a flat seabed 110 m deep (nothing to
cut: every straight leg is free), so only the rule decides which waypoint goes.

* Of a short leg's two ends, the one whose removal leaves the longer new leg goes first; the mission's ends, its
  fixed vertices, a leg of exactly ``min_leg`` and a short leg whose ends cannot go stay (and do not block a later
  merge).
* A merge whose new leg is steeper than the limit and than both legs it replaces is refused (a vertical new leg,
  and one 0.5 deg over a 20 deg limit: the 1e-9 deg tolerance, not one degree); one steeper than the limit but not
  than the steeper old leg is allowed.
* An end that comes back to the point before it (A, V, A) goes: the new leg has no length.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.guidance.mission.legs import merge_short_legs
from auvplan.world import Bounds, Margins, Terrain, World

_X = np.arange(-200.0, 401.0, 50.0)
_Y = np.arange(-50.0, 51.0, 50.0)
FLAT = World(Bounds(-200.0, 400.0, -50.0, 50.0, -120.0, 0.0),
             Terrain(_X, _Y, np.full((_Y.size, _X.size), -110.0), name="flat"), margins=Margins(min_altitude=10.0),
             name="flat")


def _line(*x: float, z: float = -50.0) -> np.ndarray:
    return np.array([[v, 0.0, z] for v in x])


@pytest.mark.parametrize(("x", "keep"), [
    ((0.0, 100.0, 100.3, 300.0), [0, 1, 3]),  # V at 100.3 goes: B -> D (200 m) is longer than A -> C (100.3 m)
    ((0.0, 200.0, 200.3, 300.0), [0, 2, 3]),  # B at 200 goes: A -> C (200.3 m) is longer than B -> D (100 m)
    ((0.0, 0.3, 100.0), [0, 2]),  # a short first leg: its far end goes, never the start (three points merge)
    ((0.0, 100.0, 100.3), [0, 2]),  # a short last leg: its near end goes, never the goal
    ((0.0, 100.0, 101.0, 200.0), [0, 1, 2, 3]),  # a leg of exactly min_leg stays
])
def test_which_end_of_a_short_leg_goes(x, keep):
    assert merge_short_legs(FLAT, _line(*x), 1.0).tolist() == keep


def test_a_short_leg_between_fixed_vertices_stays_and_a_later_one_still_merges():
    w = _line(0.0, 100.0, 100.3, 200.0, 200.3, 300.0)
    # 1-2 is stuck (both fixed); of 3-4, waypoint 3 goes (2 -> 4: 100.3 m, longer than 3 -> 5: 99.7 m)
    assert merge_short_legs(FLAT, w, 1.0, fixed=[1, 2]).tolist() == [0, 1, 2, 4, 5]
    assert merge_short_legs(FLAT, w, 1.0, fixed=[1]).tolist() == [0, 1, 4, 5]  # 2 goes, then 3 (1 -> 4 longer)
    assert merge_short_legs(FLAT, w, 1.0, fixed=[2]).tolist() == [0, 2, 4, 5]


def _pitch_case(b: tuple[float, float]) -> np.ndarray:
    """S, A (fixed), V 0.4-0.77 m on, B (fixed) back towards A and lower, E: only V can go."""
    return np.array([[-100.0, 0.0, -50.0], [0.0, 0.0, -50.0], [0.76755, 0.0, -50.0], [b[0], 0.0, -50.0 - b[1]],
                     [100.0, 0.0, -50.0 - b[1]]])


@pytest.mark.parametrize(("b", "goes"), [
    ((0.0, 0.3), False),  # A -> B vertical (90 deg) over V -> B's 21.3 deg and the 20 deg limit
    ((0.1 / math.tan(math.radians(20.5)), 0.1), False),  # A -> B 20.5 deg over the limit and V -> B's 11.3 deg
    ((0.1 / math.tan(math.radians(19.9)), 0.1), True),  # within the limit
    ((0.52, 0.3), True),  # A -> B 30 deg over the limit but under V -> B's 72 deg: no steeper than before
])
def test_a_merge_steeper_than_the_limit_and_both_old_legs_is_refused(b, goes):
    w = _pitch_case(b)
    keep = merge_short_legs(FLAT, w, 1.0, fixed=[1, 3], max_pitch_deg=20.0).tolist()
    assert keep == ([0, 1, 3, 4] if goes else [0, 1, 2, 3, 4])


def test_an_end_that_comes_back_to_the_point_before_it_goes():
    w = _line(-100.0, 0.0, 0.3, 0.0, 100.0)  # A (fixed), V 0.3 m on, A again: A -> A has no length
    assert merge_short_legs(FLAT, w, 1.0, fixed=[1]).tolist() == [0, 1, 4]


def test_a_merge_next_to_a_leg_already_too_low_goes():
    """A (the start) 5 m over the seabed, under the 10 m margin: A -> V is not free already, V -> B is; the merged
    A -> B is not free either, and the merge loses no safety the mission had (module notes): V goes."""
    w = np.array([[0.0, 0.0, -105.0], [20.0, 0.0, -95.0], [200.0, 0.0, -50.0]])
    assert not FLAT.segments_free(np.stack([w[:2], w[::2]]), moving=False, ends_free=True).any()
    assert FLAT.segments_free(w[None, 1:], moving=False, ends_free=True).all()
    assert merge_short_legs(FLAT, w, 50.0).tolist() == [0, 2]


def test_a_moving_obstacle_does_not_decide_a_merge():
    """The merge is judged on the static world (module notes: the export's check, without the moving obstacles): a
    drifting sphere parked at t = 0 on the chord A -> B, 0.3 m from both old legs (radius 0.1 m), changes nothing;
    a static sphere there keeps V."""
    from dataclasses import replace

    from auvplan.world import LinearMotion, MovingObstacle, Sphere

    w = np.array([[-100.0, 0.0, -50.0], [0.0, 0.0, -50.0], [0.6, 0.0, -50.0], [0.6, 50.0, -50.0],
                  [0.6, 100.0, -50.0]])
    ball = Sphere((0.3, 25.0, -50.0), 0.1)
    drifting = replace(FLAT, moving=(MovingObstacle(ball, LinearMotion((0.3, 25.0, -50.0), (0.0, 0.0, 0.0))),))
    assert not drifting.segments_free(w[None, [1, 3]], moving=True, ends_free=True)[0]  # it lies on the chord
    assert merge_short_legs(drifting, w, 1.0, fixed=[1]).tolist() == [0, 1, 3, 4]
    assert merge_short_legs(replace(FLAT, obstacles=(ball,)), w, 1.0, fixed=[1]).tolist() == [0, 1, 2, 3, 4]
