"""World model: seabed, currents, obstacles and the World that combines them."""

from .currents.fields import CurrentField, GriddedCurrent, LambOseenVortices, UniformCurrent
from .currents.tides import HarmonicTables, TidalCurrent
from .land import Land
from .moving import CircleMotion, LinearMotion, MovingObstacle, RandomWalkMotion, WaypointMotion
from .obstacles import Ellipsoid, Sphere
from .terrain import Terrain
from .world import Bounds, Margins, World
from .zones import Zone, ZoneApproach, Zones

__all__ = [
    "Bounds",
    "CircleMotion",
    "CurrentField",
    "Ellipsoid",
    "GriddedCurrent",
    "Land",
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
    "Zone",
    "Zones",
    "ZoneApproach",
]
