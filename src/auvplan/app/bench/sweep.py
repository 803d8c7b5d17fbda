"""Sweeps of scenario × planner × guidance × current member × seed on dask.distributed (``auvplan bench``).

Every run goes through :func:`auvplan.sim.run_mission` and yields one flat row (status, every
cost term and metric, evaluations, CPU and wall time, optionally the gap to the grid reference).
Rows are appended to ``rows.csv`` as they arrive, so an interrupted sweep keeps what it
finished; ``resume=True`` skips the runs already in the file (and drops a line cut short by the
interruption).  Tasks are chunks of seeds of one cell, so the scheduling overhead stays small;
each run is seeded by its own seed, so the rows do not depend on the worker count or order.

With ``randomise=True`` each seed also re-draws every moving obstacle's track (start shifted
±150 m along and across its motion, speed × [0.6, 1.2], new random-walk seeds, a random phase
on loops) — the Monte Carlo an operator certifies a mission with; ``plan_once=True`` then plans
once per cell (with the scenario's seed) and flies that plan in every seed's world.  The current
ensemble's members and perturbation seeds are axes too (:mod:`auvplan.app.bench.members`).
"""

from __future__ import annotations

import csv
import json
import math
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ...errors import AuvplanError, require
from ...guidance.avoidance.local import key_waypoints
from ...guidance.avoidance.params import AVOIDANCE
from ...io.files.manifest import claim
from ...io.files.outdir import OutputError, check_inside
from ...io.scenario import loader as scenario_io
from ...io.scenario.specs import Scenario
from ...planners import PIPELINES, PlannerSpec, PlanResult, plan, reference, with_reference
from ...planners.core.registry import known, names
from ...planners.grid.planner import on_cost_function
from ...runtime.parallel import Runner
from ...sim import RunRecord, mission_route, planning_problem, run_mission, simulate
from ...world import CircleMotion, LinearMotion, MovingObstacle, RandomWalkMotion, Sphere, WaypointMotion, World
from .members import expand_members, member_columns, member_world, parse_label
from .rows import COLUMNS, Row, _cut_partial_line, _key, read_rows

__all__ = ["SweepSpec", "perturb_moving", "fast_movers", "run_chunk", "sweep", "MAX_RUNS"]

MAX_RUNS = 100_000
"""Most runs (plan + flight) one sweep may hold, over all its cells and seeds: a run takes a second or more, so
100 000 are a day of work or more on a laptop.  ``--seeds 1000000000`` used to build its list of tasks for
minutes, filling the memory, before the first run (hostile round 20)."""

