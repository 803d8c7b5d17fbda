"""The launch's dive in the closed loop (``[navigation]``; ``docs/navigation.md``, "The launch").

A mission with ``[navigation]`` starts at the surface above its first waypoint, with its GPS fix there, and dives to
it: the vertical leg the navigation budget, the fixes' times, the exported time-out and a ``.plan``'s check all count
(:func:`auvplan.sim.navigation.launch_flight`), held over the point at :data:`~auvplan.nav.budget.LAUNCH_DIVE_MPS`
through the water, so that it sinks at the ground speed ``c·e + sqrt(V² − |c|² + (c·e)²)`` along ``e`` straight down
(:func:`auvplan.endurance.ground_speed`; ``sqrt(V² − |c_h|²) − w`` for a current ``c = (c_h, w)``) and moves
``|c_h| dt`` through the water each step.  The closed loop flies it as it holds a surface dwell: a kinematic phase
(the torpedo model cannot hover), its clock, its drift without bottom lock over the water distance and its energy
(propulsion at ``V``) those of the flight the budget counts; steering starts at the first waypoint, as before.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..endurance import ground_speed, traverse
from ..nav.budget import LAUNCH_DIVE_MPS, launch_point
from ..world import World
from .mission import Mission

__all__ = ["launch_depth", "dive_step", "DOWN"]

DOWN = np.array([0.0, 0.0, -1.0])
"""The dive's direction (unit, up positive)."""


def launch_depth(world: World, mission: Mission, waypoints: NDArray[np.float64]) -> float:
    """The depth the flight dives to from the surface before its first leg (m below the surface; 0: no dive).

    Parameters
    ----------
    world : World
        Its currents.
    mission : Mission
        Its ``navigation`` (the budget that counts the dive).
    waypoints : numpy.ndarray
        ``(N, 3)`` the route (m).

    Returns
    -------
    float
        ``-z`` of the first waypoint for a mission with ``[navigation]`` whose dive the current lets the vehicle hold
        over the point (the budget's rule); 0 otherwise (the flight starts at the first waypoint, as one without
        ``[navigation]`` always does).
    """
    w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
    if mission.navigation is None or w.shape[0] < 2 or not w[0, 2] < -1e-9:
        return 0.0
    return float(-w[0, 2]) if traverse(world, np.vstack([launch_point(w), w[0]]), LAUNCH_DIVE_MPS).ok else 0.0


def dive_step(z: float, target: float, current: NDArray[np.float64], dt: float) -> tuple[float, float]:
    """One step of the dive held over the point.

    Parameters
    ----------
    z : float
        The vehicle's height now (m, up positive).
    target : float
        The first waypoint's (m): the dive ends there.
    current : numpy.ndarray
        ``(3,)`` the current at the vehicle now (m/s).
    dt : float
        The step (s).

    Returns
    -------
    z : float
        The height after the step (never below ``target``; unchanged where the current beats the dive).
    water : float
        The horizontal distance moved through the water over the part of the step spent diving (m).
    """
    g = ground_speed(np.asarray(current, dtype=float), DOWN, LAUNCH_DIVE_MPS)
    if not g > 0.0:  # the current beats the dive: held at the surface's side, no headway
        return z, 0.0
    used = min(dt, (z - target) / g)
    return max(z - g * dt, target), math.hypot(float(current[0]), float(current[1])) * used
