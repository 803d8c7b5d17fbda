"""Actions on the scenario: open a scenario or a results folder, set a key of an editable table.

Loading and rebuilding run aside (:meth:`~auvplan.serve.session.Session.long_work`: a second long
request is refused, never queued); every file the scenario names is confined to the served folders
(:meth:`~auvplan.app.page.paths.Roots.confine`) before it is read.
"""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import numpy as np

from ...app.page.check import CheckResult
from ...app.page.tomlout import dumps
from ...errors import AuvplanError
from ...io.files import limits as _limits
from ...io.scenario import loader as scenario_io
from ...sim import mission_route
from ..session import EDITABLE_TABLES, Session
from .planning import plan_survey

__all__ = ["MAX_VALUE_ITEMS", "MAX_VALUE_DEPTH", "open_scenario", "set_initial_route", "set_value"]

MAX_VALUE_ITEMS = 10_000
"""Most numbers, strings and containers one value set by the page may hold (a 10⁶-number ``start``, 4 MB
within the body limit, held the scenario's lock for 14.5 s before the loader refused it)."""
MAX_VALUE_DEPTH = 16
"""Deepest nesting of one value set by the page (800 levels answered a bare 'RecursionError', naming nothing)."""


def _check_value(table: str, key: str, value: Any) -> None:
    """Refuse a value too large or too deep for a scenario key before it is copied, written and parsed."""
    count, stack = 0, [(value, 0)]
    while stack:
        v, depth = stack.pop()
        count += 1
        if depth > MAX_VALUE_DEPTH or count > MAX_VALUE_ITEMS:
            what = f"nested over {MAX_VALUE_DEPTH} deep" if depth > MAX_VALUE_DEPTH else \
                f"over {MAX_VALUE_ITEMS:,} items"
            raise AuvplanError(f"[{table}] {key}: a value {what}; no scenario key takes one")
        if isinstance(v, str) and len(v) > MAX_VALUE_ITEMS:
            raise AuvplanError(f"[{table}] {key}: a string of {len(v):,} characters, over {MAX_VALUE_ITEMS:,}")
        children = v.values() if isinstance(v, dict) else v if isinstance(v, list) else ()
        stack.extend((c, depth + 1) for c in children)


def open_scenario(session: Session, target: str) -> None:
    """Open a scenario (built-in name or TOML file) or a results folder.

    Parameters
    ----------
    session : Session
        The page's state.
    target : str
        Built-in name, scenario file or results folder (inside the served folders).
    """
    path = session.scenario_path(target)
    with session.long_work(f"opening {target}"), session.write_lock:
        if path.is_dir():
            _open_results(session, path)
        else:
            from ...io.files.jsonfile import source_base

            text = scenario_io.scenario_text(path) if path.is_file() else ""  # bounded: not a 1.5 GB read
            # what the loader reads, before it does, against the folder it reads from (a results folder's
            # scenario.toml: the original scenario's folder its source.json names)
            session.roots.confine_text(text, str(path), source_base(path) if path.is_file() else path.parent)
            sc = scenario_io.load(path)
            session.roots.confine(sc)
            world, mission = scenario_io.build(sc)
            session.set_scenario(sc, text, str(path), sc.base_dir, world, mission)
        with session.lock:
            session.history, session.undo_stack, session.candidates = [], [], []
        session.record("open", f"opened {target}")
        if not path.is_dir():
            set_initial_route(session)
            session.undo_stack = []


def _open_results(session: Session, out: Path) -> None:
    from ...io.results import folder as results
    from ...io.results import records

    record, text = records.read_run(out)
    if not text:
        raise AuvplanError(f"{out}/scenario.toml: missing — the report needs the scenario to rebuild the world")
    base = results.scenario_base(out)
    session.roots.confine_text(text, str(out / "scenario.toml"), base)
    sc = scenario_io.loads(text, str(out / "scenario.toml"), base_dir=base)
    session.roots.confine(sc)
    world, mission = scenario_io.build(sc, terrain=results.load_terrain(out))
    session.set_scenario(sc, text, str(out / "scenario.toml"), base, world, mission)
    session.plan = record.plan
    if record.route.shape[0] >= 2:
        session.set_waypoints(record.route)
    elif record.plan is not None and record.plan.path.size:
        session.set_waypoints(mission_route(world, mission, record.plan.path))
    else:
        set_initial_route(session)
    if record.sim is not None:
        session.flight, session.flight_of = record.sim, session.waypoints.copy()


