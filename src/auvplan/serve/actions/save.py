"""The page's chosen mission saved as a normal results folder, by the writer ``auvplan run --out`` uses
(:func:`auvplan.app.results.write_results`).

``scenario.toml`` (the edited scenario), ``source.json`` and ``terrain.npz`` (what makes the folder
self-contained), the run files (``run.json``, ``run.npz``, ``route.csv``, ``keys.csv``, the plan's files
when the mission came from a plan, the flight's when it was flown), the energy files (``legs.csv`` and
the energy figures), every mission export, ``report.html``, and ``history.json`` (the page's edits).
``auvplan report``, ``export`` and ``mission check`` re-read it; nothing in an existing folder is
overwritten.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ...app.results import write_results
from ...errors import AuvplanError
from ...io.files import safeio
from ...io.files.safeio import RESULT_NAMES, atomic_write, prepare_out
from ...io.results import records
from ...sim import RunRecord
from ..session import Session

__all__ = ["save_results", "SAVE_NAMES"]

SAVE_NAMES = (*RESULT_NAMES, "history.json", "candidates.json")
"""Files a save writes."""


def save_results(session: Session, name: str) -> Path:
    """Write the session's current mission into a new results folder ``name`` in the first served folder.

    Parameters
    ----------
    session : Session
        The page's session.
    name : str
        The folder's name: letters, digits, ``-``, ``_`` and ``.``; it must not exist yet.

    Returns
    -------
    pathlib.Path
        The folder.
    """
    if not isinstance(name, str) or not name or name.startswith(".") or \
            any(not (c.isalnum() or c in "-_.") for c in name) or len(name) > 120:
        raise AuvplanError(f"save {str(name)[:80]!r}: a folder name of letters, digits, '-', '_' and '.' only")
    out = session.roots.resolve(name, must_exist=False)
    if out.exists() or out.is_symlink():
        raise AuvplanError(f"{out}: exists; results are never overwritten — choose another name")
    with session.lock:
        world, mission = session.world, session.mission
        sc = session.sc
        if world is None or mission is None or sc is None:
            raise AuvplanError("no scenario is open")
        w = session.waypoints.copy()
        flight = session.flight_summary() is not None
        record = RunRecord(sc.name, sc.seed, session.plan, w, session.keys.copy(), session.flight if flight else None)
        text, source = session.text, session.source
        history = list(session.history)
        candidates = session.candidate_rows()
    with safeio.session():  # the folder is locked while it is written, released after (a refusal leaves no lock)
        _write(out, session, record, text, source, history, candidates)
    return out


def _write(out: Path, session: Session, record: RunRecord, text: str, source: str, history: list[dict[str, Any]],
           candidates: list[dict[str, Any]]) -> None:
    world, mission = session.world, session.mission
    assert world is not None and mission is not None
    prepare_out(out, SAVE_NAMES, job="run")
    write_results(out, world, mission, record, text, source)  # the folder `auvplan run --out` writes
    atomic_write(out / "history.json", json.dumps(history, indent=1) + "\n")
    atomic_write(out / "candidates.json", json.dumps(records.jsonable(candidates), indent=1) + "\n")
