"""Line-of-sight guidance baselines (Fossen 2011, 2014): proportional LOS and integral LOS.

LOS:  ψ_d = ψ_leg − atan(e / Δ)                        (e cross-track, right positive; Δ lookahead)
ILOS: ψ_d = ψ_leg − atan((e + σ y_int) / Δ),  ẏ_int = Δ e / ((e + σ y_int)² + Δ²)

Both know nothing of obstacles.  Without current compensation (the default) ψ_d is flown as a
heading: a current c⊥ across the leg (positive to starboard) then holds plain LOS at the steady
cross-track error e_ss = Δ·tan(asin(c⊥/U)) (U the through-water speed), which ILOS's integral
removes.  With ``current_compensation`` the law's angle is a course over ground, turned into a
heading with the measured current (crab angle β = asin(c⊥/U), :func:`crab_heading`) — the same
conversion the hybrid field of document 001 uses, so the two can be compared like with like;
LOS then holds the line with no steady error.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .route import RoutePoint, RouteTracker, crab_heading

__all__ = ["LosParams", "los_heading", "LosGuidance"]


@dataclass(frozen=True)
class LosParams:
    """LOS and ILOS settings.

    Attributes
    ----------
    lookahead : float
        Δ (m), the look-ahead distance along the leg.
    sigma : float
        ILOS integral gain σ (-).
    switch_radius : float
        Leg switching radius (m).
    current_compensation : bool
        Turn the commanded course into a heading with the measured current (crab angle), as the
        corrected hybrid field does; false flies the law's angle as a heading (Fossen's LOS).
    """

    lookahead: float = 15.0
    sigma: float = 0.4
    switch_radius: float = 10.0
    current_compensation: bool = False

    def __post_init__(self) -> None:
        if not self.lookahead > 0 or self.sigma < 0 or not self.switch_radius > 0:
            raise ValueError("lookahead and switch_radius must be positive and sigma >= 0")


def los_heading(course: float, cross: float, lookahead: float, integral: float = 0.0, sigma: float = 0.0) -> float:
    """Apply the pure LOS/ILOS law.

    Parameters
    ----------
    course : float
        Compass course of the active leg ψ_leg (rad).
    cross : float
        Cross-track error e, positive to starboard (m).
    lookahead : float
        Lookahead distance Δ (m).
    integral : float, optional
        ILOS integral state y_int (m).
    sigma : float, optional
        ILOS integral gain σ; 0 gives plain LOS.

    Returns
    -------
    float
        Commanded compass heading ψ_d (rad).
    """
    return course - math.atan((cross + sigma * integral) / lookahead)


class LosGuidance:
    """LOS (``integral=False``) or ILOS path following along a route.

    Parameters
    ----------
    route : RouteTracker
        The route to follow.
    params : LosParams
        Lookahead, integral gain, switch radius.
    integral : bool, optional
        ILOS (True) or plain LOS (False).
    """

    def __init__(self, route: RouteTracker, params: LosParams, integral: bool = False) -> None:
        self.route = route
        self.params = params
        self.integral = integral
        self.y_int = 0.0
        self.name = "ilos" if integral else "los"

    def reset(self) -> None:
        """Forget the integral state and restart the route."""
        self.y_int = 0.0
        self.route.reset()

    def command(self, x: float, y: float, z: float, current: Sequence[float] | NDArray[np.float64], speed: float,
                obstacles: Sequence[Sequence[float]], dt: float) -> tuple[float, bool, RoutePoint]:
        """Compute the heading command for one step (LOS knows nothing of obstacles).

        With ``current_compensation`` the law's angle is a course made good through ``current`` at
        the through-water ``speed``.

        Parameters
        ----------
        x, y, z : float
            Vehicle position (m).
        current : sequence of float
            Current at the vehicle, east, north, up (m/s); used with ``current_compensation``.
        speed : float
            Speed through the water (m/s); used with ``current_compensation``.
        obstacles : sequence of (float, float, float)
            Nearby obstacles; unused (LOS knows nothing of obstacles).
        dt : float
            Time step of the ILOS integral (s).

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
        p = self.params
        sigma = p.sigma if self.integral else 0.0
        psi_d = los_heading(rp.course, rp.cross, p.lookahead, self.y_int, sigma)
        if p.current_compensation:
            psi_d = crab_heading(psi_d, current, speed, self.route.tail[rp.leg])
        if self.integral:
            e = rp.cross
            self.y_int += dt * p.lookahead * e / ((e + sigma * self.y_int) ** 2 + p.lookahead**2)
        return psi_d, True, rp
