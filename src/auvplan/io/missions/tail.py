"""Legs flown tail-first in the mission files: which formats carry them, how, and reading them back.

The time-optimal planner's ``tail_first`` legs (:mod:`auvplan.planners.timeopt.tail`) are flown heading
*against* the track while a current stronger than the vehicle carries it along (``PlanResult.tail``; the
route's flags: :func:`auvplan.sim.record_tail`).  A vehicle that flies such a leg nose-first arrives at
another time, or not at all, so a file leaves auvplan only in a format that says so:

* ``mission.csv`` — a column ``tail_first`` (1/0) for the leg that reaches each waypoint (the first leg's
  on the first row, as ``speed``);
* ``mission.geojson`` — the mission feature's property ``tail_first_legs`` (leg indices);
* ``mission.kml`` — the mission placemark's ``ExtendedData`` ``tail_first_legs`` (indices, space-separated);
* ``mission.yaml`` (``nav_msgs/Path``) — each pose is oriented along the leg it starts; on a tail-first
  leg it faces the other way (yaw + 180°), the heading the vehicle holds.

MOOS-IvP's ``BHV_Waypoint``, ArduSub's WPNav (QGroundControl ``.plan``) and GPX steer or describe every leg
nose-first: a mission with tail-first legs is not written in them (:func:`refusal` says why, naming the
legs).  A mission without such legs is written exactly as before in every format.
"""

from __future__ import annotations

import csv
import json
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...errors import DataError
from . import parsed

__all__ = ["TAIL_FORMATS", "any_tail", "refusal", "read_tail"]

TAIL_FORMATS = ("geojson", "kml", "csv", "yaml")
"""Export formats (:data:`auvplan.io.missions.export.EXPORT_FORMATS`) that carry tail-first legs."""

_WHY = {"moos": "MOOS-IvP's BHV_Waypoint steers every leg nose-first",
        "plan": "ArduSub's WPNav flies every leg nose-first along the 3D line",
        "gpx": "GPX has no way to say a leg is flown heading against it"}

_KML_NS = "http://www.opengis.net/kml/2.2"


def any_tail(tail: ArrayLike | None) -> bool:
    """Whether any leg is flown tail-first.

    Parameters
    ----------
    tail : array_like of bool or None
        Per-leg flags (None: no leg).

    Returns
    -------
    bool
        True when at least one flag is set.
    """
    return tail is not None and bool(np.any(np.asarray(tail, dtype=bool)))


def refusal(fmt: str, tail: ArrayLike) -> str:
    """Why ``mission.<fmt>`` is not written for a mission with tail-first legs (one line).

    Parameters
    ----------
    fmt : str
        An export format not in :data:`TAIL_FORMATS`.
    tail : array_like of bool
        ``(N - 1,)`` the mission's tail-first legs.

    Returns
    -------
    str
        The reason, naming the legs and the formats that carry them.
    """
    legs = np.flatnonzero(np.asarray(tail, dtype=bool))
    shown = ", ".join(str(int(i)) for i in legs[:8]) + (", …" if legs.size > 8 else "")
    return (f"mission.{fmt} not written: {_WHY.get(fmt, 'the format steers every leg nose-first')}, and leg"
            f"{'s' if legs.size > 1 else ''} {shown} of this mission {'are' if legs.size > 1 else 'is'} flown "
            f"tail-first (a current stronger than the vehicle carries it); use {', '.join(TAIL_FORMATS)}")


def _leg_indices(path: Path, raw: object, legs: int, spaced: bool = False) -> list[int]:
    """``tail_first_legs`` as leg indices: a list of integers ``0 <= i < legs`` (GeoJSON), or such integers
    separated by spaces (KML); anything else is a :class:`~auvplan.errors.DataError` naming the file, the key
    and the value (a string ``"0"`` or a number ``0.5`` is not read as leg 0)."""
    if spaced and isinstance(raw, str):  # KML: indices separated by spaces
        items: object = [int(t) if re.fullmatch(r"[0-9]{1,9}", t, re.ASCII) else t for t in raw.split()]
    else:
        items = raw
    if isinstance(items, list) and all(type(i) is int and 0 <= i < legs for i in items):
        return list(items)
    try:
        shown = repr(raw) if spaced else json.dumps(raw)  # as the file writes it
    except (ValueError, TypeError, RecursionError):
        shown = repr(raw)
    shown = shown if len(shown) <= 60 else shown[:57] + "..."  # (the first line of a long value)
    raise DataError(f"{path}: tail_first_legs = {shown} is not a list of leg indices (integers 0 to {legs - 1})")


def _yaw_of(q: dict[str, float]) -> float:
    x, y, z, w = (float(q[k]) for k in "xyzw")
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def read_tail(path: str | Path, legs: int) -> NDArray[np.bool_] | None:
    """The tail-first legs a mission file carries (module notes), or None.

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file (already readable by :func:`auvplan.io.missions.readback.readers.read_mission`).
    legs : int
        Its number of legs.

    Returns
    -------
    numpy.ndarray of bool or None
        ``(legs,)`` flags; None when the file has no tail-first leg or does not say.  (A ROS Path leg of
        1e-9 m or less has no direction and is never flagged.)

    Raises
    ------
    DataError
        ``tail_first_legs`` that is not a list of leg indices of this mission (named with the file and value).
    """
    import yaml

    path = Path(path)
    suffix = path.suffix.lower()
    flags = np.zeros(legs, dtype=bool)
    try:
        text = path.read_text(encoding="utf-8")
        if suffix == ".csv":
            rows = list(csv.DictReader(text.splitlines()))
            if not rows or "tail_first" not in rows[0] or len(rows) != legs + 1:
                return None
            flags = np.array([r["tail_first"].strip() == "1" for r in rows[1:]])
        elif suffix in (".geojson", ".json"):
            for f in parsed.loads(text).get("features", []):
                props = f.get("properties") or {}
                if props.get("name") == "mission":
                    flags[_leg_indices(path, props.get("tail_first_legs", []), legs)] = True
        elif suffix == ".kml":
            for pm in ET.fromstring(text).iter(f"{{{_KML_NS}}}Placemark"):
                if (pm.findtext(f"{{{_KML_NS}}}name") or "") == "mission":
                    for d in pm.iter(f"{{{_KML_NS}}}Data"):
                        if d.get("name") == "tail_first_legs":
                            flags[_leg_indices(path, d.findtext(f"{{{_KML_NS}}}value") or "", legs, True)] = True
        elif suffix in (".yaml", ".yml"):
            poses = yaml.safe_load(text)["poses"]
            if len(poses) != legs + 1:
                return None
            p = np.array([[float(ps["pose"]["position"][k]) for k in "xy"] for ps in poses])
            for i in range(legs):
                d = p[i + 1] - p[i]
                if math.hypot(*d) > 1e-9:
                    flags[i] = math.cos(_yaw_of(poses[i]["pose"]["orientation"]) - math.atan2(d[1], d[0])) < 0.0
        else:
            return None
    except DataError:
        raise
    except (OSError, ValueError, KeyError, TypeError, AttributeError, OverflowError, IndexError, RecursionError,
            ET.ParseError, yaml.YAMLError):
        return None
    return flags if flags.any() else None
