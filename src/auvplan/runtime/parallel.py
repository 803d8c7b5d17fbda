"""Embarrassingly parallel jobs on dask.distributed: the one mapper every long job uses (``bench``, the departure
sweep of ``plan --depart-between``, the robust candidates of an ensemble plan, ``survey``).

A :class:`Runner` maps a top-level function over a list of tasks

* in this process (``workers=0``, no scheduler: dask is not even imported),
* on a ``LocalCluster`` of ``workers`` single-threaded processes (``--workers N``), or
* on an existing scheduler (``--scheduler tcp://host:8786``, e.g. a dask-jobqueue ``SLURMCluster``'s:
  ``docs/parallel.md``).

A task that raises is run again up to ``retries`` times (dask's ``retries=``; the same count in this
process).  With a ``checkpoints`` folder and a key per task (:func:`task_key`: the hash of everything the
task's result depends on), each result is pickled into ``<checkpoints>/<key>.pkl`` as it arrives — by
this process, atomically (a temporary file and one ``os.replace``), never by a worker, whose disk may be
another machine's — and a task whose file is there is not run again: a killed job, run again, computes
only the tasks it had not finished.  The folder holds only those files and is made with the first of them;
a symbolic link or a file in its place is refused.  :func:`forget` removes a finished job's files, its folder
once empty and, under the cache (:func:`cache_folder`), the cache's own folders once empty.

Starting the workers (a ``LocalCluster`` spawns processes that import dask) or reaching a scheduler takes
seconds: an ``announce`` callable is told when it starts and when it is done (the command line prints those
as stage lines; issue 56, never silent).

Results come back in task order whatever order they finish in, and nothing a task computes depends on
the worker that runs it (each task carries its own seed), so 1 and N workers give the same results.
"""

from __future__ import annotations

import contextlib
import hashlib
import logging
import os
import pickle
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Generic, TypeVar

from ..errors import AuvplanError, require

__all__ = ["Runner", "MapResult", "task_key", "cache_folder", "forget", "CHECKPOINTS", "SCHEDULER_CONNECT_S"]

T = TypeVar("T")
R = TypeVar("R")

CHECKPOINTS = ".auvplan-tasks"
"""Name of the checkpoint folder inside a job's output folder."""

SCHEDULER_CONNECT_S = 5.0
"""Longest wait to reach a ``--scheduler`` and hear its handshake (s; dask's ``distributed.comm.timeouts.connect``
when shorter): a scheduler that is up answers in milliseconds, and dask's own 30 s kept a dead address silent for
half a minute."""


def task_key(*parts: object) -> str:
    """The key of a task: the SHA-256 of the ``repr`` of everything its result depends on.

    Numpy arrays among them (a moving obstacle's waypoints in a scenario) are written whole and to the last
    bit (numpy's own ``repr`` rounds to 8 digits and elides all but the ends of an array over 1000 values).

    Parameters
    ----------
    *parts : object
        The job's name, the package version, the inputs (frozen dataclasses and numbers: their ``repr`` is
        their value).

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    import numpy as np

    with np.printoptions(threshold=sys.maxsize, floatmode="unique"):
        text = repr(parts)
    return hashlib.sha256(text.encode()).hexdigest()


def cache_folder(job: str) -> Path:
    """The checkpoint folder of a job run without an output folder (``$XDG_CACHE_HOME/auvplan/tasks/JOB``).

    Parameters
    ----------
    job : str
        The job's name.

    Returns
    -------
    pathlib.Path
        The folder (not created).
    """
    return _cache_root() / "tasks" / job


def _cache_root() -> Path:
    """``$XDG_CACHE_HOME/auvplan`` (``~/.cache/auvplan``)."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "auvplan"


@dataclass(frozen=True)
class MapResult(Generic[R]):
    """What :meth:`Runner.map` returns.

    Attributes
    ----------
    results : list
        One per task, in task order.
    computed : int
        Tasks run (their results were not checkpointed).
    reused : int
        Tasks whose checkpoint was read instead.
    """

    results: list[R]
    computed: int
    reused: int


