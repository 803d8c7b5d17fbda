"""What the commands of the command line share: progress on stderr and their output (a human line, or one JSON
object with ``--json``) into a stdout that names itself when it cannot be written (:func:`named_stdout`).  The check
of ``--out`` before any work is each job's (:func:`auvplan.io.files.safeio.prepare_out` in :mod:`auvplan.app`)."""

from __future__ import annotations

import contextlib
import json
import logging
import sys
import threading
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any, TextIO

from ..errors import AuvplanError

if TYPE_CHECKING:
    import argparse

    from ..planners import PlannerSpec

__all__: list[str] = []  # handlers: CLI internals, not library API


class _Live:
    """The one live line on stderr (a bar, or a stage's clock) and a daemon thread that redraws it whenever
    stderr has been quiet for :data:`QUIET_S` (issue 56: no phase of a command is silent for more than ~2 s;
    the redrawn line shows the elapsed time, a bar its rate and estimate).  The planner's, the flight's and
    the loading stage's updates print as before; the thread only fills the silences.  The silence is counted
    from the last line drawn by any live line or stage, not from the new line's start: a stage that follows
    another is drawn once stderr has been quiet for :data:`QUIET_S` in all, where it waited for its own
    :data:`QUIET_S` after the silence before it (1.5-1.9 s at stage changes at a load of 8 on 2 cores)."""

    def __init__(self) -> None:
        self.display: Any = None
        self.stop = threading.Event()
        self.thread: threading.Thread | None = None
        self.drawn = 0.0  # time.time() of the last line drawn by a live line gone, or by a stage

    def said(self) -> None:
        """A line was written to stderr (a stage): the silence starts now."""
        self.drawn = time.time()

    def show(self, bar: Any) -> None:
        """Make ``bar`` the live line (the thread starts with the first; :func:`finish` ends it, before the
        command prints its result)."""
        self._forget(self.display)
        if self.display is None and not self.drawn and bar is not None and not bar.disable:
            self.drawn = bar.start_t  # the command's first line: its own delay (nothing for a quick stage)
        self.display = bar
        if self.thread is None and bar is not None and not bar.disable:
            self.stop.clear()
            self.thread = threading.Thread(target=self._run, name="auvplan-progress", daemon=True)
            self.thread.start()

    def _run(self) -> None:
        while not self.stop.wait(QUIET_S / 3):
            self.tick()

    def tick(self) -> bool:
        """Redraw the live line if stderr has been quiet for :data:`QUIET_S` (the thread's step).

        Returns
        -------
        bool
            Whether it was redrawn.
        """
        bar = self.display
        if bar is None or bar.disable or bar._time() - max(_drew(bar), self.drawn) < QUIET_S:
            return False
        bar.delay = 0  # drawn, even within its delay (the silence began before it): close() clears it
        bar.refresh()
        bar.last_print_t = bar._time()
        return True

    def _forget(self, bar: Any) -> None:
        """A live line is replaced or closed: when it last drew is when the silence started."""
        if bar is not None and hasattr(bar, "start_t"):  # closed or not (a bar disabled from the start has none)
            self.drawn = max(self.drawn, _drew(bar))

    def end(self) -> None:
        """Stop the thread and clear the live line (the command is over, or prints its result)."""
        self.stop.set()
        if self.thread is not None:
            self.thread.join()
            self.thread = None
        if self.display is not None:
            self._forget(self.display)
            self.display.close()
            self.display = None


def _drew(bar: Any) -> float:
    """When a tqdm line last drew (``time.time()``; 0 for one not drawn yet: a stage clock within its delay)."""
    drawn: float = bar.last_print_t
    return drawn if drawn >= bar.start_t + getattr(bar, "delay", 0.0) else 0.0


QUIET_S = 0.75
"""How long stderr stays quiet while a command works before the live line is redrawn (s, :class:`_Live`)."""

LIVE = _Live()
"""The live line of the running command (ended by :func:`finish`)."""


class LogLines(logging.Handler):
    """The command line's log records on stderr above the live line (:func:`stage_line`'s way): a warning that
    comes while a stage's clock is drawn (a reader's, replayed from the cache when the read ends) is a line of
    its own, not written onto the clock's; the clock is redrawn beneath it."""

    def emit(self, record: logging.LogRecord) -> None:
        """Write one record (the handler's format) with ``tqdm.write``."""
        try:
            text = self.format(record)
        except Exception:  # logging's own rule: a record that does not format is reported, not raised
            self.handleError(record)
            return
        from tqdm import tqdm

        tqdm.write(text, file=sys.stderr)
        LIVE.said()


