"""``tools/mutate.py`` kills a mutant whose tests wait for ever (no CPU used) at its wall-clock limit, with the
subprocesses its tests started, and counts it caught by a timeout, reported as a wall-clock one.  Its only limit
was CPU time (the fallback, 100x that limit, was at least 17 min): a mutant that made a test block on a lock, an
event or a hung subprocess stalled the run.

The hang is a child blocked on reading a pipe nobody writes (no race: it is blocked whenever it is polled), with
a grandchild blocked the same way; the wall-clock limit is passed a fake clock, not waited for."""

from __future__ import annotations

import contextlib
import os
import select
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[2] / "tools"))

import mutate  # noqa: E402


def test_a_hung_mutant_is_killed_at_the_wall_clock_limit_with_its_subprocesses():
    block_r, block_w = os.pipe()  # nobody writes: reading it blocks for ever, using no CPU
    alive_r, alive_w = os.pipe()  # held open by the child and the grandchild: EOF once both are dead
    ready_r, ready_w = os.pipe()  # one byte from each when it is about to block

    def hang() -> None:
        os.close(alive_r)
        os.fork()  # the grandchild (a test's subprocess) hangs too
        os.write(ready_w, b"x")
        os.read(block_r, 1)

    pid = mutate._fork([], hang)
    os.close(alive_w)
    os.close(ready_w)
    try:
        got = b""
        while len(got) < 2:  # both hold the pipe before the limit is judged (else there is no grandchild to kill)
            chunk = os.read(ready_r, 2)
            assert chunk, "the child died before it hung"
            got += chunk
        assert mutate._reap(pid, started=0.0, cpu_limit=1e9, wall_limit=100.0, now=lambda: 50.0) is None
        got = mutate._reap(pid, started=0.0, cpu_limit=1e9, wall_limit=100.0, now=lambda: 100.5)
        assert got == ("timeout", -9, "wall")
        ready, _, _ = select.select([alive_r], [], [], 60.0)  # a safety net: the group is dead at once
        assert ready and os.read(alive_r, 1) == b""  # EOF: no process of the group holds the pipe
    finally:
        with contextlib.suppress(OSError):
            os.killpg(pid, 9)
        for fd in (block_r, block_w, alive_r, ready_r):
            os.close(fd)


def test_a_finished_mutant_is_its_exit_status():
    pid = mutate._fork([], lambda: os._exit(3))
    got = None
    while got is None:  # polled until the child has exited (a state), never a pause as the oracle
        got = mutate._reap(pid, started=0.0, cpu_limit=1e9, wall_limit=1e9, now=lambda: 0.0)
    assert got == ("killed", 3, "")


def test_the_report_counts_wall_clock_timeouts_as_caught_and_names_them():
    ms = [{"status": "killed"}, {"status": "timeout", "timeout": "cpu"}, {"status": "timeout", "timeout": "wall"},
          {"status": "survived"}, {"status": "not run"}]
    s = mutate.summary({"mutants": ms})
    assert (s["tested"], s["killed"], s["timeout"], s["timeout_wall"], s["survived"]) == (4, 1, 2, 1, 1)
    assert s["score"] == 3 / 4  # a timeout is a caught mutant
    assert mutate._timeouts(s) == "2 (1 wall)"