@dataclass(frozen=True)
class Runner:
    """Where and how a job's tasks run (module notes).

    Attributes
    ----------
    workers : int
        Local worker processes (a ``LocalCluster``); 0 runs the tasks one by one in this process.
    scheduler : str, optional
        Address of an existing dask scheduler (overrides ``workers``).
    retries : int
        Runs again of a task that raised, before the job fails.
    checkpoints : pathlib.Path, optional
        Folder of the per-task checkpoints (none without it).
    processes : bool
        Worker processes (True) or threads of this process (False: a quick cluster for tests).
    announce : callable, optional
        Told in a sentence when the workers start or the scheduler is reached, and when they are ready (a
        stage line on stderr; None: nothing said).
    """

    workers: int = 0
    scheduler: str | None = None
    retries: int = 1
    checkpoints: Path | None = None
    processes: bool = True
    announce: Callable[[str], None] | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        if self.workers < 0 or self.retries < 0:
            raise AuvplanError(f"workers {self.workers}, retries {self.retries}: need 0 or more")

    @property
    def distributed(self) -> bool:
        """Whether the tasks run on dask (a scheduler or local workers)."""
        return bool(self.scheduler) or self.workers > 0

    def map(self, fn: Callable[..., R], tasks: Sequence[T], keys: Sequence[str] | None = None, shared: Any = None,
            progress: Callable[[int, int], None] | None = None,
            on_result: Callable[[int, R], None] | None = None) -> MapResult[R]:
        """Run ``fn`` on every task (``fn(shared, task)`` when ``shared`` is given, else ``fn(task)``).

        Parameters
        ----------
        fn : callable
            A module-level function (pickled to the workers).
        tasks : sequence
            The tasks (picklable).
        keys : sequence of str, optional
            One :func:`task_key` per task: their checkpoints (with ``checkpoints``).
        shared : object, optional
            What every task needs (sent once to each worker, not once per task).
        progress : callable, optional
            Called as ``progress(done, total)`` as tasks finish (checkpointed ones first).
        on_result : callable, optional
            Called as ``on_result(index, result)`` in this process as each result arrives.

        Returns
        -------
        MapResult
            The results in task order, and how many were computed or read back.
        """
        if keys is not None and len(keys) != len(tasks):
            raise ValueError("one key per task")
        folder = _folder(self.checkpoints) if keys is not None else None
        results: dict[int, R] = {}
        for i in range(len(tasks)):
            done = _load(folder, keys[i]) if folder is not None and keys is not None else None
            if done is not None:
                results[i] = done[0]
        reused = len(results)

        def arrived(i: int, result: R) -> None:
            if folder is not None and keys is not None:
                _save(folder, keys[i], result)
            results[i] = result
            if on_result is not None:
                on_result(i, result)
            if progress is not None:
                progress(len(results), len(tasks))

        for i in sorted(results):
            if on_result is not None:
                on_result(i, results[i])
        if progress is not None:
            progress(reused, len(tasks))
        todo = [i for i in range(len(tasks)) if i not in results]
        call = fn if shared is None else _Bound(fn, shared)
        if not self.distributed:
            for i in todo:
                arrived(i, self._retry(call, tasks[i]))
        elif todo:
            self._dask(fn, shared, [(i, tasks[i]) for i in todo], arrived)
        return MapResult([results[i] for i in range(len(tasks))], len(todo), reused)

    def _retry(self, call: Callable[[T], R], task: T) -> R:
        for attempt in range(self.retries + 1):
            try:
                return call(task)
            except Exception:
                if attempt == self.retries:
                    raise
                logging.getLogger(__name__).warning("task failed; running it again (%d of %d)", attempt + 1,
                                                    self.retries)
        raise AssertionError("unreachable")

    def _dask(self, fn: Callable[..., R], shared: Any, todo: list[tuple[int, T]],
              arrived: Callable[[int, R], None]) -> None:
        require("dask", "bench")
        from dask.distributed import KilledWorker, as_completed

        log = logging.getLogger("distributed")  # its start-up lines only with -v (a root logger at INFO)
        level = log.level
        if logging.getLogger().getEffectiveLevel() > logging.INFO:
            log.setLevel(logging.WARNING)
        say = self.announce or (lambda _: None)
        t0 = time.monotonic()
        client, cluster = self._connect(say)
        futures: dict[Any, int] = {}
        try:
            n = len(client.scheduler_info().get("workers", {}))
            say(f"{_count(n, 'dask worker')} ready in {time.monotonic() - t0:.1f} s; {_count(len(todo), 'task')} "
                "to run")
            args = () if shared is None else (client.scatter(shared, broadcast=True),)
            futures = {client.submit(fn, *args, task, pure=False, retries=self.retries): i for i, task in todo}
            for fut in as_completed(futures):
                try:
                    result = fut.result()
                except KilledWorker as exc:  # the worker process died under it (killed: out of memory?)
                    raise AuvplanError(f"task {futures[fut] + 1} of the job: every dask worker that ran it died while "
                                       "running it (killed, out of memory?); the tasks finished before are kept "
                                       "when the job checkpoints them: run it again with fewer --workers") from exc
                arrived(futures[fut], result)
        finally:
            client.cancel(list(futures))
            client.close()
            if cluster is not None:
                say("stopping the dask workers …")
                # a worker still tearing down after 4 s is killed: dask's warning of it is no news here
                log.setLevel(max(log.getEffectiveLevel(), logging.ERROR))
                cluster.close()
            log.setLevel(level)

    def _connect(self, say: Callable[[str], None]) -> tuple[Any, Any]:
        """A client of the scheduler, or of a new ``LocalCluster`` (returned too, to be closed)."""
        from dask.distributed import Client, LocalCluster

        if self.scheduler:
            import dask
            from dask.utils import parse_timedelta

            wait = min(float(parse_timedelta(dask.config.get("distributed.comm.timeouts.connect"), "s") or 0.0)
                       or SCHEDULER_CONNECT_S, SCHEDULER_CONNECT_S)
            say(f"reaching the dask scheduler at {self.scheduler} …")
            try:
                _handshake(self.scheduler, wait)
                return Client(self.scheduler, timeout=wait), None
            except (OSError, ValueError, TypeError) as exc:  # no scheduler there, or an address dask cannot parse
                text = " ".join(str(exc).split()) or type(exc).__name__
                raise AuvplanError(f"--scheduler {self.scheduler!r}: no dask scheduler reached there within {wait:g} s "
                                   f"({text})") from exc
        say(f"starting {_count(self.workers, 'dask worker')} ({'processes' if self.processes else 'threads'}: "
            "a LocalCluster) …")
        # the scheduler's HTTP server (health checks, no dashboard) on a free local port: on its default,
        # 8787, taken by another cluster, dask warns on stderr
        cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=self.processes,
                               dashboard_address=None, silence_logs=logging.WARNING,
                               scheduler_kwargs={"dashboard_address": "127.0.0.1:0"})
        return Client(cluster), cluster