@dataclass(frozen=True)
class SweepSpec:
    """What a sweep runs.

    Attributes
    ----------
    scenarios : tuple of str
        Built-in names or TOML files.
    planners : tuple of str
        Planner names (``"scenario"`` = each scenario's own), each optionally with a pipeline,
        ``name/pipeline`` (e.g. ``iabc/progressive``; :data:`auvplan.planners.PIPELINES`).
    guidance : tuple of str
        ``hybrid``, ``los``, ``ilos`` (``"scenario"`` = each scenario's own).
    seeds : int
        Seeds 0 .. seeds-1 per cell.
    budget : int
        Objective evaluations per plan (0 = the scenario's), spent exactly: the seeded pipeline's default
        budget is pinned, so IABC's stop of a swarm stalled behind its lattice corridor never applies in a
        sweep and every planner of a cell spends the same evaluations.
    reference : bool
        Also compute the grid reference once per cell and each run's gap to it.
    randomise : bool
        Re-draw the moving obstacles' tracks per seed (Monte Carlo).
    plan_once : bool
        Plan once per cell and fly that plan in every seed (with ``randomise``).
    chunk : int
        Seeds per task.
    avoidance : tuple of str
        Local avoidance variants (``"scenario"`` = each scenario's own); any other is a further
        axis, written into the guidance column as ``guidance+avoidance``.
    members : tuple of str
        Current ensemble members (``"scenario"`` = the scenario's own currents, ``"each"`` = every
        member of its ``[currents] members``, or member names): each is the only current of its
        cells, written into the scenario column as ``scenario@member`` (:mod:`auvplan.app.bench.members`).
    member_seeds : tuple of int
        Perturbation seeds: the ``perturbation`` members re-drawn with each (an axis;
        ``scenario@member~seed``); empty = the scenario's own seeds.
    """

    scenarios: tuple[str, ...] = ("dynamic-terrain",)
    planners: tuple[str, ...] = ("scenario",)
    guidance: tuple[str, ...] = ("scenario",)
    seeds: int = 10
    budget: int = 0
    reference: bool = False
    randomise: bool = False
    plan_once: bool = False
    chunk: int = 10
    avoidance: tuple[str, ...] = ("scenario",)
    members: tuple[str, ...] = ("scenario",)
    member_seeds: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        if not self.members or any(not m.strip() for m in self.members):
            raise AuvplanError(f"--members {' '.join(self.members)!r}: name members, 'each' or 'scenario'")
        if any(isinstance(s, bool) or not isinstance(s, int) or s < 0 for s in self.member_seeds):
            raise AuvplanError(f"--member-seeds {self.member_seeds!r}: seeds are integers >= 0")
        for a in self.avoidance:
            if a != "scenario" and a not in AVOIDANCE:
                raise AuvplanError(f"unknown avoidance {a!r}; choose from scenario, {', '.join(AVOIDANCE)}")
        for p in self.planners:
            name, slash, pipeline = p.partition("/")
            if p != "scenario" and not known(name):
                raise AuvplanError(f"unknown planner {p!r}; choose from scenario, {', '.join(names())}")
            if slash and pipeline not in PIPELINES:
                raise AuvplanError(f"unknown pipeline in {p!r}; choose from {', '.join(PIPELINES)}")
        for g in self.guidance:
            if g not in ("scenario", "hybrid", "los", "ilos"):
                raise AuvplanError(f"unknown guidance {g!r}; choose from scenario, hybrid, los, ilos")
        if self.seeds < 1 or self.chunk < 1 or self.budget < 0:
            raise AuvplanError("need seeds >= 1, chunk >= 1 and budget >= 0")
        if self.seeds > MAX_RUNS:
            raise AuvplanError(f"--seeds {self.seeds}: over the {MAX_RUNS:,} runs a sweep may hold (a day of work "
                               "or more); sweep fewer seeds, or split the sweep")

    def tasks(self) -> list[tuple[str, str, str, tuple[int, ...]]]:
        """List the sweep's tasks: chunks of seeds of one cell, in a fixed order.

        ``"scenario"`` is resolved to each scenario's own planner and guidance (planner
        ``"route"`` for a scenario that flies a fixed route).

        Returns
        -------
        list of (str, str, str, tuple of int)
            ``(scenario, planner, guidance, seeds)`` chunks.
        """
        out: list[tuple[str, str, str, tuple[int, ...]]] = []
        runs = 0
        for s0 in self.scenarios:
            sc = scenario_io.load(s0)
            own_planner = "route" if sc.mission.route else sc.planner.name
            labels = [s0]
            if self.members != ("scenario",) or self.member_seeds:
                labels = expand_members(s0, sc, scenario_io.build(sc)[0], self.members, self.member_seeds)
            runs += len(labels) * len(self.planners) * len(self.guidance) * len(self.avoidance) * self.seeds
            if runs > MAX_RUNS:  # counted before the cells are built (at most: a repeated cell is run once)
                raise AuvplanError(f"the sweep holds {runs:,} runs (scenarios × members × planners × guidance × "
                                   f"avoidance × --seeds {self.seeds}), over the {MAX_RUNS:,} allowed (a day of work "
                                   "or more); sweep fewer seeds or fewer variants")
            out += self._cells(labels, sc, own_planner)
        return out

    def _cells(self, labels: list[str], sc: Scenario, own_planner: str) -> list[tuple[str, str, str, tuple[int, ...]]]:
        out: list[tuple[str, str, str, tuple[int, ...]]] = []
        seen: set[tuple[str, str, str, int]] = set()  # a cell once ('scenario' may name a listed planner)
        for s in labels:
            for p in self.planners:
                p = own_planner if p == "scenario" or own_planner == "route" else p
                for g0 in self.guidance:
                    for a in self.avoidance:
                        g = sc.guidance.name if g0 == "scenario" else g0
                        g = g if a == "scenario" else f"{g}+{a}"
                        for lo in range(0, self.seeds, self.chunk):
                            if (s, p, g, lo) not in seen:  # (a list scan here was quadratic in the chunks)
                                seen.add((s, p, g, lo))
                                out.append((s, p, g, tuple(range(lo, min(lo + self.chunk, self.seeds)))))
        return out