def set_initial_route(session: Session) -> None:
    """The scenario's fixed route, else the straight start → goal line made into a mission (floors
    raised over the seabed: :func:`auvplan.sim.mission_route`), or, where that line enters a charted zone,
    the coarse lattice path round the zones (:func:`auvplan.planners.swarm.seeding.coarse_reference`).

    Parameters
    ----------
    session : Session
        The page's state.
    """
    world, mission = session.require()
    if mission.route:
        session.set_waypoints(np.asarray(mission.route, dtype=float))
        return
    if session.sc is not None and session.sc.survey is not None:  # the scenario's own survey
        plan_survey(session, session.doc, "the scenario's [survey]")
        return
    session.set_waypoints(mission_route(world, mission, _draft_line(world, mission)))


def _draft_line(world: Any, mission: Any) -> Any:
    """The straight start → goal line; where it enters a charted zone, the swarm planners' coarse lattice
    path round the zones instead (a draft the page opens with must not cross its own no-go zones: on
    ``chagos-reefs`` the straight line crosses Salomon atoll's reef)."""
    line = np.linspace(np.asarray(mission.start, dtype=float), np.asarray(mission.goal, dtype=float), 50)
    if not world.zones or not world.zones.exact.segments_enter(np.stack([line[:-1], line[1:]], axis=1)).any():
        return line
    from ...planners.swarm.seeding import coarse_reference
    from ...sim.pipeline import planning_problem

    _, path = coarse_reference(planning_problem(world, mission), mission.planner)
    return path if path.shape[0] >= 2 else line


def set_value(session: Session, table: str, key: str, value: Any) -> CheckResult:
    """Set ``[table] key = value`` (None removes the key) and rebuild the world and mission.

    Parameters
    ----------
    session : Session
        The page's state.
    table : str
        One of :data:`EDITABLE_TABLES`.
    key : str
        The key; the loader refuses unknown keys and bad values.
    value : object
        A TOML value (number, string, boolean or list), or None.

    Returns
    -------
    CheckResult
        The current mission checked under the new settings.
    """
    with session.long_work(f"setting [{table}] {key}"), session.write_lock:
        if table not in EDITABLE_TABLES:
            raise AuvplanError(f"[{table}]: the page edits only {', '.join(EDITABLE_TABLES)}")
        doc = copy.deepcopy(session.doc)
        t = doc.setdefault(table, {})
        if not isinstance(t, dict) or not isinstance(key, str):
            raise AuvplanError(f"[{table}] {key!r}: not a key of a table")
        _check_value(table, key, value)
        if value is None:
            t.pop(key, None)
        else:
            t[key] = value
        _rebuild(session, doc)
        session.record("set", f"[{table}] {key} = {'(default)' if value is None else value}")
        assert session.result is not None
        return session.result


def _rebuild(session: Session, doc: dict[str, Any]) -> None:
    """Validate ``doc`` with the scenario loader and rebuild the world (the same terrain)."""
    assert session.world is not None
    text = dumps(doc)
    session.roots.confine_text(text, session.source, session.base_dir)
    sc = scenario_io.loads(text, session.source, base_dir=session.base_dir)
    session.roots.confine(sc)
    world, mission = scenario_io.build(sc, terrain=session.world.terrain)
    w, plan, flight, flight_of = session.waypoints, session.plan, session.flight, session.flight_of
    # the work of checking it under the new settings, before they become the session's
    _limits.check_route_endurance("serve: the mission", w, mission.endurance.ds_m)
    same_vehicle = doc.get("vehicle") == session.doc.get("vehicle")
    session.set_scenario(sc, text, session.source, session.base_dir, world, mission)
    with session.lock:
        session.plan = plan
        if same_vehicle:
            session.flight, session.flight_of = flight, flight_of
        session.doc = doc
    session.set_waypoints(w)
