"""What makes an exported mission deployable (issue 51): its datum, its safety envelope, its payload events
and the altitude of its terrain-following legs, built once from the World and Mission and written by
every format that can carry them (:mod:`auvplan.io.missions.deploy_formats`; read back by
:mod:`auvplan.io.missions.readback.deploy_read`).

* **Datum** — the geodetic origin ``(lat, lon)`` of the local frame (WGS 84, pyproj's azimuthal
  equidistant about it: :class:`auvplan.io.data.geo.LocalFrame`).
* **Envelope** — the operating region: the polygon of the world's ``[bounds]`` (x/y), the deepest depth the
  mission may reach (``[mission] max_depth_m`` clipped to the vehicle's rating), the least altitude above
  the seabed (``[mission] min_altitude_m``), the exclusion polygons of the ``[land]`` inside the bounds, and
  a time-out: the predicted duration × :data:`TIMEOUT_FACTOR`, the duration the mission is flown in
  (:func:`predicted_duration`: its launch's dive from the surface, its legs through the World's current at their
  speeds, every wait at a surface fix), never the still-water time of the legs alone (:func:`mission_timeout`: the
  one figure every format's time-out is).
* **Payload** — one flag per leg: the sensor is on while the vehicle flies a survey line (legs joining two
  vertices of the same line), off on turns and transits; the events are the legs where it switches.
* **Altitude** — with ``[mission] follow_altitude_m``, every leg is terrain-following: the planned altitude
  above the chart's seabed at each waypoint, flown by the vehicle's altimeter where the format can say so,
  with the planned depth schedule as the bound (never deeper than planned).
* **Planned times** — the arrival at each waypoint at the planned speed (one, or one per leg) after the waits
  before it, through the World's current (:func:`flown_times`; :func:`planned_times` in still water, the fallback,
  :func:`leg_speeds`): the stamps of every format (re-exported by :mod:`auvplan.io.missions.formats`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from ...sim import Mission
from ...world import World

__all__ = ["ROUNDED_RISE_M", "TIMEOUT_FACTOR", "Envelope", "DeployInfo", "deploy_info", "payload_from_labels",
           "payload_events", "planned_times", "leg_speeds", "predicted_duration", "mission_timeout", "flown_times"]

TIMEOUT_FACTOR = 1.5
"""Mission time-out = predicted duration × this factor (the helm's ``max_time``; the envelope's ``max_time_s``)."""


@dataclass(frozen=True)
class Envelope:
    """The operating region of a mission (local frame, m; s).

    Attributes
    ----------
    polygon : tuple of (float, float)
        Counter-clockwise vertices of the region (the ``[bounds]`` rectangle), not closed.
    max_depth_m : float
        Deepest depth allowed (m below the surface).
    min_altitude_m : float
        Least altitude above the seabed (m); 0: none.
    max_time_s : float
        Time-out (s): ``predicted_s × timeout_factor``.
    predicted_s : float
        The mission's predicted duration (s).
    timeout_factor : float
        The factor of the time-out.
    exclusions : tuple of polygons
        Each a tuple of ``(x, y)`` vertices (land inside the bounds, simplified, never touching the mission).
    """

    polygon: tuple[tuple[float, float], ...]
    max_depth_m: float
    min_altitude_m: float
    max_time_s: float
    predicted_s: float
    timeout_factor: float = TIMEOUT_FACTOR
    exclusions: tuple[tuple[tuple[float, float], ...], ...] = ()

    def contains(self, xy: ArrayLike) -> NDArray[np.bool_]:
        """Whether each point lies in the region and outside every exclusion.

        Parameters
        ----------
        xy : array_like
            ``(N, 2)`` points (m).

        Returns
        -------
        numpy.ndarray of bool
            ``(N,)``; points on the boundary count as inside.
        """
        p = shapely.points(np.asarray(xy, dtype=float)[:, :2])
        ok = shapely.covers(shapely.Polygon(self.polygon), p)
        for ex in self.exclusions:
            ok &= ~shapely.intersects(shapely.Polygon(ex), p)
        return np.asarray(ok, dtype=bool)


@dataclass(frozen=True)
class DeployInfo:
    """What the exports carry beside the waypoints (module notes).

    Attributes
    ----------
    origin : tuple of float or None
        Datum ``(lat, lon)`` (degrees).
    envelope : Envelope or None
        The operating region.
    payload : numpy.ndarray of bool or None
        ``(N - 1,)`` the sensor is on during leg i; None: the mission has no payload events.
    altitude : numpy.ndarray or None
        ``(N,)`` planned altitude above the chart's seabed at each waypoint (m) when the legs are
        terrain-following; None otherwise.
    follow_altitude_m : float
        The target altitude of terrain following (m; 0: off).
    terrain_items : numpy.ndarray of bool or None
        ``(N,)`` with ``altitude``: the waypoints a QGroundControl plan writes in the terrain frame, so that ArduSub
        follows the seabed on the leg into them — those where that flight keeps the vehicle's pitch limit
        (:func:`auvplan.guidance.mission.terrain_legs.flown_pitch_depth`); the others at their planned depth, whose
        straight leg the fitted mission keeps within it.  None: every waypoint with an altitude.
    leg_floor : numpy.ndarray or None
        ``(N - 1,)`` with ``altitude``: each leg's least altitude on the chart at its held depth (the leg's envelope,
        :func:`auvplan.guidance.mission.flycheck.leg_figures`), the most a MOOS ``BHV_MinAltitudeX`` may ask for:
        a floor above it would lift the vehicle off the depth ``mission check`` judged wherever the charted seabed
        rises between two waypoints.  None: no bound beyond the waypoints' altitudes.
    times_s : numpy.ndarray or None
        ``(N,)`` the planned arrival at each waypoint as flown (:func:`flown_times`; s from the first): the ``.csv``
        times and the ``.yaml`` stamps.  None: at the planned speeds in still water.
    """

    origin: tuple[float, float] | None
    envelope: Envelope | None = None
    payload: NDArray[np.bool_] | None = None
    altitude: NDArray[np.float64] | None = None
    follow_altitude_m: float = 0.0
    terrain_items: NDArray[np.bool_] | None = None
    leg_floor: NDArray[np.float64] | None = None
    times_s: NDArray[np.float64] | None = None


def planned_times(waypoints: ArrayLike, speed: float | ArrayLike,
                  dwell: ArrayLike | None = None) -> NDArray[np.float64]:
    """Compute the planned arrival time at each waypoint at ``speed`` along the 3D legs, after the waits at the
    waypoints before it.

    Parameters
    ----------
    waypoints : array_like
        ``(N, 3)`` waypoints (m).
    speed : float or array_like
        Planned speed (m/s), one for all legs or ``(N - 1,)`` one per leg.
    dwell : array_like, optional
        ``(N,)`` the wait at each waypoint (s; a surface fix's ``surface_s``, :attr:`auvplan.nav.NavPlan.dwell_s`):
        a waypoint is reached after the waits of those before it (its own follows its arrival).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` times (s), 0 at the first point.
    """
    w = np.asarray(waypoints, dtype=float)
    legs = np.linalg.norm(np.diff(w, axis=0), axis=1)
    times: NDArray[np.float64] = np.r_[0.0, np.cumsum(legs / leg_speeds(speed, legs.size))]
    if dwell is not None:
        d = np.asarray(dwell, dtype=float).reshape(-1)
        if d.shape != times.shape:
            raise ValueError(f"dwell: one wait per waypoint ({times.size}), got {d.size}")
        times = times + np.r_[0.0, np.cumsum(d[:-1])]
    return times


def predicted_duration(world: World, waypoints: ArrayLike, speed: float | ArrayLike, dwell: ArrayLike | None = None,
                       tail: ArrayLike | None = None) -> float:
    """The time a mission takes as it is flown (s): launched at the surface above its first waypoint, the dive to it
    (a vertical leg at :data:`~auvplan.nav.budget.LAUNCH_DIVE_MPS` held over the point), then each leg through the
    World's current at its speed, every wait at a waypoint (a surface fix's ``surface_s``) included — the flight the
    navigation budget and the fixes' times count (:func:`auvplan.sim.navigation.launch_flight`).

    Parameters
    ----------
    world : World
        Its currents.
    waypoints : array_like
        ``(N, 3)`` the mission (m).
    speed : float or array_like
        Planned through-water speed, one or one per leg (m/s).
    dwell : array_like, optional
        ``(N,)`` the wait at each waypoint (s); the last one's is after the mission (it is recovered there).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first.

    Returns
    -------
    float
        The duration from the launch to the arrival at the last waypoint (s).  Where the current beats the vehicle
        (the energy check refuses the mission) the legs and the dive at their speeds in still water, the waits
        included.
    """
    from ...nav.budget import LAUNCH_DIVE_MPS
    from ...sim.navigation import launch_flight

    w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
    if len(w) < 2:
        return 0.0
    v = leg_speeds(speed, len(w) - 1)
    back = None if tail is None or np.asarray(tail).size != len(w) - 1 else tail
    flown = launch_flight(world, w, v, back, dwell)
    if flown is not None:
        return float(flown.dive_s + flown.times_s[-1])
    return float(max(-w[0, 2], 0.0) / LAUNCH_DIVE_MPS + planned_times(w, v, dwell)[-1])


def flown_times(world: World, mission: Mission, waypoints: ArrayLike, speed: float | ArrayLike,
                dwell: ArrayLike | None = None, tail: ArrayLike | None = None) -> NDArray[np.float64] | None:
    """The arrival at each waypoint as the mission is flown through the World's current at each leg's speed, the waits
    counted (s from the arrival at the first): with ``[navigation]`` the legs flown once the launch's dive is over
    (:func:`auvplan.sim.navigation.launch_flight`: the fixes' times, ``fixes.csv``'s), without it from the scenario's
    start time (the energy budget's flight, ``legs.csv``'s, and the closed loop's).

    Parameters
    ----------
    world : World
        Its currents.
    mission : Mission
        Its ``navigation``.
    waypoints : array_like
        ``(N, 3)`` the mission (m).
    speed : float or array_like
        Planned through-water speed, one or one per leg (m/s).
    dwell : array_like, optional
        ``(N,)`` the wait at each waypoint (s).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first.

    Returns
    -------
    numpy.ndarray or None
        ``(N,)`` (s); None where the current beats the vehicle.
    """
    from ...endurance import traverse
    from ...sim.navigation import launch_flight

    w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
    if len(w) < 2:
        return None
    v = leg_speeds(speed, len(w) - 1)
    back = None if tail is None or np.asarray(tail).size != len(w) - 1 else tail
    if mission.navigation is not None:
        flown = launch_flight(world, w, v, back, dwell)
        if flown is not None:
            return np.asarray(flown.times_s, dtype=float)
    tr = traverse(world, w, v, 0.0, tail=back, dwell=dwell)
    return np.asarray(tr.times - tr.times[0], dtype=float) if tr.ok else None


def mission_timeout(predicted_s: float) -> float:
    """The time-out every format carries (the MOOS helm's ``max_time``, the envelope's ``max_time_s``): the predicted
    duration (:func:`predicted_duration`, or a longer simulated flight) × :data:`TIMEOUT_FACTOR`, to 0.1 s.

    Parameters
    ----------
    predicted_s : float
        The mission's predicted duration (s).

    Returns
    -------
    float
        The time-out (s).
    """
    return round(float(predicted_s) * TIMEOUT_FACTOR, 1)


def leg_speeds(speed: float | ArrayLike, legs: int) -> NDArray[np.float64]:
    """One planned speed per leg: ``speed`` repeated, or the ``(legs,)`` speeds given (issue 38).

    Parameters
    ----------
    speed : float or array_like
        One speed for all legs or one per leg (m/s).
    legs : int
        Number of legs.

    Returns
    -------
    numpy.ndarray
        ``(legs,)`` speeds (m/s).

    Raises
    ------
    ValueError
        When per-leg speeds do not match the legs.
    """
    v = np.asarray(speed, dtype=float)
    if v.ndim and v.size != legs:
        raise ValueError(f"{v.size} leg speeds for {legs} legs")
    return np.broadcast_to(v, (legs,)).astype(float)


def payload_from_labels(labels: ArrayLike) -> NDArray[np.bool_]:
    """The sensor state of each leg of a survey route: on along a line, off on turns and transits.

    Parameters
    ----------
    labels : array_like of int
        ``(N,)`` line number of each route vertex, negative for turns and transits
        (:class:`auvplan.survey.mission.SurveyPlan`).

    Returns
    -------
    numpy.ndarray of bool
        ``(N - 1,)`` True where leg i joins two vertices of the same line.
    """
    lab = np.asarray(labels, dtype=np.int64)
    return np.asarray((lab[:-1] == lab[1:]) & (lab[:-1] >= 0), dtype=bool)


def payload_events(payload: ArrayLike) -> list[tuple[int, bool]]:
    """The switching events of per-leg sensor states: ``(waypoint, on)`` at each change, the sensor off
    before the first leg and after the last.

    Parameters
    ----------
    payload : array_like of bool
        ``(N - 1,)`` sensor state per leg.

    Returns
    -------
    list of (int, bool)
        The waypoint index where the state changes and the new state.
    """
    p = np.r_[False, np.asarray(payload, dtype=bool), False]
    return [(int(i), bool(p[i + 1])) for i in np.flatnonzero(p[1:] != p[:-1])]


def _exclusions(world: World, box: shapely.Polygon,
                mission: shapely.Geometry) -> tuple[tuple[tuple[float, float], ...], ...]:
    """Land inside the bounds as exclusion polygons, simplified (≤ ~1 % of the box's side) but never
    touching the mission's track (the tolerance is lowered until it does not, down to the exact land)."""
    if world.land is None:
        return ()
    land = shapely.intersection(world.land.geometry, box)
    if land.is_empty:
        return ()
    side = max(box.bounds[2] - box.bounds[0], box.bounds[3] - box.bounds[1])
    tol = 0.01 * side
    while True:
        g = shapely.simplify(land, tol, preserve_topology=True) if tol > 0 else land
        if tol <= 0 or not shapely.intersects(g, mission):
            break
        tol = tol / 4 if tol > 0.5 else 0.0
    polys = [p for p in getattr(g, "geoms", [g]) if isinstance(p, shapely.Polygon) and not p.is_empty]
    return tuple(tuple((float(x), float(y)) for x, y in list(p.exterior.coords)[:-1]) for p in polys)


def deploy_info(world: World, mission: Mission, waypoints: ArrayLike, speed: float | ArrayLike,
                flown_s: float | None = None, payload: ArrayLike | None = None, dwell: ArrayLike | None = None,
                tail: ArrayLike | None = None) -> DeployInfo:
    """The datum, envelope, payload and altitudes of a mission (module notes).

    Parameters
    ----------
    world : World
        Bounds, seabed, land, margins and origin.
    mission : Mission
        The vehicle's depth rating and ``follow_altitude_m``.
    waypoints : array_like
        ``(N, 3)`` the mission (m).
    speed : float or array_like
        Planned speed, or one per leg (m/s).
    flown_s : float, optional
        Duration of the simulated flight (s): the prediction is the longer of it and :func:`predicted_duration`.
    payload : array_like of bool, optional
        ``(N - 1,)`` sensor state per leg (:func:`payload_from_labels`).
    dwell : array_like, optional
        ``(N,)`` the wait at each waypoint (s; a surface fix's ``surface_s``): the predicted duration counts it.
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first.

    Returns
    -------
    DeployInfo
        What the exports carry.
    """
    w = np.asarray(waypoints, dtype=float)
    b = world.bounds
    poly = ((b.xmin, b.ymin), (b.xmax, b.ymin), (b.xmax, b.ymax), (b.xmin, b.ymax))
    predicted = predicted_duration(world, w, speed, dwell, tail)
    if flown_s is not None and np.isfinite(flown_s):
        predicted = max(predicted, float(flown_s))
    depth = world.margins.max_depth if np.isfinite(world.margins.max_depth) else mission.vehicle.max_depth_m
    track = shapely.LineString(w[:, :2]) if len(w) > 1 else shapely.Point(w[0, :2])
    env = Envelope(tuple((float(x), float(y)) for x, y in poly), float(depth), float(world.margins.min_altitude),
                   mission_timeout(predicted), predicted, TIMEOUT_FACTOR,
                   _exclusions(world, shapely.Polygon(poly), track))
    altitude = items = floor = None
    if mission.follow_altitude_m > 0 and world.terrain is not None:
        from ...guidance.mission.flycheck import leg_figures

        altitude = w[:, 2] - np.asarray(world.seabed(w[:, 0], w[:, 1]), dtype=float)
        items = _terrain_items(world, w, mission.vehicle.max_pitch_deg)
        floor = leg_figures(world, w[:-1], w[1:], "held")[0] if len(w) > 1 else np.zeros(0)
    pay = None if payload is None or not np.any(payload) else np.asarray(payload, dtype=bool)
    times = flown_times(world, mission, w, speed, dwell, tail)
    return DeployInfo(world.origin, env, pay, altitude, float(mission.follow_altitude_m), items, floor, times)


ROUNDED_RISE_M = 1.5e-3
"""The most the writing of a terrain-frame leg can change its rise along it: the ``.plan`` carries each item's
altitude to the millimetre (0.5 mm at each end) and its position to 1e-9 degree (0.1 mm, whose seabed under a 4:1
slope moves 0.5 mm); a leg followed within the pitch limit only by less is written at its planned depth."""


def _followed_free(world: World, w: NDArray[np.float64], track: NDArray[np.float64],
                   leg: NDArray[np.intp]) -> NDArray[np.bool_]:
    """Per leg: its seabed-following track (``track``, its segments' legs ``leg``) keeps every limit ``mission
    check`` judges it by (the seabed, static obstacles, the surface, the depth band, the bounds and the zones), as
    the straight leg the fit made does."""
    from ...guidance.mission.flycheck import leg_figures
    from ...guidance.mission.limits import waypoint_limits

    alt, bad, _ = leg_figures(world, track[:-1], track[1:], "ramp")
    bad |= alt < world.margins.min_altitude
    lim = waypoint_limits(world, track)
    vertices = np.array([*lim.above_surface, *lim.outside_depth_band, *lim.outside_bounds], dtype=np.intp)
    bad[vertices[vertices > 0] - 1] = True  # vertex v ends segment v - 1
    if world.zones:
        bad[world.zones.exact.entries(np.stack([track[:-1], track[1:]], axis=1))[0]] = True
    free = np.ones(len(w) - 1, dtype=bool)
    free[leg[bad]] = False
    return free


def _terrain_items(world: World, w: NDArray[np.float64], max_pitch_deg: float) -> NDArray[np.bool_]:
    """The waypoints whose leg in can be flown following the seabed within the pitch limit once written
    (:data:`ROUNDED_RISE_M` over the leg's length on its steepest tangent; the first: the launch leg, never
    followed) and clear of everything its straight leg is (:func:`_followed_free`: over a bump the straight leg
    passes 20 m above, the track climbs with the seabed, out of the depth band or into a zone); a leg already as
    steep as a straight line keeps the terrain frame; a waypoint within :data:`ROUNDED_RISE_M` of the depth
    band's edges (the surface, ``min_depth_m``, ``max_depth_m``) keeps its depth."""
    from ...guidance.mission.terrain_legs import flown_track
    from ...path.flyable import leg_pitch_deg

    assert world.terrain is not None
    items = np.ones(len(w), dtype=bool)
    if len(w) > 1:
        flown = flown_track(world.terrain, w, np.ones(len(w) - 1, dtype=bool))  # every leg followed, once
        pitch = flown.pitch
        with np.errstate(divide="ignore"):
            rounded = np.degrees(np.arctan(np.tan(np.radians(pitch)) + ROUNDED_RISE_M /
                                           np.hypot(*np.diff(w[:, :2], axis=0).T)))
        items[1:] = ((rounded <= max_pitch_deg + 1e-9) | (pitch <= np.abs(leg_pitch_deg(w)) + 1e-9)) & \
            _followed_free(world, w, flown.track, flown.leg)
    # a waypoint on an edge of the depth band (a surface fix, a leg at the deepest allowed) keeps its depth: an
    # altitude to the millimetre over the seabed at the rounded position reads back a fraction of a millimetre
    # above the surface or below max_depth_m, and a surface fix is no altitude an altimeter holds
    m = world.margins
    items &= (w[:, 2] < -max(m.min_depth, 0.0) - ROUNDED_RISE_M) & (w[:, 2] > -m.max_depth + ROUNDED_RISE_M)
    return items
