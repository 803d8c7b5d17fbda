"""Lipschitz envelopes: the largest function under a cap (the smallest over a floor) whose slope stays
within a bound, ``min_j cap_j + L |s - s_j|``.  The survey lines bend within ``max_bend_deg`` under their
overlap limits with the upper envelope, and hold the altitude within the pitch limit with the lower."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["upper_envelope", "lower_envelope"]


def upper_envelope(s: NDArray[np.float64], cap: NDArray[np.float64], slope: float) -> NDArray[np.float64]:
    """The largest function under ``cap`` with ``|dc/ds| <= slope``: ``min_j cap_j + slope |s - s_j|``.

    Parameters
    ----------
    s : numpy.ndarray
        ``(K,)`` station coordinates (m).
    cap : numpy.ndarray
        ``(K,)`` upper bounds; ``inf`` where unconstrained.
    slope : float
        Largest slope.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` the envelope (``inf`` everywhere when nothing is constrained).
    """
    finite = np.isfinite(cap)
    if not finite.any():
        return np.full(s.size, np.inf)
    return np.asarray(np.min(cap[finite][None, :] + slope * np.abs(s[:, None] - s[finite][None, :]), axis=1))


def lower_envelope(s: NDArray[np.float64], floor: NDArray[np.float64], slope: float) -> NDArray[np.float64]:
    """The smallest function over ``floor`` with ``|dz/ds| <= slope``: ``max_j floor_j - slope |s - s_j|``.

    Parameters
    ----------
    s : numpy.ndarray
        ``(K,)`` coordinates along (m).
    floor : numpy.ndarray
        ``(K,)`` lower bounds.
    slope : float
        Largest slope.

    Returns
    -------
    numpy.ndarray
        ``(K,)`` the envelope.
    """
    return -upper_envelope(s, -floor, slope)
