"""Tail-first legs: a line held with the far root of the crab equation, the vehicle carried along it backwards.

To hold a leg's line (unit tangent ŝ) at through-water speed V in the current c the vehicle's
heading ĥ must cancel the cross current, ``V ĥ⊥ = −c⊥``, which leaves two headings:
``ĥ·ŝ = ±√(1 − |c⊥|²/V²)``, with ground speeds along the line

    g₊ = c·ŝ + √(V² − |c⊥|²)      (heading along the line: the leg of :mod:`.kernels`)
    g₋ = c·ŝ − √(V² − |c⊥|²)      (heading against it: *tail-first*)

Where the current along the line beats the vehicle (``c·ŝ > √(V² − |c⊥|²)``) ``g₋`` is positive:
the vehicle heads one way and is carried the other, slowly.  That is the flight of Zermelo's
optimum where ``c·ĥ < −V`` along its heading — it arrives *later* than the forward crab, at the place
and time from which the turning current later carries it on — and the only way a search that
cannot wait can arrive late at a node in a current stronger than the vehicle.  :func:`tail_leg`
times such a leg (midpoint steps in time of ``ds / V`` seconds: ``g₋`` may be small); it is
rejected (``inf``) where ``g₋`` is not positive (the vehicle would be carried backwards along a line
it heads against), where no heading holds the line (``|c⊥| > HOLD V``) and past the table's end.
"""

from __future__ import annotations

import math

from ..._types import FloatArray
from ...runtime.jit import kernel
from ...world.currents.crab import HOLD, crab_speed
from .kernels import Float32Array, current_at

__all__ = ["tail_speed", "tail_leg"]


@kernel
def tail_speed(u: float, v: float, w: float, ex: float, ey: float, ez: float, speed: float) -> float:
    """Ground speed along a unit tangent of the tail-first heading (module notes).

    Parameters
    ----------
    u, v, w : float
        Current (m/s; east, north, up).
    ex, ey, ez : float
        Unit tangent of the line.
    speed : float
        Through-water speed V (m/s).

    Returns
    -------
    float
        ``c·ŝ − √(V² − |c⊥|²)`` (m/s); ``nan`` where no heading holds the line (``|c⊥| > HOLD V``).
    """
    return crab_speed(u, v, w, ex, ey, ez, speed, True, HOLD)


@kernel
def tail_leg(cur: Float32Array, org: FloatArray, step: FloatArray, t0: float, dt: float,
             ax: float, ay: float, az: float, bx: float, by: float, bz: float, t: float, speed: float,
             ds: float) -> float:
    """Arrival time at the end of a straight leg flown tail-first (module notes).

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, nz, 3)`` (m/s, float32).
    org, step : numpy.ndarray
        First node and node spacing of the table's lattice ``(3,)`` (m).
    t0, dt : float
        First time and time step of the table (s).
    ax, ay, az, bx, by, bz : float
        Start and end of the leg (m).
    t : float
        Departure time (s).
    speed : float
        Through-water speed (m/s).
    ds : float
        Largest integration sub-step (m); the time step is ``ds / speed``.

    Returns
    -------
    float
        Arrival time (s); ``inf`` when the leg cannot be flown tail-first.
    """
    ex, ey, ez = bx - ax, by - ay, bz - az
    length = math.sqrt(ex * ex + ey * ey + ez * ez)
    if length == 0.0:
        return t
    ex, ey, ez = ex / length, ey / length, ez / length
    tau = ds / speed
    t_end = t0 + dt * (cur.shape[0] - 1)
    s = 0.0
    while t <= t_end:
        u, v, w = current_at(cur, org, step, t0, dt, ax + s * ex, ay + s * ey, az + s * ez, t)
        g0 = tail_speed(u, v, w, ex, ey, ez, speed)
        if not g0 > 0.0:
            return math.inf
        sm = min(s + 0.5 * tau * g0, length)
        u, v, w = current_at(cur, org, step, t0, dt, ax + sm * ex, ay + sm * ey, az + sm * ez, t + 0.5 * tau)
        g = tail_speed(u, v, w, ex, ey, ez, speed)
        if not g > 0.0:
            return math.inf
        if s + tau * g >= length:
            return t + (length - s) / g
        s += tau * g
        t += tau
    return math.inf
