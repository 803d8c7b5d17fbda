"""Reading a results folder back: the :class:`~auvplan.sim.RunRecord` that
:func:`auvplan.io.results.records.write_run` wrote as ``run.json`` + ``run.npz`` (:func:`read_run`), every
missing or malformed member named with its file, and whether the folder's ``scenario.toml`` is still the one
the run wrote (:func:`check_scenario`)."""

from __future__ import annotations

import hashlib
import re
import zipfile
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..._types import Status
from ...errors import DataError
from ..files.jsonfile import MAX_SCENARIO_BYTES, read_bounded_text, read_json
from ..files.limits import check_npz

if TYPE_CHECKING:  # imported where a run is read back: a plan's writer needs only SIM_ARRAYS (issue 56)
    from ...sim import RunRecord

__all__ = ["SIM_ARRAYS", "read_run", "scenario_sha256", "check_scenario"]


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
        text = read_bounded_text(scenario_file, MAX_SCENARIO_BYTES, "a scenario file") \
            if scenario_file.is_file() else ""  # a 1.5 GB one was read whole (hostile round 22)
        return _record_from(rec, _Arrays(arr, files["run.npz"])), text
    except _ArrayFault as exc:
        raise DataError(f"{files['run.npz']}: {exc}") from exc
    except _Fault as exc:  # a label of the wrong type or size: named before it reaches a report
        raise DataError(f"{files['run.json']}: {exc}") from exc
    except (KeyError, TypeError, ValueError, AttributeError, IndexError, UnicodeDecodeError, OverflowError) as exc:
        raise DataError(f"{files['run.json']}: malformed run record ({type(exc).__name__}: {exc})") from exc