def perturb_moving(world: World, seed: int) -> World:
    """Re-draw every moving obstacle's track from ``seed`` (see the module notes).

    Parameters
    ----------
    world : World
        The scenario's world.
    seed : int
        Seed of the draws.

    Returns
    -------
    World
        The same world with the moving obstacles' tracks re-drawn (start shifted ±150 m, speed ×
        [0.6, 1.2], new random-walk seeds, a random phase on loops).
    """
    rng = np.random.default_rng(10_000 + seed)
    moving = []
    for o in world.moving:
        m = o.motion
        if isinstance(m, LinearMotion):
            v = np.asarray(m.velocity) * rng.uniform(0.6, 1.2)
            along = v / max(float(np.linalg.norm(v)), 1e-9)
            across = np.array([-along[1], along[0], 0.0])
            start = np.asarray(m.start) + rng.uniform(-150, 150) * along + rng.uniform(-150, 150) * across
            m = LinearMotion(tuple(start), tuple(v))
        elif isinstance(m, RandomWalkMotion):
            m = replace(m, seed=int(rng.integers(1 << 30)), speed=m.speed * rng.uniform(0.6, 1.2),
                        start=tuple(np.asarray(m.start) + np.r_[rng.uniform(-150, 150, 2), 0.0]))
        elif isinstance(m, CircleMotion):
            m = replace(m, phase=float(rng.uniform(0, 2 * np.pi)))
        elif isinstance(m, WaypointMotion):
            k = int(rng.integers(len(m.points)))
            m = WaypointMotion(np.roll(m.points, k, axis=0), m.speed * rng.uniform(0.6, 1.2), m.loop)
        moving.append(MovingObstacle(o.shape, m, o.name, o.appears, o.disappears))
    return replace(world, moving=tuple(moving))


