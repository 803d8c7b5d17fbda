"""The legs of a QGroundControl ``.plan`` its vehicle flies following the seabed: those ending at an item in
the terrain frame (``MAV_FRAME_GLOBAL_TERRAIN_ALT`` = 10; ArduSub holds the altitude above the seabed between
items, :mod:`auvplan.guidance.mission.terrain_legs`), read back for ``auvplan mission check``."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...._types import BoolArray
from ...files.jsonfile import read_bounded_text
from .. import parsed
from .qgc_items import plan_items
from .readers import MAX_MISSION_BYTES

__all__ = ["TERRAIN_FRAME", "terrain_legs"]

TERRAIN_FRAME = 10
"""``MAV_FRAME_GLOBAL_TERRAIN_ALT``: an item's altitude is above the terrain (QGC altitude mode 4)."""


def terrain_legs(path: str | Path) -> BoolArray:
    """Which legs of a ``.plan`` (home first, as :func:`auvplan.io.missions.readback.readers.parse_qgc_plan` reads
    it) end at a terrain-frame item (a waypoint, a loiter read as one, a survey's generated waypoint).

    The first leg, from the home on the surface down to the first item, is the launch: flown as a straight
    descent (its depth band is exempt, as in :func:`~auvplan.guidance.mission.flycheck.fly_check`), never
    marked.

    Parameters
    ----------
    path : str or pathlib.Path
        A ``.plan`` file :func:`~auvplan.io.missions.readback.readers.read_mission` has read.

    Returns
    -------
    numpy.ndarray of bool
        One flag per leg (one per position :func:`~auvplan.io.missions.readback.qgc_items.plan_items` reads; the home
        leg's first and False).
    """
    doc = parsed.loads(read_bounded_text(Path(path), MAX_MISSION_BYTES, "a mission file"))
    frames = [it.frame for it in plan_items(doc) if it.moves]  # the reader's legs (the same walk)
    flags = np.array([f == TERRAIN_FRAME for f in frames], dtype=bool)
    if flags.size:
        flags[0] = False
    return flags