def starting(text: str) -> None:
    """The clock of a command's first stage (its imports), until the job reports (:func:`reporter`)."""
    from tqdm import tqdm

    LIVE.end()
    LIVE.show(_stage_clock(tqdm, text, False))


def stage(text: str) -> None:
    """A stage of a command that has no progress reporter (``survey``): its line on stderr, then its clock as
    the live line, in place of the one before.

    Parameters
    ----------
    text : str
        The stage.
    """
    from tqdm import tqdm

    LIVE.end()
    tqdm.write(f"auvplan: {text} …", file=sys.stderr)
    LIVE.said()
    LIVE.show(_stage_clock(tqdm, text, False))


def finish() -> None:
    """End the running command's live line (called by :func:`auvplan.cli.main` when a command returns)."""
    LIVE.end()


def _stage_clock(tqdm: Any, text: str, quiet: bool) -> Any:
    """A bar-less live line for a stage: its text and the time it has taken so far."""
    return tqdm(total=None, desc=text, bar_format="auvplan: {desc} … {elapsed}", file=sys.stderr, leave=False,
                disable=quiet, mininterval=QUIET_S, delay=QUIET_S)  # nothing drawn for a stage done within it


class Progress:
    """Progress of the long stages on stderr: a tqdm bar for the swarm planners' iterations and one
    for the flight (simulated time against the flight's expected duration), a line for the other
    stages; all silent with ``quiet`` (``-q`` or ``--json``).  Whatever is live is redrawn when stderr
    has been quiet for a second (:class:`_Live`)."""

    def __init__(self, spec: PlannerSpec, scenario: str, quiet: bool) -> None:
        from ..planners import get as get_planner

        tqdm: Any = _Silent
        if not quiet:
            from tqdm import tqdm as tqdm_
            tqdm = tqdm_

        self._tqdm, self.quiet, self.scenario = tqdm, quiet, scenario
        self.flight_bar: Any = None
        self.clock: Any = None
        # only the iterating planners (the swarm optimisers) report progress; the others get a line, not a
        # bar stuck at 0
        iterative = get_planner(spec.name).iterative
        LIVE.end()  # the loading stage's clock (:func:`reporter`)
        self.bar = tqdm(total=spec.iterations, desc=f"{spec.name} on {scenario}", file=sys.stderr,
                        disable=quiet or not iterative, leave=False, mininterval=0.5)
        if iterative:
            LIVE.show(self.bar)
        else:
            self.stage(f"planning with {spec.name}")

    def __call__(self, iteration: int, best: float) -> None:
        self.bar.update(iteration - self.bar.n)
        self.bar.set_postfix_str(f"best {best:.6g}", refresh=False)

    def flight(self, t: float, expected: float) -> None:
        """The simulation's callback: simulated seconds flown of about ``expected``."""
        if self.flight_bar is None:
            self.bar.close()
            self._end_clock()
            self.flight_bar = self._tqdm(total=max(1, round(expected)), desc=f"flight on {self.scenario}", unit="s",
                                         file=sys.stderr, disable=self.quiet, leave=False, mininterval=0.5)
            LIVE.show(self.flight_bar)
        bar = self.flight_bar
        if round(expected) != bar.total:  # the estimate follows the flight (issue 56: never stuck at 100 %)
            bar.total = max(1, round(expected))
        bar.update(min(round(t), bar.total) - bar.n)

    def stage(self, text: str) -> None:
        """One line on stderr for a stage without a bar (the report, a lattice plan), and its clock."""
        if not self.quiet:
            self._end_clock()
            self._tqdm.write(f"auvplan: {text} …", file=sys.stderr)
            LIVE.said()
            self.clock = _stage_clock(self._tqdm, text, self.quiet)
            LIVE.show(self.clock)

    def _end_clock(self) -> None:
        if self.clock is not None:
            self.clock.close()
            self.clock = None

    def close(self) -> None:
        self.bar.close()
        self._end_clock()
        if self.flight_bar is not None:
            self.flight_bar.close()
        if not self.quiet:  # what follows (energy, checks, files) has a clock until the next stage or the end
            self.clock = _stage_clock(self._tqdm, f"{self.scenario}: after the plan and the flight", self.quiet)
            LIVE.show(self.clock)


