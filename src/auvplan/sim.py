"""Mission definition and closed-loop simulation."""

from __future__ import annotations

from dataclasses import dataclass, field

from .guidance.hybrid import HybridParams
from .guidance.local import AvoidanceParams
from .guidance.los import LosParams
from .planners.base import PlannerSpec, PlanningProblem
from .vehicles import VehicleParams
from .world import World

__all__ = ["SimSettings", "Mission", "planning_problem"]


@dataclass(frozen=True)
class SimSettings:
    """Closed-loop settings: step ``dt`` (s), time limit (s; 0 = 3 × nominal), arrival radius (m),
    deadlock window (s without progress along the route)."""

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


@dataclass(frozen=True)
class Mission:
    """What to do in a World: end points, an optional fixed route, and every component's settings."""

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
    sim: SimSettings = field(default_factory=SimSettings)


def planning_problem(world: World, mission: Mission) -> PlanningProblem:
    """The global planning problem of a mission in a world."""
    v = mission.vehicle
    return PlanningProblem(world, mission.start, mission.goal, v.speed, v.hotel_power, v.drag_k)
