"""``plan --depart-between`` as a job: the departure sweep of the time-optimal planner, its files, and the
durations and instants of its arguments."""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import __version__
from ..errors import AuvplanError
from ..io.files.safeio import atomic_write, discard_on_failure, prepare_out, save_figure
from ..runtime.parallel import CHECKPOINTS, Runner, cache_folder, forget, task_key
from .durations import is_offset, parse_duration

if TYPE_CHECKING:
    from ..io.scenario.specs import Scenario
    from ..planners import PlannerSpec, PlanningProblem
    from ..planners.timeopt.planner import SweepRow, SweepSummary, TimeSetup
    from ..sim import Mission

__all__ = ["SWEEP_NAMES", "SweepRun", "parse_duration", "is_offset", "parse_instant", "sweep_scenario"]

SWEEP_NAMES = ("sweep.csv", "sweep_summary.json", "sweep.png")
"""Files of a sweep's ``--out``."""


@dataclass(frozen=True)
class SweepRun:
    """A departure sweep.

    Attributes
    ----------
    scenario : Scenario
        The scenario.
    rows : list of SweepRow
        One per departure.
    energy : list of dict
        Each departure's energy figures.
    summary : dict
        The best departure and what it saves.
    table : list of dict
        The rows of ``sweep.csv``.
    t0 : float
        First departure (s after start_time).
    step : float
        Departure step (s).
    computed : int
        Departures planned by this call (the others were read back from a killed run's checkpoints).
    """

    scenario: Scenario
    rows: list[SweepRow]
    energy: list[dict[str, float]]
    summary: SweepSummary
    table: list[dict[str, Any]]
    t0: float
    step: float
    computed: int = 0


def parse_instant(text: str, start_time: str, what: str) -> float:
    """Seconds after the mission's start_time of an ISO 8601 time or a '+6h' offset.

    Parameters
    ----------
    text : str
        The instant.
    start_time : str
        ``[mission] start_time`` (empty: none).
    what : str
        The option it came from, for the message.

    Returns
    -------
    float
        Seconds after start_time.
    """
    from ..io.data.ocean.tides import parse_start_time

    if is_offset(text):
        return parse_duration(text, what)
    if not start_time:
        raise AuvplanError(f"{what} {text!r}: a date-time needs [mission] start_time (or give an offset: +6h)")
    try:
        return parse_start_time(text) - parse_start_time(start_time)
    except ValueError as exc:
        raise AuvplanError(f"{what} {exc}") from None


def sweep_scenario(scenario: str, depart_between: Sequence[str], step: str, objective: str | None = None,
                   out: str | None = None, force: bool = False,
                   progress: Callable[[str, int, int], None] = lambda name, done, total: None,
                   runner: Runner | None = None, stage: Callable[[str], None] = lambda text: None) -> SweepRun:
    """The time-optimal plan of every departure between two instants, its energy, and the best departure.

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file.
    depart_between : pair of str
        First and last departure: ISO 8601 times, or offsets after ``[mission] start_time`` (``+6h``).
    step : str
        Departure step (``15min``, ``900s``, ``2h``).
    objective : {"time", "energy"}, optional
        Objective of the timed plans (default: the scenario's).
    out : str, optional
        Folder of ``sweep.csv``, ``sweep_summary.json`` and ``sweep.png`` (checked before any work).
    force : bool
        Replace those files.
    progress : callable
        Called with (the scenario's name, departures done, departures in all).
    runner : Runner, optional
        Where the departures run (:class:`auvplan.runtime.parallel.Runner`: this process by default, local workers or a
        dask scheduler); each finished departure is checkpointed in ``out/.auvplan-tasks`` (or the user's cache
        folder without ``out``) until the sweep's files are written, so a killed sweep run again plans only the
        departures it had not finished.
    stage : callable
        Told what the sweep does after its last departure (writing its files).

    Returns
    -------
    SweepRun
        The scenario, the rows, each departure's energy, the summary, the table, the first departure and the step.
    """
    with discard_on_failure(out):  # a sweep that fails before its files leaves no folder it made (as run)
        if out is not None:
            prepare_out(out, SWEEP_NAMES, force=force, job="sweep")
        return _sweep(scenario, depart_between, step, objective, out, progress, runner, stage)


