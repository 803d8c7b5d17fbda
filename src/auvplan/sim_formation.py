"""Several vehicles in one closed loop: a formation along the route (``[[vehicles]]``, ``[formation]``).

:func:`run_formation` is the formation's pipeline: the global plan of the leader's route (or the
fixed survey line) → the executable mission (:func:`auvplan.sim.mission_route`) → every slot's
swept track checked against the seabed and reshaped to column where it fails
(:func:`auvplan.guidance.formation_plan.plan_formation`) → :func:`simulate_formation`.

:func:`simulate_formation` steps every vehicle together at ``dt``: each is the single-vehicle model
of :mod:`auvplan.vehicles` (under-actuated, one rudder, PD heading autopilot, Nomoto yaw, surge lag,
pitch-driven depth, drift in the current, wave disturbance), driven by its own formation guidance
(:func:`auvplan.guidance.formation.formation_command`); obstacle distances, collisions and the
moving obstacles' tracks are :mod:`auvplan.sim`'s own.  The run stops at the first contact (seabed,
obstacle, or two hulls closer than ``contact_m``); a vehicle's run ends when it reaches its final
slot (within the arrival radius, once the leader has arrived).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._types import ArrayLike, RngLike, Status, as_rng
from .guidance.formation import FormationParams
from .guidance.formation_plan import FormationPlan, plan_formation
from .guidance.formation_steer import FormationCommand, formation_command
from .planners.base import PlanResult, Progress
from .sim import FAR, Mission, SimResult, _distance, _obstacle_shapes, planned_route
from .vehicles import Vehicle, VehicleState
from .world import World

__all__ = ["FormationResult", "FormationRecord", "simulate_formation", "run_formation"]


@dataclass(frozen=True, eq=False)
class FormationResult:
    """The closed loop of a formation: one :class:`SimResult` per vehicle and the formation's figures.

    In each vehicle's SimResult ``cross_track`` is the signed cross error to the line through its
    slot along the slot's course (the error its route attraction nulls) and ``route_error`` its size.

    Attributes
    ----------
    status : Status
        ``EXACT`` when every vehicle reached its final slot, else the first failure.
    names : tuple of str
        Vehicle names, leader first.
    runs : tuple of SimResult
        Each vehicle's time series (its own length: a vehicle stops recording when it arrives).
    slots : tuple of ndarray (N_i, 3)
        Each vehicle's slot position at its recorded steps.
    error : tuple of ndarray (N_i,)
        Formation error: distance from the vehicle to its slot (m).
    t : ndarray (N,)
        Times of the fleet's recorded steps.
    vehicle_distance : ndarray (N,)
        Least centre distance between two running vehicles at each of them (inf with one left).
    shapes : tuple of str
        The shape being flown at each recorded step.
    events : tuple of (float, str, str)
        ``(time, kind, message)``: arrivals, collision, deadlock, timeout.
    wall_time_s : float
        Wall-clock time of the run.
    """

    status: Status
    names: tuple[str, ...]
    runs: tuple[SimResult, ...]
    slots: tuple[np.ndarray, ...]
    error: tuple[np.ndarray, ...]
    t: np.ndarray
    vehicle_distance: np.ndarray
    shapes: tuple[str, ...]
    events: tuple[tuple[float, str, str], ...]
    wall_time_s: float

    @property
    def metrics(self) -> dict[str, Any]:
        """Fleet figures and one entry per vehicle (formation error RMS/max, arrivals, clearances)."""
        per: dict[str, dict[str, Any]] = {}
        for name, run, err in zip(self.names, self.runs, self.error):
            m = run.metrics
            per[name] = {
                "status": m["status"], "arrived": m["arrived"], "duration_s": m["duration_s"],
                "distance_m": m["distance_m"],
                "formation_error_rms_m": float(np.sqrt(np.mean(err**2))) if err.size else 0.0,
                "formation_error_max_m": float(err.max()) if err.size else 0.0,
                "min_altitude_m": m["min_altitude_m"], "min_obstacle_distance_m": m["min_obstacle_distance_m"],
            }
        collisions = sum(1 for e in self.events if e[1] in ("collision", "unavoidable"))
        return {
            "status": self.status.value,
            "vehicles": len(self.names),
            "arrivals": sum(1 for v in per.values() if v["arrived"]),
            "collisions": collisions,
            "vehicle_contacts": sum(1 for e in self.events if e[1] == "collision" and "vehicle" in e[2]),
            "min_vehicle_distance_m": float(self.vehicle_distance.min()) if self.vehicle_distance.size else math.inf,
            "formation_error_rms_m": max(v["formation_error_rms_m"] for v in per.values()),
            "formation_error_max_m": max(v["formation_error_max_m"] for v in per.values()),
            "min_altitude_m": min(v["min_altitude_m"] for v in per.values()),
            "min_obstacle_distance_m": min(v["min_obstacle_distance_m"] for v in per.values()),
            "duration_s": float(self.t[-1]) if self.t.size else 0.0,
            "wall_time_s": self.wall_time_s,
            "per_vehicle": per,
        }


@dataclass(frozen=True, eq=False)
class FormationRecord:
    """Everything a formation mission produced: the leader's plan, the checked formation plan and the run.

    Attributes
    ----------
    scenario : str
        Scenario name.
    seed : int
        Seed of the run (-1 for a generator).
    plan : PlanResult or None
        The global plan (None for a fixed route).
    formation : FormationPlan or None
        Shapes and checked slot tracks (None when the plan failed).
    result : FormationResult or None
        The closed loop (None when a plan failed).
    """

    scenario: str
    seed: int
    plan: PlanResult | None
    formation: FormationPlan | None
    result: FormationResult | None

    @property
    def status(self) -> Status:
        """The global plan's failure, the formation plan's, or the flight's outcome."""
        if self.plan is not None and not self.plan.status.ok:
            return self.plan.status
        if self.formation is None or not self.formation.status.ok:
            return Status.INFEASIBLE
        return self.result.status if self.result is not None else Status.INFEASIBLE


