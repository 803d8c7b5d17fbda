"""The command line's contract (issue #20): exit 2 with one line naming the culprit for bad input,
exit 130 on Ctrl-C, arguments checked before any work, ``--out`` safe (no user file overwritten,
no link followed, atomic writes), results folders self-contained, ``--resume`` append-only."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest

import auvplan.sim
from auvplan import cli
from auvplan._types import Status
from auvplan.app.bench.rows import COLUMNS
from auvplan.app.bench.sweep import SweepSpec, sweep
from auvplan.io.files.manifest import MANIFEST, written
from auvplan.io.files.outdir import OutputError
from auvplan.io.files.safeio import atomic_write, prepare_out


def run_cli(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("argv, needle", [
    (("plan", "track-arc", "--seed", "-1"), "--seed: -1 must be >= 0"),
    (("plan", "track-arc", "--budget", "-5"), "--budget: -5 must be >= 1"),
    (("plan", "track-arc", "--seed", "x1"), "'x1' is not an integer"),
    (("bench", "--workers", "0"), "--workers: 0 must be >= 1"),
    (("bench", "--seeds", "0"), "--seeds: 0 must be >= 1"),
    (("bench", "--chunk", "0"), "--chunk: 0 must be >= 1"),
])
def test_bad_arguments_exit_2_before_any_work(capsys, argv, needle):
    code, _, err = run_cli(capsys, *argv)
    assert code == 2
    assert needle in err


def test_out_naming_a_file_is_refused_before_the_mission(capsys, tmp_path, monkeypatch):
    target = tmp_path / "afile"
    target.write_text("mine")
    monkeypatch.setattr(auvplan.sim, "run_mission",
                        lambda *a, **k: pytest.fail("the mission ran before --out was checked"))
    code, _, err = run_cli(capsys, "run", "track-single", "--out", target)
    assert code == 2 and "--out names an existing file" in err and str(target) in err
    assert target.read_text() == "mine"


def test_an_out_below_a_file_is_refused_before_the_mission(capsys, tmp_path, monkeypatch):
    (tmp_path / "afile").write_text("x")
    monkeypatch.setattr(auvplan.sim, "run_mission", lambda *a, **k: pytest.fail("the mission ran"))
    code, _, err = run_cli(capsys, "run", "track-single", "--out", tmp_path / "afile" / "sub")
    assert code == 2 and "cannot create the output folder" in err and "afile/sub" in err


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write anywhere")
def test_unwritable_out_is_refused_before_the_mission(capsys, tmp_path, monkeypatch):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    monkeypatch.setattr(auvplan.sim, "run_mission", lambda *a, **k: pytest.fail("the mission ran"))
    code, _, err = run_cli(capsys, "run", "track-single", "--out", locked / "sub")
    assert code == 2 and "locked" in err


def test_keyboard_interrupt_exits_130_naming_the_folder(capsys, tmp_path, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(auvplan.sim, "run_mission", interrupted)
    code, _, err = run_cli(capsys, "run", "track-single", "--out", tmp_path / "r")
    assert code == 130
    assert err.strip().splitlines()[-1] == f"auvplan: interrupted; nothing written into {tmp_path / 'r'}"
    assert not (tmp_path / "r").exists()  # before any result: the folder it made is not left behind

    def interrupted_writing(*args, **kwargs):  # after a result file was written
        atomic_write(tmp_path / "r" / "run.json", "{}")
        raise KeyboardInterrupt

    monkeypatch.setattr(auvplan.sim, "run_mission", interrupted_writing)
    code, _, err = run_cli(capsys, "run", "track-single", "--out", tmp_path / "r")
    assert code == 130
    assert err.strip().splitlines()[-1] == f"auvplan: interrupted; partial results in {tmp_path / 'r'}"
    assert not [p for p in (tmp_path / "r").iterdir() if p.name.endswith(".tmp")]  # nothing half-written


@pytest.mark.parametrize("exc", [ValueError("bad value\nsecond line"), OSError(28, "No space left on device")])
def test_library_errors_are_one_line_exit_2(capsys, tmp_path, monkeypatch, exc):
    def boom(*args, **kwargs):
        raise exc

    monkeypatch.setattr(auvplan.sim, "run_mission", boom)
    code, _, err = run_cli(capsys, "run", "track-single")
    assert code == 2
    assert err.count("\n") == 1 and "Traceback" not in err


def test_out_refuses_a_planted_user_file_without_force(capsys, tmp_path):
    out = tmp_path / "r"
    out.mkdir()
    (out / "path.csv").write_text("my own survey lines\n")
    code, _, err = run_cli(capsys, "plan", "flow-spheres", "--out", out)
    assert code == 2 and "path.csv" in err and "--force" in err
    assert (out / "path.csv").read_text() == "my own survey lines\n"
    code, _, _ = run_cli(capsys, "plan", "flow-spheres", "--out", out, "--force")
    assert code == 0
    assert (out / "path.csv").read_text().startswith("x,y,z")
    assert "path.csv" in written(out)


def test_a_planted_symlink_is_not_followed(capsys, tmp_path):
    out = tmp_path / "r"
    code, _, _ = run_cli(capsys, "plan", "flow-spheres", "--out", out)
    assert code == 0
    victim = tmp_path / "outside.txt"
    victim.write_text("precious")
    (out / "mission.csv").symlink_to(victim)
    code, _, err = run_cli(capsys, "export", out, "--format", "csv")
    assert code == 2 and "symbolic link" in err
    assert victim.read_text() == "precious"
    code, _, _ = run_cli(capsys, "export", out, "--format", "csv", "--force")  # replaces the link itself
    assert code == 0
    assert victim.read_text() == "precious"
    assert not (out / "mission.csv").is_symlink() and "x,y,z" in (out / "mission.csv").read_text()


def test_atomic_write_refuses_files_it_did_not_write_and_links(tmp_path):
    user = tmp_path / "mission.csv"
    user.write_text("mine")
    with pytest.raises(OutputError, match="not written by auvplan"):
        atomic_write(user, "theirs")
    (tmp_path / "link.json").symlink_to(user)
    with pytest.raises(OutputError, match="symbolic link"):
        atomic_write(tmp_path / "link.json", "theirs")
    assert user.read_text() == "mine"
    atomic_write(tmp_path / "new.json", "1")
    atomic_write(tmp_path / "new.json", "2")  # its own file: replaced
    assert (tmp_path / "new.json").read_text() == "2"


def test_atomic_write_never_leaves_half_a_file(tmp_path, monkeypatch):
    path = atomic_write(tmp_path / "a.json", "old")

    def broken_replace(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", broken_replace)
    with pytest.raises(OutputError, match="a.json"):
        atomic_write(path, "new" * 1000)
    monkeypatch.undo()
    assert path.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == [MANIFEST, "a.json"]  # no temp file left


def test_prepare_out_with_force_adopts_files_and_removes_links_only(tmp_path):
    target = tmp_path / "target.txt"
    target.write_text("keep")
    out = tmp_path / "out"
    out.mkdir()
    (out / "run.json").symlink_to(target)
    (out / "notes.txt").write_text("unrelated")
    with pytest.raises(OutputError):
        prepare_out(out)
    prepare_out(out, force=True)
    assert not (out / "run.json").exists() and target.read_text() == "keep"
    assert (out / "notes.txt").read_text() == "unrelated"


def _scenario_with_relative_data(folder: Path) -> Path:
    src = Path(__file__).parents[2] / "src" / "auvplan" / "data"
    folder.mkdir()
    shutil.copy(src / "etopo1_seed_marcus_wake.nc", folder / "grid.nc")
    text = (src / "scenarios" / "dynamic-terrain.toml").read_text()
    assert 'builtin = "etopo1-marcus-wake"' in text
    path = folder / "mine.toml"
    path.write_text(text.replace('builtin = "etopo1-marcus-wake"', 'file = "grid.nc"'))
    return path


def test_a_moved_results_folder_re_renders_its_report(capsys, tmp_path):
    scenario = _scenario_with_relative_data(tmp_path / "project")
    out = tmp_path / "results"
    code, _, err = run_cli(capsys, "plan", scenario, "--planner", "grid", "--out", out)
    assert code == 0, err
    moved = tmp_path / "elsewhere" / "results"
    moved.parent.mkdir()
    shutil.move(out, moved)
    shutil.rmtree(tmp_path / "project")  # the scenario and its data file are gone
    (moved / "report.html").unlink(missing_ok=True)
    code, out_text, err = run_cli(capsys, "report", moved)
    assert code == 0, err
    assert (moved / "report.html").stat().st_size > 10_000
    code, _, err = run_cli(capsys, "export", moved, "--format", "geojson", "csv")
    assert code == 0, err
    feats = json.loads((moved / "mission.geojson").read_text())["features"]
    assert feats and all(f["geometry"]["coordinates"] for f in feats)


@pytest.mark.parametrize("name, content", [("run.json", "{not json"), ("run.json", '["a list"]'),
                                           ("run.json", '{"plan": {"status": "NOPE"}}'),
                                           ("source.json", "[1, 2"), ("run.npz", "not a zip")])
def test_malformed_results_files_exit_2_naming_the_file(capsys, tmp_path, name, content):
    out = tmp_path / "r"
    assert run_cli(capsys, "plan", "flow-spheres", "--out", out)[0] == 0
    (out / name).write_text(content)
    code, _, err = run_cli(capsys, "report", out)
    assert code == 2, err
    assert err.count("\n") == 1 and (name in err or str(out) in err)


def test_resume_appends_and_never_rewrites(tmp_path):
    spec = SweepSpec(scenarios=("track-single",), guidance=("los",), seeds=3, chunk=1)
    out = tmp_path / "b"
    sweep(SweepSpec(scenarios=("track-single",), guidance=("los",), seeds=2, chunk=1), out, workers=1,
          progress=False)
    rows = out / "rows.csv"
    before = rows.read_bytes()
    inode = rows.stat().st_ino
    with rows.open("ab") as fh:
        fh.write(b"track-single,route,los,2,EXA")  # a line a kill cut short
    done = sweep(spec, out, workers=1, resume=True, progress=False)
    assert rows.stat().st_ino == inode  # the same file, appended to
    after = rows.read_bytes()
    assert after.startswith(before)
    assert after.count(b"\n") == before.count(b"\n") + 1
    lines = after.decode().splitlines()
    assert len(done) == 3 and lines[0] == ",".join(COLUMNS)
    assert all(len(ln.split(",")) == len(COLUMNS) for ln in lines)  # the cut line trimmed, not run into
    assert [r["seed"] for r in done] == ["0", "1", "2"] and done[2]["status"] in {s.value for s in Status}
