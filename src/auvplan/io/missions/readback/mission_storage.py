"""The mission storage a ``.plan`` needs on the board, and whether the operator's board holds it.

AP_Mission keeps ``(storage − 4) // 15`` commands, the home (command 0) included
(:data:`~auvplan.io.missions.readback.qgc_items.AP_MISSION_CAPACITY`): 655 on a board with 16 KiB of storage,
1 312 with 32 KiB of FRAM, and with ``BRD_SD_MISSION = N`` (KiB) the mission lives in a microSD file of
``min(N · 1024, 0xFFFF)`` bytes instead (``StorageAccess::attach_file``; the board's own areas are then unused),
4 368 at most (N = 64).  A file over 4 368 commands is refused whatever the board
(:func:`~auvplan.io.missions.readback.qgc_items.plan_items`); below it, ``mission check`` names the smallest of
the three that holds the file (and the ``BRD_SD_MISSION`` it needs over 1 312), and with the board named
(``--board-storage 16k | 32k | sd:N``) a file the board cannot hold fails: ArduSub refuses its upload
(``MissionItemProtocol::handle_mission_count``: a count over ``num_commands_max`` is answered
``MAV_MISSION_NO_SPACE``, "Only N items are supported").  ``export``, ``run`` and ``survey`` with the board named
refuse to write such a ``.plan``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .qgc_items import (
    AP_MISSION_CAPACITY,
    AP_MISSION_COMMAND_BYTES,
    AP_MISSION_HEADER_BYTES,
    AP_MISSION_STORAGE_BYTES,
)

__all__ = ["SD_MISSION_KIB_MAX", "BoardStorage", "board_storage", "mission_bytes", "sd_mission_kib",
           "mission_storage", "storage_line", "board_refusal"]

SD_MISSION_KIB_MAX = 64
"""The largest ``BRD_SD_MISSION`` (KiB; ``AP_BoardConfig``'s range 0-64, ``attach_file`` caps the file at 0xFFFF
bytes)."""

_WORDS = {"16k": "a 16 KiB-storage board", "32k": "a board with 32 KiB of FRAM"}


@dataclass(frozen=True)
class BoardStorage:
    """The mission storage of the operator's board (``--board-storage``).

    Attributes
    ----------
    name : str
        As given: ``"16k"``, ``"32k"`` or ``"sd:N"``.
    storage_bytes : int
        Bytes of mission storage: 9 842, 19 684, or ``min(N · 1024, 0xFFFF)`` for ``BRD_SD_MISSION = N``.
    """

    name: str
    storage_bytes: int

    @property
    def commands(self) -> int:
        """Commands it holds, the home included: ``(storage_bytes − 4) // 15``."""
        return (self.storage_bytes - AP_MISSION_HEADER_BYTES) // AP_MISSION_COMMAND_BYTES

    @property
    def words(self) -> str:
        """The board in words (``a 16 KiB-storage board``, ``BRD_SD_MISSION = 24``)."""
        return _WORDS.get(self.name, f"BRD_SD_MISSION = {self.name[3:]}")


def board_storage(text: str) -> BoardStorage:
    """Read ``--board-storage``: ``16k``, ``32k`` or ``sd:N`` (``BRD_SD_MISSION`` in KiB, 1 to 64).

    Parameters
    ----------
    text : str
        The value given.

    Returns
    -------
    BoardStorage
        The board's mission storage.

    Raises
    ------
    ValueError
        Naming the value and the forms accepted.
    """
    if text == "16k":
        return BoardStorage(text, AP_MISSION_STORAGE_BYTES["16 KiB"])
    if text == "32k":
        return BoardStorage(text, AP_MISSION_STORAGE_BYTES["32 KiB"])
    kib = text[3:] if text.startswith("sd:") else ""
    if not (kib.isascii() and kib.isdigit() and 1 <= int(kib) <= SD_MISSION_KIB_MAX):
        raise ValueError(f"{text!r}: not 16k, 32k or sd:N (BRD_SD_MISSION, whole KiB from 1 to "
                         f"{SD_MISSION_KIB_MAX})")
    n = int(kib)
    return BoardStorage(f"sd:{n}", min(AP_MISSION_STORAGE_BYTES["microSD"], 1024 * n))


def mission_bytes(commands: int) -> int:
    """Bytes of mission storage ``commands`` take (the home included): ``4 + 15 · commands``.

    Parameters
    ----------
    commands : int
        Commands, the home included.

    Returns
    -------
    int
        The bytes.
    """
    return AP_MISSION_HEADER_BYTES + AP_MISSION_COMMAND_BYTES * int(commands)


def sd_mission_kib(commands: int) -> int | None:
    """The least ``BRD_SD_MISSION`` (KiB) whose file holds ``commands``, or None when none does (over 4 368).

    Parameters
    ----------
    commands : int
        Commands, the home included.

    Returns
    -------
    int or None
        ``ceil((4 + 15 · commands) / 1024)``, when at most 64.
    """
    need = mission_bytes(commands)
    return math.ceil(need / 1024) if need <= AP_MISSION_STORAGE_BYTES["microSD"] else None


