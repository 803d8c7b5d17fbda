"""Flying the truth while re-planning on the forecast in flight (issue 39).

The vehicle navigates through the water (dead reckoning: deep water beyond its DVL's bottom lock) and
gets a position fix when it re-plans (surfacing or an acoustic fix).  A plan made on the *forecast* is
a route and the through-water velocity that holds it in the forecast's current:
``w(t) = ġ(t) − c_forecast(x(t), t)``, |w| = V; flying the plan means commanding that velocity
(heading and speed) on its schedule.  In the *truth* the vehicle then moves at
``ẋ = w(t) + c_true(x, t)`` (integrated by the midpoint rule every ``dt`` seconds) and drifts off the route
by the forecast's error.

* :func:`fly_open_loop`: the plan made at the start is flown to its end; the vehicle then gets a fix and
  homes to the goal on a plan made on the forecast from there (flown holding its track,
  :func:`auvplan.endurance.traverse`).
* :func:`fly_replanning`: every ``interval_s`` (a schedule) the vehicle gets a fix and re-plans on the
  forecast from its true position and clock; the last plan ends as the open loop's does.

A flight succeeds when it reaches the goal with its battery reserve kept and its track (every
integration step, the exact segment test of the world) meets no seabed, land or obstacle.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..._types import RngLike, Status
from ...endurance import EnergyModel, traverse
from ...world import CurrentField, World
from ...world.currents.ensemble import ShiftedCurrent
from .. import Mission, planned_route

__all__ = ["ReplanParams", "Flight", "fly_open_loop", "fly_replanning"]

F64 = NDArray[np.float64]


@dataclass(frozen=True)
class ReplanParams:
    """When to re-plan and how finely to fly.

    Attributes
    ----------
    interval_s : float
        Time between fixes and re-plans (s).
    dt : float
        Integration step of the flight through the truth (s).
    ds : float
        Longest sub-step of the plans' schedules and of the homing legs (m).
    max_replans : int
        Give up after this many re-plans.
    """

    interval_s: float = 3600.0
    dt: float = 60.0
    ds: float = 250.0
    max_replans: int = 500

    def __post_init__(self) -> None:
        if not (self.interval_s > 0 and self.dt > 0 and self.ds > 0) or self.max_replans < 0:
            raise ValueError("interval_s, dt and ds must be positive and max_replans >= 0")


@dataclass(frozen=True, eq=False)
class Flight:
    """One flight through the truth.

    Attributes
    ----------
    status : Status
        ``EXACT`` (arrived, reserve kept), ``RESERVE_BROKEN``, ``COLLISION`` (the track met the seabed,
        land or an obstacle) or ``INFEASIBLE`` (no plan, or the true current blocks the homing leg).
    arrival_s : float
        Time at the goal (s; ``inf`` when not arrived).
    energy_wh : float
        Energy drawn until arrival or the end of the flight (Wh).
    track : numpy.ndarray
        ``(M, 3)`` positions flown (m).
    times : numpy.ndarray
        ``(M,)`` their times (s).
    replans : int
        Plans after the first one (the homing plan included).
    plan_cpu_s : tuple of float
        CPU time of every plan (s).
    message : str
        The outcome in words.
    """

    status: Status
    arrival_s: float
    energy_wh: float
    track: F64
    times: F64
    replans: int
    plan_cpu_s: tuple[float, ...]
    message: str = ""

    @property
    def arrived(self) -> bool:
        """Whether the vehicle reached the goal."""
        return math.isfinite(self.arrival_s)

    @property
    def success(self) -> bool:
        """Arrived with the reserve kept and no collision."""
        return self.status is Status.EXACT


def _plan_from(forecast: CurrentField, world: World, mission: Mission, pos: F64, t: float,
               seed: RngLike) -> tuple[F64 | None, float]:
    """A plan on the forecast from ``pos`` at time ``t`` (the planner's clock starts at t) and its CPU time."""
    w = replace(world, currents=ShiftedCurrent(forecast, t))
    m = replace(mission, start=(float(pos[0]), float(pos[1]), float(pos[2])), route=())
    c0 = time.process_time()
    _, route = planned_route(w, m, seed)
    return route, time.process_time() - c0


@dataclass(frozen=True, eq=False)
class _Schedule:
    """A plan's through-water velocity against time: ``w[j]`` from ``t[j]`` to ``t[j + 1]``."""

    t: F64
    w: F64

    @property
    def end(self) -> float:
        return float(self.t[-1])

    def at(self, t: float) -> F64:
        j = int(np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, self.w.shape[0] - 1))
        out: F64 = self.w[j]
        return out


def _schedule(world: World, forecast: CurrentField, route: F64, speed: float, t0: float,
              ds: float) -> _Schedule | None:
    """The through-water velocity that holds ``route`` in the forecast from ``t0`` (None when it is blocked)."""
    tr = traverse(replace(world, currents=forecast), route, speed, t0, ds)
    if not tr.ok:
        return None
    dt = np.diff(tr.node_t)
    keep = dt > 0
    a, b = tr.nodes[:-1][keep], tr.nodes[1:][keep]
    ta, tb = tr.node_t[:-1][keep], tr.node_t[1:][keep]
    ground = (b - a) / (tb - ta)[:, None]
    mid = 0.5 * (a + b)
    cur = np.array([forecast.velocity(m, 0.5 * (x + y)) for m, x, y in zip(mid, ta, tb)]).reshape(-1, 3)
    return _Schedule(np.r_[ta, tb[-1]], ground - cur)


