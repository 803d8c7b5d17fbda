"""Local avoidance of moving obstacles with key waypoints and an APF (document 004)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["AvoidanceParams"]


@dataclass(frozen=True)
class AvoidanceParams:
    """Document 004's APF parameters (METHODS.md §4).

    Attributes
    ----------
    name : str
        ``"apf"`` (document 004) or ``"none"`` (follow the global path blindly).
    radius : float
        r, repulsion radius measured from the obstacle surface (m).
    k_att, w_att : float
        k1 and w1 of |F_att| = k1 d(p, g)^w1.
    k_rep, w_obs, w_goal : float
        k2, w2 and w3 of |F_rep| = k2 (1/d_o - 1/r) d_g^w3 / d_o^w2.
    arrive : float
        ε1, sub-goal arrival threshold (m).
    minimum_radius : float
        r1, radius of the local-minimum count (m).
    minimum_count : int
        ε2, number of own past points within r1 that means "trapped".
    escape_radius : float
        Radius about the vehicle in which random escape sub-goals are drawn (m).
    """

    name: str = "apf"
    radius: float = 30.0
    k_att: float = 1.0
    w_att: float = 0.0
    k_rep: float = 100.0
    w_obs: float = 1.0
    w_goal: float = 1.0
    arrive: float = 10.0
    minimum_radius: float = 3.0
    minimum_count: int = 25
    escape_radius: float = 40.0

    def __post_init__(self) -> None:
        if self.name not in ("apf", "none"):
            raise ValueError(f"name = {self.name!r}: choose 'apf' or 'none'")
        for k in ("radius", "arrive", "minimum_radius", "escape_radius"):
            if not getattr(self, k) > 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be positive")
        if self.minimum_count < 2:
            raise ValueError(f"minimum_count = {self.minimum_count}: must be >= 2")
        for k in ("k_att", "k_rep"):
            if getattr(self, k) < 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be >= 0")
