"""The command line's argument types, checked by argparse before any work (a clear usage error, exit 2): bounded
integers, a dask scheduler's address, choices whose names are read only when asked for, an ``--out`` folder, a
departure sweep's step and departures, a pitch angle."""

from __future__ import annotations

import argparse
import importlib
import math
import os
import re
from collections.abc import Callable, Collection, Iterator
from typing import TYPE_CHECKING

from ...errors import AuvplanError

if TYPE_CHECKING:
    from ...io.missions.readback.mission_storage import BoardStorage

__all__: list[str] = []


def _int_at_least(low: int, high: int | None = None, why: str = "") -> Callable[[str], int]:
    """An argparse type: an integer >= ``low`` (and <= ``high``, for the reason ``why``; a clear usage error
    otherwise, before any work)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"{value} must be >= {low}")
        if high is not None and value > high:
            raise argparse.ArgumentTypeError(f"{value} must be <= {high}{f' ({why})' if why else ''}")
        return value

    parse.__name__ = f"integer >= {low}" if high is None else f"integer in [{low}, {high}]"
    return parse


_ADDRESS = re.compile(r"((tcp|tls|ws|wss|ucx)://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):[0-9]{1,5}|inproc://\S+")


def _scheduler(text: str) -> str:
    """An argparse type: a dask scheduler's address, ``[tcp://]host:port`` (checked before any work: a bad
    one used to surface after the job's set-up as dask's ``ValueError: missing port number``)."""
    port = text.rpartition(":")[2]
    if not _ADDRESS.fullmatch(text) or (port.isdigit() and not 0 < int(port) < 65536):
        raise argparse.ArgumentTypeError(f"{text!r} is not a dask scheduler address (e.g. tcp://host:8786)")
    return text


_scheduler.__name__ = "scheduler address"


class _Choices(Collection[str]):
    """argparse ``choices`` read when first needed (a ``--planner`` value, or that command's ``--help``;
    each such argument has a ``metavar``, else argparse would list the choices when the parser is built)."""

    def __init__(self, load: Callable[[], Collection[str]], extra: tuple[str, ...] = ()) -> None:
        self._load, self._extra = load, extra

    def _get(self) -> tuple[str, ...]:
        return (*self._extra, *self._load())  # read each time: a planner may be registered after the parser

    def __contains__(self, value: object) -> bool:
        return value in self._get()

    def __iter__(self) -> Iterator[str]:
        return iter(self._get())

    def __len__(self) -> int:
        return len(self._get())


def _planner_names() -> tuple[str, ...]:
    """The registered planners (:mod:`auvplan.planners.core.registry`): built-in and plugged in."""
    from ...planners.core.registry import names

    return names()


def _names_in(module: str, name: str) -> Callable[[], tuple[str, ...]]:
    """A loader of the tuple ``module.name`` (imported when the choices are first read)."""
    return lambda: tuple(getattr(importlib.import_module(module), name))


_AVOIDANCE = _Choices(_names_in("auvplan.guidance.avoidance.local", "AVOIDANCE"))
_PIPELINES = _Choices(_names_in("auvplan.planners.core.registry", "PIPELINES"))
_FORMATS = _Choices(_names_in("auvplan.io.missions.export", "EXPORT_FORMATS"))
_BENCH_AVOIDANCE = _Choices(_names_in("auvplan.guidance.avoidance.local", "AVOIDANCE"), ("scenario",))


_SEED = _int_at_least(0)
_POSITIVE = _int_at_least(1)
_CPUS = os.cpu_count() or 1
_WORKERS = _int_at_least(1, max(4, 4 * _CPUS), f"4 worker processes per CPU at most; this machine has {_CPUS}")
"""``--workers``: a LocalCluster of 100 000 processes froze the machine before its first task."""
_RETRIES = _int_at_least(0, 100, "a task that fails 100 times fails for a reason")
"""``--retries``: 10⁹ ran a task that fails for good 10⁹ times (hostile round 20)."""

_MAX_SWEEP_S = 366 * 86400.0
"""Longest departure step and farthest departure offset of a sweep (a year: tide tables are per year)."""


def _out_folder(text: str) -> str:
    """``--out``: a folder path, not empty (``--out "$UNSET"`` wrote into the current folder) and without control
    characters (a newline made a folder each one-line message named wrongly; hostile round 20)."""
    if not text.strip():
        raise argparse.ArgumentTypeError(f"{text!r}: an empty folder name (the current folder is --out .)")
    if any(not c.isprintable() for c in text):
        raise argparse.ArgumentTypeError(f"{text!r}: a control or formatting character in the folder name")
    return text


def _step(text: str) -> str:
    """An argparse type: a finite duration in (0, 366 d] ('15min', '900s', '2h'); the text is kept."""
    from ...app.durations import parse_duration

    try:
        value = parse_duration(text, "--step")
    except AuvplanError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("--step ")) from None
    if not (math.isfinite(value) and 0 < value <= _MAX_SWEEP_S):
        raise argparse.ArgumentTypeError(f"{text!r}: a step must lie in (0 s, 366 d]")
    return text


def _departure(text: str) -> str:
    """An argparse type: an offset within 366 d after start_time ('+6h') or an ISO 8601 time in 1678..2261."""
    from ...app.durations import is_offset, parse_duration

    if is_offset(text):
        try:
            value = parse_duration(text, "--depart-between")
        except AuvplanError as exc:
            raise argparse.ArgumentTypeError(str(exc).removeprefix("--depart-between ")) from None
        if not (math.isfinite(value) and abs(value) <= _MAX_SWEEP_S):
            raise argparse.ArgumentTypeError(f"{text!r}: an offset must lie within 366 d of [mission] start_time")
        return text
    from ...io.data.ocean.currents import parse_time

    try:
        parse_time(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return text


def _pitch(text: str) -> float:
    """An argparse type: a finite pitch angle in (0, 90] degrees."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0.0 < value <= 90.0:  # also refuses nan and inf
        raise argparse.ArgumentTypeError(f"{text} must be a finite angle in (0, 90] degrees")
    return value


_pitch.__name__ = "pitch in (0, 90] degrees"


def _board_storage(text: str) -> BoardStorage:
    """An argparse type: the board's mission storage, ``16k``, ``32k`` or ``sd:N`` (``BRD_SD_MISSION``, 1-64 KiB;
    :func:`auvplan.io.missions.readback.mission_storage.board_storage`)."""
    from ...io.missions.readback.mission_storage import board_storage

    try:
        return board_storage(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


_board_storage.__name__ = "board storage"