def fast_movers(world: World, route: ArrayLike, speed: float, seed: int, n: int = 6) -> World:
    """``world`` with its moving obstacles replaced (issue #36's fast-mover Monte Carlo,
    ``benchmarks/avoidance.py``) by ``n`` fast movers drawn from ``seed``.

    Each mover is a sphere of 15–30 m radius at 1.8–3.0 m/s (1.2–2× the vehicle's cruise speed) placed
    on the route at a random 10–90 % of its length and timed (±40 s) to be there when the vehicle
    arrives at cruise speed; its motion is one of (equally likely): a straight run at any angle to the
    route (head-on, crossing from either side, overtaking); a shuttle 300 m across the route and
    back; a shuttle 300 m along it; an orbit of 60–100 m radius about the route point.

    Parameters
    ----------
    world : World
        The scenario's world (seabed, bounds).
    route : numpy.ndarray
        ``(N, 3)`` route the vehicle flies (m).
    speed : float
        The vehicle's cruise speed (m/s).
    seed : int
        Seed of the draws.
    n : int
        Number of movers.

    Returns
    -------
    World
        The same world with the ``n`` movers as its moving obstacles.
    """
    rng = np.random.default_rng(20_000 + seed)
    route = np.asarray(route, dtype=float).reshape(-1, 3)
    seg = np.diff(route, axis=0)
    cum = np.r_[0.0, np.cumsum(np.linalg.norm(seg, axis=1))]
    movers = []
    for i in range(n):
        s = rng.uniform(0.1, 0.9) * cum[-1]
        k = min(int(np.searchsorted(cum, s, side="right")) - 1, len(seg) - 1)
        tangent = seg[k] / np.linalg.norm(seg[k])
        normal = np.array([tangent[1], -tangent[0], 0.0]) / max(np.hypot(tangent[0], tangent[1]), 1e-9)
        point = route[k] + (s - cum[k]) * tangent
        u = rng.uniform(1.8, 3.0)
        t_meet = s / speed + rng.uniform(-40.0, 40.0)
        kind = int(rng.integers(4))
        if kind == 0:  # straight, any angle to the route
            heading = np.arctan2(tangent[0], tangent[1]) + rng.uniform(-np.pi, np.pi)
            v = u * np.array([np.sin(heading), np.cos(heading), 0.0])
            motion: LinearMotion | WaypointMotion | CircleMotion = LinearMotion(tuple(point - v * t_meet), tuple(v))
        elif kind in (1, 2):  # shuttle across / along, on the route point at t_meet
            axis = normal if kind == 1 else tangent * np.array([1.0, 1.0, 0.0])
            a_end, b_end = point - 150.0 * axis, point + 150.0 * axis
            d0 = (150.0 - u * t_meet) % 600.0  # arc from a_end on the loop a -> b -> a at t = 0
            pts = [a_end + d0 * axis, b_end, a_end] if d0 <= 300.0 else [b_end - (d0 - 300.0) * axis, a_end, b_end]
            motion = WaypointMotion(np.array(pts), u, True)
        else:  # orbit about the route point
            radius = rng.uniform(60.0, 100.0)
            motion = CircleMotion(tuple(point), float(radius), float(2 * np.pi * radius / u),
                                  float(rng.uniform(0, 2 * np.pi)))
        movers.append(MovingObstacle(Sphere((0.0, 0.0, 0.0), float(rng.uniform(15.0, 30.0))), motion,
                                     f"fast-{i}"))
    return replace(world, moving=tuple(movers))


def _row(scenario: str, planner: str, guidance: str, seed: int, record: RunRecord, ref: PlanResult | None, cpu: float,
         wall: float) -> Row:
    row: dict[str, Any] = dict.fromkeys(COLUMNS, "")
    row.update(scenario=scenario, planner=planner, guidance=guidance, seed=seed, status=record.status.value,
               cpu_s=round(cpu, 4), wall_s=round(wall, 4))
    p = record.plan
    if p is not None:
        t = p.cost_terms
        row.update(plan_status=p.status.value, cost=p.cost, length=t.get("length", ""),
                   terrain=t.get("terrain", ""), energy=t.get("energy", ""), length_m=t.get("length_m", ""),
                   energy_j=t.get("energy_j", ""), plan_duration_s=t.get("duration_s", ""),
                   plan_min_clearance_m=t.get("min_clearance_m", ""), plan_collisions=t.get("collisions", ""),
                   evaluations=p.evaluations, iterations=p.iterations)
        if ref is not None and math.isfinite(p.reference_cost):
            row.update(reference_cost=p.reference_cost, gap_pct=p.gap_pct)
    s = record.sim
    if s is not None:
        m = s.metrics
        row.update(arrived=m["arrived"], sim_duration_s=m["duration_s"], distance_m=m["distance_m"],
                   min_clearance_m=m["min_clearance_m"], min_obstacle_distance_m=m["min_obstacle_distance_m"],
                   collisions=m["collisions"], cross_track_rms_m=m["cross_track_rms_m"],
                   cross_track_max_m=m["cross_track_max_m"], escapes=m["escapes"])
    else:
        row["arrived"] = False
    out = {k: (round(v, 6) if isinstance(v, float) and math.isfinite(v) else v) for k, v in row.items()}
    out["_history"] = [] if p is None else [float(h) for h in p.history]
    out["_trace"] = [] if p is None else np.asarray(p.trace, dtype=float).tolist()
    return out


