"""The executable waypoint mission: built from a plan and safe under every executor's depth semantics
(:mod:`.waypoints`), its convex limits (:mod:`.limits`) and the mission fitted to the vehicle (:mod:`.fit`).

The names of :mod:`.waypoints` are re-exported here (``from auvplan.guidance.mission import fly_check``).
"""

from __future__ import annotations

from .waypoints import (
    SEMANTICS,
    MissionCheck,
    MissionCheckDict,
    build_waypoints,
    default_tolerance,
    envelope_hits,
    envelopes_free,
    fly_check,
    held_track,
    leg_figures,
    leg_floors,
    segment_figures,
)

__all__ = ["SEMANTICS", "MissionCheck", "MissionCheckDict", "leg_floors", "envelope_hits", "envelopes_free",
           "build_waypoints", "default_tolerance", "fly_check", "held_track", "leg_figures", "segment_figures"]
