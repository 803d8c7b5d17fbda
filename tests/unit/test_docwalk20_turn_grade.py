"""A survey's join turn changes depth at one grade along its length (docwalk20).

``turn_between`` spread the depth change over the turn's vertices by their count: the turn into a sidescan
survey's first line (a 0.54 m chord beside a 173 m straight, 13.7 m to descend) flew 81° of pitch on the short
chord, in an ``auvplan survey`` that said EXACT and exports whose ``mission check`` failed on the pitch.
Oracle: z linear in the horizontal distance along the turn (a constant grade, total rise over total run).
"""

from __future__ import annotations

import numpy as np

from auvplan.survey.joins import turn_between


def test_the_turn_descends_at_one_grade_along_its_length() -> None:
    a = np.array([[0.0, 0.0, -10.0], [100.0, 0.0, -10.0]])  # east, ending at (100, 0)
    b = np.array([[130.0, 200.0, -30.0], [130.0, 400.0, -30.0]])  # north from (130, 200), 20 m deeper
    inner, _ = turn_between(a, b, 10.0)
    path = np.vstack([a[-1:], inner, b[:1]])
    run = np.r_[0.0, np.cumsum(np.hypot(*np.diff(path[:, :2], axis=0).T))]
    chords = np.diff(run)
    assert chords.max() > 10.0 * chords.min()  # arcs' chords and a long straight: unequal legs
    np.testing.assert_allclose(path[:, 2], -10.0 - 20.0 * run / run[-1], atol=1e-9)
