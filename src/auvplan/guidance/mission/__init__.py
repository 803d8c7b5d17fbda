"""The executable waypoint mission: built from a plan (:mod:`.waypoints`) and safe under every executor's depth
semantics (its legs' envelopes, :mod:`.envelopes`), re-flown as each executor flies it (:mod:`.flycheck`), its
convex limits (:mod:`.limits`) and the mission fitted to the vehicle (:mod:`.fit`).

The names of :mod:`.waypoints`, :mod:`.envelopes` and :mod:`.flycheck` are re-exported here
(``from auvplan.guidance.mission import fly_check``).
"""

from __future__ import annotations

from .envelopes import envelope_hits, envelopes_free, leg_floors
from .flycheck import SEMANTICS, MissionCheck, MissionCheckDict, fly_check, held_track, leg_figures, segment_figures
from .waypoints import build_waypoints, default_tolerance

__all__ = ["SEMANTICS", "MissionCheck", "MissionCheckDict", "leg_floors", "envelope_hits", "envelopes_free",
           "build_waypoints", "default_tolerance", "fly_check", "held_track", "leg_figures", "segment_figures"]
