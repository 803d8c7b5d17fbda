"""What one page works on — the state of ``auvplan serve``: a scenario, its world, the mission being edited,
the candidates, the history — and the primitives that commit a change to it.

The actions that change it live in :mod:`auvplan.serve.actions`, one module per group (scenario,
editing, planning, save); every change goes through the code of the command line: scenario settings are
read back by :func:`auvplan.io.scenario.loader.loads` (a bad value is refused with the line ``auvplan
validate`` prints), a survey area is planned by :func:`auvplan.survey.mission.plan_survey`, a re-plan is
:func:`auvplan.sim.planned_route`, a flight :func:`auvplan.sim.simulate`, and every edit is re-checked by
:class:`~.check.IncrementalCheck` (``mission check``).

Three locks (issue 48): ``lock`` guards the state and is held only to read or commit it, never while
anything is computed; ``write_lock`` orders the writers of the mission (each bounded: an edit, an undo,
the commit of long work); :meth:`Session.long_work` lets one long job (open, set, survey, plan, fly,
save) run at a time and refuses a second at once (:class:`Busy`), and :meth:`Session.require_epoch`
drops long work that a newer edit overtook (:class:`Superseded`).
"""

from __future__ import annotations

import contextlib
import threading
import tomllib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..app.page.check import CheckResult, CheckSettings, IncrementalCheck
from ..app.page.paths import Roots
from ..errors import AuvplanError
from ..guidance.avoidance.local import key_waypoints
from ..io.files import limits as _limits
from ..io.scenario.builtins import builtin_scenarios
from ..io.scenario.builtins import resolve as resolve_scenario
from ..io.scenario.specs import Scenario
from ..planners import PlanResult
from ..sim import Mission, SimResult, with_leg_speeds
from ..world import World
from .navband import SIMPLIFY_M, nav_band  # (re-exported)

__all__ = ["Session", "Candidate", "Busy", "Superseded", "Stopped", "EDITABLE_TABLES", "MAX_WAYPOINTS", "SIMPLIFY_M",
           "builtin_names", "nav_band"]

_F64 = NDArray[np.float64]

EDITABLE_TABLES = ("vehicle", "mission", "endurance", "planner", "guidance", "avoidance")
"""Scenario tables whose keys the page may set (the loader validates each key and value)."""

MAX_WAYPOINTS = 20_000
"""Most waypoints a mission may have on the page."""

MAX_HISTORY = 500
"""Edits kept for undo (the history's text is kept whole)."""

class Busy(AuvplanError):
    """Long work (a survey, a plan, a flight, a rebuild, a save) is already running: asked again later."""


class Superseded(AuvplanError):
    """Long work finished after a newer edit of the mission: its result is dropped (the edit wins)."""