def scenario_sha256(data: str | bytes) -> str:
    """The SHA-256 of a results folder's ``scenario.toml`` as written (its UTF-8 bytes), kept in ``run.json``.

    Parameters
    ----------
    data : str or bytes
        The file's text, or its bytes as read back.

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    return hashlib.sha256(data.encode("utf-8") if isinstance(data, str) else data).hexdigest()


def check_scenario(out_dir: Path) -> None:
    """Refuse a results folder whose ``scenario.toml`` is not the one its run wrote (replaced or edited after it).

    ``run.json``'s ``scenario_sha256`` is the SHA-256 of the scenario text the run saved: a report or export of
    the run in another scenario's world would draw a mix (the run's track over another seabed, its exports judged
    against other bounds).  A folder written before the field existed is not checked.

    Parameters
    ----------
    out_dir : pathlib.Path
        The results folder.

    Raises
    ------
    DataError
        One line naming ``scenario.toml``, both digests' first 12 digits and what to do; or naming ``run.json``'s
        key when its value is not a SHA-256.
    """
    out = Path(out_dir)
    rec = read_json(out / "run.json")
    want = rec.get("scenario_sha256") if isinstance(rec, dict) else None
    if want is None:
        return
    if not isinstance(want, str) or not re.fullmatch(r"[0-9a-f]{64}", want):
        raise DataError(f"{out / 'run.json'}: scenario_sha256 = {_shown(want)}: expected 64 hexadecimal digits")
    path = out / "scenario.toml"
    try:
        got = scenario_sha256(path.read_bytes())
    except OSError:
        return  # missing: the caller names it
    if got != want:
        raise DataError(f"{path}: not the scenario this run saved (SHA-256 {got[:12]}…, run.json's scenario_sha256 "
                        f"{want[:12]}…): it was replaced or edited after the run, and a report or export would mix "
                        "this run with another world — restore it, or run the scenario again")


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


LABEL_MAX = 200
"""Longest label read back from ``run.json`` (a scenario's name is at most 128 characters, a planner's or a guidance
law's a word): a longer one is a hand-edited or hostile file, refused before it reaches a report."""

MESSAGE_MAX = 4000
"""Longest message read back (a planner's or an event's sentence)."""


class _Fault(Exception):
    """A value of ``run.json`` of the wrong type or size (the message names its key and value)."""


class _Fields:
    """One table of ``run.json`` read with its types checked: a label is a short printable string, a number a JSON
    number (not a boolean or a string of digits), an integer an integer; a wrong one is a :class:`_Fault` naming the
    key (``plan.planner = 5: expected a string``)."""

    def __init__(self, table: Any, where: str) -> None:
        if not isinstance(table, dict):
            raise _Fault(f"{where.rstrip('.') or 'the run record'} = {_shown(table)}: expected an object")
        self.table, self.where = table, where

    def _get(self, key: str, default: Any) -> Any:
        if key not in self.table and default is _REQUIRED:
            raise _Fault(f"{self.where}{key}: missing")
        return self.table.get(key, default)

    def text(self, key: str, default: Any = None, longest: int = LABEL_MAX) -> str:
        v = self._get(key, _REQUIRED if default is None else default)
        if not isinstance(v, str):
            raise _Fault(f"{self.where}{key} = {_shown(v)}: expected a string")
        if len(v) > longest:
            raise _Fault(f"{self.where}{key}: a string of {len(v)} characters (at most {longest} here)")
        if not v.replace("\n", " ").isprintable():  # no control character (a message: line breaks)
            raise _Fault(f"{self.where}{key} = {_shown(v)}: a control or formatting character")
        return v

    def status(self, key: str) -> Status:
        v = self.text(key)
        try:
            return Status(v)
        except ValueError:
            raise _Fault(f"{self.where}{key} = {_shown(v)}: not a status ({', '.join(x.value for x in Status)})") \
                from None

    def number(self, key: str, value: Any = None) -> float:
        v = self.table.get(key) if value is None else value
        if v is None:
            return float("nan")
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise _Fault(f"{self.where}{key} = {_shown(v)}: expected a number")
        return float(v)

    def integer(self, key: str, default: Any = 0) -> int:
        v = self._get(key, default)
        if v is None:
            return 0
        if isinstance(v, bool) or not isinstance(v, int):
            raise _Fault(f"{self.where}{key} = {_shown(v)}: expected an integer")
        return v


_REQUIRED = object()


def _shown(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 60 else f"{text[:57]}..."


def _events(s: _Fields) -> tuple[tuple[Any, ...], ...]:
    """``simulation.events``: ``[t, kind, text]`` rows (a time, a label, a message)."""
    rows = s.table.get("events", [])
    if not isinstance(rows, list):
        raise _Fault(f"simulation.events = {_shown(rows)}: expected a list of [time, kind, text]")
    out = []
    for i, e in enumerate(rows):
        if not isinstance(e, list) or len(e) != 3:
            raise _Fault(f"simulation.events[{i}] = {_shown(e)}: expected [time, kind, text]")
        row = _Fields({"time": e[0], "kind": e[1], "text": e[2]}, f"simulation.events[{i}].")
        out.append((row.number("time"), row.text("kind"), row.text("text", longest=MESSAGE_MAX)))
    return tuple(out)


def _record_from(rec: dict[str, Any], arr: Mapping[str, Any]) -> RunRecord:
    from ...planners.core.base import PlanResult
    from ...sim import RunRecord, SimResult

    top = _Fields(rec, "")
    _check_arrays(arr, rec.get("simulation") is not None)
    plan = None
    if rec.get("plan") is not None:
        p = _Fields(rec["plan"], "plan.")
        terms = {k: p.number(k) for k in ("length_m", "energy_j", "duration_s", "min_clearance_m")}
        cost_terms = _Fields(p.table.get("cost_terms") or {}, "plan.cost_terms.")
        terms.update({k: cost_terms.number(k) for k in cost_terms.table})
        terms["collisions"] = p.integer("collisions")
        plan = PlanResult(p.status("status"), arr.get("plan_path", np.empty((0, 3))), p.number("cost"), terms,
                          p.integer("evaluations"), p.integer("iterations"), p.number("wall_time_s"),
                          arr.get("plan_history", np.empty(0)), p.text("planner"), None,
                          p.text("message", "", longest=MESSAGE_MAX) if p.table.get("message") is not None else "",
                          **({"tail": arr["plan_tail"] > 0.5} if "plan_tail" in arr else {}))
    sim = None
    if rec.get("simulation") is not None:
        s = _Fields(rec["simulation"], "simulation.")
        arrived = s.table.get("arrived")
        if not isinstance(arrived, bool):
            raise _Fault(f"simulation.arrived = {_shown(arrived)}: expected true or false")
        sim = SimResult(status=s.status("status"), arrived=arrived,
                        **{k: arr[f"sim_{k}"] for k in SIM_ARRAYS},
                        events=_events(s), guidance=s.text("guidance"),
                        wall_time_s=s.number("wall_time_s"), escapes=s.integer("escapes"),
                        avoidance=s.text("avoidance", "none"))
    route = arr.get("route", np.empty((0, 3)))
    return RunRecord(top.text("scenario"), top.integer("seed", _REQUIRED), plan, route, arr.get("keys", route[:0]),
                     sim)
