"""Every value of a tidal station file checked before it is used (hostile round 20).

A station file is JSON that anyone can write.  Before this check a table where a list belongs, a constituent
list that is a number, ``first_year: null`` or ``Infinity`` ended in a Python traceback (``TypeError``,
``IndexError``, ``AttributeError``, ``OverflowError``); a station without a ``name`` in a bare ``KeyError``; and
``NaN``, ``null``, ``true`` or ``1e308`` as an amplitude, a phase, a position, a speed or a node factor were read
as they came (a current of NaN everywhere, ``validate`` OK).  :func:`check_tide_doc` refuses each, naming the
file, the entry and the value.  The bounds are wide enough for any real table: speeds up to 360°/h (a period
of an hour: the highest harmonic tables go to M12, 174°/h), node factors in [0, 10], amplitudes and means up to
20 m/s, zone offsets within ±14 h.
"""

from __future__ import annotations

import math
from typing import Any

from ....errors import DataError

__all__ = ["check_tide_doc", "MAX_STATIONS", "MAX_CONSTITUENTS", "MAX_YEARS"]

MAX_STATIONS = 10_000
"""Most stations a file may hold (the built-in Salish Sea file: 78)."""
MAX_CONSTITUENTS = 400
"""Most constituents (XTide's harmonics files: under 200)."""
MAX_YEARS = 1000
"""Most yearly columns of the equilibrium and node-factor tables (the built-ins: 21)."""


def _number(where: str, key: str, v: Any, lo: float = -math.inf, hi: float = math.inf) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or not lo <= v <= hi:
        span = "" if (lo, hi) == (-math.inf, math.inf) else f" in [{lo:g}, {hi:g}]"
        raise DataError(f"{where}: {key} = {str(v)[:40]}: expected a finite number{span}")
    return float(v)


def _list(where: str, key: str, v: Any, n: int | None, most: int) -> list[Any]:
    if not isinstance(v, list) or not 0 < len(v) <= most or (n is not None and len(v) != n):
        size = f"{n}" if n is not None else f"1 to {most:,}"
        got = f"a list of {len(v)}" if isinstance(v, list) else type(v).__name__
        raise DataError(f"{where}: {key}: expected a list of {size} entries (got {got})")
    return v


def _tables(doc: dict[str, Any], where: str) -> None:
    """The constituents, their speeds and the yearly tables."""
    names = _list(where, "constituents", doc["constituents"], None, MAX_CONSTITUENTS)
    for i, c in enumerate(names):
        if not isinstance(c, str) or not c or not c.isprintable():
            raise DataError(f"{where}: constituents[{i}] = {str(c)[:40]!r}: expected a constituent's name")
    if len(set(names)) < len(names):
        raise DataError(f"{where}: constituents: {next(c for c in names if names.count(c) > 1)!r} is listed twice")
    n = len(names)
    for i, v in enumerate(_list(where, "speed_deg_per_hour", doc["speed_deg_per_hour"], n, n)):
        _number(where, f"speed_deg_per_hour[{i}] ({names[i]})", v, 0.0, 360.0)
    year = doc["first_year"]
    if isinstance(year, bool) or not isinstance(year, int) or not 1678 <= year <= 2261:
        raise DataError(f"{where}: first_year = {str(year)[:40]}: expected a year in 1678..2261")
    years = None
    for key, lo, hi in (("equilibrium_deg", -1e6, 1e6), ("node_factor", 0.0, 10.0)):
        rows = _list(where, key, doc[key], n, n)  # one row per constituent, one column per year
        for i, row in enumerate(rows):
            row = _list(where, f"{key}[{i}] ({names[i]})", row, years, MAX_YEARS)
            years = len(row)
            for j, v in enumerate(row):
                _number(where, f"{key}[{i}][{j}] ({names[i]}, {year + j})", v, lo, hi)


def _station(s: Any, i: int, names: set[str], where: str) -> None:
    if not isinstance(s, dict):
        raise DataError(f"{where}: stations[{i}]: expected a station object (got {type(s).__name__})")
    name = s.get("name")
    if not isinstance(name, str) or not name.strip() or not name.isprintable():
        raise DataError(f"{where}: stations[{i}] name = {str(name)[:60]!r}: expected the station's name (text)")
    at = f"stations[{i}] ({name[:60]})"
    for key, lo, hi in (("lat", -90.0, 90.0), ("lon", -360.0, 360.0), ("depth_m", 0.0, 12_000.0),
                        ("flood_dir_deg", -360.0, 720.0), ("ebb_dir_deg", -360.0, 720.0), ("mean_m_s", -20.0, 20.0),
                        ("zone_hours", -14.0, 14.0)):
        if key not in s:
            raise DataError(f"{where}: {at}: no {key}")
        _number(where, f"{at} {key}", s[key], lo, hi)
    for key, lo, hi in (("amplitude_m_s", 0.0, 20.0), ("phase_deg", -1e6, 1e6)):
        table = s.get(key)
        if not isinstance(table, dict):
            raise DataError(f"{where}: {at} {key}: expected an object of constituent: value (got "
                            f"{type(table).__name__})")
        for c, v in table.items():
            if c not in names:  # dropped without a word: a lower-case 'm2' left the station without its M2
                raise DataError(f"{where}: {at} {key}: {c[:40]!r} is not one of the file's constituents")
            _number(where, f"{at} {key}[{c!r}]", v, lo, hi)


def check_tide_doc(doc: dict[str, Any], where: str) -> None:
    """Raise a :class:`~auvplan.errors.DataError` naming the entry and its value when the station file ``doc``
    holds a value of the wrong type, not finite, or out of range.

    Parameters
    ----------
    doc : dict
        The station file's JSON object (its keys present: :func:`~auvplan.io.data.ocean.tides.read_tide_file`).
    where : str
        The file (or the built-in's name), for the message.
    """
    _tables(doc, where)
    names = set(doc["constituents"])
    stations = _list(where, "stations", doc["stations"], None, MAX_STATIONS)
    for i, s in enumerate(stations):
        _station(s, i, names, where)
