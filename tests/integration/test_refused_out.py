"""A refused command leaves the disk as it found it: no ``.auvplan.lock``, no empty manifest, no folder it made —
for every command that takes ``--out`` (or writes into DIR), refused by a user's file in the way, another job's
folder or a scenario that does not load after the folder was prepared."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from auvplan import cli
from auvplan.io.files import outdir, safeio
from auvplan.io.files.manifest import MANIFEST
from auvplan.io.files.outdir import LOCK
from auvplan.io.files.safeio import prepare_out

BAD = 'name = "bad"\n[terrain]\nbuiltin = "nosuch"\n'  # loads no [mission]: refused after --out is prepared


@pytest.fixture(autouse=True)
def _release_locks():
    yield
    outdir.release_all()


def _tree(root: Path) -> dict[str, bytes]:
    """Every file and folder below ``root`` with its bytes (a folder: b'/')."""
    out = {}
    for dirpath, dirs, files in os.walk(root):
        for d in dirs:
            out[os.path.relpath(os.path.join(dirpath, d), root)] = b"/"
        for f in files:
            out[os.path.relpath(os.path.join(dirpath, f), root)] = Path(dirpath, f).read_bytes()
    return out


def _refused(capsys, *argv: str) -> str:
    code = cli.main(["-q", *argv])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, (code, err)
    return err


@pytest.mark.parametrize(("argv", "in_the_way"), [
    (("plan", "flow-spheres"), "metrics.json"),
    (("simulate", "flow-spheres"), "track.csv"),
    (("run", "flow-spheres"), "report.html"),
    (("survey", "shelf-survey"), "lines.csv"),
    (("plan", "flow-spheres", "--depart-between", "+0h", "+1h"), "sweep.csv"),
    (("bench", "--scenarios", "flow-spheres", "--seeds", "1"), "rows.csv"),
    (("demo",), "report.html"),
])
def test_a_user_file_in_the_way_leaves_the_folder_as_it_was(tmp_path, capsys, argv, in_the_way):
    out = tmp_path / "mine"
    out.mkdir()
    (out / in_the_way).write_text("the user's own\n")
    before = _tree(tmp_path)
    err = _refused(capsys, *argv, "--out", str(out))
    assert f"{out / in_the_way}: a file auvplan did not write is in the way" in err
    assert _tree(tmp_path) == before  # no .auvplan.lock, no manifest


@pytest.mark.parametrize("command", ["report", "export"])
def test_report_and_export_into_a_folder_with_a_user_file_leave_it_as_it_was(tmp_path, capsys, command):
    (tmp_path / "run.json").write_text("{}")
    before = _tree(tmp_path)
    _refused(capsys, command, str(tmp_path))
    assert _tree(tmp_path) == before


def test_another_jobs_folder_is_refused_and_left_as_it_was(tmp_path, capsys):
    out = tmp_path / "r"
    out.mkdir()
    (out / MANIFEST).write_text(json.dumps({"files": ["metrics.json"], "job": "plan"}))  # a folder without a lock
    (out / "metrics.json").write_text("{}")
    before = _tree(tmp_path)
    assert "holds the results of `auvplan plan`" in _refused(capsys, "run", "flow-spheres", "--out", str(out))
    assert _tree(tmp_path) == before


@pytest.mark.parametrize("command", ["plan", "simulate", "run", "survey"])
def test_a_scenario_refused_after_the_folder_was_prepared_leaves_nothing(tmp_path, capsys, command):
    scenario = tmp_path / "bad.toml"
    scenario.write_text(BAD)
    (tmp_path / "empty").mkdir()
    before = _tree(tmp_path)
    for out in (tmp_path / "new" / "sub", tmp_path / "empty"):
        assert "missing required table [mission]" in _refused(capsys, command, str(scenario), "--out", str(out))
    assert _tree(tmp_path) == before  # neither new/ nor new/sub made; empty/ still empty


def test_a_failure_after_results_were_written_keeps_them_and_the_manifest(tmp_path):
    """Only what no result needs goes: a partial results folder keeps its files and the manifest naming them."""
    from auvplan.io.files.safeio import atomic_write

    out = tmp_path / "new" / "r"
    with pytest.raises(RuntimeError), safeio.session():
        prepare_out(out, job="run")
        atomic_write(out / "run.json", "{}")
        raise RuntimeError("the planner failed")
    assert sorted(p.name for p in out.iterdir()) == sorted(["run.json", MANIFEST])  # the lock it made: gone
    with safeio.session():  # a success keeps its lock file (unlocked), as before
        prepare_out(tmp_path / "ok", job="run")
    assert sorted(p.name for p in (tmp_path / "ok").iterdir()) == sorted([LOCK, MANIFEST])


def test_a_lock_file_replaced_before_it_was_locked_is_locked_again(tmp_path, monkeypatch):
    """A refused command removes the lock file it made; a process that had opened it must not lock the removed file
    while a third locks the new one (two writers): :func:`outdir.acquire` locks the file the folder names."""
    real, calls = outdir._lock, []

    def racing(path, folder):
        fd = real(path, folder)
        calls.append(fd)
        if len(calls) == 1:  # the refused command removes it; another one makes a new lock file
            os.unlink(path)
            Path(path).write_text("")
        return fd

    monkeypatch.setattr(outdir, "_lock", racing)
    outdir.acquire(tmp_path)
    assert len(calls) == 2
    held = os.fstat(outdir._HELD[os.path.abspath(tmp_path)])
    named = os.stat(tmp_path / LOCK)
    assert (held.st_dev, held.st_ino) == (named.st_dev, named.st_ino)


def test_prepare_out_refused_outside_a_command_leaves_nothing(tmp_path):
    """The library call alone (``serve``'s save, a script): a refusal undoes what it made before raising."""
    (tmp_path / "path.csv").write_text("the user's\n")
    before = _tree(tmp_path)
    with pytest.raises(outdir.OutputError, match="a file auvplan did not write is in the way"):
        prepare_out(tmp_path, job="plan")  # made the lock and the manifest, then refused
    assert _tree(tmp_path) == before and not outdir.held(tmp_path)