class _Recorder:
    """Preallocated time series of one vehicle."""

    def __init__(self, n: int, n_obs: int) -> None:
        self.k = 0
        self.t = np.empty(n)
        self.p = np.empty((n, 3))
        self.h, self.v, self.d, self.e, self.pr, self.alt, self.err = (np.empty(n) for _ in range(7))
        self.slot = np.empty((n, 3))
        self.obs = np.empty((n, n_obs))

    def add(self, t: float, s: VehicleState, speed: float, cross: float, progress: float, alt: float, err: float,
            slot: ArrayLike, dists: ArrayLike) -> None:
        k = self.k
        self.t[k], self.p[k], self.h[k], self.v[k], self.d[k] = t, (s.x, s.y, s.z), s.psi, speed, s.delta
        self.e[k], self.pr[k], self.alt[k], self.err[k], self.slot[k], self.obs[k] = \
            cross, progress, alt, err, slot, dists
        self.k += 1

    def result(self, status: Status, events: Sequence[tuple[float, str, str]], wall: float) -> SimResult:
        n = self.k
        p = self.p[:n].copy()
        return SimResult(status=status, arrived=status is Status.EXACT, t=self.t[:n].copy(), position=p,
                         heading=self.h[:n].copy(), speed=self.v[:n].copy(), rudder=self.d[:n].copy(),
                         cross_track=self.e[:n].copy(), route_error=np.abs(self.e[:n]),
                         progress=self.pr[:n].copy(), altitude=self.alt[:n].copy(),
                         obstacle_distance=self.obs[:n].copy(), events=tuple(events), guidance="formation",
                         wall_time_s=wall)


def _initial_states(mission: Mission, fplan: FormationPlan) -> list[VehicleState]:
    slots, courses = fplan.structure.slots(np.array(0.0))
    out = []
    for i, spec in enumerate(mission.formation.vehicles):  # type: ignore[union-attr]
        p = spec.start if spec.start else tuple(slots[i])
        out.append(VehicleState(float(p[0]), float(p[1]), float(p[2]), float(courses[i]) % (2 * math.pi),
                                mission.vehicle.speed))
    return out


def _contact(i: int, dists: Sequence[float], alt: float, vdist: dict[int, float], names: Sequence[str],
             fp: FormationParams) -> str:
    """What vehicle ``i`` touches ('' when nothing)."""
    if alt < 0.0:
        return "the seabed"
    if dists and min(dists) < 0.0:
        return f"obstacle {int(np.argmin(dists))}"
    for j, d in vdist.items():
        if d < fp.contact_m:
            return f"vehicle {names[j]} (centres {d:.2f} m apart)"
    return ""


