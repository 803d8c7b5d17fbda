"""The planned duration of a timed path, flown through the World's own current (not the search's table).

The search and the refinement time legs through the current *table* (float32, sampled at the
lattice nodes every ``dt`` seconds, interpolated in between): fast, but its interpolation error
can make a leg a little faster than the water allows, so a plan could promise less than the
least time physics permits.  The durations a plan reports are therefore re-timed here with
the World's current field itself (:meth:`CurrentField.velocity` at every sub-step's point and
time), with the same kinematics as :mod:`.kernels` — the vehicle holds each leg's line at
through-water speed V heading to make the most headway, ``g = c·ŝ + √(V² − |c⊥|²)`` along the
unit tangent ŝ, drifting back on the line where ``g < 0`` — on sub-steps of at most ``ds`` metres
(midpoint rule in time; in time steps of ``ds / V`` seconds where ``g < V / 4``).  The time of a
path the vehicle can fly is never below the least time (the exact optimum is no slower than any
flyable path), up to the integrator's second-order error; the closed-loop follower holds the same
line (:mod:`auvplan.guidance.following.route`), so this is also the duration it flies (docs/timeopt.md).
Legs marked tail-first (:mod:`.tail`) are flown with the far root, ``g = c·ŝ − √(V² − |c⊥|²)``, in
midpoint time steps of ``ds / V`` seconds, and rejected where it is not positive.
"""

from __future__ import annotations

import math

import numpy as np

from ..._types import ArrayLike, FloatArray
from ...world import CurrentField
from ...world.currents.crab import crab_speed

__all__ = ["track_speed", "fly_times"]


def _tail_leg(field: CurrentField, a: FloatArray, b: FloatArray, t: float, speed: float, ds: float,
              t_limit: float) -> float:
    """Arrival at ``b`` from ``a`` left at ``t`` flown tail-first (the far root); ``inf`` when it cannot be."""
    d = b - a
    length = float(np.linalg.norm(d))
    if length == 0.0:
        return t
    e = d / length

    def g_at(s: float, when: float) -> float:
        c = field.velocity((a + s * e)[None], when)[0]
        return float(crab_speed(c[0], c[1], c[2], e[0], e[1], e[2], speed, True, 1.0))

    tau, s = ds / speed, 0.0
    while t <= t_limit:
        g0 = g_at(s, t)
        if not g0 > 0.0:
            return math.inf
        g = g_at(min(s + 0.5 * tau * g0, length), t + 0.5 * tau)
        if not g > 0.0:
            return math.inf
        if s + tau * g >= length:
            return t + (length - s) / g
        s, t = s + tau * g, t + tau
    return math.inf


def track_speed(current: FloatArray, tangent: FloatArray, speed: float) -> float:
    """Signed speed along a unit tangent of the heading that holds the line and makes the most headway.

    Parameters
    ----------
    current : numpy.ndarray
        Current ``(3,)`` (m/s).
    tangent : numpy.ndarray
        Unit tangent ``(3,)``.
    speed : float
        Through-water speed (m/s).

    Returns
    -------
    float
        ``c·ŝ + √(V² − |c⊥|²)`` (m/s; negative: drifting back); ``nan`` when no heading holds the line.
    """
    c, e = current, tangent
    return float(crab_speed(float(c[0]), float(c[1]), float(c[2]), float(e[0]), float(e[1]), float(e[2]), speed,
                            False, 1.0))


def _leg(field: CurrentField, a: FloatArray, b: FloatArray, t: float, speed: float, ds: float,
         t_limit: float) -> tuple[float, float]:
    """Arrival at ``b`` from ``a`` left at ``t`` and the drift behind ``a`` (m); ``(inf, ...)`` when rejected."""
    d = b - a
    length = float(np.linalg.norm(d))
    if length == 0.0:
        return t, 0.0
    e = d / length

    def g_at(s: float, when: float) -> float:
        return track_speed(field.velocity((a + s * e)[None], when)[0], e, speed)

    n = max(1, math.ceil(length / ds))
    h = length / n
    slow = 0.25 * speed
    s = 0.0
    for k in range(n):
        g = g_at((k + 0.5) * h, t + 0.5 * h / speed)
        if g >= slow:
            g = g_at((k + 0.5) * h, t + 0.5 * h / g)
        if not g >= slow:
            s = k * h
            break
        t += h / g
    else:
        return t, 0.0
    tau, s_min = ds / speed, s
    while t <= t_limit:  # slow, or drifting back: in time steps
        g0 = g_at(s, t)
        g = g_at(s + 0.5 * tau * g0, t + 0.5 * tau) if g0 == g0 else math.nan
        if g != g:
            break
        if g > 0.0 and s + tau * g >= length:
            return t + (length - s) / g, max(-s_min, 0.0)
        if g0 < 0.0 and g > g0 and -g0 < 2.0 * (g - g0):  # the turn within the step (g linear in time)
            s_min = min(s_min, s - 0.25 * g0 * g0 * tau / (g - g0))
        s, t = s + tau * g, t + tau
        s_min = min(s_min, s)
    return math.inf, max(-s_min, 0.0)


def fly_times(field: CurrentField, points: ArrayLike, depart: float, speed: float, ds: float,
              t_limit: float, tail: ArrayLike | None = None) -> tuple[FloatArray, FloatArray]:
    """Arrival at every vertex of a polyline flown through a current field (module notes).

    Parameters
    ----------
    field : CurrentField
        The current (the World's ``currents``).
    points : array_like
        Vertices ``(N, 3)`` (m).
    depart : float
        Departure from the first vertex (s after the mission's start time).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest sub-step (m).
    t_limit : float
        A drifting leg not arrived by this time is rejected (s).
    tail : array_like of bool, optional
        ``(N - 1,)``: the legs flown tail-first (:mod:`.tail`; none when omitted).

    Returns
    -------
    times : numpy.ndarray
        Arrival at each vertex ``(N,)`` (s; ``inf`` from a leg no heading can hold on).
    back : numpy.ndarray
        How far behind its start the current pushed the vehicle on each leg ``(N - 1,)`` (m).
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    times = np.full(p.shape[0], math.inf)
    back = np.zeros(max(p.shape[0] - 1, 0))
    if p.shape[0] == 0:
        return times, back
    times[0] = depart
    tails = np.zeros(back.size, dtype=bool) if tail is None else np.asarray(tail, dtype=bool)
    for i in range(1, p.shape[0]):
        if tails[i - 1]:
            times[i] = _tail_leg(field, p[i - 1], p[i], float(times[i - 1]), float(speed), float(ds), t_limit)
        else:
            times[i], back[i - 1] = _leg(field, p[i - 1], p[i], float(times[i - 1]), float(speed), float(ds), t_limit)
        if not math.isfinite(times[i]):
            break
    return times, back
