"""Brute-force avoidability oracle for moving-obstacle contacts (issue #36).

Independent of the avoidance it judges: from a vehicle state at time ``t0`` (the moment a mover is
first sensed), every *constant* manoeuvre — a heading (every ``heading_step`` degrees), a pitch and a
speed command held from ``t0`` on — is flown with the vehicle's own model (:class:`auvplan.vehicles.Vehicle`:
Nomoto yaw with the rudder's angle and rate limits, pitch lag, surge lag, no waves) against the movers'
*true* scripted tracks (:meth:`MovingObstacle.motion.position`), the seabed plus its altitude margin, and
the depth band.  The contact was avoidable (by a vehicle with these limits) when at least one manoeuvre
keeps ``margin`` metres from every mover's surface and stays inside the band over ``horizon`` s.  The
best manoeuvre's clearance is the *margin* of the case: the Monte Carlo's design criterion is that it
is at least its margin (``benchmarks/avoidance.py``: ``ORACLE_MARGIN``, ``design_margin``).

Constant manoeuvres are a subset of all the vehicle can do, so "no constant manoeuvre" does not prove a
contact unavoidable; "one exists" proves it avoidable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...vehicles import Vehicle, VehicleParams, VehicleState
from ...world import World

__all__ = ["Manoeuvre", "best_constant_manoeuvre"]

_F64 = NDArray[np.float64]


@dataclass(frozen=True)
class Manoeuvre:
    """The best constant manoeuvre found by :func:`best_constant_manoeuvre`.

    Attributes
    ----------
    heading, pitch : float
        Commanded compass heading and pitch (rad).
    speed : float
        Commanded speed through the water (m/s).
    clearance : float
        Its smallest distance from a mover's surface over the horizon (m).
    band : float
        Its worst violation of the depth band / altitude margin (m; 0 inside).
    candidates, safe : int
        Manoeuvres tried, and those keeping the margin inside the band.
    """

    heading: float
    pitch: float
    speed: float
    clearance: float
    band: float
    candidates: int
    safe: int


def _fly(vehicle: Vehicle, s0: VehicleState, psi: float, theta: float, u: float, n: int) -> _F64:
    """Positions ``(n + 1, 3)`` of the vehicle holding one command for ``n`` steps (no current, no waves)."""
    s = VehicleState(s0.x, s0.y, s0.z, s0.psi, s0.u, s0.r, s0.delta, s0.theta)
    out = np.empty((n + 1, 3))
    out[0] = (s.x, s.y, s.z)
    zero = (0.0, 0.0, 0.0)
    for k in range(n):
        vehicle.step(s, psi, theta, u, zero, (0.0, 0.0))
        out[k + 1] = (s.x, s.y, s.z)
    return out


def best_constant_manoeuvre(world: World, params: VehicleParams, state: VehicleState, t0: float,
                            horizon: float = 120.0, margin: float = 0.0, dt: float = 1.0,
                            heading_step: float = 10.0, pitch_fractions: tuple[float, ...] = (0.0, -0.8, 0.8),
                            speeds: tuple[float, ...] | None = None) -> Manoeuvre:
    """Search constant heading/pitch/speed manoeuvres from ``state`` at ``t0`` against the true tracks.

    Parameters
    ----------
    world : World
        Seabed, margins, bounds and the moving obstacles (their scripted motions are the truth).
    params : VehicleParams
        The vehicle: its turn, pitch and speed limits.
    state : VehicleState
        The vehicle's state at ``t0``.
    t0 : float
        Start of the manoeuvre (s).
    horizon : float, optional
        Duration over which the manoeuvre must stay clear (s).
    margin : float, optional
        Clearance from every mover's surface required of a safe manoeuvre (m).
    dt : float, optional
        Integration step (s).
    heading_step : float, optional
        Spacing of the heading commands (degrees).
    pitch_fractions : tuple of float, optional
        Pitch commands as fractions of the vehicle's pitch limit.
    speeds : tuple of float, optional
        Speed commands (m/s); default 60 %, 100 % of cruise and ``max_speed``.

    Returns
    -------
    Manoeuvre
        The safe manoeuvre with the largest clearance, or (none safe) the one with the largest
        clearance minus band violation.
    """
    vehicle = Vehicle(params, dt)
    n = int(math.ceil(horizon / dt))
    ts = t0 + dt * np.arange(n + 1)
    centres = np.stack([np.asarray(o.motion.position(ts)) for o in world.moving], axis=1) \
        if world.moving else np.empty((n + 1, 0, 3))
    radii = np.array([o.shape.bounding_radius for o in world.moving])
    speeds = speeds if speeds is not None else (0.6 * params.speed, params.speed, params.max_speed)
    thmax = math.radians(params.pitch_max_deg)
    best: tuple[float, float, float, float, float] | None = None
    best_key = -math.inf
    tried = safe = 0
    for hd in np.arange(0.0, 360.0, heading_step):
        for fr in pitch_fractions:
            for u in speeds:
                track = _fly(vehicle, state, math.radians(float(hd)), fr * thmax, float(u), n)
                clear = float((np.linalg.norm(track[:, None, :] - centres, axis=2) - radii).min()) \
                    if radii.size else math.inf
                c = world.clearances(track, moving=False)
                band = float(max(0.0, -min(c["altitude"].min(), c["surface"].min(), c["max_depth"].min())))
                tried += 1
                ok = clear >= margin and band <= 0.0
                safe += ok
                key = clear + (1e6 if ok else -band)
                if key > best_key:
                    best_key, best = key, (math.radians(float(hd)), fr * thmax, float(u), clear, band)
    assert best is not None
    return Manoeuvre(*best, candidates=tried, safe=safe)
