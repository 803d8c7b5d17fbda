"""Guidance, by concern: following a route (:mod:`.following`: the route and its active leg, LOS and ILOS,
document 001's hybrid field), local avoidance of moving obstacles (:mod:`.avoidance`: document 004's key
waypoints and APF, predictive avoidance and velocity obstacles), formations (:mod:`.formation`), and the
executable waypoint mission (:mod:`.mission`).

Every public name of the sub-packages is also importable from here (``from auvplan.guidance import
HybridGuidance``), imported when first used, so ``import auvplan.guidance`` stays cheap.
"""

from __future__ import annotations

import importlib
from typing import Any

_LAZY = {
    "LocalAvoidance": "avoidance.local",
    "MinimumDetector": "avoidance.local",
    "apf_force": "avoidance.local",
    "key_waypoints": "avoidance.local",
    "Manoeuvre": "avoidance.oracle",
    "best_constant_manoeuvre": "avoidance.oracle",
    "AVOIDANCE": "avoidance.params",
    "AvoidanceParams": "avoidance.params",
    "PointModelResult": "avoidance.point_model",
    "run_point_model": "avoidance.point_model",
    "PredictiveAvoidance": "avoidance.predictive",
    "TrackEstimator": "avoidance.predictive",
    "SweepMemory": "avoidance.sweep",
    "arc_chords": "avoidance.turning",
    "ctrv_position": "avoidance.turning",
    "turn_rate": "avoidance.turning",
    "CFG": "avoidance.vo",
    "closest_approach": "avoidance.vo",
    "predicted_preference": "avoidance.vo",
    "predicted_preference_windows": "avoidance.vo",
    "vo_choose": "avoidance.vo",
    "vo_choose_windows": "avoidance.vo",
    "HybridGuidance": "following.hybrid",
    "HybridParams": "following.hybrid",
    "VARIANTS": "following.hybrid",
    "goal_factor": "following.hybrid",
    "hybrid_force": "following.hybrid",
    "LosGuidance": "following.los",
    "LosParams": "following.los",
    "los_heading": "following.los",
    "PathFollower": "following.route",
    "RoutePoint": "following.route",
    "RouteTracker": "following.route",
    "crab_heading": "following.route",
    "SETTLE_M": "formation.error",
    "error_figures": "formation.error",
    "Formation": "formation.keeping",
    "FormationParams": "formation.keeping",
    "ShapeChange": "formation.keeping",
    "VEHICLE_NAME": "formation.keeping",
    "VehicleSpec": "formation.keeping",
    "FormationPlan": "formation.plan",
    "check_tracks": "formation.plan",
    "plan_formation": "formation.plan",
    "requested_breaks": "formation.plan",
    "FormationRoute": "formation.route",
    "SHAPES": "formation.route",
    "Schedule": "formation.route",
    "shape_offsets": "formation.route",
    "FormationCommand": "formation.steer",
    "dominant_pole": "formation.steer",
    "formation_command": "formation.steer",
    "vehicle_repulsion": "formation.steer",
    "MissionFit": "mission.fit",
    "fit_mission": "mission.fit",
    "fit_turns": "mission.fit",
    "flown_distance": "mission.fit",
    "WaypointLimits": "mission.limits",
    "WaypointLimitsDict": "mission.limits",
    "waypoint_limits": "mission.limits",
    "MissionCheck": "mission.flycheck",
    "MissionCheckDict": "mission.flycheck",
    "SEMANTICS": "mission.flycheck",
    "build_waypoints": "mission.waypoints",
    "default_tolerance": "mission.waypoints",
    "envelope_hits": "mission.envelopes",
    "envelopes_free": "mission.envelopes",
    "fly_check": "mission.flycheck",
    "held_track": "mission.flycheck",
    "leg_figures": "mission.flycheck",
    "leg_floors": "mission.envelopes",
    "segment_figures": "mission.flycheck",
}
"""Public name -> the module (under :mod:`auvplan.guidance`) that defines it."""

__all__ = sorted(_LAZY)


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'auvplan.guidance' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
