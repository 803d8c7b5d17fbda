"""The mission storage a ``.plan`` needs, and ``--board-storage`` (helper storage, wave 18).

AP_Mission holds ``(storage − 4) // 15`` commands, the home (command 0) included (``AP_Mission::num_commands_max``,
``AP_MISSION_EEPROM_COMMAND_SIZE`` = 15, 4 bytes of version header); ``StorageManager.cpp`` gives a non-copter vehicle
``StorageMission`` areas of 2 506 + 2 132 + 5 204 bytes on a 16 KiB board and as much again with 32 KiB of FRAM;
``BRD_SD_MISSION = N`` puts the mission in a microSD file of ``min(N · 1024, 0xFFFF)`` bytes
(``StorageAccess::attach_file``).  ``export`` wrote, and ``mission check`` passed, files between 655 and 4 368 commands
without saying which board they need.

Oracle: every capacity worked out here by hand from those byte counts (written as literals beside the sums), the
boundaries 654/655/656, 1311/1312/1313 and 4367/4368; the exported file's commands counted from its items.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from auvplan.errors import DataError
from auvplan.io.missions import export
from auvplan.io.missions.readback.mission_storage import (
    board_storage,
    mission_storage,
    sd_mission_kib,
    storage_line,
)
from auvplan.io.missions.readback.qgc_items import AP_MISSION_CAPACITY
from auvplan.sim.result import RunRecord

AREAS_16K = 2506 + 2132 + 5204  # 9 842 bytes
# by hand: (9842 - 4) // 15 = 9838 // 15 = 655 (655·15 + 4 = 9 829 ≤ 9 842 < 9 844 = 656·15 + 4)
#          (19684 - 4) // 15 = 19680 // 15 = 1312 exactly; (65535 - 4) // 15 = 65531 // 15 = 4368 (65 524 ≤ 65 535)
HAND = {"16 KiB": 655, "32 KiB": 1312, "microSD": 4368}


def test_the_three_capacities_from_the_bytes():
    assert AREAS_16K == 9842
    assert 655 * 15 + 4 <= AREAS_16K < 656 * 15 + 4 and 1312 * 15 + 4 == 2 * AREAS_16K
    assert 4368 * 15 + 4 <= 0xFFFF < 4369 * 15 + 4
    assert AP_MISSION_CAPACITY == HAND
    assert board_storage("16k").commands == 655 and board_storage("32k").commands == 1312


@pytest.mark.parametrize(("name", "commands"), [
    ("sd:1", 68),      # (1024 - 4) // 15 = 68
    ("sd:19", 1296),   # (19456 - 4) // 15 = 1296
    ("sd:20", 1365),   # (20480 - 4) // 15 = 1365
    ("sd:24", 1638),   # (24576 - 4) // 15 = 1638
    ("sd:64", 4368),   # 65 536 capped at 0xFFFF: (65535 - 4) // 15 = 4368
])
def test_a_brd_sd_mission_file_holds_what_its_bytes_hold(name, commands):
    assert board_storage(name).commands == commands


@pytest.mark.parametrize(("n", "smallest", "kib"), [
    (1, "16 KiB", None), (654, "16 KiB", None), (655, "16 KiB", None),
    (656, "32 KiB", None), (1311, "32 KiB", None), (1312, "32 KiB", None),
    (1313, "microSD", 20),   # 4 + 15·1313 = 19 699 bytes: 19.24 KiB
    (1622, "microSD", 24),   # marcus-terrain-follow's 1 621 items + the home: 24 334 bytes, 23.76 KiB
    (4367, "microSD", 64),   # 65 509 bytes
    (4368, "microSD", 64),   # 65 524 bytes
])
def test_the_smallest_capacity_that_holds_the_file(n, smallest, kib):
    rec = mission_storage(n)
    assert rec["commands"] == n and rec["bytes"] == 4 + 15 * n
    assert rec["smallest"] == smallest and rec["smallest_commands"] == HAND[smallest]
    assert rec["brd_sd_mission_kib"] == kib
    assert rec["ok"] and rec["board"] is None and rec["reason"] is None  # informative without the board
    line = storage_line(rec)
    assert line.startswith(f"mission storage: {n} commands ({n - 1} items + the home")
    assert "FAIL" not in line and "OK" not in line
    if kib is not None:
        assert f"BRD_SD_MISSION ≥ {kib}" in line


@pytest.mark.parametrize("n", [1, 68, 69, 655, 1313, 1622, 2000, 4096, 4368])
def test_the_brd_sd_mission_named_is_the_least_that_holds_the_file(n):
    """Invariant: the file of ``BRD_SD_MISSION = k`` holds ``n`` commands, that of ``k − 1`` does not."""
    k = sd_mission_kib(n)
    assert k is not None

    def holds(kib: int) -> int:
        return (min(kib * 1024, 0xFFFF) - 4) // 15

    assert holds(k) >= n and (k == 1 or holds(k - 1) < n)
    assert k == math.ceil((4 + 15 * n) / 1024)
    assert sd_mission_kib(4369) is None  # 65 539 bytes: no file holds it


@pytest.mark.parametrize(("board", "n", "ok"), [
    ("16k", 654, True), ("16k", 655, True), ("16k", 656, False),
    ("32k", 1312, True), ("32k", 1313, False),
    ("sd:24", 1638, True), ("sd:24", 1639, False),
    ("sd:64", 4368, True),
    ("sd:8", 600, False),  # (8192 - 4) // 15 = 545: a small BRD_SD_MISSION holds less than the board's own storage
])
def test_the_board_named_decides(board, n, ok):
    rec = mission_storage(n, board_storage(board))
    assert rec["ok"] is ok and rec["board"] == board
    line = storage_line(rec)
    assert line.startswith(f"mission storage {'OK' if ok else 'FAIL'} — {n} commands")
    assert f"{n} {'≤' if ok else '>'} {rec['board_commands']} on the board (--board-storage {board})" in line
    if board == "sd:8":
        assert "BRD_SD_MISSION ≥ 9 holds it" in line  # (9216 - 4) // 15 = 614 ≥ 600


@pytest.mark.parametrize("text", ["sd:0", "sd:65", "16K", "16", "sd:", "sd:1.5", "sd:-1", "64k", "", "sd:٣"])
def test_bad_board_values_are_refused(text):
    with pytest.raises(ValueError, match="not 16k, 32k or sd:N"):
        board_storage(text)


def _record(n: int) -> RunRecord:
    route = np.column_stack([np.linspace(0.0, 2000.0, n), np.zeros(n), np.full(n, -15.0)])
    return RunRecord("storage", 1, None, route, route[[0, -1]], None)


@pytest.mark.parametrize(("waypoints", "board", "written"), [
    (653, "16k", True),    # 653 waypoints + the launch's speed command = 654 items, + the home: 655 commands
    (654, "16k", False),   # 656
    (1310, "32k", True),   # 1 312
    (1311, "32k", False),  # 1 313
])
def test_write_exports_refuses_a_plan_the_board_cannot_hold(tmp_path, waypoints, board, written):
    record, origin = _record(waypoints), (10.0, 20.0)
    path = tmp_path / "mission.plan"
    if written:
        export.write_exports(tmp_path, record, origin, 1.5, ["plan"], board=board_storage(board))
        items = json.loads(path.read_text())["mission"]["items"]
        assert len(items) + 1 == waypoints + 2 == board_storage(board).commands  # the fullest file it holds
        return
    with pytest.raises(DataError) as exc:
        export.write_exports(tmp_path, record, origin, 1.5, ["plan"], board=board_storage(board))
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith(f"{path}: {waypoints + 1} items + the home = {waypoints + 2} commands")
    assert f"> the {board_storage(board).commands} that" in msg and f"(--board-storage {board})" in msg
    assert not path.exists()
    export.write_exports(tmp_path, record, origin, 1.5, ["plan"])  # without the board: written (some board holds it)
    assert len(json.loads(path.read_text())["mission"]["items"]) == waypoints + 1
