"""Reading mission files back: the parsers of every format :mod:`auvplan.io.missions.formats` writes (one per format,
:mod:`.parsers`), and the check that re-flies a file against a World (``auvplan mission check``).

:func:`read_mission` parses any of them (format from the suffix) back to local waypoints and their depth
semantics (``"held"`` for MOOS-IvP, ``"ramp"`` for the others); :func:`check_mission_file` re-flies them.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ....errors import DataError
from ....guidance.mission.flycheck import MissionCheck, fly_check
from ....guidance.mission.terrain_legs import FlownTrack, check_as_flown
from ....world import World
from ...data.geo import LocalFrame
from ...files.jsonfile import read_bounded_text
from .. import parsed
from .parsers import (
    GPX_NS,
    KML_NS,
    ZERO_ALT_M,
    ZERO_LATLON_DEG,
    _csv_mission,
    _geojson_mission,
    _kml_mission,
    csv_columns,
    parse_gpx,
    parse_moos,
    parse_qgc_plan,
    parse_ros_path,
)

__all__ = [
    "MAX_MISSION_BYTES",
    "MAX_MISSION_WAYPOINTS",
    "csv_columns",
    "MISSION_SUFFIXES",
    "GPX_NS",
    "KML_NS",
    "parse_moos",
    "parse_qgc_plan",
    "parse_gpx",
    "parse_ros_path",
    "read_mission",
    "check_mission_file",
    "ZERO_ALT_M",
    "ZERO_LATLON_DEG",
]

MAX_MISSION_BYTES = 256 * 1024 * 1024
"""Largest mission file ``mission check`` reads (a 200 km mission at full resolution is a few MB)."""


MISSION_SUFFIXES = {".moos": "moos", ".bhv": "moos", ".plan": "qgc", ".gpx": "gpx", ".yaml": "ros", ".yml": "ros",
                    ".geojson": "geojson", ".json": "geojson", ".kml": "kml", ".csv": "csv"}
"""File suffix → format read by :func:`read_mission`."""


# ---------------------------------------------------------------------- reading and checking
def read_mission(path: str | Path, origin: tuple[float, float] | None = None,
                 seabed: Callable[[Any, Any], Any] | None = None) -> tuple[NDArray[np.float64], str, str]:
    """Read a mission file (format from the suffix).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    origin : tuple of float, optional
        ``(lat, lon)`` of the local frame (degrees); needed by the geographic formats.
    seabed : callable, optional
        ``seabed(x, y)`` (m): places a QGC plan's terrain-frame items (:func:`parse_qgc_plan`).

    Returns
    -------
    waypoints : numpy.ndarray
        ``(N, 3)`` waypoints in the local frame (m).
    semantics : str
        The format's depth semantics, ``"held"`` or ``"ramp"``.
    format : str
        The format's name.

    Raises
    ------
    DataError
        Naming the file when it cannot be read.
    """
    path = Path(path)
    fmt = MISSION_SUFFIXES.get(path.suffix.lower())
    if path.is_dir():  # was "unknown mission format ''" (hostile round 20)
        raise DataError(f"{path}: a folder, not a mission file; name the file (e.g. {path / 'mission.plan'})")
    if fmt is None:
        raise DataError(f"{path}: unknown mission format {path.suffix!r}; "
                        f"expected one of {', '.join(sorted(MISSION_SUFFIXES))}")
    if fmt in ("qgc", "gpx", "geojson", "kml") and origin is None:
        raise DataError(f"{path}: a {fmt} mission is geographic: the scenario needs an [origin]")
    text = read_bounded_text(path, MAX_MISSION_BYTES, "a mission file")
    frame = LocalFrame(*origin) if origin is not None else None
    waypoints, semantics = _parse(path, fmt, text, frame, seabed)
    if len(waypoints) > MAX_MISSION_WAYPOINTS:  # 10⁶ .plan items were checked for 110-210 s, 5·10⁵ KML points 44 s
        raise DataError(f"{path}: {len(waypoints):,} waypoints, over the {MAX_MISSION_WAYPOINTS:,} a mission file may "
                        "have (a vehicle's mission holds hundreds to thousands)")
    size = np.nan_to_num(np.abs(np.atleast_2d(waypoints)), nan=0.0).max(axis=-1, initial=0.0)
    if (size > MAX_WAYPOINT_M).any():  # 1e300 used to leak numpy's overflow warnings and an 'inf m mission'
        k = int(np.argmax(size > MAX_WAYPOINT_M))
        raise DataError(f"{path}: waypoint {k} = ({', '.join(f'{v:.6g}' for v in waypoints[k])}) m lies over "
                        f"{MAX_WAYPOINT_M:g} m (the Earth's circumference) from the origin")
    return waypoints, semantics, fmt


MAX_WAYPOINT_M = 4.0e7
"""Largest coordinate of a waypoint in the local frame (m): beyond it the arithmetic of a leg overflows."""
MAX_MISSION_WAYPOINTS = 100_000
"""Most waypoints a mission file may have: every check walks them in Python (a .plan of 10⁵ items: 25 s)."""


def _parse(path: Path, fmt: str, text: str, frame: LocalFrame | None,
           seabed: Callable[[Any, Any], Any] | None) -> tuple[NDArray[np.float64], str]:
    """:func:`read_mission`'s parsing of ``text`` in the format ``fmt``: waypoints and depth semantics."""
    try:
        if fmt == "moos":
            return parse_moos(text), "held"
        if fmt == "ros":
            return parse_ros_path(text), "ramp"
        if fmt == "csv":
            return _csv_mission(text), "ramp"
        assert frame is not None  # the geographic formats need an origin (checked above)
        if fmt == "gpx":
            return parse_gpx(text, frame), "ramp"
        if fmt == "kml":
            return _kml_mission(text, frame), "ramp"
        doc = parsed.loads(text)
        return (parse_qgc_plan(doc, frame, seabed) if fmt == "qgc" else _geojson_mission(doc, frame)), "ramp"
    except DataError as exc:
        raise DataError(f"{path}: {exc}") from exc
    except RecursionError:
        raise DataError(f"{path}: nested too deeply for a {fmt} mission") from None
    except (ValueError, KeyError, TypeError, AttributeError, OverflowError, IndexError) as exc:
        raise DataError(f"{path}: not a readable {fmt} mission ({' '.join(str(exc).split())[:200]})") from exc


