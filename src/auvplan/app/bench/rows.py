"""The rows of a sweep (``auvplan bench``): the columns, reading ``rows.csv`` and ``histories.jsonl`` as an
interruption left them, and the summary per cell."""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..._types import Status
from ...errors import AuvplanError

__all__ = ["Row", "KEY", "COLUMNS", "TIMING", "read_rows", "read_histories", "summarise"]

Row = dict[str, Any]
"""One row of ``rows.csv`` (or of the summary, or one convergence record)."""

KEY = ("scenario", "planner", "guidance", "seed")
"""Columns that identify a run."""

COLUMNS = KEY + (
    "status", "plan_status", "arrived", "cost", "length", "terrain", "energy", "length_m", "energy_j",
    "plan_duration_s", "plan_min_clearance_m", "plan_collisions", "evaluations", "iterations", "reference_cost",
    "gap_pct", "sim_duration_s", "distance_m", "min_clearance_m", "min_obstacle_distance_m", "collisions",
    "cross_track_rms_m", "cross_track_max_m", "escapes", "cpu_s", "wall_s",
    "member", "member_seed", "arrival_s", "member_energy_wh", "member_success",
)
"""Columns of ``rows.csv``."""

_STATUSES = frozenset(s.value for s in Status)

TIMING = ("cpu_s", "wall_s")
"""Columns that vary from run to run of the same sweep."""


def read_rows(path: Path) -> list[Row]:
    """Read the rows of a ``rows.csv`` that are provably complete, each key once.

    A row counts only when its line ends with a newline (a line an interruption cut short, even
    one cut inside its last field, is left out and its run done again by ``--resume``), it has
    every column, its ``status`` is a status, its ``wall_s`` a number, its ``seed`` an integer ≥ 0 and no
    value holds a control character; of two rows with the same key (a tampered file) the first is kept.
    A file whose first line is not :data:`COLUMNS`' header, or holding a line the csv module cannot
    read, is refused (:class:`~auvplan.errors.AuvplanError`): a sweep never appends to it.

    Parameters
    ----------
    path : pathlib.Path
        The CSV file.

    Returns
    -------
    list of dict
        The rows, values as strings.
    """
    path = Path(path)
    if not path.is_file():
        return []
    data = path.read_bytes()
    text = data[:data.rfind(b"\n") + 1].decode("utf-8", "replace")  # complete lines only
    header = text.partition("\n")[0].rstrip("\r")
    if text and header != ",".join(COLUMNS):  # rows appended under another header made a file no reader reads
        raise AuvplanError(f"{path}: its first line is not the header `auvplan bench` writes ({header[:60]!r}…); "
                           "not resumed — choose another --out")
    rows: dict[tuple[str, ...], Row] = {}
    reader = csv.DictReader(io.StringIO(text, newline=""))
    try:
        for r in reader:
            # short or over-long (two lines run together) rows are dropped; so is a row whose seed is not a seed
            # (it ended the resumed sweep in 'ValueError: invalid literal for int()') or that holds a control
            # character (a NUL in a label reached the figures: hostile round 20)
            if None in r or None in r.values() or r.get("status") not in _STATUSES or not _is_number(r.get("wall_s")) \
                    or not str(r.get("seed")).isdigit() or not all(str(v).isprintable() for v in r.values()):
                continue
            rows.setdefault(_key(r), r)
    except csv.Error as exc:  # a field over the csv module's limit (131 072 characters): was a traceback
        raise AuvplanError(f"{path}: line {reader.line_num} is not a row of `auvplan bench` ({exc}); not resumed — "
                           "choose another --out") from None
    return list(rows.values())


def _is_number(v: Any) -> bool:
    try:
        return math.isfinite(float(v))
    except (TypeError, ValueError):
        return False


def read_histories(path: Path) -> list[Row]:
    """Read the convergence records of a sweep's ``histories.jsonl``.

    A line cut short by an interruption is left out.

    Parameters
    ----------
    path : pathlib.Path
        The JSON-lines file.

    Returns
    -------
    list of dict
        ``{"key": [scenario, planner, guidance, seed], "history": [...], "trace": [[evaluations, best], ...]}``.
    """
    path = Path(path)
    if not path.is_file():
        return []
    out: dict[tuple[Any, ...], Row] = {}
    for line in path.read_text().splitlines():
        try:
            h = json.loads(line)
            out[tuple(h["key"])] = h  # a run re-done after a kill between its two lines: the last wins
        except (ValueError, KeyError, TypeError):
            continue
    return list(out.values())


def _cut_partial_line(path: Path) -> None:
    """Truncate ``path`` after its last newline (drops a line an interruption cut short); the
    complete lines before it are never rewritten."""
    if not path.is_file():
        return
    with path.open("rb+") as fh:
        size = fh.seek(0, 2)
        if size == 0:
            return
        back = min(size, 1 << 16)
        while True:
            fh.seek(size - back)
            tail = fh.read(back)
            cut = tail.rfind(b"\n")
            if cut >= 0 or back == size:
                break
            back = min(size, back * 2)
        keep = size - back + cut + 1 if cut >= 0 else 0
        if keep < size:
            fh.truncate(keep)


def _key(row: Mapping[str, Any]) -> tuple[str, ...]:
    return tuple(str(row[k]) for k in KEY)


def _f(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


def _nanmin(values: Iterable[Any]) -> float:
    v = np.asarray(values, dtype=float)
    return float(np.nanmin(v)) if np.isfinite(v).any() else float("nan")


def summarise(rows: Iterable[Mapping[str, Any]]) -> list[Row]:
    """Summarise a sweep per cell (scenario, planner, guidance).

    Runs, success rate, cost median / IQR / best / worst, median gap to the reference, median CPU
    time, then the flights' collisions (all kinds), deadlocks, escapes (total) and smallest
    obstacle distance.

    Parameters
    ----------
    rows : iterable of mapping
        Rows of ``rows.csv``.

    Returns
    -------
    list of dict
        One row per cell (costs in the objective's unit, times in s, distances in m).
    """
    cells: dict[tuple[str, str, str], list[Mapping[str, Any]]] = {}
    for r in rows:
        cells.setdefault((r["scenario"], r["planner"], r["guidance"]), []).append(r)
    out = []
    for (s, p, g), rs in sorted(cells.items()):
        cost = np.array([_f(r["cost"]) for r in rs])
        cost = cost[np.isfinite(cost)]
        ok = [Status(r["status"]).ok for r in rs]
        q = np.percentile(cost, [25, 50, 75]) if cost.size else [np.nan] * 3
        gap = np.array([_f(r["gap_pct"]) for r in rs])
        out.append({"scenario": s, "planner": p, "guidance": g, "runs": len(rs),
                    "success_rate": float(np.mean(ok)), "cost_median": float(q[1]), "cost_iqr": float(q[2] - q[0]),
                    "cost_best": float(cost.min()) if cost.size else np.nan,
                    "cost_worst": float(cost.max()) if cost.size else np.nan,
                    "gap_pct_median": float(np.nanmedian(gap)) if np.isfinite(gap).any() else np.nan,
                    "cpu_s_median": float(np.median([_f(r["cpu_s"]) for r in rs])),
                    "collisions": int(np.nansum([_f(r["collisions"]) for r in rs])),
                    "deadlocks": sum(r["status"] == "DEADLOCK" for r in rs),
                    "escapes": int(np.nansum([_f(r["escapes"]) for r in rs])),
                    "min_obstacle_distance_m": _nanmin([_f(r["min_obstacle_distance_m"]) for r in rs])})
    return out
