"""A waypoint mission re-flown under its executor's depth semantics (:data:`SEMANTICS`: the depth held per leg,
or ramped along it; :mod:`auvplan.guidance.mission.waypoints`): every leg's least altitude, obstacle contacts
and distance (:func:`leg_figures`, :func:`segment_figures`), the track of a vehicle holding depths
(:func:`held_track`) and the whole check (:func:`fly_check` → :class:`MissionCheck`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...geometry import as_points, point_segment_distance
from ...world import World
from .envelopes import envelope_corners, envelope_hits, rect_distance
from .limits import WaypointLimits, WaypointLimitsDict, waypoint_limits

__all__ = ["SEMANTICS", "MissionCheck", "MissionCheckDict", "fly_check", "held_track", "leg_figures",
           "segment_figures"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""

SEMANTICS = ("held", "ramp")
"""Depth semantics of a waypoint executor: depth held per leg (MOOS-IvP) or ramped along it."""


class MissionCheckDict(TypedDict):
    """JSON form of a :class:`MissionCheck` (:meth:`MissionCheck.as_dict`); lengths in m, angles in degrees.

    Attributes
    ----------
    semantics : str
        ``"held"`` or ``"ramp"``.
    ok : bool
        Whether the mission keeps the altitude and obstacle margins.
    min_altitude_m, required_altitude_m, min_obstacle_distance_m, obstacle_margin_m : float
        As in :class:`MissionCheck`.
    min_altitude_leg : int or None
        The leg of the least altitude; None (JSON ``null``) when no leg was measured (no seabed in the scenario).
    obstacle_hits, legs, executor_obstacle_hits : int
        As in :class:`MissionCheck`; ``legs`` the number of legs.
    pitch_deg, executor_min_altitude_m : float
        The executor model's pitch and least altitude.
    limits : WaypointLimitsDict or None
        The waypoints above the surface, outside the depth band or outside the bounds
        (:class:`~auvplan.guidance.mission.limits.WaypointLimits`).
    """

    semantics: str
    ok: bool
    min_altitude_m: float
    min_altitude_leg: int | None
    required_altitude_m: float
    min_obstacle_distance_m: float
    obstacle_hits: int
    obstacle_margin_m: float
    legs: int
    pitch_deg: float
    executor_min_altitude_m: float
    executor_obstacle_hits: int
    limits: WaypointLimitsDict | None


@dataclass(frozen=True, eq=False)
class MissionCheck:
    """A waypoint mission re-flown under an executor's depth semantics (static world only).

    Attributes
    ----------
    semantics : str
        ``"held"`` or ``"ramp"``.
    min_altitude_m : float
        Least altitude above the seabed over every leg (exact; ``inf`` without terrain).
    min_altitude_leg : int
        Leg where it occurs (-1 without legs or terrain).
    min_obstacle_distance_m : float
        Least distance to a static obstacle surface (``inf`` without one within 200 m of an envelope).
    obstacle_hits : int
        Legs whose swept region comes within the obstacle margin of an obstacle (exact test).
    leg_altitude_m : ndarray (K,)
        Least altitude per leg.
    required_altitude_m, obstacle_margin_m : float
        The world's margins.
    pitch_deg : float
        Pitch of the depth changes of the executor model (``"held"``; ``nan`` when not flown).
    executor_min_altitude_m : float
        ``"held"``: least altitude of a vehicle that steers towards each leg's depth at
        ``pitch_deg`` from wherever the previous leg left it (exact, on its polyline track);
        ``inf`` when not flown.
    executor_obstacle_hits : int
        Segments of that track within the obstacle margin of an obstacle.
    limits : WaypointLimits or None
        The sea surface, the depth band and the bounds at every waypoint (:func:`fly_check` sets it).
    """

    semantics: str
    min_altitude_m: float
    min_altitude_leg: int
    min_obstacle_distance_m: float
    obstacle_hits: int
    leg_altitude_m: _F64
    required_altitude_m: float
    obstacle_margin_m: float
    pitch_deg: float = float("nan")
    executor_min_altitude_m: float = float("inf")
    executor_obstacle_hits: int = 0
    limits: WaypointLimits | None = None

    @property
    def ok(self) -> bool:
        """True when the least altitude (envelope and executor) is at least the required one, no
        leg meets an obstacle and every waypoint keeps the surface, depth band and bounds."""
        alt = min(self.min_altitude_m, self.executor_min_altitude_m)
        return alt >= self.required_altitude_m - 1e-6 and self.obstacle_hits == 0 and self.executor_obstacle_hits == 0 \
            and (self.limits is None or self.limits.ok)

    def as_dict(self) -> MissionCheckDict:
        """Summarise the check as plain JSON.

        Returns
        -------
        MissionCheckDict
            The scalar attributes, ``ok`` and the number of legs.
        """
        return {"semantics": self.semantics, "ok": self.ok, "min_altitude_m": self.min_altitude_m,
                "min_altitude_leg": self.min_altitude_leg if self.min_altitude_leg >= 0 else None,
                "required_altitude_m": self.required_altitude_m,
                "min_obstacle_distance_m": self.min_obstacle_distance_m, "obstacle_hits": self.obstacle_hits,
                "obstacle_margin_m": self.obstacle_margin_m, "legs": int(self.leg_altitude_m.size),
                "pitch_deg": self.pitch_deg, "executor_min_altitude_m": self.executor_min_altitude_m,
                "executor_obstacle_hits": self.executor_obstacle_hits,
                "limits": None if self.limits is None else self.limits.as_dict()}


def held_track(waypoints: ArrayLike, pitch_deg: float) -> _F64:
    """Return the track of a vehicle flying ``waypoints`` with depth held per leg (MOOS-IvP).

    On leg i it changes depth towards that of point i + 1 at ``pitch_deg`` (a straight climb or
    dive) and then holds it; a change not finished at the end of a leg carries on into the next.

    Parameters
    ----------
    waypoints : array_like
        ``(N, 3)`` waypoints (m).
    pitch_deg : float
        Pitch angle of the depth changes (degrees).

    Returns
    -------
    numpy.ndarray
        ``(M, 3)`` polyline track (m), with a corner where each depth change ends.
    """
    w = as_points(waypoints).reshape(-1, 3)
    slope = math.tan(math.radians(min(float(pitch_deg), 89.99)))
    out = [w[0]]
    z = float(w[0, 2])
    for a, b in zip(w[:-1], w[1:]):
        length = float(np.hypot(*(b[:2] - a[:2])))
        need = abs(float(b[2]) - z) / slope
        if 0.0 < need < length:  # the change ends inside the leg: a corner there
            f = need / length
            out.append(np.r_[a[:2] + f * (b[:2] - a[:2]), b[2]])
            z = float(b[2])
        elif need > 0.0:
            z += math.copysign(length * slope, float(b[2]) - z)
        out.append(np.r_[b[:2], z])
    return np.vstack(out)


def leg_figures(world: World, a: ArrayLike, b: ArrayLike, semantics: str = "held") -> tuple[_F64, NDArray[np.bool_],
                                                                                          _F64]:
    """Check each leg ``a -> b`` on its own, as :func:`fly_check` does: each leg's figures depend on its
    two ends only, so a mission edited at a few waypoints needs only its changed legs re-checked.

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    a, b : array_like
        ``(K, 3)`` leg starts and ends (m).
    semantics : {'held', 'ramp'}, optional
        ``"held"``: the leg's envelope; ``"ramp"``: the straight 3D leg.

    Returns
    -------
    altitude : numpy.ndarray
        ``(K,)`` least altitude above the seabed (m; ``inf`` without terrain).
    hits : numpy.ndarray
        ``(K,)`` bool, the leg comes within the obstacle margin of a static obstacle.
    distance : numpy.ndarray
        ``(K,)`` least distance to a static obstacle's surface (m; ``inf`` without one within 200 m).
    """
    a, b = as_points(a).reshape(-1, 3), as_points(b).reshape(-1, 3)
    m = world.margins
    if semantics == "held":
        fa, fb = a.copy(), b.copy()
        fa[:, 2] = fb[:, 2] = np.minimum(a[:, 2], b[:, 2])
        o, e1, e2 = envelope_corners(a, b)
    else:
        fa, fb = a, b
        o, e1, e2 = a, b - a, np.zeros_like(a)
    alt = world.terrain.min_altitude_between(fa, fb) if world.terrain is not None and len(a) else \
        np.full(len(a), np.inf)
    dist = np.full(len(a), np.inf)
    hits = np.zeros(len(a), dtype=bool)
    for shape in world.obstacles:
        if not len(a):
            break
        hits |= shape.segments_hit(np.stack([a, b], axis=1), m.obstacle) if semantics == "ramp" else \
            envelope_hits(shape, a, b, m.obstacle)
        near = point_segment_distance(np.asarray(shape.center), o, o + e1) - shape.bounding_radius \
            < 200.0 + np.linalg.norm(e2, axis=-1)
        if not near.any():
            continue
        d = rect_distance(shape, o[near], e1[near], e2[near])
        dist[near] = np.minimum(dist[near], d)
    return np.asarray(alt, dtype=float), hits, dist


def segment_figures(world: World, a: ArrayLike, b: ArrayLike) -> tuple[_F64, NDArray[np.int64]]:
    """Least altitude and obstacle contacts of each straight segment ``a -> b`` (an executor's track).

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    a, b : array_like
        ``(K, 3)`` segment starts and ends (m).

    Returns
    -------
    altitude : numpy.ndarray
        ``(K,)`` least altitude above the seabed (m; ``inf`` without terrain).
    hits : numpy.ndarray
        ``(K,)`` number of static obstacles each segment comes within the obstacle margin of.
    """
    a, b = as_points(a).reshape(-1, 3), as_points(b).reshape(-1, 3)
    seg = np.stack([a, b], axis=1)
    alt = world.terrain.segment_min_altitude(seg) if world.terrain is not None and len(a) else \
        np.full(len(a), np.inf)
    hits = np.zeros(len(a), dtype=np.int64)
    for sh in world.obstacles:
        if len(a):
            hits += sh.segments_hit(seg, world.margins.obstacle).astype(np.int64)
    return np.asarray(alt, dtype=float), hits


def fly_check(world: World, waypoints: ArrayLike, semantics: str = "held", pitch_deg: float = 15.0,
              launch: bool = False) -> MissionCheck:
    """Re-fly ``waypoints (N, 3)`` under ``semantics`` against the seabed and static obstacles.

    ``"held"``: on each leg the vehicle lies anywhere between the depths of its two ends (the
    envelope; altitude of the flat leg at the deeper end), and the executor model
    (:func:`held_track` at ``pitch_deg``) is flown too, since a vehicle still changing depth when
    a leg ends is outside the next leg's envelope.  ``"ramp"``: on the straight 3D leg.
    Altitudes are exact (:meth:`Terrain.segment_min_altitude`); obstacle contact is the exact
    rectangle / segment test; obstacle distances are exact for spheres and sampled every 0.25 m
    near ellipsoids.  The sea surface, the depth band and the bounds are tested at every waypoint
    (:func:`~auvplan.guidance.mission.limits.waypoint_limits`: convex, so the ends decide each leg).

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    waypoints : array_like
        ``(N, 3)`` mission waypoints (m).
    semantics : {'held', 'ramp'}, optional
        The executor's depth semantics.
    pitch_deg : float, optional
        Pitch of the executor model's depth changes (degrees, in (0, 90]; ``"held"`` only).
    launch : bool, optional
        Waypoint 0 is a launch point on the surface (a QGroundControl ``.plan``'s home): exempt
        from the depth band.

    Returns
    -------
    MissionCheck
        Least altitudes, obstacle distance and hits, and the waypoints' limits.

    Raises
    ------
    ValueError
        For an unknown semantics, a pitch outside (0, 90] or fewer than two waypoints.
    """
    if semantics not in SEMANTICS:
        raise ValueError(f"semantics = {semantics!r}: choose one of {SEMANTICS}")
    if not 0.0 < pitch_deg <= 90.0:
        raise ValueError(f"pitch_deg = {pitch_deg}: must be in (0, 90] degrees")
    w = as_points(waypoints).reshape(-1, 3)
    m = world.margins
    if len(w) < 2:
        raise ValueError(f"a mission needs at least 2 waypoints (a start and a goal), got {len(w)}")
    limits = waypoint_limits(world, w, launch)
    alt, hits, leg_dist = leg_figures(world, w[:-1], w[1:], semantics)
    dist = float(leg_dist.min()) if leg_dist.size else np.inf
    k = int(np.argmin(alt)) if np.isfinite(alt).any() else -1
    extra: dict[str, float | int] = {}
    if semantics == "held":
        trk = held_track(w, pitch_deg)
        seg_alt, seg_hits = segment_figures(world, trk[:-1], trk[1:])
        ex_alt = float(seg_alt.min()) if world.terrain is not None else np.inf
        extra = {"pitch_deg": float(pitch_deg), "executor_min_altitude_m": ex_alt,
                 "executor_obstacle_hits": int(seg_hits.sum())}
    return MissionCheck(semantics, float(alt.min()), k, dist, int(hits.sum()), alt, m.min_altitude, m.obstacle,
                        limits=limits, **extra)  # type: ignore[arg-type]
