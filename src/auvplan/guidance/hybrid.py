"""Hybrid potential-field path tracking for a single-rudder vehicle (document 001)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["HybridParams"]


@dataclass(frozen=True)
class HybridParams:
    """Gains of document 001's hybrid field.

    Attributes
    ----------
    k_route : float
        Route (cross-track) attraction gain k_H (1/m · force unit).
    k_heading : float
        Heading attraction gain k_X; with ``lookahead`` Δ (m) the heading
        attraction is k_X·Δ.
    lookahead : float
        Δ (m), the along-leg distance of the heading attraction.
    influence : float
        P_o (m), obstacle influence distance measured from the obstacle surface.
    k_repulse : float
        m_r, repulsion gain.
    goal_power : float
        n, exponent of the goal-distance factor r_at^n of the improved field.
    switch_radius : float
        Leg switching radius (m).
    """

    k_route: float = 1.0
    k_heading: float = 1.0
    lookahead: float = 15.0
    influence: float = 25.0
    k_repulse: float = 400.0
    goal_power: float = 1.0
    switch_radius: float = 10.0

    def __post_init__(self) -> None:
        for k in ("k_route", "k_heading", "lookahead", "influence", "switch_radius"):
            if not getattr(self, k) > 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be positive")
        if self.k_repulse < 0 or self.goal_power < 0:
            raise ValueError("k_repulse and goal_power must be >= 0")