def mission_storage(commands: int, board: BoardStorage | None = None) -> dict[str, Any]:
    """The storage a ``.plan`` of ``commands`` commands (the home included) needs, and whether ``board`` holds it.

    Parameters
    ----------
    commands : int
        Its commands, the home included.
    board : BoardStorage, optional
        The operator's board (``--board-storage``); without it the record is informative (``ok`` true).

    Returns
    -------
    dict
        ``commands``, ``bytes``, ``smallest`` (``"16 KiB"``, ``"32 KiB"``, ``"microSD"`` or None over 4 368),
        ``smallest_commands`` (its capacity), ``brd_sd_mission_kib`` (the ``BRD_SD_MISSION`` it needs, over
        1 312; else None), ``board`` and ``board_commands`` (None without one), ``ok`` and ``reason`` (None when
        it fits).
    """
    smallest = next((k for k, cap in AP_MISSION_CAPACITY.items() if commands <= cap), None)
    ok = commands <= board.commands if board is not None else smallest is not None
    rec: dict[str, Any] = {
        "commands": int(commands), "bytes": mission_bytes(commands), "smallest": smallest,
        "smallest_commands": AP_MISSION_CAPACITY[smallest] if smallest else None,
        "brd_sd_mission_kib": sd_mission_kib(commands) if smallest == "microSD" else None,
        "board": board.name if board is not None else None,
        "board_commands": board.commands if board is not None else None, "ok": ok, "reason": None}
    if not ok:
        rec["reason"] = (f"{commands} commands > the {board.commands} that {board.words} holds"
                         if board is not None else f"{commands} commands > the {AP_MISSION_CAPACITY['microSD']} any "
                                                   "board holds")
    return rec


def _needs(rec: dict[str, Any]) -> str:
    """What the file needs, in words (the smallest of the three capacities that holds it)."""
    c = AP_MISSION_CAPACITY
    if rec["smallest"] == "16 KiB":
        return f"fits a 16 KiB-storage board ({c['16 KiB']} commands)"
    if rec["smallest"] == "32 KiB":
        return f"needs 32 KiB of storage (FRAM: {c['32 KiB']} commands; a 16 KiB-storage board holds {c['16 KiB']})"
    if rec["smallest"] == "microSD":
        return (f"needs BRD_SD_MISSION ≥ {rec['brd_sd_mission_kib']} (KiB, a microSD file; 32 KiB of FRAM holds "
                f"{c['32 KiB']})")
    return f"no board holds it (at most {c['microSD']}, BRD_SD_MISSION = 64)"


def _sd_hint(rec: dict[str, Any]) -> str:
    """A ``BRD_SD_MISSION`` board too small for a file that fits 32 KiB of storage: the ``BRD_SD_MISSION`` that
    holds it (over 1 312 commands :func:`_needs` names it)."""
    kib = sd_mission_kib(rec["commands"])
    sd = str(rec["board"]).startswith("sd:") and rec["smallest"] in ("16 KiB", "32 KiB")
    return f"; BRD_SD_MISSION ≥ {kib} holds it" if sd and kib else ""


def storage_line(rec: dict[str, Any]) -> str:
    """:func:`mission_storage`'s record in one line (``mission check``).

    Parameters
    ----------
    rec : dict
        The record.

    Returns
    -------
    str
        ``mission storage: 1622 commands (…) — needs BRD_SD_MISSION ≥ 24 …``, ``mission storage OK|FAIL — … on the
        board (--board-storage sd:16) …`` with the board named.
    """
    n = rec["commands"]
    head = f"{n} commands ({n - 1} items + the home, {rec['bytes']} bytes): {_needs(rec)}"
    if rec["board"] is None:
        return f"mission storage: {head}"
    verdict = "OK" if rec["ok"] else "FAIL"
    sign = "≤" if rec["ok"] else ">"
    tail = "" if rec["ok"] else f"{_sd_hint(rec)}; ArduSub refuses the upload (MAV_MISSION_NO_SPACE)"
    return (f"mission storage {verdict} — {head}; {n} {sign} {rec['board_commands']} on the board (--board-storage "
            f"{rec['board']}){tail}")


def board_refusal(path: Any, commands: int, board: BoardStorage) -> str | None:
    """Why a ``.plan`` of ``commands`` commands is not written for ``board``, one line naming the file, or None.

    Parameters
    ----------
    path : path-like
        The file that would be written.
    commands : int
        Its commands, the home included.
    board : BoardStorage
        The operator's board.

    Returns
    -------
    str or None
        ``mission.plan: 1621 items + the home = 1622 commands > the 1312 that a board with 32 KiB of FRAM holds
        (--board-storage 32k); needs BRD_SD_MISSION ≥ 24 …: not written``; None when it fits.
    """
    if commands <= board.commands:
        return None
    rec = mission_storage(commands, board)
    return (f"{path}: {commands - 1} items + the home = {commands} commands > the {board.commands} that "
            f"{board.words} holds (--board-storage {board.name}); {_needs(rec)}{_sd_hint(rec)}: not written")
