"""What to fly: a :class:`Mission` (end points, an optional fixed route, every component's settings) and
its closed-loop :class:`SimParams`."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..endurance.params import EnduranceParams
from ..guidance.avoidance.params import AvoidanceParams
from ..guidance.following.hybrid import HybridParams
from ..guidance.following.los import LosParams
from ..guidance.formation.keeping import Formation
from ..nav.params import NavParams
from ..planners.core.base import PlannerSpec
from ..vehicles import VehicleParams

__all__ = ["SimParams", "SimSettings", "Mission"]


@dataclass(frozen=True)
class SimParams:
    """Closed-loop settings: time step, time limit, arrival, deadlock and recording.

    Attributes
    ----------
    dt : float
        Time step (s).
    max_time : float
        Time limit (s); 0 = 3 × the nominal duration + 120 s.
    arrival_radius : float
        Distance from the last waypoint that counts as arrival (m).
    deadlock_time : float
        Deadlock window: time without 1 m of progress along the route (s).
    record_every : int
        Record every this many steps.
    """

    dt: float = 0.1
    max_time: float = 0.0
    arrival_radius: float = 10.0
    deadlock_time: float = 120.0
    record_every: int = 1

    def __post_init__(self) -> None:
        if not self.dt > 0 or self.max_time < 0 or not self.arrival_radius > 0 or not self.deadlock_time > 0:
            raise ValueError("dt, arrival_radius and deadlock_time must be positive and max_time >= 0")
        if self.record_every < 1:
            raise ValueError(f"record_every = {self.record_every}: must be >= 1")


SimSettings = SimParams
"""Former name of :class:`SimParams` (settings are ``*Params`` throughout), kept for existing code."""


@dataclass(frozen=True)
class Mission:
    """What to do in a World: end points, an optional fixed route, and every component's settings.

    Attributes
    ----------
    name : str
        Mission (scenario) name.
    start, goal : tuple of float
        End points ``(x, y, z)`` (m).
    route : tuple of (x, y, z)
        A fixed route to follow instead of planning one (empty: plan).
    seed : int
        Default seed of the planner and of the simulation's disturbances.
    vehicle, planner, hybrid, los, avoidance, sim
        Settings of the vehicle, the global planner, the two path followers, the local
        avoidance and the closed loop.
    guidance : str
        ``"hybrid"``, ``"los"`` or ``"ilos"``.
    formation : Formation or None
        Several vehicles flying the route in formation (``[[vehicles]]``, ``[formation]``):
        :mod:`auvplan.sim.formation` flies them.
    follow_altitude_m : float
        Terrain following: the mission's depth schedule holds this altitude above the seabed
        within the vehicle's pitch limit (m; 0: off; :mod:`auvplan.guidance.mission.fit`).
    endurance : EnduranceParams
        Recovery point and the speed choice per leg (``[endurance]``, :mod:`auvplan.endurance`).
    leg_speeds : tuple of float
        Through-water speed of each leg of the route flown (m/s); empty: the vehicle's ``speed``.
    navigation : NavParams or None
        The navigation error budget (``[navigation]``): fixes planned or timed into the route, the
        predicted error, and the clearance under it (:mod:`auvplan.nav`); None: perfect navigation.
    nav_drift : bool
        Fly with a drifting navigation estimate (:mod:`auvplan.sim.drift`); off by default.
    """

    name: str
    start: tuple[float, float, float]
    goal: tuple[float, float, float]
    route: tuple[tuple[float, float, float], ...] = ()
    seed: int = 0
    vehicle: VehicleParams = field(default_factory=VehicleParams)
    planner: PlannerSpec = field(default_factory=PlannerSpec)
    guidance: str = "hybrid"
    hybrid: HybridParams = field(default_factory=HybridParams)
    los: LosParams = field(default_factory=LosParams)
    avoidance: AvoidanceParams = field(default_factory=AvoidanceParams)
    sim: SimParams = field(default_factory=SimParams)
    formation: Formation | None = None
    follow_altitude_m: float = 0.0
    endurance: EnduranceParams = field(default_factory=EnduranceParams)
    leg_speeds: tuple[float, ...] = ()
    navigation: NavParams | None = None
    nav_drift: bool = False

