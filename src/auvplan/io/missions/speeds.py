"""The speed of each leg a mission file carries (issue 38), read back for ``auvplan mission check``.

The legs are those of :func:`auvplan.io.missions.formats.read_mission`'s waypoints:

* MOOS (``.moos``/``.bhv``): leg i's ``runflag = WPT_UPDATE = speed=v`` in the depth behaviour of
  ``WPT_INDEX = i``, else the waypoint behaviour's ``speed`` (the deploy point is waypoint 0, so leg
  0 of the file's points is leg 0 here);
* QGroundControl (``.plan``): home → first item at ``cruiseSpeed``, then each
  ``MAV_CMD_DO_CHANGE_SPEED`` (178) sets the speed of the legs after it;
* CSV: the ``speed`` column, row i (i ≥ 1) the leg that reaches it.

Other formats carry no speed (None).
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...errors import DataError
from .qgc_items import PlanItem, plan_items
from .readers import csv_columns

__all__ = ["read_leg_speeds"]


def _moos(text: str, legs: int) -> list[float] | None:
    text = re.sub(r"//[^\n]*", "", text)
    base = re.search(r"Behavior\s*=\s*BHV_Waypoint\s*\{[^}]*?\n\s*speed\s*=\s*([-\d.eE+]+)", text)
    if base is None:
        return None
    v = [float(base.group(1))] * legs
    for m in re.finditer(r"Behavior\s*=\s*BHV_ConstantDepth\s*\{([^}]*)\}", text):
        body = m.group(1)
        idx = re.search(r"WPT_INDEX\s*==?\s*(\d+)", body)
        flag = re.search(r"runflag\s*=\s*WPT_UPDATE\s*=\s*speed\s*=\s*([-\d.eE+]+)", body)
        if idx and int(idx.group(1)) >= legs:
            return None  # the file has more legs than the mission it was read as
        if idx and flag:
            v[int(idx.group(1))] = float(flag.group(1))
    return v


def _qgc(doc: dict[str, Any], legs: int) -> list[float] | None:
    mission = doc["mission"]
    speed = float(mission.get("cruiseSpeed") or 0.0)
    out: list[float] = []
    for it in plan_items(doc):  # the reader's legs (the same walk)
        if it.moves:
            out.append(speed)  # the leg that reaches this position
        elif it.command == 178 and _speed(it) > 0:
            speed = _speed(it)
    return out if len(out) == legs else None


class _BadSpeed(Exception):
    """A speed command whose speed is not a number (raised past the readers' 'carries none' handling)."""


def _speed(it: PlanItem) -> float:
    """The speed of a ``MAV_CMD_DO_CHANGE_SPEED`` item (param 2, m/s; -1 or 0: unchanged)."""
    value = it.params[1] if len(it.params) > 1 else None
    try:
        if isinstance(value, bool):
            raise TypeError(value)
        return float(value)  # type: ignore[arg-type]  # checked: a number or refused
    except (TypeError, ValueError):
        raise _BadSpeed(f"MAV_CMD_DO_CHANGE_SPEED at {it.where}: speed {value!r} is not a number") from None


def read_leg_speeds(path: str | Path, legs: int) -> NDArray[np.float64] | None:
    """The speed of each of ``legs`` legs a mission file carries (module notes).

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file (already read once by :func:`auvplan.io.missions.formats.read_mission`).
    legs : int
        Its number of legs.

    Returns
    -------
    numpy.ndarray or None
        ``(legs,)`` positive speeds (m/s); None when the format carries none or they do not match.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    try:
        text = path.read_text(encoding="utf-8")
        if suffix in (".moos", ".bhv"):
            v = _moos(text, legs)
        elif suffix == ".plan":
            v = _qgc(json.loads(text), legs)
        elif suffix == ".csv":
            speed = csv_columns(text, ("speed",)).get("speed")
            v = None if speed is None else speed[1:].tolist()
        else:
            v = None
    except _BadSpeed as exc:  # the vehicle would not fly the speed the check assumed
        raise DataError(f"{path}: QGC plan: {exc}") from None
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError, IndexError):
        return None
    if v is None or len(v) != legs:
        return None
    a = np.asarray(v, dtype=float)
    fast = np.flatnonzero(np.isfinite(a) & (a > MAX_SPEED_MPS))
    if fast.size:  # 1e300 m/s was flown: numpy's overflow warnings, then an energy of inf
        raise DataError(f"{path}: leg {int(fast[0])}'s speed {a[fast[0]]:g} m/s (carried by the file) is over "
                        f"{MAX_SPEED_MPS:g} m/s: not a vehicle's speed")
    return a if bool(np.all(np.isfinite(a))) and bool(np.all(a > 0)) else None


MAX_SPEED_MPS = 100.0
"""Fastest leg speed a mission file may carry (m/s); an AUV or a glider flies at a few m/s."""
