"""The one mapper of independent tasks (auvplan.runtime.parallel): same results in this process, on threads and on
worker processes; a failed task run again; a crashed job resumed from its checkpoints without recomputing
what it had finished."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from auvplan.errors import AuvplanError
from auvplan.runtime.parallel import Runner, forget, task_key
from helpers import coarse_tides


def _draw(seed: int) -> np.ndarray:
    """A seeded task: its result depends on its seed only (oracle: the same draw made here)."""
    return np.random.default_rng(seed).standard_normal(4)


def _offset_draw(offset: float, seed: int) -> np.ndarray:
    """A task with a shared argument."""
    return offset + _draw(seed)


def _flaky(task: tuple[str, int]) -> np.ndarray:
    """Fails on its first run for seed 2 (a marker file says it ran), whichever process runs it."""
    folder, seed = task
    marker = Path(folder) / f"ran-{seed}"
    if seed == 2 and not marker.exists():
        marker.touch()
        raise RuntimeError("the first run of task 2 fails")
    return _draw(seed)


def _crash_at(task: tuple[str, int]) -> np.ndarray:
    """Fails for seed 3 while the file 'crash' is in the folder: a job killed part of the way."""
    folder, seed = task
    if seed == 3 and (Path(folder) / "crash").exists():
        raise RuntimeError("killed")
    (Path(folder) / f"computed-{seed}").touch()
    return _draw(seed)


SEEDS = [5, 1, 3, 9, 2, 7]
EXPECTED = [_draw(s) for s in SEEDS]


@pytest.fixture(scope="module")
def scheduler():
    """One dask scheduler with two single-threaded workers in this process for the whole module (a cluster of
    processes costs seconds to start; bench's tests run the LocalCluster of processes through the same Runner)."""
    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None,
                      scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as cluster:
        yield cluster.scheduler_address


def test_in_process_and_two_workers_give_the_tasks_own_results_in_order(scheduler):
    calls, said = [], []
    one = Runner().map(_offset_draw, SEEDS, shared=10.0, progress=lambda d, n: calls.append((d, n)))
    two = Runner(scheduler=scheduler, announce=said.append).map(_offset_draw, SEEDS, shared=10.0)
    assert said[0] == f"reaching the dask scheduler at {scheduler} …"  # a stage line: never silent (issue 56)
    assert said[1].startswith("2 dask workers ready in ") and said[1].endswith(" s; 6 tasks to run")
    for a, b, e in zip(one.results, two.results, EXPECTED, strict=True):
        assert np.array_equal(a, 10.0 + e) and np.array_equal(b, a)  # bit for bit, in task order
    assert one.computed == two.computed == len(SEEDS) and one.reused == 0
    assert calls[0] == (0, 6) and calls[-1] == (6, 6)


def test_a_failed_task_runs_again(tmp_path, scheduler):
    tasks = [(str(tmp_path), s) for s in SEEDS]
    got = Runner(scheduler=scheduler, retries=1).map(_flaky, tasks)  # dask's retries: seed 2 fails once
    assert all(np.array_equal(a, e) for a, e in zip(got.results, EXPECTED, strict=True))
    assert (tmp_path / "ran-2").exists()
    (tmp_path / "ran-2").unlink()
    with pytest.raises(RuntimeError, match="first run of task 2"):
        Runner(retries=0).map(_flaky, tasks)  # no retry: the failure is the job's
    (tmp_path / "ran-2").unlink()
    with pytest.raises(RuntimeError, match="first run of task 2"):  # a job that fails before any checkpoint
        Runner(retries=0, checkpoints=tmp_path / "ckpt").map(_flaky, tasks[4:5], [task_key("flaky", 2)])
    assert not (tmp_path / "ckpt").exists()  # leaves no empty checkpoint folder behind


@pytest.mark.parametrize("distributed", [False, True], ids=["in-process", "two-workers"])
def test_a_crashed_job_resumes_without_recomputing_its_finished_tasks(tmp_path, scheduler, distributed):
    address = scheduler if distributed else None
    work, ckpt = tmp_path / "work", tmp_path / "ckpt"
    work.mkdir()
    (work / "crash").touch()
    tasks = [(str(work), s) for s in SEEDS]
    keys = [task_key("test", s) for s in SEEDS]
    with pytest.raises(RuntimeError, match="killed"):
        Runner(scheduler=address, retries=0, checkpoints=ckpt).map(_crash_at, tasks, keys)
    finished = {p.stem for p in ckpt.glob("*.pkl")}
    assert keys[SEEDS.index(3)] not in finished
    if not distributed:
        assert finished == set(keys[:2])  # in this process: the two tasks before the crash
    for p in work.glob("computed-*"):
        p.unlink()
    (work / "crash").unlink()
    arrived = []
    again = Runner(scheduler=address, checkpoints=ckpt).map(
        _crash_at, tasks, keys, on_result=lambda i, r: arrived.append(i))
    assert again.reused == len(finished) and again.computed == len(SEEDS) - len(finished)
    assert len(list(work.glob("computed-*"))) == again.computed  # the finished ones were not run again
    assert sorted(arrived) == list(range(len(SEEDS)))
    assert all(np.array_equal(a, e) for a, e in zip(again.results, EXPECTED, strict=True))
    (ckpt / f".{keys[0]}.k1ll3d_x.tmp").write_bytes(b"\x80\x05half")  # what a kill -9 mid-write leaves
    (ckpt / "other.pkl").write_bytes(b"not this job's")
    forget(ckpt, keys)
    assert sorted(p.name for p in ckpt.iterdir()) == ["other.pkl"]  # the job's files gone, nothing else
    (ckpt / "other.pkl").unlink()
    forget(ckpt, keys)
    assert not ckpt.exists()


def test_checkpoints_never_go_through_a_link_and_a_cut_file_is_recomputed(tmp_path):
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "ckpt").symlink_to(tmp_path / "elsewhere")
    with pytest.raises(AuvplanError, match="checkpoint folder is a link"):
        Runner(checkpoints=tmp_path / "ckpt").map(_draw, [1], [task_key(1)])
    ckpt = tmp_path / "real"
    ckpt.mkdir()
    (ckpt / f"{task_key(1)}.pkl").write_bytes(b"\x80\x05cut")  # a file cut short: run the task again
    got = Runner(checkpoints=ckpt).map(_draw, [1], [task_key(1)])
    assert got.computed == 1 and np.array_equal(got.results[0], _draw(1))
    assert task_key("a", 1) != task_key("a", 1.0000001) and len(task_key()) == 64


