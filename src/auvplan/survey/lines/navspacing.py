"""Survey line spacing under the relative navigation error of adjacent lines (issue 52 item 5,
``docs/navigation.md``): the margin :func:`auvplan.survey.lines.placement.place_lines` brings each next line closer by.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .frame import Frame, StraightFrame

if TYPE_CHECKING:
    from .lineset import LineParams, SurveyLine

__all__ = ["nav_margin"]


def nav_margin(frame: Frame, s: NDArray[np.float64], a: SurveyLine, forward: bool, params: LineParams,
               across: float) -> NDArray[np.float64]:
    """The relative navigation error of line ``a`` and the next line at every station (issue 52).

    The estimate drifts by the same bias on both lines between fixes (the dead-reckoning model of
    :mod:`auvplan.nav.budget`): what one line's position is off from the other's at a station is the drift
    accumulated between the two passes there, ``confidence × rate × L(s)``.  ``L`` is bounded by the path
    flown: ``a`` from the station to its end (its arc, exactly), the run-ins and the turn
    (``nav_turn_m``) and the offset between the lines (at most ``across``), and the next line back to the
    station (its slope within ``max_bend_deg``: at most the along-track distance over the bend's cosine,
    plus what a curved frame adds at that offset).

    Parameters
    ----------
    frame : Frame
        The line frame.
    s : numpy.ndarray
        ``(K,)`` stations (m along).
    a : SurveyLine
        The line flown first.
    forward : bool
        ``a`` is flown in increasing station order (its end is at its last station).
    params : LineParams
        ``nav_rel_per_m``, ``nav_turn_m``, ``max_bend_deg``.
    across : float
        Largest offset between the two lines (m).

    Returns
    -------
    numpy.ndarray
        ``(K,)`` the error (m; NaN off ``a``).
    """
    out = np.full(s.size, np.nan)
    act = a.active
    x, y = frame.from_sn(s[act], a.c[act])
    arc = np.r_[0.0, np.cumsum(np.hypot(np.diff(x), np.diff(y)))]
    rest = arc[-1] - arc if forward else arc  # along a from the station to its end
    along = np.abs(s[act] - s[a.last if forward else a.first])
    curved = 0.0 if isinstance(frame, StraightFrame) else math.pi * across
    back = along / math.cos(math.radians(params.max_bend_deg)) + curved
    out[act] = params.nav_rel_per_m * (rest + params.nav_turn_m + across + back)
    return out
