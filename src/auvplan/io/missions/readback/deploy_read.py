"""Reading back what makes a mission file deployable (issue 51) and checking it against the scenario
(``auvplan mission check``): the file's datum, its safety envelope and its payload events
(:mod:`auvplan.io.missions.deploy_formats` says where each format keeps them).

* **Datum** — a local-coordinate file (MOOS, ROS 2 YAML, CSV) whose datum differs from the scenario's
  ``[origin]`` by more than 1 cm is refused (:class:`~auvplan.errors.DataError`, exit 2): its metres would be
  placed elsewhere.  The CSV's datum is the origin its ``lat``/``lon`` columns put at x = y = 0
  (:func:`csv_datum`).  A file without a datum (written before issue 51) is read as before, and said so.
* **Envelope** — it must contain the mission: every leg inside the polygon and outside the exclusions,
  the deepest waypoint within ``max_depth``, the least re-flown altitude at or above ``min_altitude``, the
  predicted duration within ``max_time`` — the energy check's duration (through the current, with a ``.plan``'s
  launch leg and holds): the time-out is judged against what the mission will take.  A file that carries none is
  reported (``envelope: null``).
* **Fence storage** — a ``.plan``'s ``geoFence`` (every polygon and circle, as ArduPilot stores them) must fit its
  fence storage (:func:`auvplan.io.missions.deploy_formats.fence_storage_problem`, the export's own rule: 672
  bytes on a 16 KiB board), else ArduSub refuses the upload; only the export was held to it, and a user's own
  ``.plan`` with a fence of 84 vertices passed.
* **Mission storage** — a ``.plan``'s commands (the home included) and the smallest of AP_Mission's three
  capacities that holds them (:mod:`auvplan.io.missions.readback.mission_storage`): said, and a failure only when
  the operator names the board (``--board-storage``) and it cannot hold them.
* **Altitude legs** — counted as legs, as the terrain-following check counts them: a ``.plan``'s launch leg (home
  to its first item) is never one, even when that item is in the terrain frame.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from ....errors import DataError
from ...data.geo import LocalFrame
from ..deploy_formats import FENCE_STORAGE_BYTES, fence_bytes, fence_storage_problem
from .deploy_files import FileDeploy, csv_datum, read_deploy  # (re-exported)
from .mission_storage import BoardStorage, mission_storage
from .readers import MISSION_SUFFIXES

__all__ = ["FileDeploy", "read_deploy", "csv_datum", "check_deploy", "file_deploy_check", "DATUM_TOLERANCE_M"]

DATUM_TOLERANCE_M = 0.01
"""Largest distance (m) between a file's datum and the scenario's origin that is taken as the same datum."""


def check_deploy(path: str | Path, origin: tuple[float, float] | None, waypoints: NDArray[np.float64],
                 min_altitude_m: float, duration_s: float, board: BoardStorage | None = None) -> dict[str, Any]:
    """Check a file's datum against the scenario and its envelope against its mission (module notes).

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file.
    origin : tuple of float or None
        The scenario's ``[origin]``.
    waypoints : numpy.ndarray
        ``(N, 3)`` the file's mission in the scenario's local frame (m).
    min_altitude_m : float
        The least altitude of the mission re-flown under the file's semantics (m).
    duration_s : float
        The mission's predicted duration (s): through the current, with a ``.plan``'s launch leg and holds.
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a ``.plan`` it cannot hold fails.

    Returns
    -------
    dict
        ``datum`` (``lat``, ``lon``, ``offset_m``, or None), ``envelope`` (its limits and ``ok``, ``reasons``,
        or None), ``payload_events``, ``altitude_legs``, a ``.plan``'s ``fence_storage`` (``bytes``,
        ``limit_bytes``, ``ok``, ``reason``) and ``mission_storage``
        (:func:`~auvplan.io.missions.readback.mission_storage.mission_storage`), and ``ok``.

    Raises
    ------
    DataError
        When the file's datum differs from the scenario's origin (or the scenario has none).
    """
    info = read_deploy(path)
    out: dict[str, Any] = {"datum": None, "envelope": None, "altitude_legs": info.altitude_legs,
                           "payload_events": [{"waypoint": i, "sensor": "on" if on else "off"}
                                              for i, on in info.payload_events]}
    if info.datum is not None:
        if origin is None:
            raise DataError(f"{path}: the file's datum is lat {info.datum[0]:.9f}, lon {info.datum[1]:.9f} but the "
                            "scenario has no [origin]: its local coordinates cannot be placed")
        dx, dy = LocalFrame(*origin).forward(np.array([info.datum[1]]), np.array([info.datum[0]]))
        off = float(np.hypot(dx[0], dy[0]))
        if off > DATUM_TOLERANCE_M:
            raise DataError(f"{path}: datum lat {info.datum[0]:.9f}, lon {info.datum[1]:.9f} differs from the "
                            f"scenario's [origin] lat {origin[0]:.9f}, lon {origin[1]:.9f} ({off:.2f} m apart): its "
                            "local coordinates would be placed that far off")
        out["datum"] = {"lat": info.datum[0], "lon": info.datum[1], "offset_m": off}
    if info.polygon is not None:
        out["envelope"] = _envelope(info, origin, waypoints, min_altitude_m, duration_s,
                                    raw=Path(path).suffix.lower() == ".plan")
    elif info.datum is not None and MISSION_SUFFIXES.get(Path(path).suffix.lower()) in ("moos", "ros"):
        # written since issue 51 (it has a datum), in a format that carries an envelope, but without one
        out["envelope"] = {"ok": False, "vertices": 0, "exclusions": 0, "predicted_s": duration_s,
                           "reasons": ["the file has a datum but no envelope (BHV_OpRegion / envelope removed)"]}
    if info.fence_items is not None:  # a .plan's fence must fit ArduPilot's storage, else ArduSub refuses it
        vertices, circles = info.fence_items
        why = fence_storage_problem(vertices, circles)
        out["fence_storage"] = {"bytes": fence_bytes(vertices, circles), "limit_bytes": FENCE_STORAGE_BYTES,
                                "ok": why is None, "reason": why}
    if info.commands is not None:  # the mission storage a .plan needs (failing only on the board named)
        out["mission_storage"] = mission_storage(info.commands, board)
    out["ok"] = ((out["envelope"] is None or out["envelope"]["ok"]) and out.get("fence_storage", {}).get("ok", True)
                 and out.get("mission_storage", {}).get("ok", True))
    return out


def _envelope(info: FileDeploy, origin: tuple[float, float] | None, w: NDArray[np.float64], min_alt: float,
              duration: float, raw: bool = False) -> dict[str, Any]:
    """Whether the envelope contains the mission: legs in the polygon and off the exclusions, depth, altitude, time
    (``raw``: a ``.plan``'s fence, in ArduPilot's longitudes, :func:`_planar_latlon`)."""
    pts = w[:, :2]
    assert info.polygon is not None
    rings = [info.polygon, *info.inclusions, *info.exclusions]
    if info.geographic:  # [lat, lon] rings: compared in latitude/longitude, as ArduPilot's fence tests them
        if origin is None:
            raise DataError("a geographic envelope needs the scenario's [origin]")
        rings, pts = _planar_latlon(rings, pts, origin, raw)
    track = _track(pts, raw and info.geographic)
    reasons = []
    for k, ring in enumerate(rings[:1 + len(info.inclusions)]):  # inside every one (ArduPilot's default)
        region = shapely.Polygon(ring)
        if not region.covers(track):
            outside = int(np.sum(~shapely.covers(region, shapely.points(pts))))
            which = "the envelope's polygon" if k == 0 else f"the fence's inclusion {k + 1}"
            reasons.append(f"the mission leaves {which} ({outside} waypoints outside)")
    hit = [k for k, e in enumerate(rings[1 + len(info.inclusions):]) if shapely.Polygon(e).intersects(track)]
    if hit:
        reasons.append(f"the mission crosses exclusion polygon{'s' if len(hit) > 1 else ''} {hit}")
    lim = info.limits
    deepest = float(-w[:, 2].min())
    if "max_depth_m" in lim and deepest > lim["max_depth_m"] + 1e-3:
        reasons.append(f"deepest waypoint {deepest:.2f} m > max_depth {lim['max_depth_m']:g} m")
    if lim.get("min_altitude_m", 0) > 0 and min_alt < lim["min_altitude_m"] - 1e-3:
        reasons.append(f"least altitude {min_alt:.2f} m < min_altitude {lim['min_altitude_m']:g} m")
    if "max_time_s" in lim and not duration <= lim["max_time_s"]:  # never arriving (the energy check's nan/inf) too
        reasons.append(f"predicted duration {duration:.0f} s > max_time {lim['max_time_s']:g} s")
    return {**lim, "vertices": len(info.polygon), "exclusions": len(info.exclusions),
            "deepest_m": deepest, "predicted_s": duration, "ok": not reasons, "reasons": reasons}


def _track(pts: NDArray[np.float64], raw: bool) -> Any:
    """The mission's legs as one shapely geometry; in raw longitudes a leg across ±180° (flown the short way, as
    ArduPilot's ``Location::get_distance_NE`` does) is cut there into its two pieces."""
    if len(pts) < 2:
        return shapely.Point(pts[0])
    if not raw:
        return shapely.LineString(pts)
    pieces: list[list[tuple[float, float]]] = [[(float(pts[0, 0]), float(pts[0, 1]))]]
    for (x0, y0), (x1, y1) in zip(pts[:-1], pts[1:]):
        step = (x1 - x0 + 180.0) % 360.0 - 180.0  # the short way
        if abs(x0 + step) > 180.0:  # crosses the antimeridian: end at ±180, go on from ∓180
            edge = math.copysign(180.0, x0 + step)
            y = y0 + (y1 - y0) * (edge - x0) / step
            pieces[-1].append((edge, y))
            pieces.append([(-edge, y)])
        pieces[-1].append((float(x1), float(y1)))
    return shapely.MultiLineString([p for p in pieces if len(p) > 1])


