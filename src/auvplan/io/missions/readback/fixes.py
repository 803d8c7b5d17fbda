"""The position fixes of a mission file read back (issue 52, ``docs/navigation.md``).

A surface waypoint (depth within 0.5 m) after the mission's first is a GPS fix whatever the file's format (a
``.plan``'s points are read home first: its mission starts at point 1, launched from the home on the surface above
it, and a start at the surface is no fix there either).  A USBL
fix is taken at depth: no mission format has a field for it, so it lives in the results folder's
``fixes.csv`` (``lat, lon, t_s, kind``) written beside every export.  :func:`fix_kinds` reads that file
when it lies beside the mission file and marks the waypoint each row names (the nearest waypoint, within
:data:`MATCH_TOLERANCE_M` horizontally; a row further from every waypoint is an error naming the file,
the row and its position).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from ....errors import DataError
from ....nav import surface_kinds
from ...data.geo import LocalFrame

__all__ = ["MATCH_TOLERANCE_M", "FIX_KINDS", "read_fixes", "fix_kinds"]

MATCH_TOLERANCE_M = 1.0
"""Largest horizontal distance (m) between a ``fixes.csv`` row and the waypoint it names (the file
writes 7 decimals of a degree: about 1 cm)."""

FIX_KINDS = ("gps", "usbl")
"""The ``kind`` column's words."""


def read_fixes(path: Path, origin: tuple[float, float]) -> tuple[np.ndarray, tuple[str, ...]]:
    """Read ``fixes.csv``: the fixes' local positions and kinds.

    Parameters
    ----------
    path : pathlib.Path
        The file (``lat, lon, t_s, kind``).
    origin : tuple of 2 float
        ``(lat, lon)`` of the scenario's local frame.

    Returns
    -------
    xy : numpy.ndarray
        ``(F, 2)`` the fixes in the local frame (m).
    kinds : tuple of str
        ``(F,)`` ``"gps"`` or ``"usbl"``.

    Raises
    ------
    DataError
        A missing column or a row whose position or kind cannot be read, naming the file, row and value.
    """
    try:
        with path.open(newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise DataError(f"{path}: cannot read the fixes: {exc}") from exc
    lat, lon, kinds = [], [], []
    for n, row in enumerate(rows, start=2):
        missing = [k for k in ("lat", "lon", "kind") if k not in row or row[k] is None]
        if missing:
            raise DataError(f"{path}: row {n}: no {missing[0]!r} column (expected lat,lon,t_s,kind)")
        kind = row["kind"].strip()
        if kind not in FIX_KINDS:
            raise DataError(f"{path}: row {n}: kind = {kind!r}: 'gps' or 'usbl'")
        try:
            a, o = float(row["lat"]), float(row["lon"])
        except ValueError:
            raise DataError(f"{path}: row {n}: lat = {row['lat']!r}, lon = {row['lon']!r}: not a position") from None
        if not (math.isfinite(a) and math.isfinite(o) and -90.0 <= a <= 90.0):
            raise DataError(f"{path}: row {n}: lat = {a}, lon = {o}: not a position")
        lat.append(a)
        lon.append(o)
        kinds.append(kind)
    if not kinds:
        return np.empty((0, 2)), ()
    x, y = LocalFrame(*origin).forward(np.asarray(lon), np.asarray(lat))
    return np.column_stack([x, y]), tuple(kinds)


def fix_kinds(points: ArrayLike, mission_file: Path,
              origin: tuple[float, float] | None) -> tuple[tuple[str, ...], str]:
    """The fix at each waypoint of a mission file: its surface waypoints, and the rows of the ``fixes.csv``
    beside it (the only place a USBL fix is kept).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` the file's waypoints (m).
    mission_file : pathlib.Path
        The mission file (``fixes.csv`` is looked for in its folder).
    origin : tuple of 2 float or None
        The scenario's ``(lat, lon)`` (without it ``fixes.csv`` cannot be placed and is not read).

    Returns
    -------
    kinds : tuple of str
        ``(N,)`` ``""``, ``"gps"`` or ``"usbl"``; none at the mission's start (a ``.plan``'s home and its first
        item: its launch is no fix to wait for).
    source : str
        Where the fixes were read from, for the check's verdict.

    Raises
    ------
    DataError
        A row of ``fixes.csv`` that no waypoint matches, naming the file, the row and its distance.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    kinds = list(surface_kinds(p))
    start = 1 if Path(mission_file).suffix.lower() == ".plan" else 0  # read home first: the mission's start is 1
    kinds[:start + 1] = [""] * len(kinds[:start + 1])
    companion = Path(mission_file).with_name("fixes.csv")
    if origin is None or not companion.is_file() or companion.resolve() == Path(mission_file).resolve():
        return tuple(kinds), "the surface waypoints"
    xy, rows = read_fixes(companion, origin)
    for n, (q, kind) in enumerate(zip(xy, rows, strict=True), start=2):
        d = np.hypot(p[:, 0] - q[0], p[:, 1] - q[1])
        if kind == "gps":  # a surfacing: the nearest surface waypoint
            d = np.where(-p[:, 2] <= 0.5, d, np.inf)
        i = int(np.argmin(d))
        if not d[i] <= MATCH_TOLERANCE_M:
            raise DataError(f"{companion}: row {n}: the {kind} fix is {d[i]:.1f} m from the nearest "
                            f"{'surface ' if kind == 'gps' else ''}waypoint of {mission_file} "
                            f"(at most {MATCH_TOLERANCE_M:g} m): not this mission's fixes")
        if i > start:
            kinds[i] = kind
    return tuple(kinds), f"the surface waypoints and {companion.name}"