def _cell_planner(pspec: PlannerSpec, planner: str, budget: int) -> PlannerSpec:
    """The scenario's planner settings as a cell's ``name[/pipeline]`` and the sweep's ``budget`` run them: the
    seeded pipeline's default budget pinned, so that it is spent exactly by every planner of the cell."""
    name, _, pipeline = planner.partition("/")
    pipeline = pipeline or pspec.pipeline
    budget = budget or (pspec.evaluations if pipeline == "seeded" else pspec.budget)
    return replace(pspec, name=name, budget=budget, pipeline=pipeline)


def run_chunk(task: tuple[str, str, str, tuple[int, ...]], spec: SweepSpec) -> list[Row]:
    """Run one chunk of seeds of one cell.

    Parameters
    ----------
    task : tuple of (str, str, str, tuple of int)
        ``(scenario, planner, guidance, seeds)`` (:meth:`SweepSpec.tasks`).
    spec : SweepSpec
        The sweep (budget, reference, randomisation).

    Returns
    -------
    list of dict
        One row (:data:`COLUMNS`; m, J, s) per seed, in seed order.
    """
    scenario, planner, guidance, seeds = task
    name, member, member_seed = parse_label(scenario)
    sc = scenario_io.load(name)
    world, mission = scenario_io.build(sc)
    field = None
    if member is not None:  # one current member as the world's only current
        world, field = member_world(sc, world, member, member_seed)
    pspec = mission.planner if planner == "route" else _cell_planner(mission.planner, planner, spec.budget)
    guidance, _, avoidance = guidance.partition("+")
    mission = replace(mission, planner=pspec, guidance=guidance)
    if avoidance:
        mission = replace(mission, avoidance=replace(mission.avoidance, name=avoidance))
    problem = planning_problem(world, mission)
    ref = reference(problem, pspec) if spec.reference and not mission.route else None
    fixed = None
    if spec.plan_once and not mission.route:
        planned = on_cost_function(plan(problem, pspec, mission.seed), problem, pspec)
        if ref is not None:
            planned = with_reference(planned, problem, pspec, ref)
        route = mission_route(world, mission, planned.path) if planned.status.ok else np.empty((0, 3))
        fixed = (planned, route, key_waypoints(route, world, mission.avoidance.collision_check)
                 if route.size else route)
    rows = []
    for seed in seeds:
        w = perturb_moving(world, seed) if spec.randomise else world
        c0, t0 = time.process_time(), time.perf_counter()
        if fixed is not None:
            planned, route, keys = fixed
            sim = simulate(w, mission, route=route, rng=seed, keys=keys) if planned.status.ok else None
            record = RunRecord(mission.name, seed, planned, route, keys, sim)
        else:
            record = run_mission(w, mission, seed)
            if record.plan is not None:  # every planner's cost on the one cost function
                record = replace(record, plan=on_cost_function(record.plan, problem, pspec))
            if ref is not None and record.plan is not None:
                record = replace(record, plan=with_reference(record.plan, problem, pspec, ref))
        rows.append(_row(scenario, planner, task[2], seed, record, ref, time.process_time() - c0,
                         time.perf_counter() - t0))
        if member is not None and field is not None:
            rows[-1].update({k: (round(v, 6) if isinstance(v, float) and math.isfinite(v) else v)
                             for k, v in member_columns(w, mission, record, member, member_seed, field).items()})
    return rows


def _chunk(spec: SweepSpec, task: tuple[str, str, str, tuple[int, ...]]) -> list[Row]:
    """:func:`run_chunk` as a task of :meth:`auvplan.runtime.parallel.Runner.map` (the spec shared)."""
    return run_chunk(task, spec)


