"""The glider flight model against a glider's own records: yo legs, calibration, depth-averaged current.

* :func:`yo_legs` cuts a record into steady dive and climb legs (ballast pumped beyond ±150 cc,
  the middle 60 % of the leg's depth span) and measures each leg's vertical speed (least-squares
  slope of depth), median pitch, ballast and depth.
* :func:`calibrate` fits the two figures a pilot trims, the neutral density (the hull volume) and
  the parasitic drag C_D0, to the legs' vertical speeds by least squares, as Merckelbach et al.
  (2010, sec. 3) calibrate their model.
* :func:`dead_reckoned_current` is the depth-averaged current the way a Slocum computes its
  ``m_water_vx/vy``: the surface fixes' displacement less the through-water displacement dead
  reckoned from the flight model's horizontal speed and the compass heading, over the time between
  the fixes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares

from .._types import ArrayLike, FloatArray
from .glider import G, GliderParams, steady_glide

__all__ = ["Leg", "yo_legs", "calibrate", "dead_reckoned_current"]

#: Earth radius for the fixes' local displacement (m).
_R = 6_371_000.0


@dataclass(frozen=True)
class Leg:
    """One steady dive or climb of a record.

    Attributes
    ----------
    t : float
        Mid time (s).
    w : float
        Measured vertical speed (m/s, up positive).
    pitch : float
        Median pitch (rad).
    ballast_cc : float
        Median ballast pumped (cc).
    depth_m : float
        Median depth (m).
    """

    t: float
    w: float
    pitch: float
    ballast_cc: float
    depth_m: float


def yo_legs(t: ArrayLike, depth: ArrayLike, pitch: ArrayLike, ballast_cc: ArrayLike,
            min_span_m: float = 10.0) -> list[Leg]:
    """The steady legs of a record (module notes).

    Parameters
    ----------
    t, depth, pitch, ballast_cc : array_like
        Time (s), depth (m), pitch (rad) and ballast pumped (cc), one value per record (NaN: none).
    min_span_m : float, default 10.0
        Legs spanning less depth are skipped (surface manoeuvres).

    Returns
    -------
    list of Leg
        In time order.
    """
    t, z, th, b = (np.asarray(a, dtype=float) for a in (t, depth, pitch, ballast_cc))
    s = np.where(np.abs(b) < 150.0, 0.0, np.sign(np.nan_to_num(b)))
    edges = np.flatnonzero(np.diff(s)) + 1
    legs = []
    for i, j in zip(np.r_[0, edges], np.r_[edges, len(t)], strict=True):
        zz = z[i:j]
        if s[i] == 0 or j - i < 6 or not np.isfinite(zz).any():
            continue
        lo, hi = np.nanmin(zz), np.nanmax(zz)
        if hi - lo < min_span_m:
            continue
        m = np.isfinite(zz) & (zz > lo + 0.2 * (hi - lo)) & (zz < hi - 0.2 * (hi - lo))
        if m.sum() < 4:
            continue
        tt = t[i:j][m]
        slope = float(np.polyfit(tt, zz[m], 1)[0])
        legs.append(Leg(float(tt.mean()), -slope, float(np.nanmedian(th[i:j][m])), float(np.nanmedian(b[i:j][m])),
                        float(np.nanmedian(zz[m]))))
    return legs


def _model_w(params: GliderParams, legs: list[Leg], density: float) -> FloatArray:
    d = np.array([[lg.pitch, lg.ballast_cc, lg.depth_m] for lg in legs])
    return steady_glide(params, d[:, 0], d[:, 1], density, density * G * d[:, 2]).w


def calibrate(params: GliderParams, legs: list[Leg], density: float = 1025.0) -> GliderParams:
    """The neutral density and C_D0 that best fit the legs' vertical speeds (least squares).

    Parameters
    ----------
    params : GliderParams
        Starting values and every other figure.
    legs : list of Leg
        The legs to fit (at least two, dives and climbs).
    density : float, default 1025.0
        In-situ density taken for the water (kg/m³).

    Returns
    -------
    GliderParams
        ``params`` with the fitted ``neutral_density`` and ``cd0``.
    """
    w = np.array([lg.w for lg in legs])

    def residual(x: FloatArray) -> FloatArray:
        return np.asarray(_model_w(replace(params, neutral_density=x[0], cd0=x[1]), legs, density) - w)

    fit = least_squares(residual, [params.neutral_density, params.cd0], x_scale=[1.0, 0.1],
                        bounds=([900.0, 0.01], [1100.0, 2.0]))
    return replace(params, neutral_density=float(fit.x[0]), cd0=float(fit.x[1]))


def dead_reckoned_current(params: GliderParams, t: ArrayLike, depth: ArrayLike, pitch: ArrayLike,
                          ballast_cc: ArrayLike, heading: ArrayLike, fix0: tuple[float, float],
                          fix1: tuple[float, float], density: float = 1025.0) -> tuple[float, float]:
    """Depth-averaged current between two surface fixes (module notes).

    Parameters
    ----------
    params : GliderParams
        The (calibrated) glider.
    t, depth, pitch, ballast_cc, heading : array_like
        The records from the first fix to the second: time (s), depth (m), pitch (rad), ballast (cc),
        compass heading (rad).
    fix0, fix1 : (lat, lon)
        The fixes at ``t[0]`` and ``t[-1]`` (degrees).
    density : float, default 1025.0
        Water density (kg/m³).

    Returns
    -------
    (float, float)
        East and north depth-averaged current (m/s).
    """
    t, z, th, b, hd = (np.asarray(a, dtype=float) for a in (t, depth, pitch, ballast_cc, heading))
    u = np.where(z > 0.5, steady_glide(params, th, b, density, density * G * z).u, 0.0)
    dt = np.diff(t)
    east = float(np.sum(dt * u[:-1] * np.sin(hd[:-1])))
    north = float(np.sum(dt * u[:-1] * np.cos(hd[:-1])))
    dx = math.radians(fix1[1] - fix0[1]) * _R * math.cos(math.radians(0.5 * (fix0[0] + fix1[0])))
    dy = math.radians(fix1[0] - fix0[0]) * _R
    span = float(t[-1] - t[0])
    return (dx - east) / span, (dy - north) / span
