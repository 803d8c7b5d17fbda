"""The time a mission file waits at each of its waypoints, read back (``mission check``; ``docs/navigation.md``).

A surface fix needs the vehicle to wait ``[navigation] surface_s`` at the surface for its GPS fix.  The exports
carry that wait (:func:`auvplan.io.missions.formats.to_qgc_plan`, :func:`~auvplan.io.missions.formats.to_moos`):

- a QGroundControl ``.plan``: the surfacing's ``MAV_CMD_NAV_WAYPOINT`` param 1, its hold (whole seconds, 16 bits:
  :func:`~auvplan.io.missions.readback.speeds.read_holds` refuses what ArduPilot cannot store);
- a MOOS-IvP ``.bhv``: a ``BHV_StationKeep`` that runs when the waypoint behaviour heads on from the surfacing
  (``condition = WPT_INDEX = j``) for ``duration`` seconds, pausing the waypoint and depth behaviours
  (``DWELL = true``) while a ``BHV_ConstantDepth`` holds the surface.

Other formats carry no wait: the check takes ``surface_s`` from the scenario for them.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ....errors import DataError
from .parsers import _moos_blocks
from .speeds import read_holds

__all__ = ["read_dwells", "moos_dwells", "DWELL_FORMATS"]

DWELL_FORMATS = (".plan", ".moos", ".bhv")
"""File suffixes whose waits are read back from the file."""

_CONDITION = re.compile(r"WPT_INDEX\s*==?\s*(\d+)")


def moos_dwells(text: str, points: int, source: str = "MOOS file") -> NDArray[np.float64]:
    """The wait at each waypoint of a behaviour file written by :func:`~auvplan.io.missions.formats.to_moos`.

    Parameters
    ----------
    text : str
        The ``.bhv`` text.
    points : int
        Its number of waypoints as :func:`~auvplan.io.missions.readback.readers.parse_moos` reads them (the start
        first when the file has its ``// start:`` line).
    source : str, optional
        The file's name, for the messages.

    Returns
    -------
    numpy.ndarray
        ``(points,)`` seconds.

    Raises
    ------
    DataError
        For a ``BHV_StationKeep`` whose ``duration`` is not a number ≥ 0 or whose waypoint is not in the file.
    """
    shift = 0 if re.search(r"//\s*start:", text) else 1  # WPT_INDEX = j: heading on from the file's point j
    out = np.zeros(points)
    for kind, pairs in _moos_blocks(text):
        if kind != "BHV_StationKeep":
            continue
        d = dict(pairs)
        idx = [int(m.group(1)) for k, v in pairs if k == "condition" and (m := _CONDITION.fullmatch(v))]
        if not idx:
            continue
        try:
            wait = float(d.get("duration", "nan"))
        except ValueError:
            wait = float("nan")
        if not wait >= 0.0 or not np.isfinite(wait):
            raise DataError(f"{source}: BHV_StationKeep {d.get('name', '?')}: duration = {d.get('duration')!r}: "
                            "expected seconds ≥ 0")
        j = idx[0] - shift
        if not 0 <= j < points:
            raise DataError(f"{source}: BHV_StationKeep {d.get('name', '?')}: condition WPT_INDEX = {idx[0]}: "
                            f"no such waypoint ({points} in the file)")
        out[j] += wait
    return out


def read_dwells(path: str | Path, points: int) -> NDArray[np.float64] | None:
    """The wait at each waypoint of a mission file, for the formats that carry one (module notes).

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file (already read once by :func:`auvplan.io.missions.formats.read_mission`).
    points : int
        Its number of points as read (a ``.plan``'s home first).

    Returns
    -------
    numpy.ndarray or None
        ``(points,)`` seconds (zeros: the file waits nowhere); None for a format that carries no wait.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in DWELL_FORMATS:
        return None
    if suffix == ".plan":
        held = read_holds(path, points)
        return np.zeros(points) if held is None else held
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise DataError(f"{path}: cannot read ({exc})") from exc
    return moos_dwells(text, points, str(path))
