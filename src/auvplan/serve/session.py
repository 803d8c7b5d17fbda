"""What one page works on: a scenario, its world, the mission being edited, the candidates, the history.

Every change goes through the code of the command line: scenario settings are edited in the
scenario document and read back by :func:`auvplan.io.scenario.loader.loads` (so a bad value is
refused with the line ``auvplan validate`` prints), a survey area becomes a ``[survey]`` table planned
by :func:`auvplan.survey.mission.plan_survey`, a re-plan is :func:`auvplan.sim.planned_route`, a
flight :func:`auvplan.sim.simulate`, and every edit is re-checked by :class:`~.check.IncrementalCheck`
(``mission check``).  The session is data in, data out; :mod:`.app` serialises it to the page.
"""

from __future__ import annotations

import copy
import threading
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import AuvplanError
from ..guidance.avoidance.local import key_waypoints
from ..io.scenario import loader as scenario_io
from ..io.scenario.builtins import builtin_scenarios
from ..io.scenario.builtins import resolve as resolve_scenario
from ..io.scenario.specs import Scenario
from ..planners import PlanResult
from ..sim import Mission, SimResult, mission_route, with_leg_speeds
from ..world import World
from .check import CheckResult, CheckSettings, IncrementalCheck
from .paths import Roots
from .plans import as_points, flown, nearest_leg, plan_area, replanned, survey_table
from .tomlout import dumps

__all__ = ["Session", "Candidate", "EDITABLE_TABLES", "MAX_WAYPOINTS", "builtin_names"]

_F64 = NDArray[np.float64]

EDITABLE_TABLES = ("vehicle", "mission", "endurance", "planner", "guidance", "avoidance")
"""Scenario tables whose keys the page may set (the loader validates each key and value)."""

MAX_WAYPOINTS = 20_000
"""Most waypoints a mission may have on the page."""

MAX_HISTORY = 500
"""Edits kept for undo (the history's text is kept whole)."""


@dataclass(frozen=True, eq=False)
class Candidate:
    """A mission kept for comparison.

    Attributes
    ----------
    name : str
        Shown in the table.
    origin : str
        ``edited``, ``survey`` or the planner's name.
    waypoints : numpy.ndarray
        ``(N, 3)`` mission (m).
    summary : dict
        Its check's figures (:attr:`CheckResult.summary`).
    plan : PlanResult or None
        The plan it was built from.
    start_time : str
        The departure it was checked for.
    """

    name: str
    origin: str
    waypoints: _F64
    summary: dict[str, Any]
    plan: PlanResult | None
    start_time: str


