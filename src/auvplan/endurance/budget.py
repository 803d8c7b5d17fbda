"""A mission's energy budget leg by leg, in the real currents at its departure time.

The vehicle holds each leg's track at the leg's through-water speed V (it crabs into the cross
current), so along the unit tangent ŝ of a leg, in the current c at its position and time:

    c∥ = c·ŝ,   c⊥² = |c|² − c∥²,   V_g = c∥ + √(V² − c⊥²)

(the same kinematics as :func:`auvplan.cost.energy_kernel` and the time planner's
``ground_speed``).  A leg flown **tail-first** (the time-optimal planner's ``tail_first``: the vehicle
heads against its track and a current stronger than itself carries it, ``PlanResult.tail``) takes the
other root, ``V_g = c∥ − √(V² − c⊥²)``, as the planner and the path followers do
(:mod:`auvplan.planners.timeopt.tail`).  Each leg is cut into sub-steps of at most ``ds`` metres; a sub-step takes
``h / V_g`` with V_g at its midpoint at the time the vehicle is half-way through it (one
predictor step from its start), so the time and the energy are exact in a steady uniform
current and second order in time-varying ones.  The leg's energy is ``P(V) × duration``
(:class:`~auvplan.endurance.power.EnergyModel`).  Where the current beats the vehicle
(V < |c⊥| or V_g ≤ 0) the leg cannot be flown and the budget's status is ``INFEASIBLE``; when
the mission would eat into the reserve, ``RESERVE_BROKEN``.

A vertex held **on station** (an ArduSub waypoint's or timed loiter's hold: its position controller keeps the
vehicle on the item) moves the vehicle through the water at the current's speed |c| there for the hold's time.
Its power is ``P(|c|)``; where |c| exceeds the vehicle's top speed (``EnergyModel.max_speed``, what its thrusters
can give: the position controller is not bound to the leg's speed while holding) the vehicle cannot hold its
position and the budget is ``INFEASIBLE``, naming the waypoint, as for a leg the current blocks.  A hold on station
at the last vertex is flown before the mission ends (ArduSub's ``verify_nav_wp`` waits it out): it is counted in
the last leg (its ``t_end`` and energy), and a reserve entered during it is named so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import Status
from ..world import World
from ..world.currents.crab import crab_speed, makes_headway
from .power import WH, EnergyModel

__all__ = ["HOLD_SAMPLES", "HOLD_STEP_S", "Traverse", "Budget", "traverse", "mission_budget", "budget_of",
           "ground_speed"]

F64 = NDArray[np.float64]


def ground_speed(current: F64, tangent: F64, speed: float, tail: bool = False) -> float:
    """Speed over ground along a unit tangent at through-water speed ``speed`` in a current.

    Parameters
    ----------
    current : numpy.ndarray
        Current ``(3,)`` (m/s).
    tangent : numpy.ndarray
        Unit tangent of the track ``(3,)``.
    speed : float
        Through-water speed (m/s).
    tail : bool, default False
        The leg is flown tail-first (heading against the track): the other root.

    Returns
    -------
    float
        ``c·ŝ + √(V² − |c⊥|²)`` (``c·ŝ − √(V² − |c⊥|²)`` tail-first) (m/s); ``nan`` where that
        heading cannot hold the track or makes no headway along it.
    """
    c, e = current, tangent
    g = float(crab_speed(float(c[0]), float(c[1]), float(c[2]), float(e[0]), float(e[1]), float(e[2]), speed,
                         bool(tail), 1.0))
    return g if makes_headway(g) else math.nan


HOLD_SAMPLES = 16
"""The instants a hold against the current is sampled at (the midpoints of its equal parts: exact in a steady
current, second order in a tide), at least: more in a current that varies when the hold is longer than
``HOLD_SAMPLES`` × :data:`HOLD_STEP_S`."""

HOLD_STEP_S = 600.0
"""Longest time between two samples of a hold in a current that varies (s): 16 samples of a 64 000 s hold (a
``.plan`` holds up to 65 535 s) were 4 000 s apart and saw a current of that period at one phase only."""


@dataclass(frozen=True, eq=False)
class Traverse:
    """A route flown through the currents: times at its vertices and at the sub-step nodes.

    Attributes
    ----------
    points : numpy.ndarray
        ``(N, 3)`` route vertices (m).
    speeds : numpy.ndarray
        ``(N - 1,)`` through-water speed of each leg (m/s).
    times : numpy.ndarray
        ``(N,)`` arrival time at each vertex (s after the mission's start time); ``nan`` past a
        leg the current blocks.
    nodes : numpy.ndarray
        ``(M, 3)`` sub-step nodes along the route, the vertices included (m).
    node_s : numpy.ndarray
        ``(M,)`` distance along the route of each node (m, 3D).
    node_t : numpy.ndarray
        ``(M,)`` time at each node (s).
    node_leg : numpy.ndarray
        ``(M,)`` leg of the sub-step that ends at each node (0 for the first node).
    ok : bool
        Whether every leg could be flown.
    message : str
        Where the current beats the vehicle, when not ``ok``.
    tail : numpy.ndarray
        ``(N - 1,)`` legs flown tail-first.
    dwell : numpy.ndarray
        ``(N,)`` time held at each vertex before the next leg (a surface fix's ``surface_s``; s).
    hold_water : numpy.ndarray
        ``(N, K)`` where a vertex is held against the current (``station``): the through-water speed that takes at
        the midpoints of the hold's K equal parts (the current's speed there, m/s; K = :data:`HOLD_SAMPLES`, more for
        a hold longer than K × :data:`HOLD_STEP_S` in a current that varies); empty: every dwell drifts (hotel power).
    end_hold : float
        Time held on station at the last vertex before the mission ends (s; 0 unless that vertex is ``station``).
    """

    points: F64
    speeds: F64
    times: F64
    nodes: F64
    node_s: F64
    node_t: F64
    node_leg: NDArray[np.int64]
    ok: bool = True
    message: str = ""
    tail: NDArray[np.bool_] = field(default_factory=lambda: np.zeros(0, dtype=bool))
    dwell: F64 = field(default_factory=lambda: np.zeros(0))
    hold_water: F64 = field(default_factory=lambda: np.zeros((0, HOLD_SAMPLES)))
    end_hold: float = 0.0

    @property
    def duration(self) -> float:
        """Time from the first to the last vertex, its hold on station included (s); ``nan`` when not ``ok``."""
        return float(self.times[-1] + self.end_hold - self.times[0])

    def leg_water_m(self) -> F64:
        """Each leg's horizontal distance through the water (m): over every sub-step that moves, the through-water
        run ``V·Δt`` less its vertical part (the current is horizontal), ``sqrt((V Δt)² − Δz²)``; in still water the
        leg's horizontal length.  The navigation budget's drift without bottom lock grows with it
        (:mod:`auvplan.nav.budget`).

        Returns
        -------
        numpy.ndarray
            ``(N - 1,)`` (m); ``nan`` for legs not flown (``ok`` False).
        """
        d = np.diff(self.nodes, axis=0)
        dt = np.diff(self.node_t)
        leg = self.node_leg[1:]
        moves = np.linalg.norm(d, axis=1) > 1e-6  # a dwell's node does not move (its vertex to rounding): no leg's
        run = self.speeds[leg] * dt
        w = np.where(moves, np.sqrt(np.maximum(run * run - d[:, 2] ** 2, 0.0)), 0.0)
        out = np.asarray(np.bincount(leg, w, self.points.shape[0] - 1), dtype=float)
        out[~np.isfinite(self.times[1:])] = math.nan
        return out

    def at(self, s: float) -> tuple[F64, float, int]:
        """Position, time and leg at distance ``s`` along the route (linear between nodes).

        Parameters
        ----------
        s : float
            Distance along the route (m), clipped to [0, length].

        Returns
        -------
        tuple
            Position ``(3,)`` (m), time (s) and leg index.
        """
        s = min(max(s, 0.0), float(self.node_s[-1]))
        j = int(np.clip(np.searchsorted(self.node_s, s, side="right"), 1, self.node_s.size - 1))
        s0, s1 = self.node_s[j - 1], self.node_s[j]
        w = 0.0 if s1 <= s0 else (s - s0) / (s1 - s0)
        pos = (1.0 - w) * self.nodes[j - 1] + w * self.nodes[j]
        return pos, float((1.0 - w) * self.node_t[j - 1] + w * self.node_t[j]), int(self.node_leg[j])


def traverse(world: World, points: ArrayLike, speeds: ArrayLike | float, depart: float = 0.0,
             ds: float = 100.0, tail: ArrayLike | None = None, dwell: ArrayLike | None = None,
             station: ArrayLike | None = None) -> Traverse:
    """Fly a route through the world's currents at each leg's through-water speed (module notes).

    Parameters
    ----------
    world : World
        Its currents (``world.currents.velocity(points, t)``).
    points : array_like
        ``(N, 3)`` route vertices (m), N ≥ 2; zero-length legs take no time.
    speeds : array_like or float
        Through-water speed of each leg ``(N - 1,)``, or one for all (m/s).
    depart : float, default 0.0
        Time at the first vertex (s after the mission's start time).
    ds : float, default 100.0
        Longest sub-step (m).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first (module notes); none by default.
    dwell : array_like, optional
        ``(N,)`` time held at each vertex before the next leg (s; a surface fix's ``surface_s``,
        :mod:`auvplan.nav`): the next leg departs that much later.
    station : array_like of bool, optional
        ``(N,)`` the vertices whose dwell holds the point against the current (an ArduSub waypoint's or timed
        loiter's hold: its position controller keeps the vehicle on the item), at the through-water speed of
        the current there (``Traverse.hold_water``); the others drift (a surface fix).  The last vertex's dwell
        counts only when it is held on station (``Traverse.end_hold``: the mission ends after it); a drift there
        (a surface fix at the goal) is after the mission.

    Returns
    -------
    Traverse
        Times at the vertices (arrival) and nodes; ``ok`` False where the current beats the vehicle.
    """
    p, v, back, hold, held_on = _route_arrays(points, speeds, ds, tail, dwell, station)
    water = np.zeros((p.shape[0] if held_on.any() else 0, _hold_samples(world, hold[held_on])))
    times = np.full(p.shape[0], math.nan)
    times[0] = depart
    track: list[_Node] = [(p[0], 0.0, depart, 0)]  # position, distance along, time, leg
    t, s_along, ok, message = depart, 0.0, True, ""
    for i in range(p.shape[0] - 1):
        if hold[i] > 0.0:  # held at the vertex (a surface fix): a node at the departure
            if held_on[i]:  # against the current: its speed at the midpoints of the hold's parts
                water[i] = _held_water(world, p[i], t, float(hold[i]), water.shape[1])
            t += float(hold[i])
            track.append((p[i].copy(), s_along, t, i))
        t, s_along, message = _fly_leg(world, p[i], p[i + 1], v[i], back[i], t, s_along, ds, i, track)
        if message:
            ok = False
            break
        times[i + 1] = t
    end = float(hold[-1]) if ok and held_on[-1] and hold[-1] > 0.0 else 0.0
    if end > 0.0:  # held on station at the last vertex before the mission ends: a node at the hold's end
        water[-1] = _held_water(world, p[-1], t, end, water.shape[1])
        track.append((p[-1].copy(), s_along, t + end, p.shape[0] - 2))
    nodes, node_s, node_t, node_leg = zip(*track)
    return Traverse(p, v, times, np.asarray(nodes), np.asarray(node_s), np.asarray(node_t),
                    np.asarray(node_leg, dtype=np.int64), ok, message, back, hold, water, end)


_Node = tuple[F64, float, float, int]
"""A node of a traverse as it is flown: position, distance along, time and leg."""


def _route_arrays(points: ArrayLike, speeds: ArrayLike | float, ds: float, tail: ArrayLike | None,
                  dwell: ArrayLike | None, station: ArrayLike | None) -> tuple[F64, F64, NDArray[np.bool_], F64,
                                                                              NDArray[np.bool_]]:
    """:func:`traverse`'s inputs checked, as arrays: points, leg speeds and tail flags, dwells and holds on station."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    if p.shape[0] < 2:
        raise ValueError(f"a route needs at least 2 points, got {p.shape[0]}")
    v = np.broadcast_to(np.asarray(speeds, dtype=float), (p.shape[0] - 1,)).copy()
    if not (np.all(np.isfinite(v)) and np.all(v > 0)) or not ds > 0:
        raise ValueError("leg speeds and ds must be positive")
    back = np.zeros(p.shape[0] - 1, dtype=bool) if tail is None else np.asarray(tail, dtype=bool).reshape(-1)
    if back.shape != v.shape:
        raise ValueError(f"tail needs one flag per leg ({v.size}), got {back.size}")
    hold = np.zeros(p.shape[0]) if dwell is None else np.broadcast_to(np.asarray(dwell, dtype=float),
                                                                       (p.shape[0],)).copy()
    held_on = np.zeros(p.shape[0], dtype=bool) if station is None else np.broadcast_to(
        np.asarray(station, dtype=bool), (p.shape[0],))
    return p, v, back, hold, held_on


def _fly_leg(world: World, a: F64, b: F64, speed: float, back: bool, t: float, s_along: float, ds: float, leg: int,
             track: list[_Node]) -> tuple[float, float, str]:
    """Fly leg ``leg`` from ``a`` to ``b`` in sub-steps of at most ``ds``, a node at each: the time and distance
    along at its end, and "" (or where the current stopped it, and the message saying so)."""
    length = float(np.linalg.norm(b - a))
    if length == 0.0:
        return t, s_along, ""
    cur = world.currents
    e = (b - a) / length
    n = max(1, math.ceil(length / ds))
    h = length / n
    for j in range(n):
        start = a + (j * h) * e
        g0 = ground_speed(cur.velocity(start, t), e, speed, back)
        g = ground_speed(cur.velocity(start + 0.5 * h * e, t + 0.5 * h / g0), e, speed, back) \
            if g0 == g0 else math.nan
        if not g == g:  # nan: the current beats the vehicle (or, tail-first, is too weak to carry it)
            what = "is too weak to carry the vehicle tail-first" if back else "beats the vehicle"
            return t, s_along, (f"leg {leg}: the current {what} at {np.round(start, 1).tolist()} "
                                f"(t = {t:.0f} s, through-water speed {speed:g} m/s)")
        t += h / g
        s_along += h
        track.append((a + ((j + 1) * h) * e, s_along, t, leg))
    return t, s_along, ""

def _hold_samples(world: World, holds: F64) -> int:
    """The samples of every hold: :data:`HOLD_SAMPLES`, or as many as keep the longest's :data:`HOLD_STEP_S` apart
    in a current that varies."""
    longest = float(np.max(holds, initial=0.0))
    if not np.isfinite(longest) or getattr(world.currents, "steady", False):
        return HOLD_SAMPLES
    return max(HOLD_SAMPLES, math.ceil(longest / HOLD_STEP_S))


def _held_water(world: World, point: F64, t: float, hold: float, samples: int) -> list[float]:
    """The current's speed at ``point`` at the midpoints of a hold's ``samples`` equal parts (m/s)."""
    mid = t + (np.arange(samples) + 0.5) * hold / samples
    return [float(np.linalg.norm(world.currents.velocity(point, float(tk)))) for tk in mid]


@dataclass(frozen=True, eq=False)
class Budget:
    """The energy budget of a mission, leg by leg (times in s after the start time, energies in Wh).

    Attributes
    ----------
    status : Status
        ``EXACT`` when the mission ends with its reserve, ``RESERVE_BROKEN`` when it would eat
        into it, ``INFEASIBLE`` when the current blocks a leg.
    message : str
        The verdict in words.
    model : EnergyModel
        Power model and battery.
    t_start, t_end : numpy.ndarray
        ``(L,)`` each leg's start and end time (s).
    length_m : numpy.ndarray
        ``(L,)`` leg lengths (m, 3D).
    speed_water, speed_ground : numpy.ndarray
        ``(L,)`` through-water speed and mean speed over ground (m/s).
    energy_leg_wh, cumulative_wh, remaining_wh : numpy.ndarray
        ``(L,)`` each leg's energy, the energy spent by its end, and the charge that can still be
        drawn then (usable minus spent) (Wh).
    traverse : Traverse
        The flight through the currents behind the figures.
    """

    status: Status
    message: str
    model: EnergyModel
    t_start: F64
    t_end: F64
    length_m: F64
    speed_water: F64
    speed_ground: F64
    energy_leg_wh: F64
    cumulative_wh: F64
    remaining_wh: F64
    traverse: Traverse = field(repr=False)

    @property
    def energy_wh(self) -> float:
        """Energy of the whole mission (Wh; ``inf`` when a leg cannot be flown)."""
        return float(self.cumulative_wh[-1]) if self.status is not Status.INFEASIBLE else math.inf

    @property
    def duration_s(self) -> float:
        """Duration of the whole mission (s)."""
        return float(self.t_end[-1] - self.t_start[0])

    @property
    def margin_wh(self) -> float:
        """Budget left at the end: usable − reserve − spent (Wh); negative when the reserve is broken."""
        return self.model.budget_wh - self.energy_wh

    def rows(self) -> list[dict[str, float]]:
        """One row per leg for ``legs.csv`` (``leg, t_start_s, t_end_s, energy_wh`` first).

        Returns
        -------
        list of dict
            Column name (unit in the name) → value.
        """
        return [{"leg": float(i), "t_start_s": float(self.t_start[i]), "t_end_s": float(self.t_end[i]),
                 "energy_wh": float(self.energy_leg_wh[i]), "length_m": float(self.length_m[i]),
                 "duration_s": float(self.t_end[i] - self.t_start[i]), "speed_water_mps": float(self.speed_water[i]),
                 "speed_ground_mps": float(self.speed_ground[i]), "cumulative_wh": float(self.cumulative_wh[i]),
                 "remaining_wh": float(self.remaining_wh[i])} for i in range(self.t_start.size)]

    def charge(self) -> tuple[F64, F64]:
        """Charge that can still be drawn against time, at every sub-step node.

        Returns
        -------
        t : numpy.ndarray
            Times (s after the start time).
        remaining_wh : numpy.ndarray
            Usable charge left (Wh); the reserve line is ``model.reserve_wh``.
        """
        tr = self.traverse
        good = np.isfinite(tr.node_t)
        t, legs = tr.node_t[good], tr.node_leg[good]
        power = self.model.power(tr.speeds)[legs]
        spent = np.r_[0.0, np.cumsum(power[1:] * np.diff(t))] / WH
        return t, self.model.usable_wh - spent


def mission_budget(world: World, route: ArrayLike, model: EnergyModel, speeds: ArrayLike | float | None = None,
                   depart: float = 0.0, ds: float = 100.0, tail: ArrayLike | None = None,
                   dwell: ArrayLike | None = None, station: ArrayLike | None = None) -> Budget:
    """Budget a route leg by leg in the world's currents from ``depart`` (module notes).

    Parameters
    ----------
    world : World
        Its currents.
    route : array_like
        ``(N, 3)`` mission waypoints (m).
    model : EnergyModel
        Power model and battery.
    speeds : array_like or float, optional
        Through-water speed per leg or for all (m/s); the vehicle's cruise speed ``model`` does
        not know, so required in practice (None: the model's least-energy still-water speed).
    depart : float, default 0.0
        Departure (s after the mission's start time).
    ds : float, default 100.0
        Longest integration sub-step (m).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first (module notes).
    dwell : array_like, optional
        ``(N,)`` time held at each vertex (s): at hotel power, counted in the leg that follows.
    station : array_like of bool, optional
        ``(N,)`` the vertices whose dwell holds the point against the current: at the power of moving through
        the water at the current's speed there (:func:`traverse`).

    Returns
    -------
    Budget
        Per-leg times, speeds and energies, and the verdict.
    """
    v = model.best_speed if speeds is None else speeds
    return budget_of(traverse(world, route, v, depart, ds, tail, dwell, station), model)


def budget_of(tr: Traverse, model: EnergyModel) -> Budget:
    """The budget of a route already flown through the currents (:func:`mission_budget` after :func:`traverse`).

    Parameters
    ----------
    tr : Traverse
        The flight (times at the vertices, through-water speeds).
    model : EnergyModel
        Power model and battery.

    Returns
    -------
    Budget
        Per-leg times, speeds and energies, and the verdict.
    """
    p = tr.points
    length = np.linalg.norm(np.diff(p, axis=0), axis=1)
    t_start, t_end = tr.times[:-1], tr.times[1:].copy()
    t_end[-1] += tr.end_hold  # the last vertex's hold on station ends the last leg
    dur = t_end - t_start
    held = tr.dwell[:-1] if tr.dwell.size == p.shape[0] else np.zeros(dur.shape)  # at the leg's start vertex
    rest = model.power(0.0) * np.ones(dur.shape)  # a dwell's power: drifting, or holding against the current
    end_wh = 0.0
    if tr.hold_water.shape[0] == p.shape[0]:
        hold_power = np.asarray(model.power(tr.hold_water), dtype=float).mean(axis=1)
        rest, end_wh = hold_power[:-1], float(hold_power[-1] * tr.end_hold / WH)
    moving = (tr.times[1:] - t_start) - held  # flying: from the departure to the arrival
    energy = np.asarray((model.power(tr.speeds) * moving + rest * held) / WH, dtype=float)
    cum = np.cumsum(energy)
    energy[-1] += end_wh
    cum[-1] += end_wh
    remaining = model.usable_wh - cum
    with np.errstate(invalid="ignore", divide="ignore"):
        ground = np.where(moving > 0, length / np.where(moving > 0, moving, 1.0), np.nan)
    status, message = _verdict(tr, model, cum, remaining, end_wh)
    return Budget(status, message, model, t_start, t_end, length, tr.speeds, ground, energy, cum, remaining, tr)


def _blocked_hold(tr: Traverse, model: EnergyModel) -> str:
    """Where the first hold on station meets a current faster than the vehicle's top speed: the reason, or ``""``
    (a hold past a leg the current blocks is never sampled: its row is zeros, the blocked leg comes first)."""
    if tr.hold_water.shape[0] != tr.points.shape[0]:
        return ""
    over = np.flatnonzero(tr.hold_water.max(axis=1) > model.max_speed)
    if over.size == 0:
        return ""
    k = int(over[0])
    return (f"the hold at waypoint {k}: the current ({float(tr.hold_water[k].max()):.2f} m/s at "
            f"{np.round(tr.points[k], 1).tolist()}, t = {float(tr.times[k]):.0f} s) beats the vehicle's top speed "
            f"{model.max_speed:g} m/s: it cannot hold its position")


def _verdict(tr: Traverse, model: EnergyModel, cum: F64, remaining: F64, end_wh: float) -> tuple[Status, str]:
    """The budget's status and message (module notes)."""
    blocked = _blocked_hold(tr, model)
    if blocked or not tr.ok:
        return Status.INFEASIBLE, f"the mission cannot be flown: {blocked or tr.message}"
    margin = model.budget_wh - float(cum[-1])
    if margin < -1e-9 * model.battery_wh:
        floor = model.reserve_wh - 1e-9 * model.battery_wh
        over = int(np.argmax(remaining < floor))
        where = f"on leg {over}"
        if over == cum.size - 1 and end_wh > 0 and remaining[-1] + end_wh >= floor:  # after the last leg's flight
            where = "in the hold at the last item"
        return Status.RESERVE_BROKEN, (
            f"RESERVE BROKEN: the mission needs {cum[-1]:.1f} Wh of a {model.budget_wh:.1f} Wh budget "
            f"({model.battery_wh:g} Wh × ({model.usable_fraction:g} usable − {model.reserve:g} reserve)); "
            f"short by {-margin:.1f} Wh, the reserve is entered {where}")
    return Status.EXACT, (f"{cum[-1]:.1f} Wh of a {model.budget_wh:.1f} Wh budget: margin {margin:.1f} Wh, "
                          f"{remaining[-1]:.1f} Wh left at the end (reserve {model.reserve_wh:.1f} Wh)")
