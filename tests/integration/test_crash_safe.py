"""Issue #32, result folders that survive crashes and concurrency: a lock per ``--out``, the manifest
naming each file before it is written, figures written atomically and recorded, a re-run after a
SIGKILL that completes, and ``bench --resume`` that re-runs exactly the rows it cannot prove complete."""

from __future__ import annotations

import csv
import io
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

from auvplan import cli
from auvplan.app.bench.job import BENCH_NAMES as _BENCH_NAMES
from auvplan.app.bench.rows import COLUMNS, KEY, read_rows
from auvplan.app.bench.sweep import SweepSpec, _todo
from auvplan.io.files import outdir
from auvplan.io.files.manifest import MANIFEST, written
from auvplan.io.files.outdir import LOCK
from auvplan.io.files.safeio import atomic_write, prepare_out, save_figure
from auvplan.viz.plots import bench_figures

SCENARIO = "track-single"  # the fastest built-in `run` (about 3 s)


@pytest.fixture(autouse=True)
def _release_locks():
    yield
    outdir.release_all()


def _auvplan(*args: str, pre: str = "") -> subprocess.CompletedProcess[str]:
    """Run the command line in a fresh interpreter, after the Python statements ``pre``."""
    code = f"import sys\n{pre}\nfrom auvplan import cli\nsys.exit(cli.main(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code, "-q", *args], capture_output=True, text=True, timeout=300)


def _assert_whole(out: Path) -> None:
    """A finished results folder: no temporary left, every file present listed in the manifest."""
    names = {p.name for p in out.iterdir()}
    assert not [n for n in names if n.endswith(".tmp")], names
    mine = written(out)
    assert names - {MANIFEST, LOCK} <= mine, names - mine
    assert {"run.json", "run.npz", "track.csv", "report.html", "sim_metrics.json"} <= names
    json.loads((out / "run.json").read_text())


_KILL_AT = """
import os, signal
_real, _n, _out = os.replace, [0], {out!r}
def _replace(a, b, **kw):
    if os.path.dirname(os.fspath(b)) != _out:  # numba's cache files (a cold cache): not a point of the count
        return _real(a, b, **kw)
    _n[0] += 1
    if _n[0] == {k} and {before}:
        os.kill(os.getpid(), signal.SIGKILL)
    _real(a, b, **kw)
    if _n[0] == {k}:
        os.kill(os.getpid(), signal.SIGKILL)
os.replace = _replace
"""
"""Kill the process at the k-th atomic replace in ``--out`` (just before it, or just after it), whatever numba's
cache holds."""


def test_a_run_killed_while_writing_is_completed_by_a_re_run(tmp_path):
    """SIGKILL at seeded random points of the writing (before and after a replace of the manifest or
    of a result file), then the same command again, without --force: it completes and the folder
    is whole (no 'a file auvplan did not write', no temporary manifest left)."""
    rng = np.random.default_rng(32)  # one point per test run (each costs two runs); tools/ can sweep them all
    for i, (k, before) in enumerate([(int(rng.integers(1, 21)), bool(rng.integers(2)))]):
        out = tmp_path / f"r{i}"
        killed = _auvplan("run", SCENARIO, "--out", str(out), pre=_KILL_AT.format(k=k, before=before, out=str(out)))
        assert killed.returncode == -signal.SIGKILL, (k, killed.stderr[-400:])
        again = _auvplan("run", SCENARIO, "--out", str(out))
        assert again.returncode == 0, (k, before, again.stderr[-400:])
        _assert_whole(out)


