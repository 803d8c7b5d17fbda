"""Compiled inner loops of the time-dependent planner: the current table lookup, the travel time
of a straight leg through a current that changes while the vehicle is on it (the label-setting
search on arrival times is :mod:`.labels`).

The current table ``cur (nt, nx, ny, nz, 3)`` holds the field at the lattice nodes every ``dt``
seconds from ``t0``; lookups are trilinear in space and linear in time, clamped at the ends.

Travel time of a leg: the vehicle holds the track at through-water speed V (it crabs), so its
ground speed along the unit tangent ŝ is ``g = c·ŝ + √(V² - |c - (c·ŝ) ŝ|²)`` (as in
:mod:`auvplan.cost`); the leg is cut into sub-steps of at most ``ds`` metres and each sub-step is
integrated with the midpoint rule in time (the current at the sub-step's midpoint, at the time the
vehicle reaches it).

Currents stronger than the vehicle (U > V).  The heading that holds the track and makes the most
headway is the ``+`` root above whatever the current; ``g`` is negative when the along-track current
beats the vehicle: the vehicle, still heading to make good the track, drifts back along the leg's
line (behind its start too) until the current eases, then goes on — the
constant-heading least-time flight of a uniform current, and what the closed-loop follower does
(it holds the active leg's line).  From the first sub-step where ``g`` falls below a quarter of V
the leg is integrated in time instead (midpoint steps of ``ds / V`` seconds).  A leg is rejected
(``inf``, never ``nan``) only where no heading holds its line (``|c⊥| > HOLD V``, 3 % short of V), where it would not
reach the end before the table does (two leg times past its end), and, in the search, where the
drift would take the vehicle more than a leg length behind its start (onto the reverse leg, which
must be free).  :func:`leg_reach` also returns how far behind its start a leg drifted, so
that the search and the planner test that stretch of water too.
"""

from __future__ import annotations

import math
from typing import TypeAlias

import numpy as np
import numpy.typing as npt

from ..._types import FloatArray
from ...runtime.jit import kernel
from ...world.currents.crab import HOLD, crab_speed

__all__ = ["HOLD", "current_at", "track_speed", "leg_time", "leg_reach", "polyline_times",
           "Float32Array"]


#: The current table's precision: ``cur (nt, nx, ny, nz, 3)`` in m/s as float32.
Float32Array: TypeAlias = npt.NDArray[np.float32]


@kernel
def _axis(value: float, origin: float, step: float, n: int) -> tuple[int, float]:
    """Index and weight of ``value`` on a uniform axis, clamped (a single-node axis gives (0, 0))."""
    if n == 1:
        return 0, 0.0
    f = (value - origin) / step
    if f <= 0.0:
        return 0, 0.0
    if f >= n - 1:
        return n - 2, 1.0
    i = int(f)
    return i, f - i


@kernel
def current_at(cur: Float32Array, org: FloatArray, step: FloatArray, t0: float, dt: float, x: float, y: float, z: float,
               t: float) -> tuple[float, float, float]:
    """Current at a point and time from the table (module notes).

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    org, step : numpy.ndarray
        First node and node spacing of the table's lattice ``(3,)`` (m).
    t0, dt : float
        First time and time step of the table (s).
    x, y, z : float
        The point (m).
    t : float
        Time (s).

    Returns
    -------
    tuple of float
        ``(u, v, w)`` (m/s), trilinear in space and linear in time, clamped at the ends.
    """
    nt, nx, ny, nz = cur.shape[0], cur.shape[1], cur.shape[2], cur.shape[3]
    it, wt = _axis(t, t0, dt, nt)
    ix, wx = _axis(x, org[0], step[0], nx)
    iy, wy = _axis(y, org[1], step[1], ny)
    iz, wz = _axis(z, org[2], step[2], nz)
    u = v = w = 0.0
    for a in range(2):
        ca = wt if a else 1.0 - wt
        if ca == 0.0:
            continue
        for b in range(2):
            cb = ca * (wx if b else 1.0 - wx)
            if cb == 0.0:
                continue
            for c in range(2):
                cc = cb * (wy if c else 1.0 - wy)
                if cc == 0.0:
                    continue
                for d in range(2):
                    cd = cc * (wz if d else 1.0 - wz)
                    if cd == 0.0:
                        continue
                    u += cd * cur[it + a, ix + b, iy + c, iz + d, 0]
                    v += cd * cur[it + a, ix + b, iy + c, iz + d, 1]
                    w += cd * cur[it + a, ix + b, iy + c, iz + d, 2]
    return u, v, w


