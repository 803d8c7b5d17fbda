"""The time-dependent planner as a planner (``[planner] name = "timeopt"``) and the departure sweep.

:func:`plan_timeopt` plans one departure (lattice search + time-aware refinement,
:mod:`.timeopt`).  :func:`departure_sweep` plans every departure of a window on one lattice and
one current table, and beside each flies the straight line and the *steady-current plan* (the
time-optimal plan for the current frozen at the departure time, as a planner without time would
make it) through the real, changing current — the "percent saved" of planning with time.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import NotRequired, TypedDict

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray, Status
from ...cost import evaluate_paths
from ...path import polyline_length
from ..core.base import PlannerSpec, PlanningProblem, PlanResult
from ..core.common import check_endpoints, cost_model_for, search_box
from .front import FrontGrid, build_grid
from .front_plan import front_flight
from .search import (
    CurrentTable,
    Lattice,
    TimedPath,
    build_lattice,
    build_table,
    drift_free,
    refine,
    time_search,
    timed_traverse,
)
from .timing import fly_times

__all__ = ["TimeSetup", "SweepRow", "SweepSummary", "setup", "flown", "plan_timeopt", "departure_row",
           "departure_sweep", "sweep_summary"]


@dataclass(frozen=True, eq=False)
class TimeSetup:
    """A lattice and a current table shared by the plans of one problem.

    Parameters
    ----------
    lattice : Lattice
        Nodes and free legs over the search box.
    table : CurrentTable
        The current at the nodes over the departures and the horizon.
    cell : float
        Lattice spacing (m).
    ds : float
        Largest integration sub-step of a leg (m).
    build_s : float
        CPU time of building both (s).
    grid : FrontGrid, optional
        The front method's horizontal grid and current table (``method = "front"``).
    """

    lattice: Lattice
    table: CurrentTable
    cell: float
    ds: float
    build_s: float
    grid: FrontGrid | None = None


def _power(problem: PlanningProblem, speed: float) -> float:
    return problem.hotel_power + problem.drag_k * speed**3


def setup(problem: PlanningProblem, spec: PlannerSpec, t0: float, t1: float) -> TimeSetup:
    """Lattice over the search box and the current table from ``t0`` to ``t1`` + the horizon.

    Parameters
    ----------
    problem : PlanningProblem
        World, end points and speed.
    spec : PlannerSpec
        ``spec.timeopt``: cell, levels, time step, horizon, sub-step.
    t0, t1 : float
        First and last departure to cover (s after the mission's start time).

    Returns
    -------
    TimeSetup
        The shared lattice and table.
    """
    clock = time.process_time()
    p = spec.timeopt
    lower, upper = search_box(problem)
    cell = p.cell or max(upper[0] - lower[0], upper[1] - lower[1]) / 100.0
    lattice = build_lattice(problem.world, lower, upper, cell, p.levels, float(problem.start[2]))
    dist = float(np.linalg.norm(problem.goal - problem.start))
    slowest = problem.speed * (min(p.speeds) if p.objective == "energy" else 1.0)
    horizon = p.horizon_s or 1.5 * dist / slowest + 7200.0
    table = build_table(problem.world, lattice, t0, t1 + horizon, p.dt)
    grid = None
    if p.method == "front":
        grid = build_grid(problem.world, lower, upper, cell, (float(problem.start[2]), float(problem.goal[2])), t0,
                          t1 + horizon, p.dt)
    return TimeSetup(lattice, table, cell, p.substep or 0.5 * cell, time.process_time() - clock, grid)


#: Sub-step (m) of the World timing of the front's flights: they drift and turn with the current, where
#: the midpoint rule's error is larger than on a lattice leg (a reversing tide against 1000 m cells:
#: 125 m steps timed 0.009 % short of the least time, 20 m steps 3·10⁻⁷).
FRONT_DS = 20.0


def _front(problem: PlanningProblem, spec: PlannerSpec, ts: TimeSetup, grid: FrontGrid, depart: float,
           speeds: list[float], notes: list[str] | None) -> tuple[TimedPath | None, bool]:
    """The front method's best flight over ``speeds`` (:mod:`.front_plan`), None when it has none, and
    whether every front that missed the goal ran out of table (a longer one may reach it)."""
    p = spec.timeopt
    limit = ts.table.t1 + (ts.table.t1 - ts.table.t0)
    found, exhausted = [], True
    for v in speeds:
        out = front_flight(problem.world, grid, problem.start, problem.goal, depart, v, p.headings, FRONT_DS,
                           limit)
        if out.path is not None:
            found.append(out.path)
            continue
        exhausted = exhausted and out.front.exhausted
        if notes is not None:
            notes.append(out.front.reason or "the front reached the goal but no flight it gave passed the exact "
                         "segment test")
    if not found:
        return None, exhausted
    return min(found, key=lambda tp: tp.duration * (_power(problem, tp.speed) if p.objective == "energy" else 1.0)), \
        False


def _fly(problem: PlanningProblem, spec: PlannerSpec, ts: TimeSetup, depart: float, speed: float | None = None,
         table: CurrentTable | None = None, notes: list[str] | None = None, last: bool = True) -> TimedPath | None:
    """Search then refine one departure (on ``table``, default the real one) at ``speed``, or by
    ``spec.timeopt.objective`` over the speeds it allows (the least duration, or the least energy);
    the front method first when chosen (``notes`` receives why it found nothing; unless ``last``, a
    front that ran out of table returns None for a longer table rather than search the lattice)."""
    tab = ts.table if table is None else table
    p = spec.timeopt
    if speed is not None:
        speeds = [speed]
    else:
        speeds = [problem.speed] if p.objective == "time" else [f * problem.speed for f in p.speeds]
    if ts.grid is not None and table is None:
        if ts.lattice.shape[2] == 1 and ts.grid.free.all():  # open water at one depth: the front alone
            found, exhausted = _front(problem, spec, ts, ts.grid, depart, speeds, notes)
            if found is not None or (exhausted and not last):
                return found
        else:  # seabed or depth levels: the lattice's plan, its depth schedule, then the front on it
            lat = _fly(problem, spec, ts, depart, speed, ts.table)
            lat_t = flown(problem, ts, lat).duration if lat is not None else math.inf
            grid = ts.grid
            if lat is not None and ts.lattice.shape[2] > 1:
                lower, upper = search_box(problem)
                grid = build_grid(problem.world, lower, upper, ts.cell, ts.grid.z, ts.grid.t0, ts.grid.t1,
                                  ts.grid.dt, (lat.times, lat.points[:, 2]))
            found, exhausted = _front(problem, spec, ts, grid, depart, [lat.speed] if lat is not None else speeds,
                                      notes)
            if found is not None and not found.duration > lat_t:
                return found
            if lat is None and exhausted and not last:
                return None
            return lat
    raws = [time_search(problem.world, ts.lattice, tab, problem.start, problem.goal, depart, v, ts.ds, p.labels,
                        p.label_dt, p.max_labels, p.tail_first) for v in speeds]
    scored = [(r.duration * (_power(problem, r.speed) if p.objective == "energy" else 1.0), r)
              for r in raws if r is not None and np.isfinite(r.duration)]
    if not scored:
        return None
    raw = min(scored, key=lambda s: s[0])[1]
    vstep = ts.lattice.step[2] if ts.lattice.shape[2] > 1 else 0.0
    refined = refine(problem.world, tab, raw, ts.cell, vstep, ts.ds, p.relax_iterations)
    for cand in (refined, raw):  # the refinement may move a leg whose drift back meets the seabed
        if (cand.tail is not None or drift_free(problem.world, timed_traverse(tab, cand.points, float(cand.times[0]),
                                                                             cand.speed, ts.ds))) \
                and (table is not None or np.isfinite(flown(problem, ts, cand).duration)):
            return cand  # (where the current beats the vehicle, a line held at the table's edge of the
            # cone may be lost in the World's own current: then the other candidate)
    return refined


def flown(problem: PlanningProblem, ts: TimeSetup, tp: TimedPath) -> TimedPath:
    """A timed path re-timed through the World's current itself (:mod:`.timing`): the duration a plan reports.

    Parameters
    ----------
    problem : PlanningProblem
        The World (its current field).
    ts : TimeSetup
        The sub-step (a quarter of the search's) and the table's span (a drifting leg not
        arrived one span after the table's end is rejected).
    tp : TimedPath
        The path, its departure and speed.

    Returns
    -------
    TimedPath
        The same vertices with the times and drifts flown through the field (``inf`` from a leg
        no heading can hold on).
    """
    if tp.timed:
        return tp
    limit = ts.table.t1 + (ts.table.t1 - ts.table.t0)
    times, back = fly_times(problem.world.currents, tp.points, float(tp.times[0]), tp.speed, 0.25 * ts.ds, limit,
                            tp.tail)
    return TimedPath(tp.points, times, tp.speed, back, tp.tail)


def _failure(status: Status, message: str, t0: float) -> PlanResult:
    return PlanResult.failure(status, message, "timeopt", time.perf_counter() - t0)


def _result(problem: PlanningProblem, spec: PlannerSpec, tp: TimedPath, ts: TimeSetup, t0: float) -> PlanResult:
    tp = flown(problem, ts, tp)
    if not np.isfinite(tp.duration):
        return _failure(Status.INFEASIBLE, "flown through the current field itself (not the planner's table), "
                        "the plan meets a cross current no heading can hold; try a smaller [planner.timeopt] dt or "
                        "cell", t0)
    length = float(polyline_length(tp.points))
    energy = _power(problem, tp.speed) * tp.duration
    # geometric clearance (seabed along every segment, exactly; static obstacles), as the other planners
    exact = evaluate_paths(problem.world, tp.points[None], cost_model_for(problem, spec), exact=True)
    seg_ok = problem.world.segments_free(np.stack([tp.points[:-1], tp.points[1:]], axis=1), moving=False)
    terms = {
        "length": length, "terrain": 0.0, "energy": energy,
        "length_m": length, "energy_j": energy, "duration_s": tp.duration,
        "depart_s": float(tp.times[0]), "arrive_s": float(tp.times[-1]), "speed_m_s": tp.speed,
        "min_clearance_m": float(exact.min_clearance[0]), "violations": int((~seg_ok).sum()),
        "collisions": int((~seg_ok).sum()),  # deprecated alias of "violations" (CHANGELOG 0.2.0)
        "lattice_nodes": int(ts.lattice.free.sum()), "lattice_legs": ts.lattice.legs,
    }
    cost = tp.duration if spec.timeopt.objective == "time" else energy
    drift_ok = drift_free(problem.world, tp)
    terms["drift_back_m"] = float(tp.back.max()) if tp.back is not None and tp.back.size else 0.0
    terms["tail_first_legs"] = int(tp.tail.sum()) if tp.tail is not None else 0
    free = bool(seg_ok.all()) and drift_ok
    message = "" if free else "the refined path failed the exact segment test" if not seg_ok.all() else \
        "the current pushes the vehicle back behind a leg's start onto the seabed or an obstacle"
    return PlanResult(Status.EXACT if free else Status.INFEASIBLE, tp.points, cost, terms, ts.lattice.legs, 1,
                      time.perf_counter() - t0, np.array([cost]), "timeopt", None, message, times=tp.times,
                      tail=tp.tail)


def plan_timeopt(problem: PlanningProblem, spec: PlannerSpec, ts: TimeSetup | None = None) -> PlanResult:
    """Plan the departure ``spec.timeopt.depart_s`` (module notes of :mod:`.timeopt`).

    Parameters
    ----------
    problem : PlanningProblem
        World, end points, speed and power figures.
    spec : PlannerSpec
        ``spec.timeopt``: departure, objective, lattice and refinement settings.
    ts : TimeSetup, optional
        A lattice and table to reuse (built when omitted; rebuilt with a longer horizon when the
        plan runs past its end).

    Returns
    -------
    PlanResult
        The timed plan (``times`` per vertex) or a failure status.
    """
    t0 = time.perf_counter()
    bad = check_endpoints(problem)
    if bad is not None:
        return _failure(bad[0], bad[1], t0)
    p = spec.timeopt
    depart = p.depart_s
    for attempt in range(3):  # the horizon doubles when a plan runs past the end of the table
        ts = ts or setup(problem, spec, depart, depart)
        notes: list[str] = []
        best = _fly(problem, spec, ts, depart, notes=notes, last=attempt == 2)
        if best is None and attempt < 2:  # no path within the table: a longer one may have one
            spec = replace(spec, timeopt=replace(p, horizon_s=2.0 * (ts.table.t1 - depart)))
            p, ts = spec.timeopt, None
            continue
        if best is None:
            front = f"front: {notes[0]}; " if notes else ""
            return _failure(Status.INFEASIBLE, f"{front}no lattice path reaches the goal from departure {depart:.0f} s "
                            f"within {ts.table.t1 - depart:.0f} s (no heading makes good a way there against a current "
                            "stronger than the vehicle, or the seabed encloses the goal; try a smaller "
                            "[planner.timeopt] cell or another departure)", t0)
        if best.times[-1] < ts.table.t1 or attempt == 2:  # (the last attempt keeps its own table)
            break
        spec = replace(spec, timeopt=replace(p, horizon_s=2.0 * (ts.table.t1 - depart)))
        p, ts = spec.timeopt, None
    assert best is not None and ts is not None  # the loop breaks on its last attempt at the latest
    return _result(problem, spec, best, ts, t0)


@dataclass(frozen=True)
class SweepRow:
    """One departure of a sweep: durations (s) and energies (J) of the three ways to fly it.

    Parameters
    ----------
    depart_s : float
        Departure (s after the mission's start time).
    duration_s, energy_j : float
        The timed plan's travel time (s) and energy (J); ``inf`` when none.
    straight_duration_s, straight_energy_j : float
        The straight line at cruise speed through the changing current (``nan`` when not free).
    steady_duration_s, steady_energy_j : float
        The steady-current plan flown through the changing current.
    cpu_s : float
        CPU time of planning this departure (s).
    """

    depart_s: float
    duration_s: float
    energy_j: float
    straight_duration_s: float
    straight_energy_j: float
    steady_duration_s: float
    steady_energy_j: float
    cpu_s: float


def departure_sweep(problem: PlanningProblem, spec: PlannerSpec, departs: ArrayLike,
                    paths: list[tuple[FloatArray, float, BoolArray | None] | None] | None = None,
                    progress: Callable[[int, int], None] | None = None) -> tuple[list[SweepRow], TimeSetup]:
    """Plan every departure time on one lattice and table (module notes).

    Parameters
    ----------
    problem : PlanningProblem
        World, end points, speed and power figures.
    spec : PlannerSpec
        ``spec.timeopt`` settings.
    departs : array_like
        Departure times (s after the mission's start time).
    paths : list, optional
        When given, receives each departure's timed plan as ``(points (M, 3), speed, tail)`` (None
        where there is none; ``tail`` the ``(M - 1,)`` tail-first legs or None), for the energy budget
        of each departure (:mod:`auvplan.endurance`).
    progress : callable, optional
        Called as ``progress(done, total)`` after each departure (the command line's bar and ETA).

    Returns
    -------
    rows : list of SweepRow
        One row per departure.
    setup : TimeSetup
        The lattice and table they share.
    """
    departs = np.asarray(departs, dtype=float)
    ts = setup(problem, spec, float(departs.min()), float(departs.max()))
    rows = []
    for d in departs:
        row, path = departure_row(problem, spec, ts, float(d))
        rows.append(row)
        if paths is not None:
            paths.append(path)
        if progress is not None:
            progress(len(rows), len(departs))
    return rows, ts


def departure_row(problem: PlanningProblem, spec: PlannerSpec, ts: TimeSetup,
                  depart: float) -> tuple[SweepRow, tuple[FloatArray, float, BoolArray | None] | None]:
    """One departure of a sweep: its timed plan, and the straight line and steady-current plan flown beside it.

    Depends only on its arguments (one departure is one task of a parallel sweep, :mod:`auvplan.runtime.parallel`).

    Parameters
    ----------
    problem : PlanningProblem
        World, end points, speed and power figures.
    spec : PlannerSpec
        ``spec.timeopt`` settings.
    ts : TimeSetup
        The sweep's lattice and table (:func:`setup` over every departure).
    depart : float
        The departure (s after the mission's start time).

    Returns
    -------
    row : SweepRow
        The departure's row.
    path : tuple or None
        Its timed plan ``(points (M, 3), speed, tail)`` (None where there is none).
    """
    d = depart
    v = problem.speed
    power = _power(problem, v)
    straight_ok = problem.world.path_free(np.stack([problem.start, problem.goal]))
    clock = time.process_time()
    tp = _fly(problem, spec, ts, d)
    tp = flown(problem, ts, tp) if tp is not None else None
    cpu = time.process_time() - clock
    line = flown(problem, ts, TimedPath(np.stack([problem.start, problem.goal]), np.array([d, d]), v))
    sl = line.duration if straight_ok else math.nan
    it = int(round((d - ts.table.t0) / ts.table.dt))
    frozen = replace(ts.table, cur=ts.table.cur[it:it + 1], t0=float(d))
    steady = _fly(problem, spec, ts, d, v, table=frozen)
    steady = flown(problem, ts, steady) if steady is not None else None
    sd = steady.duration if steady is not None else math.inf
    # the plan is the best the planner knows as flown through the real current: where the table's
    # interpolation let the steady plan or the straight line fly faster, that one (by ppm)
    cands = [c for c in (tp, steady, line if straight_ok else None) if c is not None and np.isfinite(c.duration)]
    tp = min(cands, key=lambda c: c.duration * (_power(problem, c.speed) if spec.timeopt.objective == "energy"
                                                else 1.0)) if cands else None
    dur = tp.duration if tp is not None else math.inf
    energy = dur * _power(problem, tp.speed) if tp is not None else math.inf
    row = SweepRow(float(d), dur, energy, sl, sl * power, sd, sd * power, cpu)
    return row, ((tp.points, tp.speed, tp.tail) if tp is not None else None)


class SweepSummary(TypedDict):
    """:func:`sweep_summary`'s figures: departures (s after the start time), durations (s), energies (J),
    percentages saved (%), CPU time (s); only ``feasible_departures`` when no departure is feasible."""

    feasible_departures: int
    best_depart_s: NotRequired[float]
    best_duration_s: NotRequired[float]
    best_energy_j: NotRequired[float]
    worst_depart_s: NotRequired[float]
    worst_duration_s: NotRequired[float]
    worst_energy_j: NotRequired[float]
    saved_vs_worst_pct: NotRequired[float]
    saved_vs_straight_pct: NotRequired[float]
    saved_vs_steady_pct: NotRequired[float]
    energy_saved_vs_worst_pct: NotRequired[float]
    energy_saved_vs_straight_pct: NotRequired[float]
    energy_saved_vs_steady_pct: NotRequired[float]
    mean_saved_vs_steady_pct: NotRequired[float]
    mean_saved_vs_straight_pct: NotRequired[float]
    cpu_per_departure_s: NotRequired[float]
    best_depart_utc: NotRequired[str]
    """The best departure as UTC ISO text (added by the CLI when the mission has a start time)."""


def sweep_summary(rows: list[SweepRow], energy: bool = False) -> SweepSummary:
    """Best and worst departures and the percent saved by planning with time.

    The percent saved by the best timed plan against the worst departure, and against the
    straight line and the steady-current plan (both at cruise speed) flown at the best departure.

    Parameters
    ----------
    rows : list of SweepRow
        The sweep.
    energy : bool, default False
        Rank departures by energy instead of duration.

    Returns
    -------
    SweepSummary
        ``feasible_departures`` (only that key when none is), the best and worst departures with
        their durations (s) and energies (J), the percentages saved, and the CPU time per departure (s).
    """
    ok = [r for r in rows if np.isfinite(r.duration_s)]
    if not ok:
        return {"feasible_departures": 0}
    key = (lambda r: r.energy_j) if energy else (lambda r: r.duration_s)
    best, worst = min(ok, key=key), max(ok, key=key)

    def saved(a: float, b: float) -> float:
        return 100.0 * (b - a) / b if np.isfinite(b) and b > 0 else math.nan

    return {
        "feasible_departures": len(ok),
        "best_depart_s": best.depart_s, "best_duration_s": best.duration_s, "best_energy_j": best.energy_j,
        "worst_depart_s": worst.depart_s, "worst_duration_s": worst.duration_s, "worst_energy_j": worst.energy_j,
        "saved_vs_worst_pct": saved(best.duration_s, worst.duration_s),
        "saved_vs_straight_pct": saved(best.duration_s, best.straight_duration_s),
        "saved_vs_steady_pct": saved(best.duration_s, best.steady_duration_s),
        "energy_saved_vs_worst_pct": saved(best.energy_j, worst.energy_j),
        "energy_saved_vs_straight_pct": saved(best.energy_j, best.straight_energy_j),
        "energy_saved_vs_steady_pct": saved(best.energy_j, best.steady_energy_j),
        "mean_saved_vs_steady_pct": float(np.nanmean([saved(r.duration_s, r.steady_duration_s) for r in ok])),
        "mean_saved_vs_straight_pct": float(np.nanmean([saved(r.duration_s, r.straight_duration_s) for r in ok])),
        "cpu_per_departure_s": float(np.mean([r.cpu_s for r in rows])),
    }
