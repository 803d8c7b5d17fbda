"""Small synthetic scenes shared by the tests."""

from __future__ import annotations

import numpy as np

from auvplan.world import Bounds, Margins, Terrain, World


def flat_world(depth: float = 100.0, size: float = 1000.0, min_altitude: float = 5.0, obstacles=(), **kw) -> World:
    """Open square world over a flat seabed."""
    x = np.linspace(0.0, size, 21)
    t = Terrain(x, x, np.full((21, 21), -depth), name="flat")
    return World(Bounds(0.0, size, 0.0, size, -depth, 0.0), t, obstacles=obstacles,
                 margins=Margins(min_altitude=min_altitude, **kw), name="flat")
