"""The datum, safety envelope, payload events and terrain-following altitude (:mod:`auvplan.io.missions.deploy`)
as each mission format carries them (issue 51; docs/missions.md "Hand it to the vehicle").

* **MOOS-IvP** (``mission.moos``): ``LatOrigin``/``LongOrigin`` — MOOS global parameters, found by every MOOS
  app's ``CMOOSFileReader::GetValue`` (the first ``name = value`` line of the file) — in a top-level brace block,
  which pHelmIvP's behaviour-file parser skips (``Populator_BehaviorSet::handleLine``: a ``{ ... }`` block at
  top level is ignored).  ``BHV_OpRegion`` (``polygon``, ``max_depth``, ``min_altitude``, ``max_time``, and its
  ``breached_poly_flag``/``breached_depth_flag``/``breached_altitude_flag``/``breached_time_flag`` set
  ``ABORT = true``; a breach also makes the helm all-stop).  Every mission behaviour runs while
  ``ABORT = false`` and ``RETURN = false``; the waypoint behaviour's ``endflag`` sets ``RETURN = true`` and
  ``MISSION_COMPLETE = true`` at the last point, after which no behaviour runs (the helm all-stops).  Payload:
  ``PAYLOAD = on|off`` posted by the ``runflag`` of the leg where it switches (``initialize PAYLOAD = off``, the
  waypoint ``endflag`` turns it off).  Terrain following: one ``BHV_MinAltitudeX`` per leg (``min_altitude``:
  depth ≤ water depth − altitude from the altimeter) beside the leg's ``BHV_ConstantDepth``, the bound; never above
  the leg's least charted altitude at its held depth (``DeployInfo.leg_floor``), so that over the chart it never
  lifts the vehicle off the depths ``mission check`` judged — only a seabed shallower than charted does.
* **QGroundControl** (``mission.plan``): ``geoFence.polygons`` — one ``inclusion: true`` polygon (the bounds)
  and one ``inclusion: false`` per exclusion, within ArduPilot's fence storage (:data:`FENCE_STORAGE_BYTES`;
  exclusions that do not fit are simplified inside their land, :func:`fence_exclusions`); terrain-following
  items in ``MAV_FRAME_GLOBAL_TERRAIN_ALT`` (10,
  QGC ``AltitudeMode`` 4 = ``AltitudeModeTerrainFrame``) with the altitude above the seabed; payload
  ``MAV_CMD_DO_SET_RELAY`` (181; relay 0, 1 = on, 0 = off) after the waypoint where it switches.
* **ROS 2 YAML**: top-level ``datum: {lat, lon}``, ``envelope`` and ``payload_events``.
* **GeoJSON / KML**: an ``envelope`` polygon (and ``exclusion`` polygons) with ``max_depth_m``,
  ``min_altitude_m``, ``max_time_s``; the mission's ``payload_on_legs`` and ``payload_events``.
* **CSV**: an ``altitude`` column (terrain following) and a ``payload`` column (1: the sensor is on from this
  waypoint to the next).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...errors import DataError
from ..data.geo import LocalFrame
from .deploy import DeployInfo, Envelope, payload_events

__all__ = ["moos_datum", "moos_envelope", "moos_leg_extras", "qgc_geofence", "qgc_relay", "yaml_extras",
           "geo_ring", "mission_props", "envelope_props", "envelope_rings", "fence_bytes", "fence_storage_problem",
           "fence_exclusions", "ALTITUDE_PWT", "RELAY", "FENCE_STORAGE_BYTES"]

ALTITUDE_PWT = 200
"""Priority weight of the terrain-following altitude behaviour (above the depth bound's 100)."""
RELAY = 181
"""MAVLink ``MAV_CMD_DO_SET_RELAY``: param1 relay instance, param2 setting (1 on, 0 off)."""
FENCE_STORAGE_BYTES = 672
"""ArduSub's fence storage on a board with 16 KiB or more (a Pixhawk): its ``StorageFence`` areas of 160 + 256 +
256 bytes (``StorageManager.cpp``, the layout of every vehicle but Copter; ``max_items()`` = 672 / 8 = 84, "84
fence points on Pixhawk").  ``AC_PolyFence_loader::write_fence`` refuses a fence whose
``fence_storage_space_required`` exceeds it ("Fence exceeds storage size"): 4 bytes of header, per polygon 1
type + 1 count byte and 8 per vertex, and the end-of-storage byte after them (:func:`fence_bytes`) — one polygon
of at most 83 vertices.  (``BRD_SD_FENCE`` can move it to an SD card; the default is kept.)"""


def moos_datum(origin: tuple[float, float] | None) -> list[str]:
    """The datum block at the top of ``mission.moos`` (empty without an origin).

    Parameters
    ----------
    origin : tuple of float or None
        ``(lat, lon)`` (degrees).

    Returns
    -------
    list of str
        The lines.
    """
    if origin is None:
        return []
    return ["// datum: MOOS global parameters (every MOOS app reads them with CMOOSFileReader::GetValue);",
            "// the braces make pHelmIvP's behaviour-file parser skip them",
            "{", f"  LatOrigin  = {origin[0]:.9f}", f"  LongOrigin = {origin[1]:.9f}", "}", ""]


def moos_envelope(env: Envelope | None, name: str) -> list[str]:
    """The ``BHV_OpRegion`` block of the envelope (convex polygon: the bounds rectangle).

    Parameters
    ----------
    env : Envelope or None
        The envelope (None: no block).
    name : str
        Mission name (the behaviour's name prefix).

    Returns
    -------
    list of str
        The lines.
    """
    if env is None:
        return []
    poly = ":".join(f"{x:.3f},{y:.3f}" for x, y in env.polygon)
    lines = ["", "Behavior = BHV_OpRegion", "{", f"  name                   = {name}_opregion",
             "  pwt                    = 100",
             "  condition              = DEPLOY = true", f"  polygon                = {poly}",
             f"  max_depth              = {env.max_depth_m:.3f}"]
    if env.min_altitude_m > 0:
        lines.append(f"  min_altitude           = {env.min_altitude_m:.3f}")
    lines += [f"  max_time               = {env.max_time_s:.1f}   "
              f"// {env.timeout_factor:g} x the predicted {env.predicted_s:.0f} s",
              "  trigger_exit_time      = 1",
              "  breached_poly_flag     = ABORT = true", "  breached_depth_flag    = ABORT = true",
              "  breached_altitude_flag = ABORT = true", "  breached_time_flag     = ABORT = true", "}"]
    return lines


def moos_leg_extras(deploy: DeployInfo | None, leg: int) -> tuple[list[str], list[str]]:
    """Lines inside leg ``leg``'s depth behaviour (payload runflag) and the blocks after it (altitude).

    Parameters
    ----------
    deploy : DeployInfo or None
        Payload and altitudes.
    leg : int
        The leg (``WPT_INDEX``).

    Returns
    -------
    inside : list of str
        Lines for the depth behaviour's body.
    after : list of str
        The ``BHV_MinAltitudeX`` block of a terrain-following leg.
    """
    if deploy is None:
        return [], []
    inside: list[str] = []
    if deploy.payload is not None:
        on = dict(payload_events(deploy.payload))
        if leg in on:
            inside.append(f"  runflag   = PAYLOAD = {'on' if on[leg] else 'off'}")
    after: list[str] = []
    if deploy.altitude is not None:
        a = min(deploy.follow_altitude_m or np.inf, float(deploy.altitude[leg]), float(deploy.altitude[leg + 1]),
                np.inf if deploy.leg_floor is None else float(deploy.leg_floor[leg]))  # never above the checked leg
        after = ["", "Behavior = BHV_MinAltitudeX", "{", f"  name         = altitude_{leg}",
                 f"  pwt          = {ALTITUDE_PWT}", "  condition    = DEPLOY = true",
                 f"  condition    = WPT_INDEX = {leg}", "  condition    = RETURN = false",
                 "  condition    = ABORT = false", f"  min_altitude = {max(a, 0.0):.3f}", "}"]
    return inside, after


def geo_ring(frame: LocalFrame, poly: tuple[tuple[float, float], ...], per_edge: int = 8) -> NDArray[np.float64]:
    """The lat, lon ring of a local polygon, each edge divided in ``per_edge`` (so the geographic polygon
    follows the local one closely), not closed.

    Parameters
    ----------
    frame : LocalFrame
        The local frame.
    poly : tuple of (float, float)
        Local vertices (m).
    per_edge : int, optional
        Pieces per edge.

    Returns
    -------
    numpy.ndarray
        ``(M, 2)`` lat, lon (degrees).
    """
    p = np.asarray(poly, dtype=float)
    q = np.roll(p, -1, axis=0)
    s = np.arange(per_edge) / per_edge
    pts = (p[:, None, :] + s[None, :, None] * (q - p)[:, None, :]).reshape(-1, 2)
    lon, lat = frame.inverse(pts[:, 0], pts[:, 1])
    return np.column_stack([lat, lon])


def _refuse_antimeridian(ring: NDArray[np.float64], what: str) -> None:
    """Refuse a fence ring across ±180° longitude: ArduPilot tests its fence on the stored latitude and longitude as a
    plane (``Polygon_outside`` in ``AC_PolyFence_loader::breached``, no wrap), so it would read the region round the
    other side of the Earth; several inclusions are intersected by default (``FENCE_OPTIONS``), so no split holds."""
    lon = np.asarray(ring, dtype=float)[:, 1]
    if lon.size and float(np.max(np.abs(np.diff(np.r_[lon, lon[:1]])))) > 180.0:
        raise DataError(f"QGC plan: {what} crosses ±180° longitude (from {lon.min():.6f} to {lon.max():.6f}): "
                        "ArduPilot tests a fence in latitude/longitude degrees without wrapping "
                        "(AC_PolyFence_loader::breached) and would read the region round the other side of the "
                        "Earth; no .plan geofence can hold it")


def fence_bytes(vertices: list[int], circles: int = 0) -> int:
    """Bytes of ArduPilot's fence storage that polygons and circles take (``AC_PolyFence_loader``,
    :data:`FENCE_STORAGE_BYTES`).

    Parameters
    ----------
    vertices : list of int
        Each polygon's number of vertices.
    circles : int, default 0
        Circles (a ``.plan``'s ``geoFence.circles``): 1 type byte, 4 + 4 of latitude and longitude and 4 of radius.

    Returns
    -------
    int
        4 (header) + Σ (2 + 8 n) + 13 per circle + 1 (end of storage: ``fence_storage_space_required`` leaves it
        out, but ``write_fence`` writes it after the fence and ``scan_eeprom`` reads the fence back up to it).
    """
    return 4 + sum(2 + 8 * int(n) for n in vertices) + 13 * int(circles) + 1


def fence_storage_problem(vertices: list[int], circles: int = 0) -> str | None:
    """Why ArduPilot would refuse to store a fence (:func:`fence_bytes` over :data:`FENCE_STORAGE_BYTES`), or None.

    Parameters
    ----------
    vertices : list of int
        Each polygon's number of vertices.
    circles : int, default 0
        Circles.

    Returns
    -------
    str or None
        One clause naming the bytes and the limit, None when it fits.
    """
    need = fence_bytes(vertices, circles)
    if need <= FENCE_STORAGE_BYTES:
        return None
    what = f"{len(vertices)} polygons of {sum(vertices)} vertices" + (f" and {circles} circles" if circles else "")
    return (f"the geofence ({what}) takes {need} bytes of fence storage with its end-of-storage byte, more than the "
            f"{FENCE_STORAGE_BYTES} bytes of ArduPilot's (a 16 KiB board; one polygon of at most "
            f"{(FENCE_STORAGE_BYTES - 7) // 8} vertices): ArduSub cannot store it (AC_PolyFence_loader::write_fence: "
            "\"Fence exceeds storage size\", or the end-of-storage marker past the storage)")


def fence_exclusions(exclusions: tuple[tuple[tuple[float, float], ...], ...],
                     budget: int) -> tuple[tuple[tuple[float, float], ...], ...]:
    """Exclusion polygons that fit in ``budget`` bytes of fence storage, each inside the one it stands for.

    When they do not fit as they are, ears are clipped (a convex vertex whose triangle holds no other vertex of its
    polygon is removed: the polygon stays simple and loses that triangle, so it stays inside the land it stands
    for, and the fence never fires where the mission may go), always the ear of least area over all the polygons,
    until they fit; a polygon down to a triangle is dropped whole when its area is the least to lose.  This is
    Visvalingam-Whyatt's simplification, restricted to the removals that only shrink.

    Parameters
    ----------
    exclusions : tuple of polygons
        ``(x, y)`` vertices in the local frame (m), not closed.
    budget : int
        Bytes left for them (each polygon takes 2 + 8 n).

    Returns
    -------
    tuple of polygons
        ``exclusions`` when they fit, else their clipped polygons, in the same order (those dropped left out).
    """
    if fence_bytes([len(e) for e in exclusions]) - 5 <= budget:
        return exclusions
    rings = [_ccw(np.asarray(e, dtype=float)) for e in exclusions if len(e) >= 3]
    best = [_least_ear(v) for v in rings]
    used = sum(2 + 8 * len(v) for v in rings)
    while used > budget:
        k = min((k for k in range(len(rings)) if rings[k].size), key=lambda k: best[k][0])
        i = best[k][1]
        if i < 0:  # a triangle (or no ear left): the whole polygon goes
            used -= 2 + 8 * len(rings[k])
            rings[k] = rings[k][:0]
            continue
        rings[k] = np.delete(rings[k], i, axis=0)
        used -= 8
        best[k] = _least_ear(rings[k])
    return tuple(tuple((float(x), float(y)) for x, y in v) for v in rings if v.size)


def _ccw(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """A ring counter-clockwise, without repeated consecutive vertices."""
    v = v[np.any(v != np.roll(v, 1, axis=0), axis=1)] if len(v) > 1 else v
    area = 0.5 * float(np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]))
    return v if area >= 0 else v[::-1].copy()


