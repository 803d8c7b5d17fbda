"""Depth profiles within a pitch limit: the Lipschitz envelopes above and below a profile (:func:`cone_max`,
:func:`cone_min`) and the profile as near a target as the limit allows, never below a floor
(:func:`pitch_profile`).  Used by :mod:`auvplan.path.flyable` (which re-exports them), the planners' repair of a
plan to the vehicle's limits and the fit of a flown mission.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["cone_max", "cone_min", "pitch_profile"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""


def cone_max(s: ArrayLike, g: ArrayLike, slope: float) -> _F64:
    """The least ``slope``-Lipschitz function above ``g``: ``max_j (g_j - slope |s - s_j|)``.

    Two linear passes (exact for sorted ``s``): a profile that must clear ``g`` and may climb or
    dive at most ``slope`` starts its climbs early and ends its dives late.

    Parameters
    ----------
    s : array_like
        ``(N,)`` non-decreasing abscissae (m along the path).
    g : array_like
        ``(N,)`` values to stay above (m).
    slope : float
        Largest |dz/ds|.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` the envelope.
    """
    s, out = np.asarray(s, dtype=float), np.array(g, dtype=float)
    ds = np.diff(s) * slope
    for i in range(1, out.size):
        out[i] = max(out[i], out[i - 1] - ds[i - 1])
    for i in range(out.size - 2, -1, -1):
        out[i] = max(out[i], out[i + 1] - ds[i])
    return out


def cone_min(s: ArrayLike, g: ArrayLike, slope: float) -> _F64:
    """The greatest ``slope``-Lipschitz function below ``g``: ``min_j (g_j + slope |s - s_j|)``.

    Parameters
    ----------
    s : array_like
        ``(N,)`` non-decreasing abscissae (m).
    g : array_like
        ``(N,)`` values to stay below (m).
    slope : float
        Largest |dz/ds|.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` the envelope.
    """
    return -cone_max(s, -np.asarray(g, dtype=float), slope)


def pitch_profile(s: ArrayLike, target: ArrayLike, floor: ArrayLike, slope: float, z_start: float, z_goal: float,
                  ceiling: float = math.inf, deepest: float = -math.inf) -> tuple[_F64, bool]:
    """A depth profile within a pitch limit: as near ``target`` as the limit allows, never below ``floor``.

    ``z = max(min(T, z_start + k s, z_goal + k (S - s), ceiling), F, z_start - k s, z_goal - k (S - s), deepest)``
    with ``k = slope``, ``T = cone_min(target)`` (the target, with climbs and dives it cannot fly
    cut to the pitch limit) and ``F = cone_max(floor)`` (the floor with its climbs started early
    and its dives ended late).  Every term is k-Lipschitz, so ``z`` is; ``z >= floor``; ``z`` equals
    the target wherever the target is flyable and clear of the floor; ``z(0) = z_start`` and
    ``z(S) = z_goal`` when the ends are compatible (``F`` and the other end's cone allow them).

    Parameters
    ----------
    s : array_like
        ``(N,)`` horizontal distance along the path (m, non-decreasing).
    target : array_like
        ``(N,)`` desired z (m, up).
    floor : array_like
        ``(N,)`` lowest allowed z (seabed + least altitude; m).
    slope : float
        ``tan(max_pitch)``.
    z_start, z_goal : float
        Pinned ends (m).
    ceiling : float, optional
        Highest allowed z (``-min_depth``).
    deepest : float, optional
        Lowest allowed z (``-max_depth``).

    Returns
    -------
    z : numpy.ndarray
        ``(N,)`` the profile (m).
    feasible : bool
        Whether it meets both ends and stays under the ceiling.
    """
    s = np.asarray(s, dtype=float)
    big_s = float(s[-1] - s[0]) if s.size else 0.0
    rel = s - (s[0] if s.size else 0.0)
    upper = np.minimum.reduce([cone_min(s, target, slope), z_start + slope * rel, z_goal + slope * (big_s - rel),
                               np.full(s.shape, ceiling)])
    lower = np.maximum.reduce([cone_max(s, floor, slope), z_start - slope * rel, z_goal - slope * (big_s - rel),
                               np.full(s.shape, deepest)])
    z = np.maximum(upper, lower)
    ok = bool(s.size == 0 or (abs(z[0] - z_start) <= 1e-6 and abs(z[-1] - z_goal) <= 1e-6
                              and bool(np.all(z <= ceiling + 1e-6))))
    return z, ok
