"""Reading a results folder back: the :class:`~auvplan.sim.RunRecord` that
:func:`auvplan.io.results.records.write_run` wrote as ``run.json`` + ``run.npz`` (:func:`read_run`), every
missing or malformed member named with its file."""

from __future__ import annotations

import zipfile
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..._types import Status
from ...errors import DataError
from ..files.jsonfile import read_json
from ..files.limits import check_npz

if TYPE_CHECKING:  # imported where a run is read back: a plan's writer needs only SIM_ARRAYS (issue 56)
    from ...sim import RunRecord

__all__ = ["SIM_ARRAYS", "read_run"]


SIM_ARRAYS = ("t", "position", "heading", "speed", "rudder", "cross_track", "route_error", "progress", "altitude",
              "obstacle_distance")
"""The arrays of a :class:`~auvplan.sim.SimResult` kept in ``run.npz`` (as ``sim_<name>``)."""


def read_run(out_dir: Path) -> tuple[RunRecord, str]:
    """Read back the :class:`RunRecord` written by :func:`auvplan.io.results.records.write_run` into ``out_dir``.

    Parameters
    ----------
    out_dir : pathlib.Path
        Results folder.

    Returns
    -------
    record : RunRecord
        The run.
    scenario_text : str
        The stored scenario (empty when missing).

    Raises
    ------
    DataError
        Naming the missing or unreadable file.
    """
    out = Path(out_dir)
    files = {n: out / n for n in ("run.json", "run.npz")}
    for p in files.values():
        if not p.is_file():
            raise DataError(f"{p}: missing — is {out} a directory written by `auvplan run --out`?")
    rec = read_json(files["run.json"])
    check_npz(files["run.npz"])  # the members' headers against the budget, before a byte of data is read
    try:
        with np.load(files["run.npz"], allow_pickle=False) as npz:
            arr = {k: npz[k] for k in npz.files}
    except (ValueError, OSError, EOFError, zipfile.BadZipFile) as exc:
        raise DataError(f"{files['run.npz']}: cannot read the run's arrays: {' '.join(str(exc).split())[:200]}") \
            from exc
    try:
        scenario_file = out / "scenario.toml"
        text = scenario_file.read_text(encoding="utf-8") if scenario_file.is_file() else ""
        return _record_from(rec, _Arrays(arr, files["run.npz"])), text
    except _ArrayFault as exc:
        raise DataError(f"{files['run.npz']}: {exc}") from exc
    except (KeyError, TypeError, ValueError, AttributeError, IndexError, UnicodeDecodeError, OverflowError) as exc:
        raise DataError(f"{files['run.json']}: malformed run record ({type(exc).__name__}: {exc})") from exc


class _ArrayFault(Exception):
    """A member of ``run.npz`` missing or of the wrong shape (blamed on run.npz, not run.json)."""


class _Arrays(dict[str, Any]):
    """The members of ``run.npz``; a missing or malformed one is an :class:`_ArrayFault`."""

    def __init__(self, arr: Mapping[str, Any], path: Path) -> None:
        super().__init__(arr)
        self.path = path

    def __getitem__(self, key: str) -> Any:
        if key not in self:
            raise _ArrayFault(f"member {key!r} is missing")
        value = super().__getitem__(key)
        if not isinstance(value, np.ndarray) or value.dtype.kind not in "biuf":
            raise _ArrayFault(f"member {key!r} is not a numeric array")
        return value

    def get(self, key: str, default: Any = None) -> Any:
        return self[key] if key in self else default


def _points(arr: Mapping[str, Any], key: str, rows: int | None = None) -> None:
    """Member ``key`` (when present) is ``(rows, 3)`` finite points."""
    if key not in arr:
        return
    a = arr[key]
    if a.ndim != 2 or a.shape[1] != 3 or (rows is not None and a.shape[0] != rows):
        want = f"({rows if rows is not None else 'N'}, 3)"
        raise _ArrayFault(f"member {key!r} has the shape {a.shape}, not {want}")
    ok = np.isfinite(a).all(axis=1)
    if not ok.all():
        raise _ArrayFault(f"member {key!r} holds a value that is not finite (row {int(np.argmin(ok))})")


def _check_arrays(arr: Mapping[str, Any], flown: bool) -> None:
    """The members' shapes agree and the positions are finite (a tampered ``run.npz`` was an ``IndexError``
    traceback, or 'cannot convert float NaN to integer' naming no file: hostile round 20)."""
    for key in ("route", "keys", "plan_path"):
        _points(arr, key)
    if not flown:
        return
    t = arr["sim_t"]
    if t.ndim != 1 or not np.isfinite(t).all() or (np.diff(t) < 0).any():
        raise _ArrayFault(f"member 'sim_t' ({t.shape}) is not a finite, non-decreasing time series")
    _points(arr, "sim_position", t.shape[0])
    for k in SIM_ARRAYS[2:]:
        a = arr[f"sim_{k}"]
        if a.ndim not in (1, 2) or a.shape[0] != t.shape[0]:
            raise _ArrayFault(f"member 'sim_{k}' has {a.shape[0] if a.ndim else 0} rows, 'sim_t' {t.shape[0]}")


def _record_from(rec: dict[str, Any], arr: Mapping[str, Any]) -> RunRecord:
    from ...planners.core.base import PlanResult
    from ...sim import RunRecord, SimResult

    _check_arrays(arr, rec.get("simulation") is not None)
    plan = None
    p = rec.get("plan")
    if p is not None:
        terms = {k: _num(p.get(k)) for k in ("length_m", "energy_j", "duration_s", "min_clearance_m")}
        terms.update({k: _num(v) for k, v in (p.get("cost_terms") or {}).items()})
        terms["collisions"] = int(p.get("collisions") or 0)
        plan = PlanResult(Status(p["status"]), arr.get("plan_path", np.empty((0, 3))), _num(p.get("cost")), terms,
                          int(p.get("evaluations") or 0), int(p.get("iterations") or 0),
                          _num(p.get("wall_time_s")), arr.get("plan_history", np.empty(0)), p["planner"],
                          None, p.get("message") or "",
                          **({"tail": arr["plan_tail"] > 0.5} if "plan_tail" in arr else {}))
    sim = None
    s = rec.get("simulation")
    if s is not None:
        sim = SimResult(status=Status(s["status"]), arrived=bool(s["arrived"]),
                        **{k: arr[f"sim_{k}"] for k in SIM_ARRAYS},
                        events=tuple(tuple(e) for e in s.get("events", [])), guidance=s["guidance"],
                        wall_time_s=_num(s.get("wall_time_s")), escapes=int(s.get("escapes") or 0),
                        avoidance=s.get("avoidance", "none"))
    route = arr.get("route", np.empty((0, 3)))
    return RunRecord(str(rec["scenario"]), int(rec["seed"]), plan, route, arr.get("keys", route[:0]), sim)


def _num(v: Any) -> float:
    return float("nan") if v is None else float(v)