def _planar_latlon(rings: list[Any], pts: NDArray[np.float64], origin: tuple[float, float], raw: bool = False
                   ) -> tuple[list[NDArray[np.float64]], NDArray[np.float64]]:
    """The envelope's ``[lat, lon]`` rings and the local points as ``(longitude, latitude)`` about the origin's
    longitude (unwrapped: a ring across the antimeridian, 179.99 and -179.99, is the small one, not the band round
    the Earth), where each edge is the straight line ArduPilot's fence tests (``Polygon_outside`` on latitude and
    longitude, ``AC_PolyFence_loader::breached``).  In the local frame (azimuthal) an edge is another line: a
    100 km edge at 68° N bows ~400 m from it, so a mission near a hand-drawn fence's side passed and breached.

    ``raw`` (a ``.plan``): ArduPilot tests its fence on the stored longitudes as they are (``Polygon_outside`` on
    the ``int32`` latitude and longitude, no wrap: ``AC_PolyFence_loader::breached``), so a ring with vertices at
    179.99 and -179.99 is the band round the other side of the Earth there, and is judged so; the points are
    wrapped into [-180, 180]."""
    lon0 = 0.0 if raw else float(origin[1])

    def unwrap(lon: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray((lon - lon0 + 180.0) % 360.0 - 180.0, dtype=float)

    lon, lat = LocalFrame(*origin).inverse(pts[:, 0], pts[:, 1])
    ring_lon = (lambda r: np.asarray(r, dtype=float)[:, 1]) if raw else (lambda r: unwrap(np.asarray(r)[:, 1]))
    return ([np.column_stack([ring_lon(r), np.asarray(r)[:, 0]]) for r in rings],
            np.column_stack([unwrap(np.asarray(lon)), np.asarray(lat)]))


def file_deploy_check(path: str | Path, origin: tuple[float, float] | None, points: NDArray[np.float64], fmt: str,
                      min_altitude_m: float, duration_s: float,
                      board: BoardStorage | None = None) -> tuple[dict[str, Any], str]:
    """:func:`check_deploy` of a file read by ``mission check`` and the result in one line.

    The envelope's time-out is judged against what the mission will really take: ``duration_s``, the energy
    check's duration (:func:`~auvplan.io.missions.energy.mission_file_energy`: through the current, a ``.plan``'s
    launch leg and its holds included), the same figure both lines print.

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file.
    origin : tuple of float or None
        The scenario's ``[origin]``.
    points : numpy.ndarray
        ``(N, 3)`` the file's waypoints (a QGC plan's surface home first).
    fmt : str
        Its format (:data:`auvplan.io.missions.readback.readers.MISSION_SUFFIXES`).
    min_altitude_m : float
        Its least re-flown altitude (m).
    duration_s : float
        The mission's duration as the energy check predicts it (s).
    board : BoardStorage, optional
        The operator's board (``--board-storage``), for a ``.plan``'s ``mission_storage``.

    Returns
    -------
    record : dict
        :func:`check_deploy`'s record.
    line : str
        ``datum …; envelope OK|FAIL|none …; payload …`` (a ``.plan``'s mission storage has its own line:
        :func:`~auvplan.io.missions.readback.mission_storage.storage_line`).
    """
    rec = check_deploy(path, origin, points, min_altitude_m, duration_s, board)
    d, e = rec["datum"], rec["envelope"]
    datum = (f"datum lat {d['lat']:.6f}, lon {d['lon']:.6f} = the scenario's ({d['offset_m'] * 1000:.1f} mm)" if d
             else ("geographic coordinates" if fmt in ("qgc", "gpx", "geojson", "kml") else "no datum in the file"))
    if e is None:
        env = "envelope: none in the file (the operator must add one)"
    else:
        env = (f"envelope {'OK' if e['ok'] else 'FAIL'} — polygon of {e['vertices']} vertices"
               + (f", {e['exclusions']} exclusions" if e["exclusions"] else "")
               + "".join(f", {k} {e[k]:g}" for k in ("max_depth_m", "min_altitude_m", "max_time_s") if k in e)
               + f" (predicted {e['predicted_s']:.0f} s)" + "".join(f"; {r}" for r in e["reasons"]))
    n = len(rec["payload_events"])
    pay = f"{n} payload events" if n else "no payload events"
    alt = f"; {rec['altitude_legs']} legs at altitude" if rec["altitude_legs"] else ""
    fence = rec.get("fence_storage")
    store = f"; geofence FAIL — {fence['reason']}" if fence and not fence["ok"] else ""
    return rec, f"{datum}; {env}; {pay}{alt}{store}"