def simulate_formation(world: World, mission: Mission, fplan: FormationPlan, rng: RngLike = None,
                       progress: Callable[[float, float], object] | None = None) -> FormationResult:
    """Fly every vehicle of ``mission.formation`` along the formation plan ``fplan`` in ``world``.

    Parameters
    ----------
    world : World
        Seabed, currents, static and moving obstacles.
    mission : Mission
        Vehicle class, hybrid-field gains, simulation settings and the formation.
    fplan : FormationPlan
        The shapes along the route and the slot tracks (:func:`plan_formation`).
    rng : Generator, int or None
        Seed of the wave disturbances (the mission's seed by default).
    progress : callable, optional
        ``progress(t, expected)`` every simulated minute.

    Returns
    -------
    FormationResult
        Every vehicle's time series, the formation errors and the events.
    """
    t_wall = time.perf_counter()
    form = mission.formation
    if form is None:
        raise ValueError("the mission has no [formation]")
    fp, hp, vp, st = form.params, mission.hybrid, mission.vehicle, mission.sim
    rng = as_rng(mission.seed if rng is None else rng)
    n, dt, fr = form.n, st.dt, fplan.structure
    names = form.names
    states = _initial_states(mission, fplan)
    models = [Vehicle(vp, dt) for _ in range(n)]
    L = fr.length
    tail = (n - 1) * fp.spacing_m
    max_time = st.max_time or 3.0 * (L + tail) / vp.speed + 120.0
    n_steps = int(math.ceil(max_time / dt))
    n_rec = n_steps // st.record_every + 2
    n_static = len(world.obstacles)
    n_obs = n_static + len(world.moving)
    rec = [_Recorder(n_rec, n_obs) for _ in range(n)]
    fleet_t, fleet_d = np.empty(n_rec), np.empty(n_rec)
    fleet_shape: list[str] = []
    waves = vp.wave_sigma_r > 0 or vp.wave_sigma_v > 0
    noise = rng.standard_normal((n_steps + 1, n, 2)) if waves else np.zeros((n_steps + 1, n, 2))
    steps_t = np.arange(n_steps + 1) * dt
    tracks = np.stack([np.asarray(o.motion.position(steps_t)) for o in world.moving], axis=1) \
        if world.moving else np.empty((n_steps + 1, 0, 3))
    far = max(FAR, hp.influence + 10.0)
    velocities = np.asarray(np.gradient(tracks, dt, axis=0)) if n_steps > 0 else np.zeros_like(tracks)
    radii = [o.shape.bounding_radius for o in world.moving]
    final, _ = fr.slots_at(L)
    active, arrived = [True] * n, [False] * n
    events: list[tuple[float, str, str]] = []
    ends: list[Status] = [Status.TIMEOUT] * n
    status = Status.TIMEOUT
    s_ref, best, best_t = 0.0, np.full(n, -np.inf), np.zeros(n)
    every, expected = max(1, int(round(60.0 / dt))), (L + tail) / vp.speed
    u_lead = vp.speed
    vel = [(s.u * math.sin(s.psi), s.u * math.cos(s.psi), 0.0) for s in states]
    stop = False
    k = 0
    for k in range(n_steps + 1):
        t = k * dt
        if progress is not None and k % every == 0:
            progress(t, expected)
        pos = np.array([[s.x, s.y, s.z] for s in states])
        cur = world.currents.velocity(pos, t)
        alt = pos[:, 2] - world.terrain.elevation(pos[:, 0], pos[:, 1]) if world.terrain is not None \
            else np.full(n, np.inf)
        shapes = _obstacle_shapes(world, t, tracks[k].tolist())
        if active[0]:
            s_ref = fr.project(pos[0, 0], pos[0, 1], s_ref)
        sl, courses = fr.slots_at(s_ref)
        ahead_, _ = fr.slots_at(s_ref + 1.0)  # the slots' own motion per metre of reference progress
        stretch = [math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(sl, ahead_)]
        gamma = [math.atan2(b[2] - a[2], max(h, 1e-9)) for a, b, h in zip(sl, ahead_, stretch)]
        cmds: list[FormationCommand | None] = [None] * n
        lag = 0.0
        for i in range(n):
            if not active[i]:
                continue
            dists = [_distance(sh, pos[i], far) for sh in shapes]
            others = {j: math.dist(pos[i], pos[j]) for j in range(n) if j != i and active[j]}
            near = [(it[1][0], it[1][1], d) for it, d in zip(shapes[:n_static], dists) if it is not None]
            peers = [(pos[j, 0], pos[j, 1], vel[j][0], vel[j][1], fp.separation_m) for j in others]
            peers += [(it[1][0], it[1][1], v[0], v[1], r + 0.5 * fp.separation_m)
                      for it, d, v, r in zip(shapes[n_static:], dists[n_static:], velocities[k], radii)
                      if it is not None and d < far]
            u_ff = (u_lead if i else vp.speed) * stretch[i]
            c = formation_command(sl[i], courses[i], gamma[i], pos[i], vel[i], cur[i], states[i].u, hp, fp, near,
                                  peers, math.dist(pos[i], final[i]), u_ff, vp.speed, vp.max_speed,
                                  [(pos[j, 0], pos[j, 1]) for j in others if j < i])
            cmds[i] = c
            if i:
                lag = max(lag, c.along)
            prog = s_ref - c.along
            if k % st.record_every == 0:
                rec[i].add(t, states[i], math.hypot(vel[i][0], vel[i][1]), c.cross, prog, float(alt[i]), c.error,
                           sl[i], dists)
            what = _contact(i, dists, float(alt[i]), others, names, fp)
            if what:
                events.append((t, "collision", f"{names[i]} hit {what} at t = {t:.1f} s, "
                                              f"position {pos[i].round(2).tolist()}"))
                ends[i] = status = Status.COLLISION
                stop = True
                continue
            lead_done = arrived[0] or i == 0
            if lead_done and s_ref >= L - st.arrival_radius and c.error <= st.arrival_radius and \
                    (i or math.dist(pos[0], fr.w[-1]) <= st.arrival_radius):
                events.append((t, "arrival", f"{names[i]} within {st.arrival_radius:g} m of its final slot"))
                arrived[i], active[i], ends[i] = True, False, Status.EXACT
                continue
            if prog > best[i] + 1.0:
                best[i], best_t[i] = prog, t
            elif t - best_t[i] > st.deadlock_time:
                events.append((t, "deadlock", f"{names[i]}: no progress for {t - best_t[i]:.0f} s"))
                ends[i] = status = Status.DEADLOCK
                stop = True
        if k % st.record_every == 0:
            run = [i for i in range(n) if active[i] or arrived[i] and rec[i].t[rec[i].k - 1] == t]
            dmin = min((math.dist(pos[a], pos[b]) for a in run for b in run if a < b), default=math.inf)
            j = len(fleet_shape)
            fleet_t[j], fleet_d[j] = t, dmin
            fleet_shape.append(fr.schedule.shape_at(s_ref))
        if stop:
            break
        if all(arrived):
            status = Status.EXACT
            break
        u_lead = max(vp.speed - fp.k_wait * max(lag, 0.0), fp.min_speed_ratio * vp.speed)
        for i in range(n):
            if not active[i]:
                continue
            cmd = cmds[i]
            assert cmd is not None  # every active vehicle got its command above
            c = cmd
            u_c = u_lead if i == 0 else c.speed
            theta_c = c.gamma + math.atan(vp.depth_gain * (c.z_ref - states[i].z))
            vel[i] = models[i].step(states[i], c.psi, theta_c, u_c, cur[i], noise[k, i])
    else:
        events.append((n_steps * dt, "timeout", f"not every vehicle arrived after {max_time:.0f} s"))
    wall = time.perf_counter() - t_wall
    runs = tuple(rec[i].result(ends[i], [e for e in events if form.names[i] in e[2]], wall)
                 for i in range(n))
    m = len(fleet_shape)
    return FormationResult(status, form.names, runs, tuple(r.slot[:r.k].copy() for r in rec),
                           tuple(r.err[:r.k].copy() for r in rec), fleet_t[:m].copy(), fleet_d[:m].copy(),
                           tuple(fleet_shape), tuple(events), wall)


def run_formation(world: World, mission: Mission, rng: RngLike = None, progress: Progress | None = None,
                  flight: Callable[[float, float], object] | None = None) -> FormationRecord:
    """A formation mission end to end: leader's plan → mission → formation plan → closed loop.

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        A mission with a ``formation``.
    rng : Generator, int or None
        Seed of the planner and of the flight (the mission's seed by default).
    progress, flight : callable, optional
        The planner's and the flight's progress callbacks.

    Returns
    -------
    FormationRecord
        The plans and the run; a failed plan has no run (its status says why).
    """
    if mission.formation is None:
        raise ValueError("the mission has no [formation]")
    seed = mission.seed if rng is None else rng
    recorded = int(seed) if isinstance(seed, int | np.integer) else -1
    planned, route = planned_route(world, mission, seed, progress)
    if route is None:
        return FormationRecord(mission.name, recorded, planned, None, None)
    fplan = plan_formation(world, route, mission.formation)
    if not fplan.status.ok:
        return FormationRecord(mission.name, recorded, planned, fplan, None)
    result = simulate_formation(world, mission, fplan, seed, flight)
    return FormationRecord(mission.name, recorded, planned, fplan, result)
