"""Hybrid potential-field path tracking for a single-rudder vehicle (document 001).

Wang et al. 2020, Ship Science and Technology 42(12); METHODS.md §3.  One commanded direction
from three fields, for the active leg A → B with unit direction t̂ and right normal n̂:

* route attraction (eqs. 3–4): magnitude k_H·|e| perpendicular to the leg, towards it
  (e the cross-track error);
* heading attraction (eqs. 5–6): magnitude k_X·Δ along the leg;
  together χ = ψ_leg + atan2(−k_H e, k_X Δ) — LOS in potential-field form;
* obstacle repulsion (eqs. 7–8, the improved field with a goal-distance factor): for an obstacle
  whose surface is r_re < P_o away, F_rep = m_r (1/r_re − 1/P_o) (1/r_re²) ρ^n pointing from the
  obstacle to the vehicle, where ρ = min(r_at / P_o, 1) and r_at is the distance to the active
  waypoint (the factor vanishes as the target is reached, so a waypoint next to an obstacle stays
  reachable; normalising by P_o keeps the field's scale independent of leg length).

The resultant is the commanded direction.  Two engineering additions, both stated here and
switchable: (1) a lateral bias ``lateral_bias``·|F_rep| along the leg normal, away from the side of
the route the obstacle sits on (starboard for an obstacle on the route), which breaks the
head-on symmetry where repulsion and attraction are collinear and would deadlock; two obstacles
straddling the route cancel their biases, so the vehicle passes between them; (2) the resultant is
a course over ground, turned into a heading with the measured current (crab angle
β = asin(c⊥ / u)), as a DVL/ADCP-equipped vehicle does (``current_compensation``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .route import RoutePoint, RouteTracker

__all__ = ["HybridParams", "hybrid_force", "crab_heading", "HybridGuidance"]


@dataclass(frozen=True)
class HybridParams:
    """Gains of document 001's hybrid field.

    Attributes
    ----------
    k_route : float
        Route (cross-track) attraction gain k_H.
    k_heading : float
        Heading attraction gain k_X; the heading attraction is k_X·Δ.
    lookahead : float
        Δ (m), along-leg distance of the heading attraction.
    influence : float
        P_o (m), obstacle influence distance from the obstacle surface.
    k_repulse : float
        m_r, repulsion gain.
    goal_power : float
        n, exponent of the goal-distance factor.
    lateral_bias : float
        Lateral push as a fraction of the repulsion magnitude (0 disables).
    current_compensation : bool
        Turn the commanded course into a heading with the measured current.
    switch_radius : float
        Leg switching radius (m).
    """

    k_route: float = 1.0
    k_heading: float = 1.0
    lookahead: float = 15.0
    influence: float = 25.0
    k_repulse: float = 2.0e4
    goal_power: float = 1.0
    lateral_bias: float = 2.0
    current_compensation: bool = True
    switch_radius: float = 10.0

    def __post_init__(self) -> None:
        for k in ("k_route", "k_heading", "lookahead", "influence", "switch_radius"):
            if not getattr(self, k) > 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be positive")
        if self.k_repulse < 0 or self.goal_power < 0 or self.lateral_bias < 0:
            raise ValueError("k_repulse, goal_power and lateral_bias must be >= 0")


def hybrid_force(course: float, cross: float, params: HybridParams, x: float, y: float,
                 obstacles: Sequence[Sequence[float]], target_distance: float,
                 leg_origin: Sequence[float] | NDArray[np.float64]) -> tuple[float, float]:
    """Compute the resultant of route attraction, heading attraction and obstacle repulsion.

    Parameters
    ----------
    course : float
        Compass course of the active leg (rad).
    cross : float
        Cross-track error e, positive to starboard (m).
    params : HybridParams
        The field's gains.
    x, y : float
        Vehicle position east and north (m).
    obstacles : sequence of (float, float, float)
        ``(cx, cy, surface_distance)`` of each obstacle (m).
    target_distance : float
        Horizontal distance to the active waypoint r_at (m).
    leg_origin : sequence of float
        ``(x, y)`` of the active leg's start (m), to tell which side of the route an obstacle is on.

    Returns
    -------
    tuple of float
        The resultant's east and north components (the field's units; only its direction is used).
    """
    s, c = math.sin(course), math.cos(course)
    tx, ty = s, c            # along the leg
    nx, ny = c, -s           # right normal
    fa = params.k_heading * params.lookahead
    fh = -params.k_route * cross
    fx = fa * tx + fh * nx
    fy = fa * ty + fh * ny
    po = params.influence
    rho = min(target_distance / po, 1.0) ** params.goal_power
    for cx, cy, d in obstacles:
        if d >= po:
            continue
        d = max(d, 1e-3)
        mag = params.k_repulse * (1.0 / d - 1.0 / po) / (d * d) * rho
        rx, ry = x - cx, y - cy
        rn = math.hypot(rx, ry) or 1.0
        fx += mag * rx / rn
        fy += mag * ry / rn
        if params.lateral_bias:
            side = (cx - leg_origin[0]) * nx + (cy - leg_origin[1]) * ny
            push = -1.0 if side > 0.5 else 1.0  # away from the obstacle's side; starboard if on the route
            fx += push * params.lateral_bias * mag * nx
            fy += push * params.lateral_bias * mag * ny
    return fx, fy


def crab_heading(course: float, current: Sequence[float] | NDArray[np.float64], speed: float) -> float:
    """Return the heading that makes good ``course`` through a horizontal current.

    Parameters
    ----------
    course : float
        Wanted compass course over ground (rad).
    current : sequence of float
        Current velocity east, north (, up) (m/s).
    speed : float
        Speed through the water (m/s).

    Returns
    -------
    float
        Compass heading (rad): the course minus the crab angle asin(c⊥ / u), clipped at ±90°.
    """
    c_right = current[0] * math.cos(course) - current[1] * math.sin(course)
    return course - math.asin(max(-1.0, min(1.0, c_right / max(speed, 1e-6))))


class HybridGuidance:
    """Document 001's guidance along a route (``reset()`` to restart).

    Parameters
    ----------
    route : RouteTracker
        The route to follow.
    params : HybridParams
        The field's gains.
    """

    name = "hybrid"

    def __init__(self, route: RouteTracker, params: HybridParams) -> None:
        self.route = route
        self.params = params

    def reset(self) -> None:
        """Restart the route."""
        self.route.reset()

    def command(self, x: float, y: float, z: float, current: Sequence[float] | NDArray[np.float64], speed: float,
                obstacles: Sequence[Sequence[float]], dt: float) -> tuple[float, bool, RoutePoint]:
        """Compute the heading command for one step; the field's course is converted with the current.

        Parameters
        ----------
        x, y, z : float
            Vehicle position (m).
        current : sequence of float
            Current at the vehicle, east, north, up (m/s).
        speed : float
            Speed through the water (m/s).
        obstacles : sequence of (float, float, float)
            ``(cx, cy, surface_distance)`` of the nearby obstacles (m).
        dt : float
            Time step (s); unused (the field has no state).

        Returns
        -------
        command : float
            Commanded compass heading (rad).
        is_heading : bool
            Always True.
        point : RoutePoint
            The vehicle's position relative to the route.
        """
        rp = self.route.update(x, y)
        k = rp.leg
        b = self.route.w[k + 1]
        target = math.hypot(b[0] - x, b[1] - y)
        fx, fy = hybrid_force(rp.course, rp.cross, self.params, x, y, obstacles, target, self.route.w[k])
        course = math.atan2(fx, fy)
        psi = crab_heading(course, current, speed) if self.params.current_compensation else course
        return psi, True, rp
