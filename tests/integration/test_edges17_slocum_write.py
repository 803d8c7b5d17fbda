"""``write_slocum`` writes a glider's behaviour files all or none, each atomically, never over a pilot's file.

It wrote each file with ``Path.write_text``: a crash mid-write left a torn ``.ma`` beside the pilot's own files,
and a failure at the second file left a ``goto_l10.ma`` without its ``yo10.ma``.  The crash is injected at a
named point (the rename of the second file, the flush of the first), as tests/README.md asks.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

from auvplan.errors import DataError
from auvplan.io.missions.glider import slocum_files, write_slocum
from auvplan.vehicles.glider import GliderParams

PTS = np.array([[0.0, 0.0], [4000.0, 1500.0], [9000.0, -2500.0]])
ORIGIN = (67.25, 13.75)
GLIDER = GliderParams(yos=3, surface_every_s=7200.0)
CYCLE = dict(yos=3, underwater_s=6879.0)  # the planned cycle (planners.timeopt.glider.cycle)


def _pilot_folder(tmp_path):
    folder = tmp_path / "mafiles"
    folder.mkdir()
    mine = {"goto_l11.ma": "behavior_name=goto_list\n# the pilot's own list\n", "notes.txt": "do not touch\n"}
    for name, text in mine.items():
        (folder / name).write_text(text)
    return folder, mine


def _listing(folder):
    return {p.name: p.read_text() for p in sorted(folder.iterdir())}


def test_a_failure_at_the_second_file_leaves_the_folder_as_it_was(tmp_path, monkeypatch):
    folder, mine = _pilot_folder(tmp_path)
    real, calls = os.replace, []

    def failing(src, dst):
        calls.append(dst)
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        return real(src, dst)

    monkeypatch.setattr(os, "replace", failing)
    with pytest.raises(OSError):
        write_slocum(folder, PTS, ORIGIN, GLIDER, 12.0, **CYCLE)
    monkeypatch.setattr(os, "replace", real)
    assert len(calls) == 2  # each file renamed into place (atomic), the second one failed
    assert _listing(folder) == mine  # no torn file, no temporary, no goto list without its yo file


def test_a_crash_while_the_bytes_are_written_leaves_no_torn_file(tmp_path, monkeypatch):
    folder, mine = _pilot_folder(tmp_path)

    def crash(_fd):
        raise OSError(5, "Input/output error")

    monkeypatch.setattr(os, "fsync", crash)
    with pytest.raises(OSError):
        write_slocum(folder, PTS, ORIGIN, GLIDER, 12.0, **CYCLE)
    monkeypatch.undo()
    assert _listing(folder) == mine


def test_an_existing_file_is_refused_before_anything_is_written(tmp_path):
    folder, mine = _pilot_folder(tmp_path)
    (folder / "yo10.ma").write_text("behavior_name=yo\n# the pilot's\n")
    mine = {**mine, "yo10.ma": "behavior_name=yo\n# the pilot's\n"}
    with pytest.raises(DataError, match="yo10.ma: exists"):
        write_slocum(folder, PTS, ORIGIN, GLIDER, 12.0, **CYCLE)
    assert _listing(folder) == mine


def test_the_files_written_are_the_behaviour_files(tmp_path):
    folder, mine = _pilot_folder(tmp_path)
    written = write_slocum(folder, PTS, ORIGIN, GLIDER, 12.0, **CYCLE)
    want = slocum_files(PTS, ORIGIN, GLIDER, 12.0, **CYCLE)
    assert [p.name for p in written] == list(want)
    assert _listing(folder) == {**mine, **want}
