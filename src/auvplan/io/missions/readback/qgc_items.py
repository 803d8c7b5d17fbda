"""The items of a QGroundControl ``.plan`` in the order its vehicle executes them: the one walk every reader of a
``.plan`` shares (its waypoints :func:`auvplan.io.missions.readback.readers.parse_qgc_plan`, its
terrain-following legs :func:`auvplan.io.missions.readback.terrain_frame.terrain_legs`, its speeds and its payload
events), so that they count the same legs.

What moves the vehicle is either read as what it flies or refused (``mission check`` must judge what the vehicle
will fly, never a part of it):

- ``MAV_CMD_NAV_WAYPOINT`` (16): its position.
- The loiters ``MAV_CMD_NAV_LOITER_UNLIM`` (17) and ``_TIME`` (19) with a radius of 0 (param 3) or none: the
  vehicle goes to the point and holds it there (ArduSub's ``do_loiter_unlimited``), so they are read as a
  waypoint; with a radius: refused.  ``_UNLIM`` never completes (ArduSub's ``verify_loiter_unlimited``): only
  as the last position; before it, refused (the items after it are never flown).  ``_TURNS`` (18) is refused
  whatever its radius: ArduSub's ``do_circle`` circles the point at its radius, or at ``CIRCLE_RADIUS`` (10 m
  by default) when it is 0; so is ``_TO_ALT`` (31), which ArduSub does not fly (its ``start_command`` skips it:
  the vehicle goes on to the next item).
- A ``ComplexItem`` ``"survey"`` or ``"CorridorScan"``: the mission items QGC generated for it, which the file
  stores under ``TransectStyleComplexItem.Items`` (QGC uploads exactly these; ``VisualTransectPoints`` is only
  the drawing), walked in order under the same rules. ``"StructureScan"`` stores no items (QGC regenerates them
  from the polygon and the camera): refused, as is any other pattern.
- Refused: ``MAV_CMD_NAV_SPLINE_WAYPOINT`` (82; the spline between its items leaves the straight leg the
  check flies, and it is not bounded by it), ``MAV_CMD_NAV_RETURN_TO_LAUNCH`` (20), ``MAV_CMD_NAV_LAND`` (21),
  ``MAV_CMD_DO_JUMP`` (177; repeats part of the mission) and every command not named here.
- Skipped: the commands that do not move the vehicle (:data:`HARMLESS`): speed changes and relays (both
  written by :func:`auvplan.io.missions.formats.to_qgc_plan`) and the camera commands a survey generates.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ....errors import DataError
from ..parsed import remembered

__all__ = ["AP_MISSION_CAPACITY", "AP_MISSION_COMMAND_BYTES", "AP_MISSION_HEADER_BYTES", "AP_MISSION_MAX_COMMANDS",
           "AP_MISSION_STORAGE_BYTES", "NAV_WAYPOINT", "LOITERS",
           "LOITER_UNLIM", "HARMLESS", "REFUSED", "TRANSECT_PATTERNS", "PlanItem",
           "capacity_note", "plan_items"]

NAV_WAYPOINT = 16
"""``MAV_CMD_NAV_WAYPOINT``."""

LOITERS = {17: ("MAV_CMD_NAV_LOITER_UNLIM", 2), 19: ("MAV_CMD_NAV_LOITER_TIME", 2)}
"""The loiters at a position: command → (name, index of its radius parameter)."""

LOITER_UNLIM = 17
"""``MAV_CMD_NAV_LOITER_UNLIM``: ArduSub's ``verify_loiter_unlimited`` never completes, so it is read as its point
only as the last position (where a mission's end holds the vehicle anyway); before it: refused."""

HARMLESS = {178: "MAV_CMD_DO_CHANGE_SPEED", 181: "MAV_CMD_DO_SET_RELAY", 203: "MAV_CMD_DO_DIGICAM_CONTROL",
            206: "MAV_CMD_DO_SET_CAM_TRIGG_DIST", 2000: "MAV_CMD_IMAGE_START_CAPTURE",
            2001: "MAV_CMD_IMAGE_STOP_CAPTURE"}
"""Commands that do not move the vehicle: skipped."""

REFUSED = {82: ("MAV_CMD_NAV_SPLINE_WAYPOINT", "the spline leaves the straight leg between its items"),
           20: ("MAV_CMD_NAV_RETURN_TO_LAUNCH", "its way back is not in the file"),
           21: ("MAV_CMD_NAV_LAND", "its descent is not in the file"),
           177: ("MAV_CMD_DO_JUMP", "repeats part of the mission"),
           18: ("MAV_CMD_NAV_LOITER_TURNS", "ArduSub circles its point, at CIRCLE_RADIUS when its radius is 0"),
           31: ("MAV_CMD_NAV_LOITER_TO_ALT", "ArduSub skips it and goes on to the next item")}
"""Commands that move the vehicle in a way the file does not give: command → (name, why)."""

TRANSECT_PATTERNS = ("survey", "CorridorScan")
"""The ``complexItemType`` s whose generated items the file stores under ``TransectStyleComplexItem.Items``."""


@dataclass(frozen=True)
class PlanItem:
    """One mission item as the vehicle executes it.

    Parameters
    ----------
    where : str
        Its place in the file (``mission.items[3]``, ``mission.items[2].TransectStyleComplexItem.Items[5]``).
    command : int
        Its ``MAV_CMD``.
    frame : int or None
        Its ``MAV_FRAME``.
    params : tuple
        Its seven parameters (lat, lon, altitude in 5, 6, 7 for the items that move the vehicle).
    moves : bool
        True for a position the vehicle goes to (a waypoint, or a loiter read as one); False for a command
        that does not move it (:data:`HARMLESS`).
    """

    where: str
    command: int
    frame: int | None
    params: tuple[Any, ...]
    moves: bool


def _refuse(where: str, what: str) -> DataError:
    return DataError(f"QGC plan: {what} at {where}: not checked")


def _simple(item: Mapping[str, Any], where: str) -> PlanItem:
    """Classify one ``SimpleItem`` (module notes); raise :class:`DataError` for one that is refused."""
    command = item["command"]
    if not isinstance(command, int) or isinstance(command, bool):
        raise DataError(f"QGC plan: {where}.command = {command!r}: not a MAV_CMD number")
    params = tuple(item["params"])
    if len(params) != 7:
        raise DataError(f"QGC plan: {where}.params has {len(params)} values; expected 7")
    frame = item.get("frame")
    if command == NAV_WAYPOINT:
        return PlanItem(where, command, frame, params, True)
    if command in LOITERS:
        name, k = LOITERS[command]
        radius = params[k]
        if radius not in (None, 0):
            raise _refuse(where, f"{name} ({command}) circling {radius} m around its point")
        return PlanItem(where, command, frame, params, True)
    if command in HARMLESS:
        return PlanItem(where, command, frame, params, False)
    if command in REFUSED:
        name, why = REFUSED[command]
        raise _refuse(where, f"{name} ({command}; {why})")
    raise _refuse(where, f"unknown command {command}")


def _pattern(item: Mapping[str, Any], where: str) -> list[PlanItem]:
    """The generated items of a ``ComplexItem`` (module notes)."""
    kind = item.get("complexItemType")
    if kind not in TRANSECT_PATTERNS:
        why = ("its waypoints are not stored in the file" if kind == "StructureScan" else "an unknown pattern")
        raise _refuse(where, f"ComplexItem {kind!r} ({why})")
    generated = (item.get("TransectStyleComplexItem") or {}).get("Items")
    if not isinstance(generated, list) or not generated:
        raise DataError(f"QGC plan: {where}.TransectStyleComplexItem.Items: no generated mission items (the "
                        f"ComplexItem {kind!r} has nothing to check)")
    return [_simple(sub, f"{where}.TransectStyleComplexItem.Items[{j}]") for j, sub in enumerate(generated)]


AP_MISSION_COMMAND_BYTES = 15
"""Bytes of one stored mission command (``AP_MISSION_EEPROM_COMMAND_SIZE``, ``AP_Mission.h``)."""
AP_MISSION_HEADER_BYTES = 4
"""Bytes of the mission storage before its first command (its version number: ``AP_Mission::num_commands_max``'s
``− 4``)."""
AP_MISSION_STORAGE_BYTES = {"16 KiB": 2506 + 2132 + 5204, "32 KiB": 2 * (2506 + 2132 + 5204), "microSD": 0xFFFF}
"""Bytes of mission storage (:data:`AP_MISSION_CAPACITY`)."""
AP_MISSION_CAPACITY = {k: (b - AP_MISSION_HEADER_BYTES) // AP_MISSION_COMMAND_BYTES
                       for k, b in AP_MISSION_STORAGE_BYTES.items()}  # 655, 1312, 4368
"""Commands AP_Mission holds, the home (command 0) included: ``(storage − 4) / 15``
(``AP_Mission::num_commands_max``) over ``StorageManager.cpp``'s ``StorageMission`` areas for a non-copter
vehicle (ArduSub): 2 506 + 2 132 + 5 204 = 9 842 bytes on a board with 16 KiB of storage (Pixhawk 1, fmuv3),
19 684 bytes with 32 KiB (FRAM: Cube, Pixhawk 4), and the most a ``BRD_SD_MISSION`` file can hold (64 KiB,
``StorageAccess::attach_file`` caps it at 0xFFFF bytes)."""
AP_MISSION_MAX_COMMANDS = AP_MISSION_CAPACITY["microSD"]
"""The most commands any ArduPilot board holds (:data:`AP_MISSION_CAPACITY`)."""


def capacity_note() -> str:
    """AP_Mission's capacities in words, for messages.

    Returns
    -------
    str
        ``AP_Mission's capacity: 655 commands on a 16 KiB-storage board, …``.
    """
    c = AP_MISSION_CAPACITY
    return (f"AP_Mission's capacity: {c['16 KiB']} commands on a 16 KiB-storage board, {c['32 KiB']} on 32 KiB, "
            f"{c['microSD']} at most with BRD_SD_MISSION = 64")


def plan_items(doc: Mapping[str, Any]) -> list[PlanItem]:
    """Walk a ``.plan``'s mission items in the order the vehicle executes them (module notes).

    Parameters
    ----------
    doc : mapping
        The parsed ``.plan`` JSON.

    Returns
    -------
    list of PlanItem
        Every item the vehicle executes, a ``ComplexItem``'s generated items in its place.

    Raises
    ------
    DataError
        Naming the item (``mission.items[i]``) and its command or type when it moves the vehicle in a way the
        check cannot follow, or when the file is malformed.
    """
    return list(remembered("plan_items", doc, lambda: _walk(doc)))  # once per document in mission check (.parsed)


def _walk(doc: Mapping[str, Any]) -> list[PlanItem]:
    """:func:`plan_items` without the memo."""
    try:
        items = doc["mission"]["items"]
        if not isinstance(items, list):
            raise DataError("QGC plan: mission.items is not a list")
        out: list[PlanItem] = []
        for i, item in enumerate(items):
            where = f"mission.items[{i}]"
            if item.get("type") == "ComplexItem":
                out.extend(_pattern(item, where))
            else:
                out.append(_simple(item, where))
        if len(out) + 1 > AP_MISSION_MAX_COMMANDS:  # the home is command 0
            raise DataError(f"QGC plan: mission.items: {len(out)} items + the home = {len(out) + 1} commands > "
                            f"{capacity_note()}: no ArduPilot vehicle can hold it (the upload fails)")
        moves = [it for it in out if it.moves]
        held = next((it for it in moves[:-1] if it.command == LOITER_UNLIM), None)
        if held is not None:  # its verify never completes: the vehicle holds there, the rest is never flown
            raise _refuse(held.where, f"MAV_CMD_NAV_LOITER_UNLIM ({LOITER_UNLIM}) before the last position (ArduSub "
                                      "holds its point until the mission is stopped: the items after it are never "
                                      "flown)")
        return out
    except (KeyError, IndexError, TypeError, AttributeError) as exc:
        raise DataError(f"QGC plan: missing or malformed key ({exc})") from exc