def check_mission_file(path: str | Path, world: World, pitch_deg: float = 15.0,
                       follow: NDArray[np.bool_] | None = None, flown: FlownTrack | None = None
                       ) -> tuple[MissionCheck, str]:
    """Re-fly a mission file under its format's depth semantics (:func:`auvplan.guidance.mission.flycheck.fly_check`).

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file.
    world : World
        Seabed, static obstacles and margins (its origin for geographic formats).
    pitch_deg : float, optional
        Pitch at which held depths change (degrees).
    follow : numpy.ndarray of bool, optional
        A ``.plan``'s legs flown following the seabed (:func:`auvplan.io.missions.readback.terrain_frame.terrain_legs`):
        measured on that track (:func:`auvplan.guidance.mission.terrain_legs.check_as_flown`).
    flown : FlownTrack, optional
        That track (:func:`auvplan.guidance.mission.terrain_legs.flown_track` of the file's waypoints and
        ``follow``), when the caller has it.

    Returns
    -------
    check : MissionCheck
        Least altitudes, obstacle distance and hits.
    format : str
        The file's format.

    Raises
    ------
    DataError
        Naming the file when it cannot be read, has a non-finite waypoint or fewer than 2.
    """
    waypoints, semantics, fmt = read_mission(path, world.origin, world.seabed if world.terrain is not None else None)
    if not np.isfinite(waypoints).all():
        raise DataError(f"{path}: the mission has a waypoint that is not finite")
    if len(waypoints) < 2:
        raise DataError(f"{path}: the mission has {len(waypoints)} waypoint{'' if len(waypoints) == 1 else 's'}; "
                        "at least 2 are needed (a start and a goal)")
    if follow is not None and follow.any():
        if semantics != "ramp" or follow.size != len(waypoints) - 1:
            raise ValueError(f"follow: {follow.size} flags for a {semantics} mission of {len(waypoints)} waypoints")
        return check_as_flown(world, waypoints, follow, launch=fmt == "qgc", flown=flown), fmt
    return fly_check(world, waypoints, semantics, pitch_deg, launch=fmt == "qgc"), fmt
