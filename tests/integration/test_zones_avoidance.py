"""Local avoidance (document 004's APF) treats the charted zones as static obstacles: dodging a head-on
mover, the vehicle is repelled from the zone's nearest point and never enters it (oracle: shapely's
intersection of every flown track segment with the footprint; the zone reaches surface to seabed)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import shapely

from auvplan._types import Status
from auvplan.sim import Mission, SimParams, simulate
from auvplan.world import Bounds, LinearMotion, Margins, MovingObstacle, Sphere, World, Zone, Zones

HEAD_ON = MovingObstacle(Sphere((0, 0, 0), 30.0), LinearMotion((900.0, 15.0, -100.0), (-1.0, 0.0, 0.0)), "head-on")
ZONE = Zone("no-go", shapely.box(500.0, -150.0, 700.0, -45.0))  # south of the route, where the APF sidesteps


def _entries(track: np.ndarray) -> int:
    legs = shapely.linestrings(np.stack([track[:-1, :2], track[1:, :2]], axis=1))
    return int(shapely.intersects(legs, ZONE.footprint).sum())


def test_the_apf_dodging_a_mover_keeps_out_of_a_zone():
    world = World(Bounds(0, 1000, -500, 500, -200.0, 0), None, moving=(HEAD_ON,),
                  margins=Margins(min_altitude=5.0, min_depth=5.0))
    mission = Mission("open", (0, 0, -100.0), (1000, 0, -100.0), route=((0, 0, -100.0), (1000, 0, -100.0)),
                      sim=SimParams(dt=0.5))
    # (the same flight without the zone in the world sidesteps across it: 97 of its samples inside)
    r = simulate(replace(world, zones=Zones((ZONE,))), mission, avoidance="apf", rng=0)
    assert r.status is Status.EXACT and r.metrics["collisions"] == 0
    assert _entries(r.position) == 0
    assert np.linalg.norm(r.position[-1] - np.array([1000.0, 0.0, -100.0])) < 50.0  # arrived