class _Silent:
    """The bars and clocks of a quiet command (``-q``, ``--json``): they count and draw nothing, and tqdm, with
    the multiprocessing lock it makes for its first bar, is not imported for them (~30-60 ms, issue 56)."""

    disable = True

    def __init__(self, *args: Any, total: float | None = None, **kwargs: Any) -> None:
        self.n: float = 0
        self.total = total

    def update(self, n: float = 1) -> None:
        self.n += n

    def set_postfix_str(self, *args: Any, **kwargs: Any) -> None:
        pass

    def close(self) -> None:
        pass


def reporter(quiet: bool) -> Callable[[PlannerSpec, str], Progress]:
    """The progress reporter a job builds from its planner and scenario (:class:`auvplan.app.Reporter`); until
    the job builds it (reading the scenario and its data), a clock of that stage."""
    if not quiet:
        starting("reading the scenario and its data")
    return lambda spec, scenario: Progress(spec, scenario, quiet)


JSON_WARNINGS: list[str] = []
"""Warnings (logging and Python) raised while a ``--json`` command ran: :func:`emit` puts them in the JSON
object's ``warnings`` instead of on stderr (issue 51: ``--json`` leaves stderr empty on success)."""


def emit(record: dict[str, Any], as_json: bool, human: str) -> None:
    """A command's record: one JSON object on stdout with ``as_json`` (with the ``warnings`` collected while it
    ran, :data:`JSON_WARNINGS`), else the human text."""
    from ..io.results import records

    finish()  # the live progress line, before the result
    if as_json and JSON_WARNINGS:
        record = {**record, "warnings": list(JSON_WARNINGS)}
    if as_json:
        sys.stdout.write(json.dumps(records.jsonable(record)) + "\n")
    else:
        print(human)


def runner_of(args: argparse.Namespace) -> Any:
    """The :class:`auvplan.runtime.parallel.Runner` of ``--workers``, ``--scheduler`` and ``--retries``.

    Parameters
    ----------
    args : argparse.Namespace
        The command's arguments (those three absent: this process, one retry).

    Returns
    -------
    Runner
        Where the job's independent tasks run; starting its workers or reaching its scheduler is a stage line
        on stderr (none with ``-q`` or ``--json``).
    """
    from ..runtime.parallel import Runner

    quiet = getattr(args, "quiet", False) or getattr(args, "json", False)
    return Runner(workers=getattr(args, "workers", None) or 0, scheduler=getattr(args, "scheduler", None),
                  retries=getattr(args, "retries", 1), announce=None if quiet else stage_line)


def stage_line(text: str) -> None:
    """``auvplan: TEXT`` on stderr above the live line (which keeps being redrawn beneath it).

    Parameters
    ----------
    text : str
        The stage.
    """
    from tqdm import tqdm

    tqdm.write(f"auvplan: {text}", file=sys.stderr)
    LIVE.said()


# stdout that names itself (``auvplan scenarios > /dev/full``: a write or flush failing with an OSError raised
# 'OSError: [Errno 28] No space left on device' from wherever the command printed, without its culprit;
# BrokenPipeError, the reader gone (``| head``), passes unchanged: exit 141)
class StdoutError(AuvplanError, OSError):
    """Standard output cannot be written (names stdout and why)."""


class _Named:
    """``sys.stdout`` whose write and flush failures name it (every other attribute is the stream's)."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        try:
            return self._stream.write(text)
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise _named(exc) from exc

    def flush(self) -> None:
        try:
            self._stream.flush()
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise _named(exc) from exc

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def _named(exc: OSError) -> StdoutError:
    return StdoutError(f"stdout: cannot write the command's output ({exc.strerror or exc})")


@contextlib.contextmanager
def named_stdout() -> Iterator[None]:
    """Run one command with ``sys.stdout`` naming itself on a write failure, and flush it before leaving.

    Yields
    ------
    None
        The command runs; a failure to write stdout raises :class:`StdoutError`.

    Raises
    ------
    StdoutError
        When stdout cannot be written (in the command, or when its output is flushed at the end).
    """
    real = sys.stdout
    sys.stdout = _Named(real)
    try:
        yield
    finally:
        try:
            sys.stdout.flush()  # also after --help's SystemExit: its text is still in the buffer
        finally:
            sys.stdout = real
