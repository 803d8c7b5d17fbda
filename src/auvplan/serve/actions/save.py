"""The page's chosen mission saved as a normal results folder (as ``auvplan run --out`` writes one).

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

from ...errors import AuvplanError
from ...io import outdir
from ...io.data.geo import LocalFrame
from ...io.missions import export
from ...io.missions.energy import mission_endurance, read_leg_speeds, write_energy
from ...io.results import folder as results
from ...io.results import records
from ...io.safeio import RESULT_NAMES, atomic_write, prepare_out
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
    with outdir.session():  # the folder is locked while it is written, released after
        _write(out, session, record, text, source, history, candidates)
    return out


def _write(out: Path, session: Session, record: RunRecord, text: str, source: str, history: list[dict[str, Any]],
           candidates: list[dict[str, Any]]) -> None:
    world, mission = session.world, session.mission
    assert world is not None and mission is not None
    w = record.route
    prepare_out(out, SAVE_NAMES, job="run")
    frame = LocalFrame(*world.origin) if world.origin is not None else None
    records.write_run(out, record, text, False, world.origin)
    records.write_json(out / "source.json", {"scenario_source": str(Path(source).resolve())})
    results.save_terrain(out, world.terrain)
    endurance = mission_endurance(world, mission, record)
    if endurance is not None:
        write_energy(out, endurance, frame.inverse if frame else None)
    speeds = read_leg_speeds(out, w.shape[0] - 1)
    formats = export.exportable(record, [f for f in export.EXPORT_FORMATS
                                         if frame is not None or f not in export.GEOGRAPHIC])[0]
    export.write_exports(out, record, world.origin, mission.vehicle.speed if speeds is None else speeds, formats)
    _report(out, session, record, text, endurance)
    atomic_write(out / "history.json", json.dumps(history, indent=1) + "\n")
    atomic_write(out / "candidates.json", json.dumps(records.jsonable(candidates), indent=1) + "\n")


def _report(out: Path, session: Session, record: RunRecord, text: str, endurance: Any) -> None:
    from ...viz.report import build_report

    world = session.world
    assert world is not None
    frame = LocalFrame(*world.origin) if world.origin is not None else None
    metrics = records.summary_metrics(record)
    page = build_report(world, record, text, metrics, frame.inverse if frame else None, endurance)
    atomic_write(out / "report.html", page)
