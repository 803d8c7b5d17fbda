"""How a terrain-following mission holds its commanded altitude: the figures ``metrics.json`` reports (issue 49).

The mission as exported (its straight legs, sampled every ``ds`` metres of 3D length) and, when it was flown,
the simulated track, each measured against the seabed and the commanded altitude ``follow_altitude_m`` with its
stated band (:class:`auvplan.guidance.mission.fit.AltitudeBand`): the least and largest altitude, the RMS of
the altitude's deviation from the target, and the fraction of the length within the band.  The flown RMS is
taken where the mission at the same progress along the route is itself within the band (where the pitch limit
lets the schedule hold the target; where it cannot, the planned figures and ``altitude_band_legs`` say so).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ..guidance.mission.fit import AltitudeBand
from ..world.terrain import Terrain

__all__ = ["altitude_band_metrics"]


def _sampled(route: ArrayLike, ds: float) -> tuple[np.ndarray, np.ndarray]:
    """Points every ``ds`` metres (at most) along each straight leg, and the 3D length each stands for."""
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    d = np.diff(w, axis=0)
    length = np.linalg.norm(d, axis=1)
    n = np.maximum(np.ceil(length / ds).astype(int), 1)
    leg = np.repeat(np.arange(len(d)), n)
    frac = (np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n) + 0.5) / np.repeat(n, n)
    return w[leg] + frac[:, None] * d[leg], np.repeat(length / n, n)


def altitude_band_metrics(terrain: Terrain, route: ArrayLike, band: AltitudeBand,
                          flown: tuple[ArrayLike, ArrayLike] | None = None, ds: float = 5.0) -> dict[str, float | int]:
    """The altitude figures of a terrain-following mission, planned and flown.

    Parameters
    ----------
    terrain : Terrain
        The seabed.
    route : array_like
        ``(N, 3)`` the mission's waypoints (m).
    band : AltitudeBand
        The commanded altitude and its stated band (``target_m > 0``).
    flown : tuple of array_like, optional
        The simulated track's progress along the route (horizontal, m) and altitude (m) at each recorded step
        (``SimResult.progress``, ``SimResult.altitude``).
    ds : float, optional
        Longest spacing of the samples along a leg (m).

    Returns
    -------
    dict
        ``altitude_target_m``, ``altitude_band_m`` (the band is target ± this), ``altitude_min_m``,
        ``altitude_max_m``, ``altitude_rms_m`` (RMS of altitude − target, weighted by 3D length),
        ``altitude_band_held_fraction`` (of the 3D length within the band), ``altitude_band_legs`` (legs the fit
        reports out of the band where the pitch limit forces it); with ``flown`` also ``flown_altitude_min_m``
        and ``flown_altitude_max_m`` (the whole flight), ``flown_altitude_rms_m`` and
        ``flown_altitude_band_held_fraction`` (over the steps where the mission itself is within the band: where
        the pitch limit lets the schedule hold the target).  NaN where nothing lies over the seabed.
    """
    target, width = float(band.target_m), float(band.band_m)
    pts, weight = _sampled(route, ds)
    alt = terrain.altitude(pts)
    ok = np.isfinite(alt)
    alt, weight = alt[ok], weight[ok]
    out: dict[str, float | int] = {"altitude_target_m": target, "altitude_band_m": width}
    out |= dict.fromkeys(("altitude_min_m", "altitude_max_m", "altitude_rms_m", "altitude_band_held_fraction"),
                         math.nan)
    total = float(weight.sum())
    if total > 0.0:
        dev = alt - target
        out |= {"altitude_min_m": float(alt.min()), "altitude_max_m": float(alt.max()),
                "altitude_rms_m": math.sqrt(float((weight * dev * dev).sum()) / total),
                "altitude_band_held_fraction": float(weight[np.abs(dev) <= width + 1e-6].sum()) / total}
    out["altitude_band_legs"] = len(band.legs)
    if flown is not None:
        out |= _flown(terrain, np.asarray(route, dtype=float).reshape(-1, 3), flown, target, width)
    return out


def _flown(terrain: Terrain, w: np.ndarray, flown: tuple[ArrayLike, ArrayLike], target: float,
           width: float) -> dict[str, float]:
    """The flown figures: over the whole flight, and where the mission at the same progress is within the band."""
    progress, alt = (np.asarray(a, dtype=float).ravel() for a in flown)
    out = dict.fromkeys(("flown_altitude_min_m", "flown_altitude_max_m", "flown_altitude_rms_m",
                         "flown_altitude_band_held_fraction"), math.nan)
    ok = np.isfinite(alt) & np.isfinite(progress)
    progress, alt = progress[ok], alt[ok]
    if not alt.size:
        return out
    out |= {"flown_altitude_min_m": float(alt.min()), "flown_altitude_max_m": float(alt.max())}
    cum = np.r_[0.0, np.cumsum(np.hypot(*np.diff(w[:, :2], axis=0).T))]
    on = np.column_stack([np.interp(progress, cum, w[:, k]) for k in range(3)])  # the mission at that progress
    planned = terrain.altitude(on)
    held = np.abs(planned - target) <= width + 1e-6
    if held.any():
        dev = alt[held] - target
        out |= {"flown_altitude_rms_m": math.sqrt(float(np.mean(dev * dev))),
                "flown_altitude_band_held_fraction": float(np.mean(np.abs(dev) <= width))}
    return out