def _least_ear(v: NDArray[np.float64]) -> tuple[float, int]:
    """The ear of ``v`` (counter-clockwise) of least area, as ``(area, index)``; ``(area of v, -1)`` for a triangle
    or a polygon without an ear to clip (then it is only ever dropped whole)."""
    n = len(v)
    whole = 0.5 * abs(float(np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1])))
    if n <= 3:
        return whole, -1
    a, c = np.roll(v, 1, axis=0), np.roll(v, -1, axis=0)
    area = 0.5 * ((v[:, 0] - a[:, 0]) * (c[:, 1] - v[:, 1]) - (v[:, 1] - a[:, 1]) * (c[:, 0] - v[:, 0]))
    for i in np.argsort(area):
        if area[i] < 0:  # reflex: removing it would add area outside the land
            continue
        p, q, r = v[i - 1], v[i], v[(i + 1) % n]
        others = np.delete(v, [(i - 1) % n, i, (i + 1) % n], axis=0)
        if not np.any((_left(p, q, others) >= 0) & (_left(q, r, others) >= 0) & (_left(r, p, others) >= 0)):
            return float(area[i]), int(i)
    return whole, -1


def _left(s: NDArray[np.float64], t: NDArray[np.float64], pts: NDArray[np.float64]) -> NDArray[np.float64]:
    """Twice the signed area of (s, t, each point): positive on the left of s → t."""
    return np.asarray((t[0] - s[0]) * (pts[:, 1] - s[1]) - (t[1] - s[1]) * (pts[:, 0] - s[0]))