@kernel
def track_speed(u: float, v: float, w: float, ex: float, ey: float, ez: float, speed: float) -> float:
    """Signed speed along a unit tangent of the heading that holds the track and makes the most headway.

    Parameters
    ----------
    u, v, w : float
        Current (m/s; east, north, up).
    ex, ey, ez : float
        Unit tangent of the track.
    speed : float
        Through-water speed V (m/s).

    Returns
    -------
    float
        ``c·ŝ + √(V² - |c⊥|²)`` (m/s), negative when the along-track current beats the vehicle (it
        drifts back on the line); ``nan`` where the search takes no heading to hold the line
        (``|c⊥| > HOLD V``: a line at the very edge of what the vehicle can hold is lost for a few
        seconds' difference in timing, or in the World's current between the table's slices).
    """
    return crab_speed(u, v, w, ex, ey, ez, speed, False, HOLD)


@kernel
def _drift(cur: Float32Array, org: FloatArray, step: FloatArray, t0: float, dt: float,
           ax: float, ay: float, az: float, ex: float, ey: float, ez: float, length: float,
           s: float, t: float, speed: float, ds: float, reach_back: float) -> tuple[float, float]:
    """The rest of a leg from arc length ``s`` at time ``t``, integrated in time (module notes):
    ``(arrival, least arc length reached)``, ``(inf, ...)`` when the leg is rejected."""
    tau = ds / speed
    t_end = t0 + dt * (cur.shape[0] - 1) + 2.0 * length / speed + tau
    s_min = s
    while True:
        if t > t_end or s < -reach_back:
            return math.inf, s_min
        u, v, w = current_at(cur, org, step, t0, dt, ax + s * ex, ay + s * ey, az + s * ez, t)
        g0 = track_speed(u, v, w, ex, ey, ez, speed)
        if math.isnan(g0):
            return math.inf, s_min
        sm = s + 0.5 * tau * g0
        u, v, w = current_at(cur, org, step, t0, dt, ax + sm * ex, ay + sm * ey, az + sm * ez, t + 0.5 * tau)
        g = track_speed(u, v, w, ex, ey, ez, speed)
        if math.isnan(g):
            return math.inf, s_min
        if g > 0.0 and s + tau * g >= length:
            return t + (length - s) / g, s_min
        if g0 < 0.0 and g > g0 and -g0 < 2.0 * (g - g0):  # the turn within the step (g linear in time)
            s_min = min(s_min, s - 0.25 * g0 * g0 * tau / (g - g0))
        s += tau * g
        t += tau
        s_min = min(s_min, s)


@kernel
def leg_reach(cur: Float32Array, org: FloatArray, step: FloatArray, t0: float, dt: float,
              ax: float, ay: float, az: float,
              bx: float, by: float, bz: float, t: float, speed: float, ds: float,
              reach_back: float) -> tuple[float, float]:
    """Arrival time at the end of a straight leg through the time-varying current, and the drift.

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    org, step : numpy.ndarray
        First node and node spacing of the table's lattice ``(3,)`` (m).
    t0, dt : float
        First time and time step of the table (s).
    ax, ay, az : float
        Start of the leg (m).
    bx, by, bz : float
        End of the leg (m).
    t : float
        Departure time (s).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest integration sub-step (m).
    reach_back : float
        The leg is rejected when the vehicle drifts farther than this behind its start (m; ``inf``:
        only when it would not arrive before the table's end).

    Returns
    -------
    arrival : float
        Arrival time at the end (s); ``inf`` when the leg is rejected (module notes).
    back : float
        How far behind its start the current pushed the vehicle on the leg's line (m, >= 0).
    """
    ex, ey, ez = bx - ax, by - ay, bz - az
    length = math.sqrt(ex * ex + ey * ey + ez * ez)
    if length == 0.0:
        return t, 0.0
    ex, ey, ez = ex / length, ey / length, ez / length
    n = max(1, int(math.ceil(length / ds)))
    h = length / n
    slow = 0.25 * speed
    for k in range(n):
        s = (k + 0.5) * h
        mx, my, mz = ax + s * ex, ay + s * ey, az + s * ez
        u, v, w = current_at(cur, org, step, t0, dt, mx, my, mz, t + 0.5 * h / speed)
        g = track_speed(u, v, w, ex, ey, ez, speed)
        if g >= slow:
            u, v, w = current_at(cur, org, step, t0, dt, mx, my, mz, t + 0.5 * h / g)
            g = track_speed(u, v, w, ex, ey, ez, speed)
        if not g >= slow:  # slow, drifting back or no heading holds the line: integrate in time
            arrive, s_min = _drift(cur, org, step, t0, dt, ax, ay, az, ex, ey, ez, length, k * h, t, speed, ds,
                                   reach_back)
            return arrive, max(-s_min, 0.0)
        t += h / g
    return t, 0.0


