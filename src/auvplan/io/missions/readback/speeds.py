"""The speed of each leg a mission file carries (issue 38), read back for ``auvplan mission check``.

The legs are those of :func:`auvplan.io.missions.formats.read_mission`'s waypoints:

* MOOS (``.moos``/``.bhv``): leg i's ``runflag = WPT_UPDATE = speed=v`` in the depth behaviour of
  ``WPT_INDEX = i``, else the waypoint behaviour's ``speed`` (the deploy point is waypoint 0, so leg
  0 of the file's points is leg 0 here);
* QGroundControl (``.plan``): each ``MAV_CMD_DO_CHANGE_SPEED`` (178) sets the speed of the legs after it
  (param 2, m/s: ArduSub's ``do_change_speed`` sets WPNav's horizontal speed); the legs before the first carry
  none (NaN): ArduSub flies them at its ``WPNAV_SPEED`` parameter (cm/s; AC_WPNav's default 1000, 500 in older
  releases), which the file does not hold.  The speed is horizontal: WPNav flies a leg climbing or diving at
  ``γ`` at the speed along it that keeps the horizontal one (ArduPilot's ``kinematic_limit``: ``v / cos γ``, until
  the vertical limit ``WPNAV_SPEED_UP``/``_DN`` binds, at ``tan γ`` over their ratio to it), so the speed through
  the water is the command's times :func:`along_track_factor`.  ArduSub's ``do_change_speed`` sets the horizontal
  speed only, whatever the speed type (param 1; ``ArduSub/commands_logic.cpp``: ``wp_nav.set_speed_xy``), and a
  ``.plan`` holds no parameter, so the vertical limit is AC_WPNav's default (``WPNAV_SPEED_UP`` 2.5 m/s,
  ``WPNAV_SPEED_DN`` 1.5 m/s, ``AC_WPNav.cpp``): every leg is flown at ``min(v / cos γ, v_z / |sin γ|)``, a vertical
  leg (the launch from a home above the first item) at ``v_z`` (:func:`flown_speeds`; the leg's time is
  ``max(horizontal / v, rise / v_z)``).  The legs where the default binds are named (:func:`vertical_bound_legs`).
  ``cruiseSpeed`` and ``hoverSpeed`` are QGroundControl's estimates of the mission's time, never uploaded to
  the vehicle: not read as a speed;
* CSV: the ``speed`` column, row i (i ≥ 1) the leg that reaches it.

Other formats carry no speed (None).  :func:`judged_leg_speeds` fills the legs a file does not carry at the
scenario vehicle's speed and names them (``mission check``'s ``speed_assumed_legs``).

A ``.plan`` also carries the time held at a position (:func:`read_holds`): a ``MAV_CMD_NAV_WAYPOINT``'s or a
``MAV_CMD_NAV_LOITER_TIME``'s param 1 (whole seconds: ArduSub's ``loiter_time_max``), spent there before the next
leg.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ....errors import DataError
from ....nav.budget import LAUNCH_DIVE_MPS
from .. import parsed
from .qgc_items import PlanItem, plan_items
from .readers import csv_columns

__all__ = ["MAX_HOLD_S", "JudgedSpeeds", "WPNAV_SPEED_DN_MPS", "WPNAV_SPEED_UP_MPS", "along_track_factor",
           "flown_speeds", "judged_leg_speeds", "read_holds", "read_leg_speeds", "vertical_bound_legs"]


def along_track_factor(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The speed along each leg per unit of horizontal speed, as ArduSub's WPNav flies a ``.plan`` (module notes).

    Parameters
    ----------
    points : numpy.ndarray
        ``(N, 3)`` waypoints (m).

    Returns
    -------
    numpy.ndarray
        ``(N - 1,)`` the leg's length over its horizontal length (``1 / cos γ``); 1 for a vertical leg or one of no
        length (no horizontal speed to scale).
    """
    d = np.diff(np.asarray(points, dtype=float), axis=0)
    flat = np.hypot(d[:, 0], d[:, 1])
    full = np.linalg.norm(d, axis=1)
    return np.where(flat > 0.0, full / np.where(flat > 0.0, flat, 1.0), 1.0)


