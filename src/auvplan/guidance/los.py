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
from dataclasses import dataclass

from .route import RouteTracker, crab_heading

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
    """Pure LOS/ILOS law: commanded compass heading (rad)."""
    return course - math.atan((cross + sigma * integral) / lookahead)


class LosGuidance:
    """LOS (``integral=False``) or ILOS path following along a route."""

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

    def command(self, x: float, y: float, z: float, current, speed: float, obstacles, dt: float):
        """(heading command, True, route point); with ``current_compensation`` the law's angle is a
        course made good through ``current`` at the through-water ``speed``."""
        rp = self.route.update(x, y)
        p = self.params
        sigma = p.sigma if self.integral else 0.0
        psi_d = los_heading(rp.course, rp.cross, p.lookahead, self.y_int, sigma)
        if p.current_compensation:
            psi_d = crab_heading(psi_d, current, speed)
        if self.integral:
            e = rp.cross
            self.y_int += dt * p.lookahead * e / ((e + sigma * self.y_int) ** 2 + p.lookahead**2)
        return psi_d, True, rp