def qgc_geofence(deploy: DeployInfo | None, frame: LocalFrame) -> dict[str, Any]:
    """The ``geoFence`` of a QGC plan: the bounds as inclusion, the exclusions (version 2).

    Parameters
    ----------
    deploy : DeployInfo or None
        The envelope (None: an empty fence).
    frame : LocalFrame
        The local frame.

    Returns
    -------
    dict
        ``{"circles": [], "polygons": [...], "version": 2}``.
    """
    polys: list[dict[str, Any]] = []
    env = deploy.envelope if deploy is not None else None
    if env is not None:
        inclusion = geo_ring(frame, env.polygon, 8)
        need = fence_bytes([len(inclusion)])
        if need > FENCE_STORAGE_BYTES:  # the operating region itself: never cut (it would fire inside it)
            raise DataError(f"QGC plan: the geofence's inclusion polygon has {len(inclusion)} vertices ({need} bytes); "
                            f"ArduPilot's fence storage holds {FENCE_STORAGE_BYTES} bytes, one polygon of at most "
                            f"{(FENCE_STORAGE_BYTES - 7) // 8} vertices (AC_PolyFence_loader::write_fence)")
        exclusions = fence_exclusions(env.exclusions, FENCE_STORAGE_BYTES - need)
        for poly, inc in [(env.polygon, True), *((e, False) for e in exclusions)]:
            ring = inclusion if inc else geo_ring(frame, poly, 1)
            _refuse_antimeridian(ring, "the envelope's polygon" if inc else f"exclusion {len(polys)}")
            polys.append({"inclusion": inc, "polygon": [[round(float(a), 9), round(float(b), 9)] for a, b in ring],
                          "version": 1})
    return {"circles": [], "polygons": polys, "version": 2}


