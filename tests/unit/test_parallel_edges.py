"""What the mapper's first tests never varied.

A task whose dask workers all died under it (``KilledWorker``: a worker process killed, out of memory) ends the
job with one line (exit 2), the tasks finished before it checkpointed; it was a traceback.  The cluster is a
stand-in (a real one takes seconds to start and to lose its worker three times: `os._exit` in a task under
``Runner(workers=1)`` reproduces it, ~4 s)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from dask.distributed import KilledWorker

from auvplan.errors import AuvplanError
from auvplan.runtime.parallel import Runner, task_key


class _Future:
    def __init__(self, fn, task):
        self.fn, self.task = fn, task

    def result(self):
        if self.task == "dies":
            raise KilledWorker("dies-0", None, 3)
        return self.fn(self.task)


class _Client:
    def scheduler_info(self):
        return {"workers": {"w0": {}}}

    def submit(self, fn, task, pure, retries):
        return _Future(fn, task)

    def cancel(self, futures):
        pass

    def close(self):
        pass


def test_a_killed_worker_is_the_job_s_error_and_the_finished_tasks_are_kept(tmp_path, monkeypatch):
    monkeypatch.setattr(Runner, "_connect", lambda self, say: (_Client(), None))
    monkeypatch.setattr("dask.distributed.as_completed", lambda futures: iter(list(futures)))
    tasks = ["a", "b", "dies", "c"]
    keys = [task_key("t", t) for t in tasks]
    with pytest.raises(AuvplanError, match=r"^task 3 of the job: every dask worker that ran it died"):
        Runner(workers=2, checkpoints=tmp_path).map(str.upper, tasks, keys)
    assert sorted(p.stem for p in tmp_path.glob("*.pkl")) == sorted(keys[:2])  # a and b, finished before it


@dataclass(frozen=True)
class _Motion:
    """A scenario part holding an array (as ``WaypointMotion`` does)."""

    points: np.ndarray
    speed: float


@pytest.mark.parametrize("n", [3, 400])
def test_a_key_sees_every_value_of_an_array_to_the_last_bit(n):
    """Oracle: the arrays differ, so the keys do (numpy's repr rounded to 8 digits, and elided the middle of an
    array over 1000 values: a sweep resumed after moving an obstacle's waypoint read the old rows back)."""
    pts = np.column_stack([41262.0 + np.arange(n), 61268.0 + np.arange(n), np.full(n, -2422.0)])
    moved, nudged = pts.copy(), pts.copy()
    moved[n // 2, 0] += 0.5  # a waypoint moved half a metre
    nudged[0, 1] = np.nextafter(nudged[0, 1], np.inf)  # the last bit
    keys = {task_key("sweep", _Motion(p, 0.4)) for p in (pts, moved, nudged)}
    assert len(keys) == 3 and task_key("sweep", _Motion(pts.copy(), 0.4)) == task_key("sweep", _Motion(pts, 0.4))