def sweep(spec: SweepSpec, out: Path, workers: int = 1, scheduler: str | None = None, resume: bool = False,
          progress: bool = True, retries: int = 1) -> list[Row]:
    """Run the sweep on dask.distributed (:class:`auvplan.runtime.parallel.Runner`) and return every row (string values,
    sorted by key).

    Parameters
    ----------
    spec : SweepSpec
        The matrix.
    out : Path
        Folder of ``rows.csv`` (appended as rows arrive).
    workers : int
        Local worker processes (a ``LocalCluster``), when no ``scheduler`` is given; 0 runs the chunks in this
        process.
    scheduler : str, optional
        Address of an existing dask scheduler (``tcp://host:port``).
    resume : bool
        Keep the rows already in ``rows.csv`` and run only the missing ones; without it an
        existing ``rows.csv`` is an error (nothing is overwritten).
    progress : bool
        Show a progress bar on stderr.
    retries : int
        Runs again of a chunk that fails.

    Returns
    -------
    list of dict
        Every row (:data:`COLUMNS`), string values, sorted by key.
    """
    from tqdm import tqdm

    out = Path(out)
    path, hpath = out / "rows.csv", out / "histories.jsonl"
    for p in (path, hpath):  # appended to in place: never through a link, never outside --out
        check_inside(p)
        if p.is_symlink():
            raise OutputError(f"{p}: is a symbolic link; auvplan does not append through links")
    todo = _todo(spec, path, resume)  # rows.csv and histories.jsonl named in the manifest before they exist
    runner = Runner(workers, scheduler, retries,  # starting the workers: a stage line above the bar
                    announce=(lambda text: tqdm.write(f"auvplan: {text}", file=sys.stderr)) if progress else None)
    if runner.distributed:
        require("dask", "bench")
    bar = tqdm(total=sum(len(t[3]) for t in todo), desc="bench", file=sys.stderr, disable=not progress,
               mininterval=0.5)
    with path.open("a", newline="") as fh, hpath.open("a") as hf:
        writer = csv.DictWriter(fh, fieldnames=COLUMNS, extrasaction="ignore")

        def arrived(_: int, rows: list[Row]) -> None:  # rows.csv is the bench's checkpoint (resume=True)
            for row in rows:
                hf.write(json.dumps({"key": list(_key(row)), "history": row["_history"],
                                     "trace": row.get("_trace", [])}) + "\n")
                hf.flush()
                writer.writerow(row)
                fh.flush()
                bar.update(1)

        try:
            runner.map(_chunk, todo, shared=spec, on_result=arrived)
        finally:
            bar.close()
    return sorted(read_rows(path), key=lambda r: (r["scenario"], r["planner"], r["guidance"], int(r["seed"])))


def _todo(spec: SweepSpec, path: Path, resume: bool) -> list[tuple[str, str, str, tuple[int, ...]]]:
    """The tasks whose rows ``rows.csv`` lacks; the file made ready to append (header, no cut line)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    done = read_rows(path)  # complete lines only: a row cut anywhere in its line is run again
    if path.exists() and not resume:
        raise AuvplanError(f"{path} exists: pass --resume to complete that sweep, or choose another --out")
    # named before either file is made: a kill between the two would leave a rows.csv of auvplan's that the
    # manifest does not list, which --resume then refuses as a user's file
    claim(path.parent, [path.name, "histories.jsonl"])
    have = {_key(r) for r in done}
    todo = []
    for scenario, planner, guidance, seeds in spec.tasks():
        left = tuple(x for x in seeds if (scenario, planner, guidance, str(x)) not in have)
        if left:
            todo.append((scenario, planner, guidance, left))
    _cut_partial_line(path)  # append-only: a line cut short by a kill is trimmed, nothing else rewritten
    _cut_partial_line(path.parent / "histories.jsonl")
    if not path.is_file() or path.stat().st_size == 0:
        with path.open("w", newline="") as fh:
            csv.DictWriter(fh, fieldnames=COLUMNS).writeheader()
    return todo
