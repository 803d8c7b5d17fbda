"""Read a JSON file a user or a results folder supplies: bounded in size and nesting, finite numbers only.

``json.loads`` recurses once per nesting level (a file of 100 000 ``[`` is a ``RecursionError``
naming nothing) and turns ``1e400`` into ``inf`` (later an ``OverflowError`` far away); here each
fault is a :class:`~auvplan.errors.DataError` naming the file.
"""

from __future__ import annotations

import json
import math
import stat
from pathlib import Path
from typing import Any

from ...errors import DataError, ScenarioError

__all__ = ["MAX_JSON_BYTES", "MAX_SCENARIO_BYTES", "read_json", "read_bounded_bytes", "read_bounded_text",
           "source_base", "scenario_origin"]

MAX_SCENARIO_BYTES = 16 * 1024 * 1024
"""Largest scenario file (the largest built-in has 6.5 kB; a 100 000-waypoint route ~4 MB): hostile round 22, a
1.5 GB file was read whole (3.1 GB resident, over the memory budget, 20 s) before 'invalid TOML'."""


MAX_JSON_BYTES = 64 * 1024 * 1024
"""Largest JSON file read (``run.json`` of a long run is a few MB)."""


def read_bounded_bytes(path: Path, limit: int, what: str) -> bytes:
    """The bytes of a regular file no larger than ``limit``, naming the file on any fault.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    limit : int
        Most bytes it may have.
    what : str
        What it is, for the message (``"a mission file"``).

    Returns
    -------
    bytes
        Its content.

    Raises
    ------
    DataError
        Naming the file when it is larger, unreadable, or not a regular file (a FIFO, a device).
    """
    try:
        st = path.stat()
        if not stat.S_ISREG(st.st_mode):  # a FIFO blocked for ever, /dev/zero filled the memory
            kind = "a FIFO" if stat.S_ISFIFO(st.st_mode) else "a folder" if stat.S_ISDIR(st.st_mode) else "a device"
            raise DataError(f"{path}: is {kind}, not a regular file; {what} is read whole")
        if st.st_size > limit:
            raise DataError(f"{path}: {st.st_size:,} bytes, over the {limit:,} {what} may have")
        with path.open("rb") as fh:
            data = fh.read(limit + 1)  # the size said is not trusted: it may grow while read
    except OSError as exc:
        raise DataError(f"{path}: cannot read ({exc})") from exc
    if len(data) > limit:
        raise DataError(f"{path}: over the {limit:,} bytes {what} may have")
    return data


def read_bounded_text(path: Path, limit: int, what: str) -> str:
    """The UTF-8 text of a file no larger than ``limit`` bytes (:func:`read_bounded_bytes`), naming the file on any
    fault.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    limit : int
        Most bytes it may have.
    what : str
        What it is, for the message (``"a mission file"``).

    Returns
    -------
    str
        Its text.

    Raises
    ------
    DataError
        Naming the file when it is larger, unreadable, not UTF-8, or not a regular file (a FIFO, a device).
    """
    data = read_bounded_bytes(path, limit, what)
    try:
        return data.decode("utf-8").replace("\r\n", "\n").replace("\r", "\n")  # as read_text: universal newlines
    except UnicodeDecodeError as exc:
        raise DataError(f"{path}: cannot read ({exc})") from exc


def read_json(path: Path) -> Any:
    """Read a JSON file, bounded in size and nesting, naming the file on any fault.

    Parameters
    ----------
    path : pathlib.Path
        The file.

    Returns
    -------
    object
        The parsed value; non-finite or out-of-range numbers (``1e400``) are refused.

    Raises
    ------
    DataError
        Naming the file and the fault (too large, not UTF-8, not JSON, nested too deeply).
    """
    text = read_bounded_text(path, MAX_JSON_BYTES, "a results file")
    try:
        return json.loads(text, parse_constant=_no_constant, parse_float=_finite_float)
    except RecursionError:
        raise DataError(f"{path}: nested too deeply (not a file auvplan wrote)") from None
    except ValueError as exc:
        raise DataError(f"{path}: not valid JSON ({exc})") from exc


def _no_constant(name: str) -> float:
    raise ValueError(f"{name} is not a number JSON allows")


def _finite_float(text: str) -> float:
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(f"number {text[:40]} is out of range")
    return v


def source_base(path: Path) -> Path:
    """The folder a scenario file's relative data paths resolve against: its own, or for a results folder's
    ``scenario.toml`` (a ``source.json`` beside it: the user's text kept as written, relative paths and all)
    the original scenario's folder (:func:`scenario_origin`'s).

    Parameters
    ----------
    path : pathlib.Path
        The scenario file.

    Returns
    -------
    pathlib.Path
        The folder.

    Raises
    ------
    ScenarioError
        Naming a malformed ``source.json``.
    """
    return scenario_origin(path).parent


def scenario_origin(path: Path) -> Path:
    """The scenario file a results folder's ``scenario.toml`` was first read from: ``source.json``'s
    ``scenario_source`` followed through a results folder run again (at most 8 hops; a relative
    ``scenario_source`` is read from the folder of its ``source.json``, never from the working directory),
    or ``path`` itself.

    Parameters
    ----------
    path : pathlib.Path
        The scenario file.

    Returns
    -------
    pathlib.Path
        The original scenario file.

    Raises
    ------
    ScenarioError
        Naming a malformed ``source.json``.
    """
    path = Path(path)
    seen: set[Path] = set()
    while path.name == "scenario.toml" and (path.parent / "source.json").is_file() and len(seen) < 8:
        seen.add(path)
        src = path.parent / "source.json"
        data = read_json(src)  # bounded in size and nesting, names the file
        try:
            path = src.parent / str(data["scenario_source"])
        except (KeyError, TypeError, ValueError) as exc:
            raise ScenarioError(f"{src}: malformed ({type(exc).__name__}: {exc}); expected "
                                '{"scenario_source": "/path/to/scenario.toml"}') from exc
        if path in seen:
            break
    return path