def _fly(truth: World, sched: _Schedule, x0: F64, t0: float, t1: float, dt: float) -> tuple[F64, F64]:
    """Fly a schedule through the true currents from ``(x0, t0)`` to ``t1`` (midpoint rule)."""
    cur = truth.currents
    n = max(1, math.ceil((t1 - t0) / dt))
    h = (t1 - t0) / n
    xs, ts = [x0], [t0]
    x, t = x0.copy(), t0
    for _ in range(n):
        k1 = sched.at(t) + cur.velocity(x, t)
        xm = x + 0.5 * h * k1
        x = x + h * (sched.at(t + 0.5 * h) + cur.velocity(xm, t + 0.5 * h))
        t += h
        xs.append(x.copy())
        ts.append(t)
    return np.asarray(xs), np.asarray(ts)


def _finish(truth: World, forecast: CurrentField, mission: Mission, p: ReplanParams, seed: RngLike,
            track: list[F64], times: list[F64], cpu: list[float], replans: int) -> Flight:
    """Fix, home on a forecast plan holding the track, and judge the flight."""
    v = mission.vehicle
    model = EnergyModel.from_vehicle(v)
    xs, ts = np.vstack(track), np.concatenate(times)
    pos, t = xs[-1], float(ts[-1])
    inside = bool(truth.bounds.contains(xs).all())
    free = inside and truth.path_free(xs)

    def done(status: Status, arrival: float, message: str = "") -> Flight:
        t_end = float(ts[-1]) if not math.isfinite(arrival) else arrival
        energy = float(model.power(v.speed)) * t_end / 3600.0
        if status is Status.EXACT and energy > model.budget_wh:
            status, message = Status.RESERVE_BROKEN, f"{energy:.1f} Wh of a {model.budget_wh:.1f} Wh budget"
        return Flight(status, arrival, energy, xs, ts, replans, tuple(cpu), message)

    if not free:
        return done(Status.COLLISION, math.inf, "the track meets the seabed, land or an obstacle" if inside else
                    "the track leaves the operating box ([bounds])")
    goal = np.asarray(mission.goal, dtype=float)
    if float(np.linalg.norm(pos - goal)) <= mission.sim.arrival_radius:
        return done(Status.EXACT, t)
    if not truth.is_free(pos[None, :])[0]:
        return done(Status.COLLISION, math.inf, "the track ends in no-go water")
    route, c = _plan_from(forecast, truth, mission, pos, t, seed)
    cpu.append(c)
    replans += 1
    if route is None:
        return done(Status.INFEASIBLE, math.inf, f"no homing plan from {np.round(pos, 1).tolist()}")
    home = traverse(truth, route, v.speed, t, p.ds)
    if not home.ok:
        return done(Status.INFEASIBLE, math.inf, home.message)
    xs, ts = np.vstack([xs, home.nodes[1:]]), np.concatenate([ts, home.node_t[1:]])
    return done(Status.EXACT, float(home.node_t[-1]))


def fly_open_loop(truth: World, forecast: CurrentField, mission: Mission, params: ReplanParams | None = None,
                  seed: RngLike = None) -> Flight:
    """Fly the plan made on the forecast at the start to its end, then fix and home (module notes).

    Parameters
    ----------
    truth : World
        The world with the true currents (t = 0 at the mission's start).
    forecast : CurrentField
        The forecast the vehicle plans on.
    mission : Mission
        End points, vehicle and planner.
    params : ReplanParams, optional
        Integration settings (``interval_s`` is not used).
    seed : Generator, int or None
        Seed of the plans (the mission's by default).

    Returns
    -------
    Flight
        Arrival, energy, status and track.
    """
    return fly_replanning(truth, forecast, mission, params, seed, replan=False)


def fly_replanning(truth: World, forecast: CurrentField, mission: Mission, params: ReplanParams | None = None,
                   seed: RngLike = None, replan: bool = True) -> Flight:
    """Fly the truth, re-planning on the forecast from a fix every ``interval_s`` (module notes).

    Parameters
    ----------
    truth : World
        The world with the true currents (seabed, obstacles, margins shared with the plans).
    forecast : CurrentField
        The forecast the vehicle plans on (t = 0 at the mission's start).
    mission : Mission
        End points, vehicle and planner.
    params : ReplanParams, optional
        Schedule and integration settings.
    seed : Generator, int or None
        Seed of every plan (the mission's by default).
    replan : bool, default True
        False flies the first plan open loop (:func:`fly_open_loop`).

    Returns
    -------
    Flight
        Arrival, energy, status, the track, the number of re-plans and the CPU time of every plan.
    """
    p = params or ReplanParams()
    seed = mission.seed if seed is None else seed
    v = mission.vehicle
    pos, t = np.asarray(mission.start, dtype=float), 0.0
    track, times, cpu = [pos[None, :]], [np.zeros(1)], []
    goal = np.asarray(mission.goal, dtype=float)
    for k in range(p.max_replans + 1):
        route, c = _plan_from(forecast, truth, mission, pos, t, seed)
        cpu.append(c)
        sched = None if route is None else _schedule(truth, forecast, route, v.speed, t, p.ds)
        if sched is None:
            return _finish(truth, forecast, mission, p, seed, track, times, cpu, k)
        last = not replan or sched.end - t <= p.interval_s
        t1 = sched.end if last else t + p.interval_s
        xs, ts = _fly(truth, sched, pos, t, t1, p.dt)
        track.append(xs[1:])
        times.append(ts[1:])
        pos, t = xs[-1], float(ts[-1])
        if last or not truth.path_free(xs) or float(np.linalg.norm(pos - goal)) <= mission.sim.arrival_radius:
            return _finish(truth, forecast, mission, p, seed, track, times, cpu, k)
    return _finish(truth, forecast, mission, p, seed, track, times, cpu, p.max_replans)
