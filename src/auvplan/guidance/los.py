"""Line-of-sight guidance baselines (Fossen 2011, 2014): proportional LOS and integral LOS.

LOS:  ψ_d = ψ_leg − atan(e / Δ)                        (e cross-track, right positive; Δ lookahead)
ILOS: ψ_d = ψ_leg − atan((e + σ y_int) / Δ),  ẏ_int = Δ e / ((e + σ y_int)² + Δ²)

Both command a heading and know nothing of obstacles; ILOS's integral removes the steady
offset a cross current causes under plain LOS.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .route import RouteTracker

__all__ = ["LosParams", "los_heading", "LosGuidance"]


@dataclass(frozen=True)
class LosParams:
    """LOS settings: ``lookahead`` Δ (m), ILOS integral gain ``sigma`` (-), leg switch radius (m)."""

    lookahead: float = 15.0
    sigma: float = 0.4
    switch_radius: float = 10.0

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
        """(course or heading command, is_heading, route point)."""
        rp = self.route.update(x, y)
        p = self.params
        sigma = p.sigma if self.integral else 0.0
        psi_d = los_heading(rp.course, rp.cross, p.lookahead, self.y_int, sigma)
        if self.integral:
            e = rp.cross
            self.y_int += dt * p.lookahead * e / ((e + sigma * self.y_int) ** 2 + p.lookahead**2)
        return psi_d, True, rp
