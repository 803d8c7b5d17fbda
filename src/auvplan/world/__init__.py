"""World model: seabed, currents, obstacles and the World that combines them."""

from .currents import CurrentField, GriddedCurrent, LambOseenVortices, UniformCurrent
from .obstacles import (
    CircleMotion,
    Ellipsoid,
    LinearMotion,
    MovingObstacle,
    RandomWalkMotion,
    Sphere,
    WaypointMotion,
)
from .terrain import Terrain
from .tides import HarmonicTables, TidalCurrent
from .world import Bounds, Margins, World

__all__ = [
    "Bounds",
    "CircleMotion",
    "CurrentField",
    "Ellipsoid",
    "GriddedCurrent",
    "LambOseenVortices",
    "LinearMotion",
    "Margins",
    "MovingObstacle",
    "RandomWalkMotion",
    "Sphere",
    "Terrain",
    "HarmonicTables",
    "TidalCurrent",
    "UniformCurrent",
    "WaypointMotion",
    "World",
]