class Stopped(AuvplanError):
    """Long work stopped on the page's request (:meth:`Session.stop`): nothing of it is kept."""


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
    """The state of the page: one scenario and the mission being edited (the actions are in :mod:`.actions`).

    Parameters
    ----------
    roots : Roots
        The folders files may be read from and saved to.
    """

    def __init__(self, roots: Roots) -> None:
        self.roots = roots
        self.lock = threading.RLock()  # the state: held only to read or commit it, never while computing
        self.write_lock = threading.RLock()  # the writers of the mission, one at a time (each bounded)
        self._long = threading.Lock()  # long work, one at a time; a second is refused (Busy), never queued
        self._stop = threading.Event()  # set by stop(): the running plan or flight raises Stopped at its next step
        self.busy_with = ""
        self.epoch = 0  # bumped on every change of the waypoints: long work started before one is dropped
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
        self.undo_stack: list[_F64] = []
        self.candidates: list[Candidate] = []
        self.result: CheckResult | None = None
        self.keys: _F64 = np.empty((0, 3))  # the key waypoints of the mission (what the guidance steers by)
        self.nav_band: dict[str, Any] | None = None  # the navigation error band of the mission ([navigation])
        self.generation = 0  # bumped when the world changes: the page redraws its chart

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

    @contextlib.contextmanager
    def long_work(self, what: str) -> Iterator[int]:
        """Run long work aside: refused at once (:class:`Busy`) while other long work runs.

        Parameters
        ----------
        what : str
            What it is, for the refusal of the next one.

        Yields
        ------
        int
            The mission's epoch when the work started (:meth:`commit_if_current` drops it after a newer edit).
        """
        if not self._long.acquire(blocking=False):
            raise Busy(f"busy: {self.busy_with or 'other work'} is running; try {what} again when it is done, or "
                       "stop it")
        self.busy_with = what
        self._stop.clear()
        try:
            yield self.epoch
        finally:
            self.busy_with = ""
            self._long.release()

    def stop(self) -> str:
        """Ask the running long work to stop (a plan at its next iteration, a flight at its next simulated minute).

        Hostile round 22: a plan or a flight within the command line's bounds may run for many minutes (a slow
        vehicle over a long survey: 2·10⁷ time steps), and the page sends its requests one at a time: it waited
        behind it, with no way to stop it but to kill the server.

        Returns
        -------
        str
            What was asked to stop ('' when nothing runs).
        """
        what = self.busy_with
        if what:
            self._stop.set()
        return what

    def stop_point(self, what: str) -> None:
        """Raise :class:`Stopped` when :meth:`stop` was asked since the long work began (a progress callback).

        Parameters
        ----------
        what : str
            The work, for the message.
        """
        if self._stop.is_set():
            raise Stopped(f"{what}: stopped on request; nothing of it was kept")

    def require_epoch(self, epoch: int, what: str) -> None:
        """Refuse to commit long work started before the mission's last change (the caller holds ``write_lock``).

        Parameters
        ----------
        epoch : int
            :meth:`long_work`'s epoch.
        what : str
            The work, for the message.
        """
        if self.epoch != epoch:
            raise Superseded(f"{what}: the mission was edited while it ran; its result was dropped (the edit "
                             "stands; ask again)")

    def set_scenario(self, sc: Scenario, text: str, source: str, base: Path | None, world: World,
                     mission: Mission) -> None:
        """Make a loaded scenario the session's (its world, mission and check; the plan and flight dropped).

        Parameters
        ----------
        sc : Scenario
            The validated scenario.
        text : str
            Its TOML text.
        source : str
            Its file, for messages.
        base : pathlib.Path or None
            Folder its relative paths resolve against.
        world, mission : World, Mission
            Built from it.
        """
        doc = tomllib.loads(text) if text else {}
        checker = IncrementalCheck(world, mission)
        area = self._survey_area(sc, world, mission, base, source)
        with self.lock:
            self.sc, self.text, self.source, self.base_dir = sc, text, source, base
            self.doc = doc
            self.world, self.mission = world, mission
            self.checker = checker
            self.plan, self.flight, self.flight_of = None, None, None
            self.survey_area = area
            self.generation += 1

    def require(self) -> tuple[World, Mission]:
        """The open scenario's world and mission.

        Returns
        -------
        tuple of (World, Mission)
            Refused when no scenario is open.
        """
        if self.world is None or self.mission is None:
            raise AuvplanError("no scenario is open")
        return self.world, self.mission

    @staticmethod
    def _survey_area(sc: Scenario, world: World, mission: Mission, base: Path | None,
                     source: str) -> list[list[float]] | None:
        if sc.survey is None:
            return None
        from ..io.results.survey import survey_params

        try:
            params = survey_params(sc.survey, world, mission.vehicle, base, f"{source}: [survey]")
        except AuvplanError:
            return None
        return [list(map(float, c)) for c in params.area.exterior.coords]

    def _speeds(self, w: _F64) -> float | _F64:
        world, mission = self.require()
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
        with self.write_lock:
            return self.commit(self.waypoints)

    def commit(self, w: _F64) -> CheckResult:
        """Check ``w`` (outside the state lock) and make it the current mission; the caller holds ``write_lock``.

        Parameters
        ----------
        w : numpy.ndarray
            ``(N, 3)`` waypoints (m), bounded first by the one estimator.

        Returns
        -------
        CheckResult
            Its check.
        """
        if self.checker is None:
            raise AuvplanError("no scenario is open")
        world, mission = self.require()
        _limits.check_route_endurance("serve: the mission", w, mission.endurance.ds_m)
        speeds = self._speeds(w)
        result = self.checker.run(w, self.settings, speeds)
        keys = key_waypoints(w, world, mission.avoidance.collision_check)
        band = nav_band(world, mission, w, speeds)  # issue 52: the predicted error along the mission
        with self.lock:
            if not np.array_equal(w, self.waypoints):
                self.epoch += 1
            self.waypoints, self.result, self.keys, self.nav_band = w, result, keys, band
        return result

    def set_waypoints(self, w: Any) -> None:
        """Validate (2 to :data:`MAX_WAYPOINTS` finite points) and commit new waypoints.

        Parameters
        ----------
        w : array_like
            ``(N, 3)`` waypoints (m), built by the actions (the page's own numbers are read by
            :func:`~.bounds.scalar` and :func:`~.plans.as_points`).
        """
        p = np.asarray(w, dtype=float).reshape(-1, 3) if np.size(w) else np.empty((0, 3))  # built here, never JSON
        if not np.isfinite(p).all():
            raise AuvplanError("waypoints: every coordinate must be a finite number")
        if not 2 <= p.shape[0] <= MAX_WAYPOINTS:
            raise AuvplanError(f"the mission has {p.shape[0]} waypoints; it needs 2 to {MAX_WAYPOINTS}")
        self.commit(p.copy())

    def record(self, op: str, text: str) -> None:
        """Add a line to the history.

        Parameters
        ----------
        op : str
            The action.
        text : str
            What it did.
        """
        with self.lock:
            self.history.append({"n": len(self.history) + 1, "op": op, "text": text,
                                 "waypoints": int(self.waypoints.shape[0]),
                                 "ok": bool(self.result.summary["ok"]) if self.result else None})
            del self.history[:-MAX_HISTORY]

    def apply(self, w: _F64, op: str, text: str) -> CheckResult:
        """Commit new waypoints as an undoable edit and record it.

        Parameters
        ----------
        w : numpy.ndarray
            ``(N, 3)`` waypoints (m).
        op : str
            The action.
        text : str
            What it did.

        Returns
        -------
        CheckResult
            Their check.
        """
        previous = self.waypoints
        self.set_waypoints(w)
        with self.lock:
            self.undo_stack.append(previous)
            del self.undo_stack[:-MAX_HISTORY]
        self.record(op, text)
        assert self.result is not None
        return self.result

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

    def keep_current(self, name: str, origin: str, plan: PlanResult | None) -> Candidate:
        """Add the current mission to the candidates.

        Parameters
        ----------
        name : str
            Its name in the table.
        origin : str
            ``edited``, ``survey`` or the planner's name.
        plan : PlanResult or None
            The plan it was built from.

        Returns
        -------
        Candidate
            The kept candidate.
        """
        with self.lock:
            assert self.result is not None
            start = self.sc.mission.start_time if self.sc is not None else ""
            c = Candidate(name, origin, self.waypoints.copy(), dict(self.result.summary), plan, start)
            self.candidates.append(c)
            return c

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

    _apply = apply  # (the name the benchmarks and tests use)


def builtin_names() -> list[str]:
    """The built-in scenarios the page lists.

    Returns
    -------
    list of str
        Their names.
    """
    return list(builtin_scenarios())