def test_a_run_killed_from_outside_is_completed_by_a_re_run(tmp_path):
    out = tmp_path / "r"
    proc = subprocess.Popen([sys.executable, "-m", "auvplan", "-q", "run", SCENARIO, "--out", str(out)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    t0 = time.monotonic()
    while not (out / MANIFEST).exists() and proc.poll() is None and time.monotonic() - t0 < 120:
        time.sleep(0.01)  # polls a state, asserts nothing about time
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    again = _auvplan("run", SCENARIO, "--out", str(out))
    assert again.returncode == 0, again.stderr[-400:]
    _assert_whole(out)


_HELD_AT_FIRST_RESULT = """
import os, time
from pathlib import Path
_real, _gate, _out = os.replace, Path({gate!r}), Path({out!r})
def _replace(a, b, **kw):  # numba's cache files (a cold cache) go by; in --out the first result file waits
    if Path(b).parent == _out and not Path(b).name.startswith(".auvplan") and not _gate.exists():
        Path(str(_gate) + ".waiting").touch()
        while not _gate.exists():
            time.sleep(0.01)
    _real(a, b, **kw)
os.replace = _replace
"""
"""Hold the first run at its first result file (lock taken, manifest written) until the file ``gate`` exists,
so that the second run starts while the first one writes, however loaded the machine."""


def test_two_runs_into_one_folder_one_is_refused(tmp_path, capsys):
    out, gate = tmp_path / "r", tmp_path / "gate"
    code = f"import sys\n{_HELD_AT_FIRST_RESULT.format(gate=str(gate), out=str(out))}\nfrom auvplan import cli\n" \
           "sys.exit(cli.main(sys.argv[1:]))"
    first = subprocess.Popen([sys.executable, "-c", code, "-q", "run", SCENARIO, "--out", str(out)],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        waiting = Path(str(gate) + ".waiting")
        while not waiting.exists() and first.poll() is None:
            time.sleep(0.01)  # polls a state: the first run holds the lock and waits at its first result
        assert first.poll() is None, first.stderr.read()[-400:]
        code2 = cli.main(["-q", "run", SCENARIO, "--out", str(out)])
        err = capsys.readouterr().err
    finally:
        gate.touch()
        assert first.wait(timeout=300) == 0, first.stderr.read()[-400:]
    assert code2 == 2 and err.count("\n") == 1, err
    assert f"another auvplan process (pid {first.pid}) is writing into this folder" in err
    _assert_whole(out)  # the first run's folder, untouched by the second
    assert cli.main(["-q", "plan", SCENARIO, "--out", str(out)]) == 2  # one folder, one job (issue #48)
    assert "holds the results of `auvplan run`" in capsys.readouterr().err
    assert cli.main(["-q", "plan", SCENARIO, "--out", str(out), "--force"]) == 0  # the first exited: its lock is gone
    assert not (out / "track.csv").exists()  # the run's files went with --force: no mixed folder


def test_stale_temporaries_of_auvplan_files_are_removed_and_others_kept(tmp_path):
    out = tmp_path / "r"
    atomic_write(out / "run.json", "{}")
    (out / f".{MANIFEST}.ab12_xYz.tmp").write_text("{")  # a manifest rename a kill interrupted
    (out / ".run.json.q1w2e3r4.tmp").write_text("{")
    (out / ".notes.txt.q1w2e3r4.tmp").write_text("the user's")
    prepare_out(out)
    assert sorted(p.name for p in out.iterdir()) == sorted([MANIFEST, LOCK, "run.json", ".notes.txt.q1w2e3r4.tmp"])


def test_a_kill_during_the_writability_probe_leaves_nothing_the_next_run_keeps(tmp_path, monkeypatch):
    """CI saw it: a SIGKILL while the probe file was open left it for good (the re-run never removed it)."""
    out = tmp_path / "r"
    left = []
    real = tempfile.NamedTemporaryFile

    def killed(*args, **kwargs):  # the file is created, then the process dies before it closes
        f = real(*args, **{**kwargs, "delete": False})
        f.close()
        left.append(Path(f.name))
        raise KeyboardInterrupt

    monkeypatch.setattr(tempfile, "NamedTemporaryFile", killed)
    with pytest.raises(KeyboardInterrupt):
        prepare_out(out, job="run")
    monkeypatch.setattr(tempfile, "NamedTemporaryFile", real)
    assert len(left) == 1 and left[0].exists() and left[0].parent == out
    outdir.release_all()
    prepare_out(out, job="run")
    assert sorted(p.name for p in out.iterdir()) == sorted([MANIFEST, LOCK])


def test_the_manifest_names_a_file_before_it_is_written(tmp_path, monkeypatch):
    """A kill between the manifest and the file leaves a name without a file, never a file without its name."""
    seen = []
    real = os.replace

    def spy(a, b, **kw):
        if Path(b).name == "x.json":
            seen.append("x.json" in written(Path(b).parent))
        real(a, b, **kw)

    monkeypatch.setattr(os, "replace", spy)
    atomic_write(tmp_path / "x.json", "1")
    assert seen == [True]


def test_figures_are_written_atomically_and_recorded(tmp_path):
    rows = [{"scenario": "s", "planner": "p", "guidance": "g", "cost": str(c), "status": "EXACT"} for c in (1, 2)]
    out = prepare_out(tmp_path / "b", _BENCH_NAMES)
    [png] = bench_figures(rows, out, save=save_figure)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and "bench.png" in written(out)
    outdir.release_all()
    prepare_out(out, _BENCH_NAMES)  # a --resume of a finished sweep: no --force needed


def _rows_file(path: Path, seeds: range) -> bytes:
    buf = io.StringIO(newline="")
    w = csv.DictWriter(buf, fieldnames=COLUMNS)
    w.writeheader()
    for s in seeds:
        w.writerow({**dict.fromkeys(COLUMNS, "1.5"), "scenario": SCENARIO, "planner": "route", "guidance": "los",
                    "seed": s, "status": "EXACT", "plan_status": "EXACT", "arrived": "True", "wall_s": "0.123456"})
    return buf.getvalue().encode()


def test_resume_after_a_row_cut_at_every_byte_runs_every_row_exactly_once(tmp_path):
    spec = SweepSpec(scenarios=(SCENARIO,), guidance=("los",), seeds=4, chunk=1)
    want = {(SCENARIO, "route", "los", str(s)) for s in range(4)}
    whole = _rows_file(tmp_path / "rows.csv", range(3))
    last = whole.rstrip(b"\r\n").rfind(b"\n") + 1  # start of the last row's line
    assert whole.endswith(b"\r\n")
    for cut in range(last, len(whole) + 1):
        folder = tmp_path / f"c{cut}"
        folder.mkdir()
        (folder / "rows.csv").write_bytes(whole[:cut])
        todo = _todo(spec, folder / "rows.csv", resume=True)
        kept = [tuple(r[k] for k in KEY) for r in read_rows(folder / "rows.csv")]
        again = [(s, p, g, str(x)) for s, p, g, seeds in todo for x in seeds]
        assert sorted(kept + again) == sorted(want), cut  # every row exactly once
        assert len(kept) == (3 if cut == len(whole) else 2), cut
        assert (folder / "rows.csv").read_bytes() == whole[:cut if cut == len(whole) else last], cut


def test_report_figures_are_recorded_so_a_second_report_needs_no_force(tmp_path, capsys):
    out = tmp_path / "r"
    assert cli.main(["-q", "plan", "flow-spheres", "--out", str(out)]) == 0
    assert cli.main(["report", str(out), "--figures"]) == 0
    figs = {p.name for p in (out / "figures").iterdir()} - {MANIFEST}
    assert {"plan_view.png", "profiles.svg"} <= figs and figs == written(out / "figures")
    assert cli.main(["report", str(out), "--figures"]) == 0, capsys.readouterr().err


def test_a_bench_killed_as_it_makes_its_rows_file_is_resumed(tmp_path, monkeypatch):
    """The kill point between the making of ``rows.csv`` (its header written) and the manifest naming it: the
    folder then held a file of auvplan's that ``bench --resume`` refused as a user's ('a file auvplan did not
    write is in the way').  Every file bench opens in its folder is named before (the manifest's rule, for the
    files it appends to in place); the resume completes."""
    import importlib

    from auvplan.app.bench.job import bench

    sweep_mod = importlib.import_module("auvplan.app.bench.sweep")  # the module (the package exports its function)
    spec = SweepSpec(scenarios=(SCENARIO,), guidance=("los",), seeds=2)
    out, late = tmp_path / "b", []
    real_todo, real_open = sweep_mod._todo, Path.open

    def killed_after(*args, **kwargs):  # rows.csv made (header), then the process dies
        real_todo(*args, **kwargs)
        raise KeyboardInterrupt

    def spy(self, mode="r", *args, **kwargs):
        if any(c in mode for c in "wax") and self.parent == out and self.name not in written(out):
            late.append(self.name)
        return real_open(self, mode, *args, **kwargs)

    monkeypatch.setattr(Path, "open", spy)
    monkeypatch.setattr(sweep_mod, "_todo", killed_after)
    with pytest.raises(KeyboardInterrupt):
        bench(spec, out, workers=0)
    monkeypatch.setattr(sweep_mod, "_todo", real_todo)
    outdir.release_all()
    assert (out / "rows.csv").is_file() and late == []
    _, rows, _ = bench(spec, out, workers=0, resume=True)
    assert [r["seed"] for r in rows] == ["0", "1"] and late == []
    names = {p.name for p in out.iterdir()}
    assert names - {MANIFEST, LOCK} <= written(out) and not [n for n in names if n.endswith(".tmp")], names


# ---- mutants21 (docs/mutants.md section 8): the folder's lock, its clean-up on failure, and what --force removes


def test_the_lock_file_names_its_holder_and_a_second_holder_is_refused_naming_it(tmp_path):
    """Held by another open file (as another process would hold it; no process, no timing): refused, naming the
    pid written in the lock file, '?' when it is empty; ours names this process, an ordinary 0644 file."""
    import fcntl
    import stat

    for text, named in (("4242\n", "pid 4242"), ("", "pid ?")):
        out = tmp_path / f"held{len(text)}"
        out.mkdir()
        (out / LOCK).write_text(text)
        fd = os.open(out / LOCK, os.O_RDWR)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            holder = rf"another auvplan process \({re.escape(named)}\) is writing"
            with pytest.raises(outdir.OutputError, match=holder):
                prepare_out(out)
        finally:
            os.close(fd)
    out = prepare_out(tmp_path / "mine")
    assert (out / LOCK).read_text() == f"{os.getpid()}\n"
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE((out / LOCK).stat().st_mode) == 0o644 & ~mask


def test_a_released_folder_can_be_locked_again_and_a_linked_lock_file_is_refused(tmp_path):
    import fcntl

    out = prepare_out(tmp_path / "r")
    fd = os.open(out / LOCK, os.O_RDWR)
    try:
        with pytest.raises(BlockingIOError):  # held by prepare_out's descriptor
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        outdir.release(out)
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # released: the descriptor was closed
    finally:
        os.close(fd)
    linked = tmp_path / "l"
    linked.mkdir()
    (linked / LOCK).symlink_to(tmp_path / "elsewhere")
    with pytest.raises(outdir.OutputError, match=r"\.auvplan\.lock: is a symbolic link; auvplan does not follow it"):
        prepare_out(linked)
    assert not (tmp_path / "elsewhere").exists()


def test_missing_parents_are_made_and_links_named_like_temporaries_are_left(tmp_path):
    """prepare_out and atomic_write make every missing folder of their path; a symbolic link named like a
    temporary, or the temporaries behind a linked --out, are not auvplan's to remove."""
    out = prepare_out(tmp_path / "a" / "b" / "out")
    assert sorted(p.name for p in out.iterdir()) == [LOCK]
    atomic_write(tmp_path / "c" / "d" / "x.json", "{}")
    assert (tmp_path / "c" / "d" / "x.json").read_text() == "{}"
    user = tmp_path / "user.txt"
    user.write_text("mine")
    (out / ".run.json.q1w2e3r4.tmp").symlink_to(user)
    real = tmp_path / "real"
    real.mkdir()
    (real / ".run.json.a1s2d3f4.tmp").write_text("{")
    (tmp_path / "linked").symlink_to(real)
    outdir.release_all()
    prepare_out(out)
    prepare_out(tmp_path / "linked")
    assert (out / ".run.json.q1w2e3r4.tmp").is_symlink() and user.read_text() == "mine"
    assert (real / ".run.json.a1s2d3f4.tmp").read_text() == "{"


def test_force_removes_another_job_s_files_even_when_a_kill_left_a_name_without_its_file(tmp_path):
    """The manifest names a file before it is written: a run killed there leaves a name without a file; --force
    for another job removes the files that are there (not a link) and starts the manifest afresh."""
    out = prepare_out(tmp_path / "r", job="run")
    atomic_write(out / "track.csv", "t\n")
    (tmp_path / "user.csv").write_text("mine")
    (out / "path.csv").symlink_to(tmp_path / "user.csv")
    (out / MANIFEST).write_text(json.dumps({"files": ["path.csv", "run.json", "track.csv"], "job": "run"}))
    outdir.release_all()
    prepare_out(out, ["path.csv"], job="plan", force=True)
    assert not (out / "track.csv").exists() and (tmp_path / "user.csv").read_text() == "mine"
    assert json.loads((out / MANIFEST).read_text())["job"] == "plan"


def test_a_failed_block_removes_the_folders_it_made_and_nothing_else(tmp_path, monkeypatch):
    """discard_on_failure: the new --out, its empty checkpoint folders (nested) and the parents made for it go;
    a folder holding a result, one that existed, and the working folder stay; the block's error is raised."""
    from auvplan.io.files.safeio import discard_on_failure

    monkeypatch.chdir(tmp_path)  # a clean-up of the working folder instead of --out would show here
    (tmp_path / "keep").mkdir()
    with pytest.raises(RuntimeError, match="planner failed"):
        with discard_on_failure(tmp_path / "new" / "deeper" / "out"):
            out = prepare_out(tmp_path / "new" / "deeper" / "out", job="sweep")
            (out / ".auvplan-tasks" / "a" / "b").mkdir(parents=True)
            raise RuntimeError("planner failed")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep"]
    with pytest.raises(RuntimeError):
        with discard_on_failure(tmp_path / "done"):
            atomic_write(prepare_out(tmp_path / "done") / "run.json", "{}")
            raise RuntimeError("after a result")
    assert sorted(p.name for p in (tmp_path / "done").iterdir()) == sorted([LOCK, MANIFEST, "run.json"])
    with pytest.raises(RuntimeError):
        with discard_on_failure(tmp_path / "keep"):
            prepare_out(tmp_path / "keep")
            raise RuntimeError("an existing folder")
    with pytest.raises(RuntimeError), discard_on_failure(None):
        raise RuntimeError("no --out")
    assert (tmp_path / "keep").is_dir() and (tmp_path / "keep" / LOCK).exists()
