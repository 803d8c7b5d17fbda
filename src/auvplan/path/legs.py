"""A mission judged leg by leg as a helm flies it: no leg too short, every leg's pitch and fly-by turns.

:func:`auvplan.path.flyable.check_limits` judges a *plan*: it merges vertices within 1 % of the turn radius
and judges turns on the track simplified to 0.1 R, so that the micro-legs of a sampled spline are not
taken for turns.  A waypoint mission as a file is flown differently: a helm (MOOS-IvP's waypoint
behaviour, a QGC mission) steers to each waypoint in turn, holds the pitch of each leg from its own
two ends, and starts each fly-by turn ``R tan(Δψ/2)`` before the waypoint.  A 4 mm leg whose ends
were rounded to 1 mm then reads up to 14° of pitch, and the heading noise of a near-duplicate
waypoint is a turn no vehicle makes.  :func:`helm_check` therefore judges every leg of the file as
given (issue 49):

* **shortest leg**: no leg is shorter than :func:`shortest_leg` (3D): 1 % of the turn radius
  (:data:`SHORTEST_LEG_FRACTION`, the plan check's merge distance), at least :data:`DUPLICATE_LEG_M`:
  shorter legs are degenerate (the rounding of their ends alone moves their pitch and heading by
  degrees).  A mission whose depth schedule was fitted to the pitch limit keeps its legs at least
  :data:`FITTED_LEG_M` (2.5 m) long, so that the rounding of exported coordinates (≤ 1.1 mm: 1 mm in
  the metric formats, 10⁻⁸° of latitude or longitude) moves no leg's pitch by more than
  ``atan(2.2 mm / 2.5 m)`` = 0.05° (the builder's :data:`~auvplan.path.flyable.PITCH_SLACK_DEG`);
* **pitch** of every leg from its own ends, ``atan(|Δz| / L)``;
* **turns** at every waypoint, ``R (tan(Δψ_k/2) + tan(Δψ_{k+1}/2)) <= L_k`` on the legs as given;
* the **depth rating** at every waypoint.

Violations use the vocabulary of :class:`~auvplan.path.flyable.LimitViolation` plus ``"min_leg_m"``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .flyable import LimitReport, LimitViolation, VehicleLimits, leg_pitch_deg, leg_turn_radius

__all__ = ["SHORTEST_LEG_FRACTION", "FITTED_LEG_M", "DUPLICATE_LEG_M", "WAYPOINTS_PER_KM", "shortest_leg", "helm_check",
           "waypoint_budget"]

SHORTEST_LEG_FRACTION = 0.01
"""Shortest leg of an exported mission as a fraction of the vehicle's turn radius (2 m for R = 200 m,
0.1 m for the 10 m default; :data:`auvplan.path.flyable.MERGE_FRACTION`: the plan check treats closer
vertices as one)."""
FITTED_LEG_M = 2.5
"""Shortest leg (3D, m) of a mission whose depth schedule was fitted to the pitch limit
(:func:`auvplan.guidance.mission.fit.fit_mission`): its legs climb at up to the limit less
:data:`~auvplan.path.flyable.PITCH_SLACK_DEG`, which the rounding of a leg of 2.5 m or more cannot use up."""
DUPLICATE_LEG_M = 0.01
"""Shortest leg (3D, m) of a point vehicle's mission: waypoints closer than this are duplicates."""
WAYPOINTS_PER_KM = 40.0
"""Waypoint budget of a mission built by auvplan: at most this many per km of its 3D length, plus
:data:`WAYPOINTS_FLOOR` (a short mission round obstacles may need a waypoint every 25 m)."""
WAYPOINTS_FLOOR = 100
"""Waypoints any mission may have whatever its length (the Figs. 7-8 scenes are 60 m long)."""


def shortest_leg(limits: VehicleLimits) -> float:
    """The shortest leg a mission for a vehicle with ``limits`` may have (module notes).

    Parameters
    ----------
    limits : VehicleLimits
        Pitch limit and turn radius.

    Returns
    -------
    float
        ``max(SHORTEST_LEG_FRACTION * turn_radius_m, DUPLICATE_LEG_M)`` (m).
    """
    return max(SHORTEST_LEG_FRACTION * limits.turn_radius_m, DUPLICATE_LEG_M)


def waypoint_budget(points: ArrayLike) -> int:
    """The most waypoints a mission of this length may have (:data:`WAYPOINTS_PER_KM`, :data:`WAYPOINTS_FLOOR`).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission (m).

    Returns
    -------
    int
        ``floor(WAYPOINTS_PER_KM * length_km) + WAYPOINTS_FLOOR``.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    length = float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) if len(p) > 1 else 0.0
    return int(WAYPOINTS_PER_KM * length / 1000.0) + WAYPOINTS_FLOOR


def helm_check(points: ArrayLike, limits: VehicleLimits, min_leg: float | None = None, pitch: ArrayLike | None = None,
               depth: ArrayLike | None = None) -> LimitReport:
    """Check every leg of a waypoint mission as given against the shortest leg and the vehicle's limits.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` mission (m, z up), e.g. read back from an exported file.
    limits : VehicleLimits
        Pitch limit, turn radius and depth rating.
    min_leg : float, optional
        Shortest leg allowed (m, 3D); :func:`shortest_leg` of ``limits`` by default.
    pitch, depth : array_like, optional
        ``(N - 1,)``: each leg's steepest pitch (degrees, absolute) and greatest depth (m) as its executor flies it,
        where that is not the straight leg between its ends (a leg following the seabed,
        :func:`auvplan.guidance.mission.terrain_legs.flown_pitch_depth`); by default the straight leg's.

    Returns
    -------
    LimitReport
        Largest pitch, tightest turn and greatest depth over the legs as given, and every violation
        by leg (``"min_leg_m"`` with the leg's length as its value).
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    if len(p) < 2:
        return LimitReport(0.0, -1, math.inf, -1, float(-p[:, 2].min()) if len(p) else 0.0, (), limits)
    shortest = shortest_leg(limits) if min_leg is None else float(min_leg)
    length = np.linalg.norm(np.diff(p, axis=0), axis=1)
    pitch = np.abs(leg_pitch_deg(p)) if pitch is None else np.asarray(pitch, dtype=float).reshape(len(p) - 1)
    radius = leg_turn_radius(p) if limits.turn_radius_m > 0.0 else np.full(len(p) - 1, math.inf)
    depth = -np.minimum(p[:-1, 2], p[1:, 2]) if depth is None else np.asarray(depth, dtype=float).reshape(len(p) - 1)
    tol = 1e-9
    bad: list[LimitViolation] = []
    for k in range(len(p) - 1):
        if length[k] < shortest * (1.0 - 1e-9):
            bad.append(LimitViolation(k, "min_leg_m", float(length[k]), shortest))
        if pitch[k] > limits.max_pitch_deg + tol:
            bad.append(LimitViolation(k, "max_pitch_deg", float(pitch[k]), limits.max_pitch_deg))
        if radius[k] < limits.turn_radius_m * (1.0 - tol):
            bad.append(LimitViolation(k, "turn_radius_m", float(radius[k]), limits.turn_radius_m))
        if depth[k] > limits.max_depth_m + tol:
            bad.append(LimitViolation(k, "max_depth_m", float(depth[k]), limits.max_depth_m))
    kp, kr = int(np.argmax(pitch)), int(np.argmin(radius))
    return LimitReport(float(pitch[kp]), kp, float(radius[kr]), kr if np.isfinite(radius[kr]) else -1,
                       float(depth.max()), tuple(bad), limits)
