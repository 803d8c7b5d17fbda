"""Parameters of the local avoidance of moving obstacles (document 004's APF, issue #21's predictive
variant and issue #36's sweep and turn models); the algorithms live in :mod:`.local`, :mod:`.predictive`,
:mod:`.sweep` and :mod:`.turning`.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["AVOIDANCE", "ESCAPES", "AvoidanceParams"]


AVOIDANCE = ("predictive", "apf", "none")
"""Local avoidance variants: issue #21's predictive one, document 004's APF, none."""

ESCAPES = ("auto", "sampled", "patent")
"""Local-minimum escape rules: each avoidance's own (``auto``), issue #36's sampled sub-goal, document 004's
rule as written."""


@dataclass(frozen=True)
class AvoidanceParams:
    """Document 004's APF parameters (docs/methods.md §4) and their vehicle-scale defaults.

    Attributes
    ----------
    name : str
        ``"predictive"`` (the default: prediction + velocity obstacles, :mod:`.predictive`), ``"apf"``
        (document 004 as written) or ``"none"`` (follow the global path blindly).
    radius : float
        r, repulsion radius measured from the obstacle surface (m).
    k_att, w_att : float
        k₁ and w₁ of |F_att| = k₁ d(p, g)^w₁.
    k_rep, w_obs, w_goal : float
        k₂, w₂ and w₃ of |F_rep| = k₂ (1/d_o − 1/r) d_g^w₃ / d_o^w₂.
    arrive : float
        ε₁, sub-goal arrival threshold (m).
    minimum_radius : float
        r₁, radius of the local-minimum count (m); larger than the turning radius for a vehicle
        that cannot hover.
    minimum_count : int
        ε₂, number of own past points (one per ``history_dt``) within r₁ that means "trapped".
    history_dt : float
        Interval between remembered own positions (s).
    escape_radius : float
        Radius about the vehicle in which the sampled rule (``escape``) draws its escape sub-goals (m).
    escape : str
        The local-minimum escape rule.  ``"auto"`` (the default): ``"patent"`` under document 004's
        ``apf``, ``"sampled"`` under ``predictive`` (:attr:`escape_rule`).  ``"sampled"``: draws within
        ``escape_radius`` at about the vehicle's depth, the sub-goal kept until reached
        (``predictive`` picks the draw in sight with the shortest way on).  ``"patent"``: document 004
        steps 3.3.2.5-3.3.2.7 as written: a random obstacle-free point anywhere in the world (bounds,
        seabed, margins) replaces the sub-goal at every new path point (one per ``history_dt``) while
        the local-minimum count says trapped; once it does not, the first unvisited key waypoint is the
        sub-goal again.
    collision_check : str
        ``"exact"`` or ``"stepping"`` (document 004's test) for key waypoints.
    escape_time : float
        After the route progress has stalled for ``[sim] deadlock_time``, escapes (random
        sub-goals) are tried for this long before ``DEADLOCK`` is declared (s).
    sensor_range : float
        ``predictive``: moving obstacles are seen within this distance of their surface (m).
    horizon : float
        ``predictive``: prediction horizon of the closest approach and the velocity obstacles (s).
    margin : float
        ``predictive``: clearance from every obstacle surface a manoeuvre must keep over the horizon (m).
    velocity : str
        ``predictive``: obstacle velocities ``"known"`` (from the scenario) or ``"track"``
        (least-squares slope of the centres sensed over the last ``track_window`` s).
    track_window : float
        ``predictive``: length of the sensed track the velocity is estimated from (s).
    vertical, speed_change : bool
        ``predictive``: also consider pitch (dive / climb within the depth band and the altitude
        margin) and speed (slow down / sprint to the vehicle's ``max_speed``) changes.
    sweep : bool
        ``predictive``: add the image of every shuttle beyond its turning point to the predicted
        obstacles (:mod:`.sweep`, issue #36), so the vehicle leaves a fast mover's lane before it
        turns round.
    sweep_window : float
        ``predictive``: length of the remembered track of each sensed obstacle (s).
    turn_model : bool
        ``predictive``: predict a mover whose remembered track turns at a constant rate on its arc
        (CTRV, :mod:`.turning`) instead of its tangent.
    turn_growth : float
        ``predictive``: growth of a turning mover's predicted radius with the time ahead (m/s).
    """

    name: str = "predictive"
    radius: float = 30.0
    k_att: float = 1.0
    w_att: float = 0.0
    k_rep: float = 100.0
    w_obs: float = 1.0
    w_goal: float = 1.0
    arrive: float = 10.0
    minimum_radius: float = 15.0
    minimum_count: int = 60
    history_dt: float = 1.0
    escape_radius: float = 60.0
    escape: str = "auto"
    collision_check: str = "exact"
    escape_time: float = 300.0
    sensor_range: float = 200.0
    horizon: float = 60.0
    margin: float = 10.0
    velocity: str = "known"
    track_window: float = 5.0
    vertical: bool = True
    speed_change: bool = True
    sweep: bool = True
    sweep_window: float = 600.0
    turn_model: bool = True
    turn_growth: float = 0.05

    def __post_init__(self) -> None:
        if self.name not in AVOIDANCE:
            raise ValueError(f"name = {self.name!r}: choose {', '.join(repr(a) for a in AVOIDANCE)}")
        if self.velocity not in ("known", "track"):
            raise ValueError(f"velocity = {self.velocity!r}: choose 'known' or 'track'")
        if self.escape not in ESCAPES:
            raise ValueError(f"escape = {self.escape!r}: choose {', '.join(repr(a) for a in ESCAPES)}")
        if self.escape_time < 0:
            raise ValueError(f"escape_time = {self.escape_time}: must be >= 0")
        for k in ("radius", "arrive", "minimum_radius", "escape_radius", "history_dt", "sensor_range", "horizon",
                  "margin", "track_window", "sweep_window"):
            if not getattr(self, k) > 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be positive")
        if self.minimum_count < 2:
            raise ValueError(f"minimum_count = {self.minimum_count}: must be >= 2")
        for k in ("k_att", "k_rep", "turn_growth"):
            if getattr(self, k) < 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be >= 0")
        if self.collision_check not in ("exact", "stepping"):
            raise ValueError(f"collision_check = {self.collision_check!r}: choose 'exact' or 'stepping'")

    @property
    def escape_rule(self) -> str:
        """The escape rule in force: ``escape``, or the avoidance's own when ``"auto"``."""
        if self.escape != "auto":
            return self.escape
        return "patent" if self.name == "apf" else "sampled"
