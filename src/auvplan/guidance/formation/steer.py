"""Formation steering: each vehicle's heading and speed command towards its slot (document 001's
hybrid field plus repulsion from the other vehicles), and the linearised loop's poles.

The slots themselves (shapes, schedule, the virtual structure along the route) are in
:mod:`auvplan.guidance.formation`, whose docstring states the law; this module computes it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..following.hybrid import HybridParams, hybrid_force
from ..following.route import crab_heading
from .keeping import FormationParams, Vec

__all__ = ["vehicle_repulsion", "FormationCommand", "formation_command", "dominant_pole"]


def vehicle_repulsion(course: float, fp: FormationParams, pos: Vec, vel: Vec,
                      others: Sequence[Sequence[float]]) -> tuple[float, float]:
    """Repulsion ``(east, north)`` from the other vehicles, document 001's eqs. 7–8 on the predicted geometry.

    For each other vehicle ``(x, y, vx, vy, keep)`` (ground velocities shared over the acoustic link;
    ``keep`` the centre distance to hold: ``separation_m`` for a vehicle, radius + half of it for a
    moving obstacle) the closest approach within ``horizon_s``
    (:func:`auvplan.guidance.avoidance.vo.closest_approach`, both keeping their velocities) gives the predicted
    relative position ``r_c`` and distance ``d = |r_c| − keep``; for ``d < vehicle_influence_m`` the
    push ``k_vehicle (1/d − 1/P_v)(1/d²)`` points away
    from ``r_c`` — opposite for the two vehicles, so each opens the miss distance the same way round —
    and, on a dead head-on course (``|r_c|`` below a metre), to starboard of ``course`` (both turn
    starboard, as the rule of the road says).

    Parameters
    ----------
    course : float
        The vehicle's slot course (rad, compass): starboard of it on a dead head-on course.
    fp : FormationParams
        Gains, influence, separation and look-ahead.
    pos, vel : sequence of float
        The vehicle's position and ground velocity (x, y first).
    others : sequence of (x, y, vx, vy, keep)
        The other vehicles and moving obstacles.

    Returns
    -------
    tuple of 2 float
        The push (east, north).
    """
    if not others:
        return 0.0, 0.0
    fx = fy = 0.0
    po, horizon = fp.vehicle_influence_m, fp.horizon_s
    for ox, oy, ovx, ovy, keep in others:
        # closest approach (the horizontal, scalar form of vo.closest_approach)
        rx, ry, wx, wy = ox - pos[0], oy - pos[1], ovx - vel[0], ovy - vel[1]
        ww = wx * wx + wy * wy
        tc = min(max(-(rx * wx + ry * wy) / ww, 0.0), horizon) if ww > 1e-12 else 0.0
        cx, cy = rx + wx * tc, ry + wy * tc
        dc = math.hypot(cx, cy)
        d = max(dc - keep, 1e-3)
        if d >= po:
            continue
        mag = fp.k_vehicle * (1.0 / d - 1.0 / po) / (d * d)
        if dc < 1.0:
            ux, uy = math.cos(course), -math.sin(course)  # starboard
        else:
            ux, uy = -cx / dc, -cy / dc
        fx += mag * ux
        fy += mag * uy
    return fx, fy


def _crosses(pos: Vec, slot: Vec, points: Sequence[Sequence[float]], radius: float) -> bool:
    """True when the horizontal segment ``pos → slot`` passes within ``radius`` of one of ``points``."""
    ax, ay = pos[0], pos[1]
    dx, dy = slot[0] - ax, slot[1] - ay
    dd = dx * dx + dy * dy
    for px, py in points:
        f = min(max(((px - ax) * dx + (py - ay) * dy) / dd, 0.0), 1.0) if dd > 1e-12 else 0.0
        if math.hypot(ax + f * dx - px, ay + f * dy - py) < radius:
            return True
    return False


@dataclass
class FormationCommand:
    """One vehicle's commands and where it stands relative to its slot (plain record).

    Attributes
    ----------
    psi : float
        Heading command (rad, compass).
    speed : float
        Speed command through the water (m/s).
    z_ref : float
        The slot's z (m).
    gamma : float
        The route's flight-path angle at the slot (rad).
    cross : float
        Cross error to the slot's course line, positive to starboard (m).
    along : float
        Along error, positive when behind the slot (m).
    error : float
        Distance to the slot (m).
    """

    psi: float
    speed: float
    z_ref: float
    gamma: float
    cross: float
    along: float
    error: float


def formation_command(slot: Vec, slot_course: float, slot_gamma: float, pos: Vec, vel: Vec,
                      current: Vec, speed: float, params: HybridParams, fp: FormationParams,
                      obstacles: Sequence[Sequence[float]], others: Sequence[Sequence[float]],
                      target_distance: float, speed_ff: float, cruise: float, max_speed: float,
                      give_way: Sequence[Sequence[float]] = ()) -> FormationCommand:
    """Heading, speed and depth commands of one vehicle towards its ``slot (3,)``.

    Parameters
    ----------
    slot : sequence of 3 float
        The slot's position.
    slot_course, slot_gamma : float
        The slot's compass course and the route's flight-path angle there (rad).
    pos, vel, current : sequence of float
        The vehicle's position ``(3,)``, its ground velocity and the current at it.
    speed : float
        Its speed through the water (m/s).
    params : HybridParams
        Hybrid-field gains.
    fp : FormationParams
        Formation parameters.
    obstacles : sequence of (x, y, surface distance)
        Static obstacles near the vehicle (repulsion, eqs. 7–8, with the hybrid goal factor).
    others : sequence of (x, y, vx, vy, keep)
        The other vehicles' (and the moving obstacles') positions, ground velocities and the centre
        distance to keep (:func:`vehicle_repulsion`).
    target_distance : float
        Distance to the vehicle's final slot (the goal-distance factor's r_at).
    speed_ff : float
        The slot's own speed (m/s): the feed-forward of the speed adjustment.
    cruise, max_speed : float
        Cruise and largest speed (m/s); the command lies in [min_speed_ratio·cruise, max_speed].
    give_way : sequence of (x, y)
        Vehicles of higher priority (a lower slot: the leader first); while the straight way to the
        slot passes within ``separation_m + vehicle_influence_m`` of one, the vehicle slows to its
        least speed and so crosses astern of it instead of racing it to the crossing.

    Returns
    -------
    FormationCommand
        Heading, speed and depth commands and the slot errors.
    """
    s, c = math.sin(slot_course), math.cos(slot_course)
    dx, dy = pos[0] - slot[0], pos[1] - slot[1]
    cross = dx * c - dy * s               # to starboard of the slot's course
    along = -(dx * s + dy * c)            # positive when the vehicle is behind its slot
    fx, fy = hybrid_force(slot_course, cross, params, pos[0], pos[1], obstacles, target_distance,
                          (slot[0], slot[1]))
    rx, ry = vehicle_repulsion(slot_course, fp, pos, vel, others)
    course = math.atan2(fx + rx, fy + ry)
    psi = crab_heading(course, current, speed) if params.compensates else course
    u = min(max(speed_ff + fp.k_speed * along, fp.min_speed_ratio * cruise), max_speed)
    if give_way and _crosses(pos, slot, give_way, fp.separation_m + fp.vehicle_influence_m):
        u = fp.min_speed_ratio * cruise
    err = math.dist((pos[0], pos[1], pos[2]), (slot[0], slot[1], slot[2]))
    return FormationCommand(psi, u, float(slot[2]), slot_gamma, cross, along, err)


def dominant_pole(speed: float, params: HybridParams, fp: FormationParams, heading_wn: float, heading_zeta: float,
                  surge_time_constant: float) -> dict[str, Any]:
    """Poles of the formation loop linearised on a straight route (see the module docstring).

    Parameters
    ----------
    speed : float
        Ground speed U (m/s).
    params : HybridParams
        k_H, k_X and Δ.
    fp : FormationParams
        k_s.
    heading_wn, heading_zeta : float
        The heading autopilot's natural frequency (rad/s) and damping.
    surge_time_constant : float
        T_u (s).

    Returns
    -------
    dict
        ``cross`` the cross-error poles (3), ``along`` the along-error poles (2) and ``dominant``
        the real part closest to zero (1/s).
    """
    gain = speed * params.k_route / (params.k_heading * params.lookahead)
    wn2 = heading_wn * heading_wn
    cross = np.roots([1.0, 2.0 * heading_zeta * heading_wn, wn2, wn2 * gain])
    along = np.roots([surge_time_constant, 1.0, fp.k_speed])
    dom = max(float(np.max(cross.real)), float(np.max(along.real)))
    return {"cross": cross, "along": along, "dominant": dom}
