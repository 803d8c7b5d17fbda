"""The survey's Dubins turns (``auvplan.survey.turns``) against closed forms and their own geometry (issue 49's
mutation run of ``survey-turns``): every sampled path ends at the goal with the goal's heading, its points are at
most ``step`` apart along arcs of radius R, and the lengths of the textbook cases are exact."""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.survey.turns import dubins, sample_turn

R = 10.0


@pytest.mark.parametrize("end, length, words", [
    ((100.0, 0.0, 0.0), 100.0, {"LSL", "RSR"}),  # straight ahead
    ((0.0, 2 * R, math.pi), math.pi * R, {"LSL"}),  # a U-turn to the left, 2R across
    ((0.0, -2 * R, math.pi), math.pi * R, {"RSR"}),  # to the right
    ((2 * R, 4 * R, 0.0), math.pi * R + 2 * R, {"LSR"}),  # quarter left, 2R north, quarter right
    ((2 * R, -4 * R, 0.0), math.pi * R + 2 * R, {"RSL"}),
    ((2 * R, -2.5 * R, 0.0), math.pi * R + 0.5 * R, {"RSL"}),  # a straight shorter than R
    ((2 * R, 2.5 * R, 0.0), math.pi * R + 0.5 * R, {"LSR"}),
    ((0.0, 0.0, math.pi), None, {"LRL", "RLR"}),  # turn round on the spot: three arcs
])
def test_closed_form_lengths_and_words(end, length, words) -> None:  # type: ignore[no-untyped-def]
    t = dubins((0.0, 0.0, 0.0), end, R)
    assert t.word in words
    if length is not None:
        assert t.length == pytest.approx(length, rel=1e-9, abs=1e-9)
    else:  # back to the start facing the other way: at least the half turn's arc, πR, and no straight piece
        assert t.length >= math.pi * R - 1e-9 and t.word[1] != "S"


def test_every_path_ends_at_the_goal_with_its_heading_along_arcs_of_radius_r() -> None:
    rng = np.random.default_rng(49)
    for _ in range(300):
        start = (*rng.uniform(-50.0, 50.0, 2), float(rng.uniform(-math.pi, math.pi)))
        end = (*rng.uniform(-50.0, 50.0, 2), float(rng.uniform(-math.pi, math.pi)))
        t = dubins(start, end, R)
        pts = sample_turn(t, 1.0)
        assert pts[0] == pytest.approx(start)
        assert pts[-1, :2] == pytest.approx(end[:2], abs=1e-6 * R)
        assert math.cos(pts[-1, 2] - end[2]) == pytest.approx(1.0, abs=1e-9)
        step = np.hypot(*np.diff(pts[:, :2], axis=0).T)
        assert np.all(step <= 1.0 + 1e-9) or t.word[1] == "S"  # straight pieces are one chord
        assert t.length >= math.hypot(end[0] - start[0], end[1] - start[1]) - 1e-9
        assert step.sum() <= t.length + 1e-6  # chords are no longer than their arcs
        assert all(p >= -1e-12 for p in t.params)
        straight = math.hypot(end[0] - start[0], end[1] - start[1])
        assert t.length <= straight + 2.0 * R + 4.0 * math.pi * R + 1e-6  # a CSC path: two arcs < 2πR, the straight
        # between the circles' tangent points at most d + 2R


def test_any_positive_radius_is_taken_and_no_other() -> None:
    assert dubins((0.0, 0.0, 0.0), (0.0, 1.0, math.pi), 0.5).length == pytest.approx(0.5 * math.pi)
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(ValueError, match="must be positive"):
            dubins((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), bad)
