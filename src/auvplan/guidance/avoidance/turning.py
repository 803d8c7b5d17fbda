"""Constant turn rate and velocity (CTRV) prediction of a turning mover (issue #36).

Predictive avoidance (:mod:`.predictive`) extrapolates every sensed obstacle straight on its present
velocity.  A fast mover on an orbit (60–100 m radius at 2–3 m/s turns through 90–170° in a 60 s
horizon) is then predicted on its tangent while it curves back onto the vehicle's escape.

* **Turn rate from the track**: for a mover at constant speed and turn rate ω, the chord between two
  sightings at t₁ < t₂ points along the tangent at (t₁ + t₂)/2; the chords' compass headings,
  unwrapped, are therefore *exactly* linear in their mid-times with slope ω.  :func:`turn_rate` fits that
  line by least squares over the last ``window`` s of the remembered centres (:class:`.sweep.SweepMemory`)
  and returns ω only when the residuals stay below ``tolerance`` rad (a shuttle's reversal, a random
  walk: no CTRV) and |ω| ≥ ``min_rate``.
* **Arc as windowed chords**: :func:`arc_chords` predicts the CTRV arc
  x(s) = x₀ + ρ (cos ψ₀ − cos(ψ₀ + ω s)), y(s) = y₀ + ρ (sin(ψ₀ + ω s) − sin ψ₀), ρ = |v_h|/ω
  (compass heading ψ, clockwise from north; z on the present vertical speed), cut into chords of
  ``piece`` s.  Each chord is a straight mover valid only within its time window [s_k, s_{k+1}]
  (:func:`.vo.vo_choose_windows`), its radius grown by the chord's sagitta ρ (1 − cos(ω Δ/2)) (the
  arc never leaves the grown chord) and by ``growth`` × s_{k+1}: the prediction's uncertainty grows
  with the horizon.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["turn_rate", "ctrv_position", "arc_chords"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""


def turn_rate(track: Iterable[tuple[float, ArrayLike]], now: float, window: float = 12.0, tolerance: float = 0.05,
              min_rate: float = 0.004) -> float:
    """Turn rate ω (rad/s, compass sense: positive turns clockwise seen from above) of a remembered track.

    Parameters
    ----------
    track : iterable of (float, array_like)
        ``(t, centre)`` sightings, oldest first (s, m).
    now : float
        Present time (s); sightings older than ``now − window`` are ignored.
    window : float, optional
        Length of the fitted history (s).
    tolerance : float, optional
        Largest residual of the chord headings about the fitted line (rad) for a CTRV track.
    min_rate : float, optional
        |ω| below this is a straight mover (returns 0).

    Returns
    -------
    float
        ω, or 0.0 for a straight mover, too short a track (fewer than 4 sightings, or chords under
        0.5 m) or a track no CTRV fits.
    """
    pts = [(t, np.asarray(c, dtype=float)) for t, c in track if now - t <= window]
    if len(pts) < 4:
        return 0.0
    ts = np.array([p[0] for p in pts])
    cs = np.array([p[1] for p in pts])
    d = np.diff(cs[:, :2], axis=0)
    if float(np.hypot(d[:, 0], d[:, 1]).min()) < 0.5:
        return 0.0
    heading = np.unwrap(np.arctan2(d[:, 0], d[:, 1]))
    tm = 0.5 * (ts[1:] + ts[:-1])
    tc = tm - tm.mean()
    omega = float(tc @ (heading - heading.mean()) / (tc @ tc))
    resid = heading - heading.mean() - omega * tc
    if float(np.abs(resid).max()) > tolerance or abs(omega) < min_rate:
        return 0.0
    return omega


def ctrv_position(centre: ArrayLike, velocity: ArrayLike, omega: float, s: ArrayLike) -> _F64:
    """Positions ``(len(s), 3)`` of a CTRV mover after ``s`` seconds (exact arc; straight when ω = 0).

    Parameters
    ----------
    centre : array_like
        ``(3,)`` its centre now (m).
    velocity : array_like
        ``(3,)`` its velocity now (m/s).
    omega : float
        Turn rate (rad/s, positive clockwise seen from above).
    s : array_like
        Times ahead (s).

    Returns
    -------
    numpy.ndarray
        ``(len(s), 3)`` predicted centres (m).
    """
    c = np.asarray(centre, dtype=float)
    v = np.asarray(velocity, dtype=float)
    s = np.asarray(s, dtype=float).reshape(-1)
    if abs(omega) < 1e-12:
        out: _F64 = c + s[:, None] * v
        return out
    u = math.hypot(v[0], v[1])
    psi0 = math.atan2(v[0], v[1])
    rho = u / omega
    psi = psi0 + omega * s
    arc: _F64 = np.c_[c[0] + rho * (math.cos(psi0) - np.cos(psi)), c[1] + rho * (np.sin(psi) - math.sin(psi0)),
                      c[2] + v[2] * s]
    return arc


def arc_chords(centre: ArrayLike, velocity: ArrayLike, radius: float, omega: float, horizon: float,
               piece: float = 10.0, growth: float = 0.05) -> tuple[_F64, _F64, _F64, _F64]:
    """The CTRV arc over ``horizon`` s as straight movers valid in consecutive time windows.

    Parameters
    ----------
    centre, velocity : array_like
        ``(3,)`` the mover's centre (m) and velocity (m/s) now.
    radius : float
        Its radius (m).
    omega : float
        Its turn rate (rad/s).
    horizon : float
        Prediction horizon (s).
    piece : float, optional
        Duration of one chord (s).
    growth : float, optional
        Radius growth with the time ahead (m/s): the prediction's uncertainty.

    Returns
    -------
    C, V : numpy.ndarray
        ``(K, 3)`` chord movers: position ``C + V s`` for s in the window (m, m/s).
    R : numpy.ndarray
        ``(K,)`` radii grown by the sagitta and the uncertainty (m).
    W : numpy.ndarray
        ``(K, 2)`` time windows [s_k, s_{k+1}] (s).
    """
    n = max(1, int(math.ceil(horizon / piece)))
    s = np.linspace(0.0, horizon, n + 1)
    pts = ctrv_position(centre, velocity, omega, s)
    step = s[1] - s[0]
    V = np.diff(pts, axis=0) / step
    C = pts[:-1] - V * s[:-1, None]
    v = np.asarray(velocity, dtype=float)
    rho = math.hypot(v[0], v[1]) / abs(omega) if abs(omega) > 1e-12 else 0.0
    sag = rho * (1.0 - math.cos(0.5 * omega * step))
    R = radius + sag + growth * s[1:]
    return C, V, R, np.c_[s[:-1], s[1:]]