WPNAV_SPEED_UP_MPS = 2.5
"""AC_WPNav's default climb limit ``WPNAV_SPEED_UP`` (250 cm/s; the file does not hold it)."""
WPNAV_SPEED_DN_MPS = LAUNCH_DIVE_MPS
"""AC_WPNav's default descent limit ``WPNAV_SPEED_DN`` (150 cm/s; the file does not hold it): the navigation budget
flies the launch at it (:data:`auvplan.nav.budget.LAUNCH_DIVE_MPS`)."""


def _vertical_limits(points: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
    """Each leg's horizontal and vertical run, 3D length and AC_WPNav's default vertical limit for its sense."""
    d = np.diff(np.asarray(points, dtype=float), axis=0)
    flat, rise = np.hypot(d[:, 0], d[:, 1]), d[:, 2]
    vz = np.where(rise > 0.0, WPNAV_SPEED_UP_MPS, WPNAV_SPEED_DN_MPS)
    return flat, rise, np.linalg.norm(d, axis=1), vz


def flown_speeds(commands: NDArray[np.float64], points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The speed along each leg of a ``.plan`` as WPNav flies its commanded horizontal speed (module notes).

    ArduPilot's ``kinematic_limit``: ``v / cos γ`` until the vertical limit binds, then ``v_z / |sin γ|``, with the
    vertical limits AC_WPNav's defaults (:data:`WPNAV_SPEED_UP_MPS`, :data:`WPNAV_SPEED_DN_MPS`: ArduSub's speed
    command never sets them); a vertical leg (no horizontal run) at ``v_z``, with a command in force or none (the
    launch of a ``.plan`` without one dives at ``WPNAV_SPEED_DN`` too, not at ArduSub's ``WPNAV_SPEED``).

    Parameters
    ----------
    commands : numpy.ndarray
        ``(N - 1,)`` each leg's commanded horizontal speed (m/s; NaN: not in the file, kept).
    points : numpy.ndarray
        ``(N, 3)`` waypoints (m).

    Returns
    -------
    numpy.ndarray
        ``(N - 1,)`` (m/s; NaN: a leg with a horizontal run and no command).
    """
    flat, rise, full, vz = _vertical_limits(points)
    v = np.asarray(commands, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        along = np.minimum(v * full / flat, vz * full / np.abs(rise))
    # a vertical leg at v_z whatever the command (none too): the command sets the horizontal speed only
    out: NDArray[np.float64] = np.where(flat > 0.0, along, np.where(full > 0.0, vz, v))
    return out


def vertical_bound_legs(commands: NDArray[np.float64], points: NDArray[np.float64]) -> tuple[int, ...]:
    """The legs of a ``.plan`` flown slower than their command along the leg: AC_WPNav's default vertical limit binds.

    Parameters
    ----------
    commands : numpy.ndarray
        ``(N - 1,)`` each leg's commanded horizontal speed (m/s; NaN: not in the file, never named).
    points : numpy.ndarray
        ``(N, 3)`` waypoints (m).

    Returns
    -------
    tuple of int
        The legs with a horizontal run whose vertical speed ``v tan γ`` the command would ask is over the default
        (1 mm/s slack); a vertical leg has no command to honour (flown at ``v_z``, module notes).
    """
    flat, rise, _, vz = _vertical_limits(points)
    v = np.asarray(commands, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        asked = np.where(flat > 0.0, v * np.abs(rise) / flat, 0.0)  # a vertical leg: flown at v_z, no command
    return tuple(int(k) for k in np.flatnonzero(np.isfinite(v) & (asked > vz + 1e-3)))


def _moos(text: str, legs: int) -> list[float] | None:
    """The legs' speeds as the helm flies them: the waypoint behaviour's ``speed``, changed from leg i on by leg i's
    ``runflag = X = speed=v`` when the behaviour takes its updates from ``X`` (``updates = X``): MOOS-IvP's
    ``IvPBehavior::checkUpdates`` sets the parameter for good, so a leg without its own update keeps the last."""
    text = re.sub(r"//[^\n]*", "", text)
    block = re.search(r"Behavior\s*=\s*BHV_Waypoint\s*\{([^}]*)\}", text)
    base = None if block is None else re.search(r"(?:^|\n)\s*speed\s*=\s*([-\d.eE+]+)", block.group(1))
    if block is None or base is None:
        return None
    takes = re.search(r"(?:^|\n)\s*updates\s*=\s*(\w+)\s*(?:\n|$)", block.group(1))
    flags: dict[int, float] = {}
    for m in re.finditer(r"Behavior\s*=\s*BHV_ConstantDepth\s*\{([^}]*)\}", text):
        body = m.group(1)
        idx = re.search(r"WPT_INDEX\s*==?\s*(\d+)", body)
        flag = None if takes is None else re.search(
            rf"runflag\s*=\s*{takes.group(1)}\s*=\s*speed\s*=\s*([-\d.eE+]+)", body)
        if idx and int(idx.group(1)) >= legs:
            return None  # the file has more legs than the mission it was read as
        if idx and flag:
            flags[int(idx.group(1))] = float(flag.group(1))
    v, speed = [], float(base.group(1))
    for i in range(legs):  # an update holds until the next one
        speed = flags.get(i, speed)
        v.append(speed)
    return v


def _qgc(doc: dict[str, Any], legs: int) -> tuple[list[float], str | None] | None:
    """The legs' speeds (NaN before the first speed command: not in the file) and where that command is."""
    speed, first = math.nan, None  # not cruiseSpeed: QGroundControl never uploads it
    out: list[float] = []
    for it in plan_items(doc):  # the reader's legs (the same walk)
        if it.moves:
            out.append(speed)  # the leg that reaches this position
        elif it.command == 178 and _speed(it) > 0:
            speed = _speed(it)
            first = it.where if first is None else first
    return (out, first) if len(out) == legs else None


class _BadSpeed(Exception):
    """A speed that is not a number (a ``.plan``'s speed command, a CSV's cell), raised past the readers' 'carries
    none' handling."""


def _speed(it: PlanItem) -> float:
    """The speed of a ``MAV_CMD_DO_CHANGE_SPEED`` item (param 2, m/s; -1, 0 or null: unchanged).

    ArduSub changes its speed only for a speed above 0 (``Sub::do_change_speed``, ArduSub/commands_logic.cpp:
    ``if (cmd.content.speed.target_ms > 0) { wp_nav.set_speed_NE_cms(...) }``, the float copied unchecked by
    ``AP_Mission::mavlink_int_to_mission_cmd``: ``cmd.content.speed.target_ms = packet.param2``).  QGroundControl
    writes a NaN parameter as null: NaN > 0 is false, so a null speed changes nothing (it was refused as 'not a
    number').
    """
    value = it.params[1] if len(it.params) > 1 else None
    if value is None:
        return math.nan  # QGC's NaN: ArduSub keeps its speed
    try:
        if isinstance(value, bool):
            raise TypeError(value)
        return float(value)  # checked: a number or refused
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
        ``(legs,)`` positive speeds (m/s), a ``.plan``'s legs before its first speed command NaN (not in the file:
        :func:`judged_leg_speeds`); None when the format carries none or they do not match.
    """
    v = _read(Path(path), legs)
    return None if v is None else v[0]


def _read(path: Path, legs: int) -> tuple[NDArray[np.float64], str | None] | None:
    """:func:`read_leg_speeds` and, for a ``.plan``, where its first speed command is."""
    suffix = path.suffix.lower()
    first = None
    try:
        text = path.read_text(encoding="utf-8")
        if suffix in (".moos", ".bhv"):
            v = _moos(text, legs)
        elif suffix == ".plan":
            got = _qgc(parsed.loads(text), legs)
            v, first = (None, None) if got is None else got
        elif suffix == ".csv":
            try:
                speed = csv_columns(text, ("speed",), empty=math.nan).get("speed")  # empty: that leg's not in the file
            except ValueError as exc:  # a word typed in: it dropped the column, the vehicle's speed judged silently
                raise _BadSpeed(str(exc)) from None
            v = None if speed is None else speed[1:].tolist()
        else:
            v = None
    except _BadSpeed as exc:  # the vehicle would not fly the speed the check assumed
        raise DataError(f"{path}: {'QGC plan: ' if suffix == '.plan' else ''}{exc}") from None
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError, IndexError):
        return None
    if v is None or len(v) != legs:
        return None
    a = np.asarray(v, dtype=float)
    fast = np.flatnonzero(a > MAX_SPEED_MPS)  # inf too (it dropped every carried speed); a NaN carries none
    if fast.size:  # 1e300 m/s was flown: numpy's overflow warnings, then an energy of inf
        raise DataError(f"{path}: leg {int(fast[0])}'s speed {a[fast[0]]:g} m/s (carried by the file) is over "
                        f"{MAX_SPEED_MPS:g} m/s: not a vehicle's speed")
    slow = np.flatnonzero(a <= 0)  # a CSV's 0 or -1.5 (a .plan's 178 of speed <= 0 changes nothing: NaN here)
    if slow.size:  # it dropped every speed the file carries, all judged at the vehicle's speed as "not in the file"
        raise DataError(f"{path}: leg {int(slow[0])}'s speed {a[slow[0]]:g} m/s (carried by the file) is not "
                        "positive: no vehicle flies it (leave it empty: judged at the vehicle's speed, named)")
    known = np.isfinite(a)  # NaN: not in the file (a .plan's legs before its first 178, a CSV's empty speed cell)
    if not known.any():
        return None
    return a, first


@dataclass(frozen=True)
class JudgedSpeeds:
    """The speed ``mission check`` judges each leg of a mission file at.

    Parameters
    ----------
    speeds : numpy.ndarray
        ``(legs,)`` m/s: the file's, and ``assumed_mps`` where it carries none.
    assumed_legs : tuple of int
        The legs whose speed is not in the file (numbered from 0: a ``.plan``'s launch from its home is leg 0).
    assumed_mps : float
        The scenario vehicle's speed, at which they are judged (m/s).
    line : str
        Which legs and why, one line; empty when the file carries every leg's speed.
    """

    speeds: NDArray[np.float64]
    assumed_legs: tuple[int, ...]
    assumed_mps: float
    line: str


def judged_leg_speeds(path: str | Path, legs: int, speed: float,
                      points: NDArray[np.float64] | None = None) -> JudgedSpeeds:
    """The speed of each leg of a mission file as the vehicle will fly it, the legs it does not carry at ``speed``.

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file.
    legs : int
        Its number of legs (a ``.plan``'s launch from its home included).
    speed : float
        The scenario vehicle's speed (m/s).
    points : numpy.ndarray, optional
        ``(legs + 1, 3)`` the file's waypoints (m): a ``.plan``'s speed commands are horizontal, so each leg they
        set is flown at :func:`flown_speeds` of their speed through the water (without: as written).

    Returns
    -------
    JudgedSpeeds
        The speeds, the legs judged at ``speed`` and the line that says so (a ``.plan``: ``leg speeds before
        mission.items[3] not in the file: ArduSub flies its WPNAV_SPEED parameter; judged at 1 m/s``).
    """
    path = Path(path)
    got = _read(path, legs)
    v, first = (np.full(legs, np.nan), None) if got is None else got
    pts = points if path.suffix.lower() == ".plan" else None
    flown = v if pts is None else flown_speeds(v, pts)
    assumed = tuple(int(k) for k in np.flatnonzero(~np.isfinite(flown)))  # a .plan's vertical legs: at v_z
    line = ""
    if assumed:
        if path.suffix.lower() == ".plan":
            where = f"before {first}" if first is not None else "(no MAV_CMD_DO_CHANGE_SPEED above 0 before them)"
            line = (f"leg speeds {where} not in the file: ArduSub flies its WPNAV_SPEED parameter; judged at "
                    f"{speed:g} m/s (legs {_ranges(assumed)})")
        else:
            line = f"leg speeds not in the file: judged at the vehicle's speed {speed:g} m/s (legs {_ranges(assumed)})"
    if pts is not None:  # WPNav keeps the horizontal speed: faster on a slope, up to the vertical limit
        bound = vertical_bound_legs(v, pts)
        if bound:
            line = "; ".join([*([line] if line else []), (
                f"vertical limit not in the file (ArduSub's speed command sets the horizontal speed only): AC_WPNav's "
                f"defaults WPNAV_SPEED_UP {WPNAV_SPEED_UP_MPS:g} / WPNAV_SPEED_DN {WPNAV_SPEED_DN_MPS:g} m/s bind, "
                f"those legs flown slower than commanded (legs {_ranges(bound)})")])
    return JudgedSpeeds(np.where(np.isfinite(flown), flown, float(speed)), assumed, float(speed), line)


def _ranges(legs: tuple[int, ...]) -> str:
    """``0-4, 7``: consecutive legs as a range."""
    out: list[str] = []
    for k in legs:
        if out and k == int(out[-1].split("-")[-1]) + 1:
            out[-1] = f"{out[-1].split('-')[0]}-{k}"
        else:
            out.append(str(k))
    return ", ".join(out)


MAX_SPEED_MPS = 100.0
"""Fastest leg speed a mission file may carry (m/s); an AUV or a glider flies at a few m/s."""


MAX_HOLD_S = 65535.0
"""Longest hold an item can carry (s): ArduPilot stores param 1 of a waypoint or a timed loiter in 16 bits."""


def _refuse_holds(path: Path, moves: list[PlanItem]) -> None:
    """Refuse a hold ArduPilot cannot store: ``AP_Mission::mavlink_int_to_mission_cmd`` copies param 1 (a float)
    into the 16-bit unsigned ``cmd.p1`` (``cmd.p1 = packet.param1;``), which ``Sub::do_nav_wp`` holds
    (``loiter_time_max = cmd.p1``).  C++ converts a float to an integer by truncation, defined when the truncated
    value fits: 65535.5 holds 65535 s and -0.5 holds 0 (as :func:`read_holds` reads them); a hold that truncates
    below 0 or above :data:`MAX_HOLD_S` (-1, 65536) is undefined (it wraps or saturates by platform): refused."""
    for it in moves:
        p1 = it.params[0] if it.command in (16, 19) else 0
        if isinstance(p1, (int, float)) and not isinstance(p1, bool) and not -1.0 < p1 < MAX_HOLD_S + 1.0:
            raise DataError(f"{path}: QGC plan: {it.where}.params[0] = {p1!r}: a hold ArduPilot cannot store "
                            f"(truncated to whole seconds it must lie in 0-{MAX_HOLD_S:.0f}: AP_Mission keeps it "
                            "in 16 bits)")


def read_holds(path: str | Path, points: int) -> NDArray[np.float64] | None:
    """The time a ``.plan`` holds at each of its ``points`` (home first) before the next leg (module notes).

    Parameters
    ----------
    path : str or pathlib.Path
        The mission file (already read once by :func:`auvplan.io.missions.formats.read_mission`).
    points : int
        Its number of points (the home and each position
        :func:`auvplan.io.missions.readback.qgc_items.plan_items` reads).

    Returns
    -------
    numpy.ndarray or None
        ``(points,)`` seconds (the home's 0; whole seconds as ArduSub counts them); None for another format, a
        file without a hold, or one that does not match.

    Raises
    ------
    DataError
        If a hold is negative or over :data:`MAX_HOLD_S` (ArduPilot stores it in 16 bits), naming the item.
    """
    path = Path(path)
    if path.suffix.lower() != ".plan":
        return None
    try:
        moves = [it for it in plan_items(parsed.loads(path.read_text(encoding="utf-8"))) if it.moves]
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError, IndexError, DataError):
        return None
    hold = [0.0]
    for it in moves:
        p1 = it.params[0] if it.command in (16, 19) else 0  # an unlimited loiter is the last position: no leg after
        if isinstance(p1, bool) or not isinstance(p1, (int, float)) or not p1 > 0:
            p1 = 0  # null (QGC's NaN) or none: no hold
        hold.append(float(np.floor(float(p1))))
    _refuse_holds(path, moves)
    return np.asarray(hold) if len(hold) == points and any(hold) else None