@kernel
def leg_time(cur: Float32Array, org: FloatArray, step: FloatArray, t0: float, dt: float,
             ax: float, ay: float, az: float,
             bx: float, by: float, bz: float, t: float, speed: float, ds: float) -> float:
    """Arrival time at the end of a straight leg (:func:`leg_reach`, at most a leg length of drift).

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    org, step : numpy.ndarray
        First node and node spacing of the table's lattice ``(3,)`` (m).
    t0, dt : float
        First time and time step of the table (s).
    ax, ay, az : float
        Start of the leg (m).
    bx, by, bz : float
        End of the leg (m).
    t : float
        Departure time (s).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest integration sub-step (m).

    Returns
    -------
    float
        Arrival time at the end (s); ``inf`` when the leg is rejected.
    """
    back = math.sqrt((bx - ax) ** 2 + (by - ay) ** 2 + (bz - az) ** 2)
    return leg_reach(cur, org, step, t0, dt, ax, ay, az, bx, by, bz, t, speed, ds, back)[0]


@kernel
def polyline_times(cur: Float32Array, org: FloatArray, step: FloatArray, t0: float, dt: float,
                   p: FloatArray, t_start: float,
                   speed: float, ds: float, out: FloatArray, back: FloatArray) -> None:
    """Arrival time at every vertex of a polyline.

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    org, step : numpy.ndarray
        First node and node spacing of the table's lattice ``(3,)`` (m).
    t0, dt : float
        First time and time step of the table (s).
    p : numpy.ndarray
        Vertices ``(N, 3)`` (m).
    t_start : float
        Departure time from the first vertex (s).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest integration sub-step (m).
    out : numpy.ndarray
        Receives the arrival times ``(N,)`` (s; ``inf`` after a rejected leg).
    back : numpy.ndarray
        Receives how far behind its start each leg drifted ``(N - 1,)`` (m).
    """
    out[0] = t_start
    for i in range(1, p.shape[0]):
        out[i], back[i - 1] = leg_reach(cur, org, step, t0, dt, p[i - 1, 0], p[i - 1, 1], p[i - 1, 2],
                                        p[i, 0], p[i, 1], p[i, 2], out[i - 1], speed, ds, math.inf)


@kernel
def two_legs(cur: Float32Array, org: FloatArray, step: FloatArray, t0: float, dt: float,
             a: FloatArray, cand: FloatArray,
             c: FloatArray, t_a: FloatArray, speed: float, ds: float, out: FloatArray) -> None:
    """Arrival at ``c[i]`` through each candidate ``cand[i, j]`` from ``a[i]`` left at ``t_a[i]``."""
    for i in range(cand.shape[0]):
        for j in range(cand.shape[1]):
            tm = leg_time(cur, org, step, t0, dt, a[i, 0], a[i, 1], a[i, 2], cand[i, j, 0], cand[i, j, 1],
                          cand[i, j, 2], t_a[i], speed, ds)
            if math.isinf(tm):
                out[i, j] = math.inf
            else:
                out[i, j] = leg_time(cur, org, step, t0, dt, cand[i, j, 0], cand[i, j, 1], cand[i, j, 2],
                                     c[i, 0], c[i, 1], c[i, 2], tm, speed, ds)