def qgc_relay(on: bool, jump: int) -> dict[str, Any]:
    """A ``MAV_CMD_DO_SET_RELAY`` item switching the payload (relay 0).

    Parameters
    ----------
    on : bool
        Switch on (1) or off (0).
    jump : int
        Its ``doJumpId``.

    Returns
    -------
    dict
        The plan item.
    """
    return {"type": "SimpleItem", "autoContinue": True, "command": RELAY, "doJumpId": jump, "frame": 2,
            "params": [0, 1 if on else 0, 0, 0, 0, 0, 0]}


def yaml_extras(deploy: DeployInfo | None) -> list[str]:
    """Top-level ``datum``, ``envelope`` and ``payload_events`` of the ROS 2 YAML.

    Parameters
    ----------
    deploy : DeployInfo or None
        What to write (None: nothing).

    Returns
    -------
    list of str
        The lines.
    """
    if deploy is None:
        return []
    lines = []
    if deploy.origin is not None:
        lines.append(f"datum: {{lat: {deploy.origin[0]:.9f}, lon: {deploy.origin[1]:.9f}}}")
    env = deploy.envelope
    if env is not None:
        poly = ", ".join(f"[{x:.3f}, {y:.3f}]" for x, y in env.polygon)
        lines.append(f"envelope: {{polygon: [{poly}], max_depth_m: {env.max_depth_m:.3f}, "
                     f"min_altitude_m: {env.min_altitude_m:.3f}, max_time_s: {env.max_time_s:.1f}, "
                     f"predicted_s: {env.predicted_s:.1f}, timeout_factor: {env.timeout_factor:g}}}")
    if deploy.payload is not None:
        ev = ", ".join(f"{{waypoint: {i}, sensor: {'true' if on else 'false'}}}" for i, on in
                       payload_events(deploy.payload))
        lines.append(f"payload_events: [{ev}]")
    return lines