class Session:
    """The state of the page: one scenario and the mission being edited.

    Parameters
    ----------
    roots : Roots
        The folders files may be read from and saved to.
    """

    def __init__(self, roots: Roots) -> None:
        self.roots = roots
        self.lock = threading.RLock()
        self.source = ""
        self.base_dir: Path | None = None
        self.doc: dict[str, Any] = {}
        self.text = ""
        self.sc: Scenario | None = None
        self.world: World | None = None
        self.mission: Mission | None = None
        self.checker: IncrementalCheck | None = None
        self.settings = CheckSettings()
        self.waypoints: _F64 = np.empty((0, 3))
        self.plan: PlanResult | None = None
        self.flight: SimResult | None = None
        self.flight_of: _F64 | None = None
        self.survey_area: list[list[float]] | None = None
        self.history: list[dict[str, Any]] = []
        self._undo: list[_F64] = []
        self.candidates: list[Candidate] = []
        self.result: CheckResult | None = None
        self.keys: _F64 = np.empty((0, 3))  # the key waypoints of the mission (what the guidance steers by)
        self.generation = 0  # bumped when the world changes: the page redraws its chart

    # ------------------------------------------------------------------ loading
    def scenario_path(self, name: str) -> Path:
        """A scenario the page may open: a built-in name or a TOML file inside the served folders.

        Parameters
        ----------
        name : str
            Built-in name or file name.

        Returns
        -------
        pathlib.Path
            The TOML file.
        """
        if name in builtin_scenarios():
            return resolve_scenario(name)
        return self.roots.resolve(name)

    def open(self, target: str) -> None:
        """Open a scenario (built-in name or TOML file) or a results folder.

        Parameters
        ----------
        target : str
            Built-in name, scenario file or results folder (inside the served folders).
        """
        path = self.scenario_path(target)
        with self.lock:
            if path.is_dir():
                self._open_results(path)
            else:
                text = path.read_text(encoding="utf-8") if path.is_file() else ""
                sc = scenario_io.load(path)
                world, mission = scenario_io.build(sc)
                self._set_scenario(sc, text, str(path), path.parent, world, mission)
            self.history, self._undo, self.candidates = [], [], []
            self._record("open", f"opened {target}")
            if not path.is_dir():
                self._set_initial_route()
                self._undo = []

    def _open_results(self, out: Path) -> None:
        from ..io.results import folder as results
        from ..io.results import records

        record, text = records.read_run(out)
        if not text:
            raise AuvplanError(f"{out}/scenario.toml: missing — the report needs the scenario to rebuild the world")
        base = results.scenario_base(out)
        sc = scenario_io.loads(text, str(out / "scenario.toml"), base_dir=base)
        world, mission = scenario_io.build(sc, terrain=results.load_terrain(out))
        self._set_scenario(sc, text, str(out / "scenario.toml"), base, world, mission)
        self.plan = record.plan
        if record.route.shape[0] >= 2:
            self._set_waypoints(record.route)
        elif record.plan is not None and record.plan.path.size:
            self._set_waypoints(mission_route(world, mission, record.plan.path))
        else:
            self._set_initial_route()
        if record.sim is not None:
            self.flight, self.flight_of = record.sim, self.waypoints.copy()

    def _set_scenario(self, sc: Scenario, text: str, source: str, base: Path | None, world: World,
                      mission: Mission) -> None:
        self.sc, self.text, self.source, self.base_dir = sc, text, source, base
        self.doc = tomllib.loads(text) if text else {}
        self.world, self.mission = world, mission
        self.checker = IncrementalCheck(world, mission)
        self.plan, self.flight, self.flight_of = None, None, None
        self.survey_area = self._survey_area()
        self.generation += 1

    def _set_initial_route(self) -> None:
        """The scenario's fixed route, else the straight start → goal line made into a mission (floors
        raised over the seabed: :func:`auvplan.sim.mission_route`)."""
        world, mission = self._require()
        if mission.route:
            self._set_waypoints(np.asarray(mission.route, dtype=float))
            return
        if self.sc is not None and self.sc.survey is not None:  # the scenario's own survey
            self._plan_survey(self.doc, "the scenario's [survey]")
            return
        line = np.linspace(np.asarray(mission.start, dtype=float), np.asarray(mission.goal, dtype=float), 50)
        self._set_waypoints(mission_route(world, mission, line))

    def _require(self) -> tuple[World, Mission]:
        if self.world is None or self.mission is None:
            raise AuvplanError("no scenario is open")
        return self.world, self.mission

    def _survey_area(self) -> list[list[float]] | None:
        if self.sc is None or self.sc.survey is None or self.world is None:
            return None
        from ..io.results.survey import survey_params

        try:
            params = survey_params(self.sc.survey, self.world, self.mission.vehicle if self.mission else None,
                                   self.base_dir, f"{self.source}: [survey]")
        except AuvplanError:
            return None
        return [list(map(float, c)) for c in params.area.exterior.coords]

    # ------------------------------------------------------------------ checking
    def _speeds(self, w: _F64) -> float | _F64:
        world, mission = self._require()
        if mission.endurance.speeds == "fixed" or w.shape[0] < 2:
            return mission.vehicle.speed
        return np.asarray(with_leg_speeds(world, mission, w).leg_speeds, dtype=float)

    def check(self) -> CheckResult:
        """Re-check the current mission (only its changed legs are computed).

        Returns
        -------
        CheckResult
            ``mission check``'s verdicts on the current waypoints.
        """
        with self.lock:
            if self.checker is None:
                raise AuvplanError("no scenario is open")
            self.result = self.checker.run(self.waypoints, self.settings, self._speeds(self.waypoints))
            world, mission = self._require()
            self.keys = key_waypoints(self.waypoints, world, mission.avoidance.collision_check)
            return self.result

    def _set_waypoints(self, w: Any) -> None:
        p = as_points(w, "waypoints").reshape(-1, 3) if np.size(w) else np.empty((0, 3))
        if not 2 <= p.shape[0] <= MAX_WAYPOINTS:
            raise AuvplanError(f"the mission has {p.shape[0]} waypoints; it needs 2 to {MAX_WAYPOINTS}")
        self.waypoints = p.copy()
        self.check()

    def _record(self, op: str, text: str) -> None:
        self.history.append({"n": len(self.history) + 1, "op": op, "text": text,
                             "waypoints": int(self.waypoints.shape[0]),
                             "ok": bool(self.result.summary["ok"]) if self.result else None})
        del self.history[:-MAX_HISTORY]

    # ------------------------------------------------------------------ editing
    def edit(self, op: str, index: int | None = None, x: float | None = None, y: float | None = None,
             z: float | None = None) -> CheckResult:
        """Move, insert or delete a waypoint, or set its depth; then re-check.

        Parameters
        ----------
        op : {'move', 'insert', 'delete', 'depth'}
            ``move`` waypoint ``index`` to ``(x, y)`` (and ``z`` when given); ``insert`` a waypoint at
            ``(x, y)`` into the nearest leg (depth interpolated along it, or ``z``); ``delete`` waypoint
            ``index``; ``depth``: set waypoint ``index``'s ``z``.
        index : int, optional
            The waypoint.
        x, y, z : float, optional
            Local coordinates (m).

        Returns
        -------
        CheckResult
            The check of the edited mission.
        """
        with self.lock:
            w = self.waypoints.copy()
            n = w.shape[0]
            if op in ("move", "delete", "depth"):
                if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < n:
                    raise AuvplanError(f"waypoint {index!r}: no such waypoint (0 to {n - 1})")
            xyz = [None if v is None else float(as_points(v, f"{op} {k}")) for k, v in (("x", x), ("y", y), ("z", z))]
            if op == "move":
                if xyz[0] is None or xyz[1] is None:
                    raise AuvplanError("move: x and y are needed")
                w[index, 0], w[index, 1] = xyz[0], xyz[1]
                if xyz[2] is not None:
                    w[index, 2] = xyz[2]
                text = f"moved waypoint {index} to ({xyz[0]:.0f}, {xyz[1]:.0f}, {w[index, 2]:.0f}) m"
            elif op == "depth":
                if xyz[2] is None:
                    raise AuvplanError("depth: z is needed")
                w[index, 2] = xyz[2]
                text = f"set waypoint {index} to depth {-xyz[2]:.1f} m"
            elif op == "insert":
                if xyz[0] is None or xyz[1] is None:
                    raise AuvplanError("insert: x and y are needed")
                leg, f = nearest_leg(w, np.array([xyz[0], xyz[1]]))
                zi = w[leg, 2] + f * (w[leg + 1, 2] - w[leg, 2]) if xyz[2] is None else xyz[2]
                w = np.insert(w, leg + 1, [xyz[0], xyz[1], zi], axis=0)
                index = leg + 1
                text = f"inserted waypoint {index} at ({xyz[0]:.0f}, {xyz[1]:.0f}, {zi:.0f}) m"
            elif op == "delete":
                if n <= 2:
                    raise AuvplanError("delete: a mission needs at least 2 waypoints (a start and a goal)")
                w = np.delete(w, int(index or 0), axis=0)
                text = f"deleted waypoint {index}"
            else:
                raise AuvplanError(f"edit op = {op!r}: choose move, insert, delete or depth")
            return self._apply(w, op, text)

    def _apply(self, w: _F64, op: str, text: str) -> CheckResult:
        previous = self.waypoints
        self._set_waypoints(w)
        self._undo.append(previous)
        del self._undo[:-MAX_HISTORY]
        self._record(op, text)
        assert self.result is not None
        return self.result

    def undo(self) -> CheckResult:
        """Go back to the waypoints before the last edit.

        Returns
        -------
        CheckResult
            The check of the restored mission.
        """
        with self.lock:
            if not self._undo:
                raise AuvplanError("undo: nothing to undo")
            self._set_waypoints(self._undo.pop())
            self._record("undo", "undid the last edit")
            assert self.result is not None
            return self.result

    def set_check(self, semantics: str, pitch_deg: float) -> CheckResult:
        """Check under another executor's semantics or pitch.

        Parameters
        ----------
        semantics : {'held', 'ramp'}
            Depth held per leg (MOOS-IvP) or ramped along it (every other export).
        pitch_deg : float
            Pitch of the held executor's depth changes (degrees).

        Returns
        -------
        CheckResult
            The new check.
        """
        with self.lock:
            try:
                self.settings = CheckSettings(str(semantics), float(pitch_deg))
            except (TypeError, ValueError) as exc:
                raise AuvplanError(f"--pitch {exc}") from None
            return self.check()

    # ------------------------------------------------------------------ the scenario
    def set_value(self, table: str, key: str, value: Any) -> CheckResult:
        """Set ``[table] key = value`` (None removes the key) and rebuild the world and mission.

        Parameters
        ----------
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
        with self.lock:
            if table not in EDITABLE_TABLES:
                raise AuvplanError(f"[{table}]: the page edits only {', '.join(EDITABLE_TABLES)}")
            doc = copy.deepcopy(self.doc)
            t = doc.setdefault(table, {})
            if not isinstance(t, dict) or not isinstance(key, str):
                raise AuvplanError(f"[{table}] {key!r}: not a key of a table")
            if value is None:
                t.pop(key, None)
            else:
                t[key] = value
            self._rebuild(doc)
            self._record("set", f"[{table}] {key} = {'(default)' if value is None else value}")
            assert self.result is not None
            return self.result

    def _rebuild(self, doc: dict[str, Any]) -> None:
        """Validate ``doc`` with the scenario loader and rebuild the world (the same terrain)."""
        assert self.world is not None
        text = dumps(doc)
        sc = scenario_io.loads(text, self.source, base_dir=self.base_dir)
        world, mission = scenario_io.build(sc, terrain=self.world.terrain)
        w, plan, flight, flight_of = self.waypoints, self.plan, self.flight, self.flight_of
        self._set_scenario(sc, text, self.source, self.base_dir, world, mission)
        self.plan = plan
        if doc.get("vehicle") == self.doc.get("vehicle"):
            self.flight, self.flight_of = flight, flight_of
        self.doc = doc
        self._set_waypoints(w)

    # ------------------------------------------------------------------ survey, plan, fly
    def survey(self, polygon_xy: Any = None, file: str | None = None) -> CheckResult:
        """Make the mission a survey of an area drawn on the chart (local x, y) or read from a file.

        Parameters
        ----------
        polygon_xy : array_like, optional
            ``(K, 2)`` polygon in the local frame (m).
        file : str, optional
            GeoJSON or KML file inside the served folders (its largest polygon).

        Returns
        -------
        CheckResult
            The check of the survey mission.
        """
        with self.lock:
            self._require()
            path = self.roots.resolve(file) if file else None
            doc = survey_table(self.doc, None if path else polygon_xy, path)
            what = f"the area of {file}" if file else f"a drawn area of {len(doc['survey']['polygon_xy'])} points"
            return self._plan_survey(doc, what)

    def _plan_survey(self, doc: dict[str, Any], what: str) -> CheckResult:
        world, mission = self._require()
        s = plan_area(world, mission, doc, self.source, self.base_dir)
        self.doc, self.text, self.sc, self.survey_area, self.plan = s.doc, s.text, s.scenario, s.area, None
        result = self._apply(s.route, "survey", f"survey of {what}: {s.label}")
        self._keep("survey", "survey", None)
        return result

    def replan(self, planner: str | None = None, seed: int | None = None) -> CheckResult:
        """Plan the mission again (global plan → executable mission) and keep it as a candidate.

        Parameters
        ----------
        planner : str, optional
            A registered planner (the scenario's by default).
        seed : int, optional
            Seed (the scenario's by default).

        Returns
        -------
        CheckResult
            The check of the new mission (it becomes the current one).
        """
        with self.lock:
            world, mission = self._require()
            name = planner or mission.planner.name
            s = (self.sc.seed if self.sc else 0) if seed is None else seed
        plan, route = replanned(world, mission, name, s)
        with self.lock:
            self.plan = plan
            result = self._apply(route, "plan", f"planned with {name} seed {s}: {route.shape[0]} waypoints")
            self._keep(f"{name} seed {s}", name, plan)
            return result

    def fly(self) -> None:
        """Fly the current mission in the closed loop (currents, moving obstacles, the guidance)."""
        with self.lock:
            world, mission = self._require()
            w = self.waypoints.copy()
            seed = self.sc.seed if self.sc else 0
        sim = flown(world, mission, w, seed)
        with self.lock:
            self.flight, self.flight_of = sim, w
            self._record("fly", f"flew the mission: {sim.status.value}")

    def flight_summary(self) -> dict[str, Any] | None:
        """The last flight of the current waypoints (None when there is none or the mission changed since).

        Returns
        -------
        dict or None
            ``status``, the metrics and the decimated track ``x``, ``y``.
        """
        sim = self.flight
        if sim is None or self.flight_of is None or not np.array_equal(self.flight_of, self.waypoints):
            return None
        from ..sim import decimate

        d = decimate(sim)
        metrics = {k: (float(v) if isinstance(v, float | int | np.floating) and not isinstance(v, bool) else v)
                   for k, v in sim.metrics.items()}
        return {"status": sim.status.value, "metrics": metrics, "x": d.position[:, 0].tolist(),
                "y": d.position[:, 1].tolist()}

    # ------------------------------------------------------------------ candidates
    def _keep(self, name: str, origin: str, plan: PlanResult | None) -> Candidate:
        assert self.result is not None
        start = self.sc.mission.start_time if self.sc is not None else ""
        c = Candidate(name, origin, self.waypoints.copy(), dict(self.result.summary), plan, start)
        self.candidates.append(c)
        return c

    def keep(self, name: str = "") -> Candidate:
        """Keep the current mission as a candidate.

        Parameters
        ----------
        name : str, optional
            Its name in the table.

        Returns
        -------
        Candidate
            The kept candidate.
        """
        with self.lock:
            label = (name or f"edited {len(self.candidates) + 1}").strip()[:80]
            return self._keep(label, "edited", self.plan)

    def choose(self, index: int) -> CheckResult:
        """Make candidate ``index`` the current mission.

        Parameters
        ----------
        index : int
            Row of the candidates table.

        Returns
        -------
        CheckResult
            Its check.
        """
        with self.lock:
            if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < len(self.candidates):
                raise AuvplanError(f"candidate {index!r}: no such candidate")
            c = self.candidates[index]
            self.plan = c.plan
            return self._apply(c.waypoints, "choose", f"chose candidate {c.name}")

    def candidate_rows(self) -> list[dict[str, Any]]:
        """The candidates table.

        Returns
        -------
        list of dict
            ``name``, ``origin``, ``waypoints``, ``start_time`` and the figures of each.
        """
        keys = ("ok", "length_m", "duration_s", "energy_wh", "margin_wh", "min_altitude_m", "tightest_turn_m",
                "max_pitch_deg")
        return [{"name": c.name, "origin": c.origin, "waypoints": int(c.waypoints.shape[0]),
                 "start_time": c.start_time, **{k: c.summary.get(k) for k in keys}} for c in self.candidates]


def builtin_names() -> list[str]:
    """The built-in scenarios the page lists.

    Returns
    -------
    list of str
        Their names.
    """
    return list(builtin_scenarios())