def _table(run) -> list[dict]:
    """A sweep's rows without the CPU seconds (a measurement, not a result)."""
    return [{k: v for k, v in row.items() if k != "cpu_s"} for row in run.table]


def test_departure_sweep_killed_resumes_and_two_workers_give_the_same_rows(tmp_path, scheduler, monkeypatch):
    from auvplan.app import sweep as job

    scenario, out = coarse_tides(tmp_path), tmp_path / "out"
    real, done = job._departure, []

    def killed_at_the_second(shared, depart):  # a crash after the first departure
        if len(done) == 1:
            raise RuntimeError("killed")
        done.append(depart)
        return real(shared, depart)

    monkeypatch.setattr(job, "_departure", killed_at_the_second)
    with pytest.raises(RuntimeError, match="killed"):
        job.sweep_scenario(str(scenario), ["+0h", "+6h"], "6h", out=str(out), runner=Runner(retries=0))
    assert len(list((out / ".auvplan-tasks").glob("*.pkl"))) == 1
    monkeypatch.setattr(job, "_departure", real)
    job._SETUP.clear()  # a new process after the kill
    said: list[str] = []
    resumed = job.sweep_scenario(str(scenario), ["+0h", "+6h"], "6h", out=str(out), force=True, stage=said.append)
    assert resumed.computed == 1  # the second departure only
    assert said == [f"writing sweep.csv, sweep_summary.json, sweep.png to {out} …"]  # the tail is told
    assert not (out / ".auvplan-tasks").exists()  # the sweep's files are written: its checkpoints are gone
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    job._SETUP.clear()  # the workers build the sweep's lattice and table themselves
    two = job.sweep_scenario(str(scenario), ["+0h", "+6h"], "6h", runner=Runner(scheduler=scheduler))
    assert two.computed == 2 and [r.depart_s for r in two.rows] == [0.0, 21600.0]
    assert _table(two) == _table(resumed)  # bit for bit: durations, energies, points of no return
    assert not (tmp_path / "cache" / "auvplan").exists()  # no empty folder left in the user's cache
    assert {k: v for k, v in two.summary.items() if k != "cpu_per_departure_s"} == {
        k: v for k, v in resumed.summary.items() if k != "cpu_per_departure_s"}
    assert all(np.isfinite(r.duration_s) and r.duration_s <= r.steady_duration_s * (1 + 1e-6) for r in two.rows)


def test_workers_and_scheduler_are_one_choice(capsys):
    from auvplan.cli import main

    assert main(["plan", "juan-de-fuca-tides", "--depart-between", "+0h", "+1h", "--workers", "2",
                 "--scheduler", "tcp://127.0.0.1:8786"]) == 2
    assert "not allowed with argument" in capsys.readouterr().err
    assert main(["survey", "shelf-survey", "--workers", "0"]) == 2  # at least one worker, or none given