def mission_props(deploy: DeployInfo | None) -> dict[str, Any]:
    """Properties of the GeoJSON mission feature (and KML ``ExtendedData``): datum, payload, altitudes.

    Parameters
    ----------
    deploy : DeployInfo or None
        What to write (None: nothing).

    Returns
    -------
    dict
        ``datum``, ``payload_on_legs``, ``payload_events``, ``altitude_m`` where known.
    """
    if deploy is None:
        return {}
    out: dict[str, Any] = {}
    if deploy.origin is not None:
        out["datum"] = {"lat": deploy.origin[0], "lon": deploy.origin[1]}
    if deploy.payload is not None:
        out["payload_on_legs"] = [int(i) for i in np.flatnonzero(deploy.payload)]
        out["payload_events"] = [{"waypoint": i, "sensor": "on" if on else "off"}
                                 for i, on in payload_events(deploy.payload)]
    if deploy.altitude is not None:
        out["altitude_m"] = [round(float(a), 3) for a in deploy.altitude]
    return out


def envelope_props(env: Envelope) -> dict[str, Any]:
    """The envelope's limits as GeoJSON properties / KML ``ExtendedData``.

    Parameters
    ----------
    env : Envelope
        The envelope.

    Returns
    -------
    dict
        ``name``, ``max_depth_m``, ``min_altitude_m``, ``max_time_s``, ``predicted_duration_s``, ``timeout_factor``.
    """
    return {"name": "envelope", "max_depth_m": round(env.max_depth_m, 3),
            "min_altitude_m": round(env.min_altitude_m, 3),
            "max_time_s": env.max_time_s, "predicted_duration_s": round(env.predicted_s, 1),
            "timeout_factor": env.timeout_factor}


def envelope_rings(deploy: DeployInfo | None, frame: LocalFrame) -> list[tuple[str, NDArray[np.float64]]]:
    """The lat/lon rings of the envelope and its exclusions (not closed).

    Parameters
    ----------
    deploy : DeployInfo or None
        The envelope (None: no ring).
    frame : LocalFrame
        The local frame.

    Returns
    -------
    list of (str, numpy.ndarray)
        ``("envelope" | "exclusion", (M, 2) lat, lon)``.
    """
    env = deploy.envelope if deploy is not None else None
    if env is None:
        return []
    return [("envelope", geo_ring(frame, env.polygon)), *(("exclusion", geo_ring(frame, e, 1)) for e in env.exclusions)]