def _handshake(address: str, wait: float) -> None:
    """Connect to the scheduler at ``address`` and hear its handshake within ``wait`` (s), or raise ``OSError``.

    dask's ``Client`` bounds the TCP connection by its timeout, then waits for the handshake with none: an address
    that accepts and stays silent (another service on the port, a proxy) hung the job for good; one that answers
    something else (an HTTP server: the dashboard's port 8787) was read as a frame of exabytes, a ``MemoryError``
    traceback.  Run on a thread of its own (its own event loop, whatever the caller runs)."""
    import asyncio
    from concurrent.futures import ThreadPoolExecutor

    from distributed.comm.core import connect
    from distributed.security import Security

    async def reach() -> None:
        try:
            comm = await asyncio.wait_for(connect(address, timeout=wait, **Security().get_connection_args("client")),
                                          wait)
        except TimeoutError as exc:  # connect's own timeouts are OSErrors naming the address
            raise OSError(f"connected, but no dask handshake came back within {wait:g} s") from exc
        except (OSError, ValueError, TypeError):  # the Runner's own message names them (a TLS setup's too)
            raise
        except Exception as exc:  # a frame of garbage read as a length: MemoryError ...
            raise OSError(f"something answered, but not a dask scheduler ({type(exc).__name__}; the dashboard's "
                          "port?)") from exc
        await comm.close()

    with ThreadPoolExecutor(1) as pool:
        pool.submit(asyncio.run, reach()).result()


def _count(n: int, noun: str) -> str:
    """``"1 task"``, ``"2 tasks"``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


@dataclass(frozen=True)
class _Bound:
    """``fn`` with its shared first argument (in this process)."""

    fn: Callable[..., Any]
    shared: Any

    def __call__(self, task: Any) -> Any:
        return self.fn(self.shared, task)


def _folder(path: Path | None) -> Path | None:
    """The checkpoint folder (made with its first checkpoint); a link or a file in its place is refused."""
    if path is None:
        return None
    path = Path(path)
    if path.is_symlink() or (path.exists() and not path.is_dir()):
        raise AuvplanError(f"{path}: the checkpoint folder is a link or a file; auvplan writes only a folder of "
                           "its own there")
    return path


def _load(folder: Path, key: str) -> tuple[Any] | None:
    """The checkpointed result of a task (in a 1-tuple), or None (no file, or one that does not read)."""
    p = folder / f"{key}.pkl"
    if p.is_symlink() or not p.is_file():
        return None
    try:
        with p.open("rb") as fh:
            return (pickle.load(fh),)
    except Exception:  # cut short or from another version: run the task again
        return None


def _save(folder: Path, key: str, result: Any) -> None:
    """Checkpoint a result: a temporary file in the folder, then one ``os.replace``."""
    folder.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{key}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            pickle.dump(result, fh, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(tmp, folder / f"{key}.pkl")
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def forget(folder: Path | None, keys: Sequence[str]) -> None:
    """Remove the checkpoints of a finished job (with the temporaries a killed write left), the folder when
    nothing else is in it and, for a folder under the cache (:func:`cache_folder`), the cache's folders left
    empty (no empty folder stays in ``~/.cache``).

    Parameters
    ----------
    folder : pathlib.Path, optional
        The checkpoint folder.
    keys : sequence of str
        The job's task keys.
    """
    if folder is None or Path(folder).is_symlink() or not Path(folder).is_dir():
        return
    for key in keys:  # each checkpoint and any temporary of it a kill left half-written (``.KEY.XXXX.tmp``)
        for p in [Path(folder) / f"{key}.pkl", *Path(folder).glob(f".{key}.*.tmp")]:
            with contextlib.suppress(OSError):
                p.unlink()
    root = _cache_root()
    chain = [Path(folder)] + [p for p in Path(folder).parents if p == root or root in p.parents]
    for empty in chain:  # the folder, then (under the cache) each parent up to the cache's own, while empty
        try:
            empty.rmdir()
        except OSError:
            return