def _sweep(scenario: str, depart_between: Sequence[str], step: str, objective: str | None, out: str | None,
           progress: Callable[[str, int, int], None], runner: Runner | None,
           stage: Callable[[str], None]) -> SweepRun:
    """:func:`sweep_scenario` after its folder is prepared."""
    from ..io.results import records
    from ..io.scenario import loader as scenario_io
    from ..io.scenario.build import check_plan_sizes
    from ..planners.timeopt.planner import sweep_summary
    from ..sim import planning_problem

    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    spec = replace(mission.planner, name="timeopt")
    if objective:
        spec = replace(spec, timeopt=replace(spec.timeopt, objective=objective))
    t0, t1 = (parse_instant(v, sc.mission.start_time, "--depart-between") for v in depart_between)
    dt = parse_duration(step, "--step")
    if not (t1 >= t0 and dt > 0 and (t1 - t0) / dt <= 500):
        raise AuvplanError(f"--depart-between {list(depart_between)} --step {step}: need T1 >= T0 and at most "
                           "500 departures")
    b = world.bounds
    check_plan_sizes(sc, (b.xmax - b.xmin, b.ymax - b.ymin), t1 - t0, timeopt=True)  # the table: sweep + horizon
    departs = np.arange(t0, t1 + 0.5 * dt, dt)
    job = _Sweep(task_key("sweep", __version__, repr(sc), repr(spec), t0, t1, _input_stamps(sc)),
                 planning_problem(world, mission),
                 spec, mission, float(departs.min()), float(departs.max()))
    keys = [task_key(job.key, float(d)) for d in departs]
    runner = replace(runner or Runner(), checkpoints=Path(out) / CHECKPOINTS if out else cache_folder("sweep"))
    progress(sc.name, 0, len(departs))
    done = runner.map(_departure, [float(d) for d in departs], keys, shared=job,
                      progress=lambda n, total: progress(sc.name, n, total))
    rows, energy = [r for r, _ in done.results], [e for _, e in done.results]
    summary = sweep_summary(rows, energy=spec.timeopt.objective == "energy")
    if sc.mission.start_time and summary.get("feasible_departures"):
        from ..io.data.ocean.tides import parse_start_time, utc_iso

        summary["best_depart_utc"] = utc_iso(parse_start_time(sc.mission.start_time) + summary["best_depart_s"])
    table = [{**dataclasses.asdict(r), **e} for r, e in zip(rows, energy)]
    if out:
        stage(f"writing {', '.join(SWEEP_NAMES)} to {out} …")
        folder = Path(out)
        atomic_write(folder / "sweep.csv", ",".join(table[0]) + "\n"
                     + "".join(",".join(f"{v:.6g}" for v in row.values()) + "\n" for row in table))
        records.write_json(folder / "sweep_summary.json", summary)
        from ..viz.timeplots import sweep_figure

        save_figure(folder / "sweep.png", sweep_figure(rows, f"{sc.name}: departure sweep"), dpi=120)
    forget(runner.checkpoints, keys)  # the results are out: a re-run starts afresh
    return SweepRun(sc, rows, energy, summary, table, t0, dt, done.computed)


def _input_stamps(sc: Scenario) -> list[Any]:
    """What a sweep's checkpoints depend on besides the scenario's text: every data file it names, with the
    files of its data set (size, time and SHA-256 of the bytes: a current forecast downloaded again under the
    same name is another sweep; a shapefile's ``.dbf``, a GeoTIFF's ``.aux.xml``, every file of a FileGDB folder) and
    the code (:func:`auvplan.io.data.cache.code_stamp`: an edit of auvplan within one version).

    Parameters
    ----------
    sc : Scenario
        The scenario (relative names resolve against its folder).

    Returns
    -------
    list
        The stamps, in a fixed order (a file that cannot be read: its name alone).
    """
    from ..io.data.cache import code_stamp, dataset_files, file_stamp
    from ..io.scenario.specs import named_files

    stamps: list[Any] = [code_stamp()]
    for key, name in named_files(sc):
        path = Path(name) if Path(name).is_absolute() or sc.base_dir is None else sc.base_dir / name
        # a vector file or a GeoTIFF with its sidecars, as the readers' cache keys it (a shapefile's .dbf, .prj);
        # a current or tide file alone (no sidecars: a sibling forecast.2024.nc is another data set)
        for f in [path] if key.startswith("[currents]") else dataset_files(path):
            # a folder the reader opens (a FileGDB ``.gdb``): every file in it, not its name alone
            for g in sorted(p for p in f.rglob("*") if p.is_file()) if f.is_dir() else [f]:
                try:
                    stamps.append(file_stamp(g))
                except OSError:
                    stamps.append(str(g))
    return stamps


@dataclass(frozen=True)
class _Sweep:
    """What every departure of a sweep shares (sent once to each worker)."""

    key: str
    problem: PlanningProblem
    spec: PlannerSpec
    mission: Mission
    t0: float
    t1: float


_SETUP: dict[str, TimeSetup] = {}
_SETUP_LOCK = threading.Lock()


def _departure(job: _Sweep, depart: float) -> tuple[SweepRow, dict[str, float]]:
    """One task of a sweep: a departure's row and energy (the lattice and table built once per process)."""
    from ..io.missions.energy import sweep_energy
    from ..planners.timeopt.planner import departure_row, setup

    with _SETUP_LOCK:
        ts = _SETUP.get(job.key)
        if ts is None:
            _SETUP.clear()  # one sweep's table at a time (~100 MB)
            ts = _SETUP[job.key] = setup(job.problem, job.spec, job.t0, job.t1)
    row, path = departure_row(job.problem, job.spec, ts, depart)
    return row, sweep_energy(job.problem.world, job.mission, [path], np.array([depart]))[0]
