"""The point of no return: the last point along a mission from which the vehicle can still reach a
recovery point (home, the mission's start, or a named rally point) with its reserve.

At distance ``s`` along the route, reached at time t(s) with E_out(s) spent, the vehicle turns
back and flies a return route to the recovery point R from t(s), through the same time-varying
currents, at the return speed V_r (:func:`~auvplan.endurance.budget.traverse`):

    f(s) = E_out(s) + P(V_r) T_ret(s, t(s)) − (usable − reserve)

The return route is the straight line to R when the world lets it through (seabed, obstacles,
bounds: :meth:`~auvplan.world.World.path_free`), otherwise the route flown so far retraced back to
the latest waypoint from which R is in free straight line, then straight to R (home is always
reached that way).  f is scanned at ``samples`` points and its first sign change refined by
bisection to ``tol`` metres: the point of no return is the *first* point where turning back no
longer leaves the reserve (the conservative answer when f is not monotonic).  When f ≤ 0 along the
whole mission the vehicle can turn back anywhere (``whole_mission``); when f(0) > 0 it cannot even
go out and come straight back.

Closed form (tested): on a straight leg with the current u along it, speed V and power P, the
round trip to distance s costs P s (1/(V + u) + 1/(V − u)), so s* = budget (V² − u²) / (2 P V).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import Status
from ..world import World
from .budget import Traverse, traverse
from .power import WH, EnergyModel

__all__ = ["PointOfNoReturn", "point_of_no_return", "return_route"]

F64 = NDArray[np.float64]


@dataclass(frozen=True)
class PointOfNoReturn:
    """Where the vehicle must turn back at the latest (local frame, s after the start time, Wh).

    Attributes
    ----------
    status : Status
        ``EXACT`` when found (or ``whole_mission``), ``INFEASIBLE`` when the vehicle cannot turn
        back even at the start or the recovery point cannot be reached.
    position : tuple of float
        The point ``(x, y, z)`` (m).
    t_s : float
        Time the vehicle passes it (s after the mission's start time).
    s_m : float
        Distance along the route (m).
    leg : int
        Leg it lies on.
    energy_out_wh, energy_back_wh : float
        Energy spent reaching it and returning from it (Wh).
    whole_mission : bool
        Whether the recovery point can be reached with the reserve from every point of the mission.
    recovery : tuple of float
        The recovery point (m).
    message : str
        The finding in words.
    """

    status: Status
    position: tuple[float, float, float]
    t_s: float
    s_m: float
    leg: int
    energy_out_wh: float
    energy_back_wh: float
    whole_mission: bool
    recovery: tuple[float, float, float]
    message: str


def return_route(world: World, points: F64, position: F64, leg: int, recovery: F64,
                 free_from: NDArray[np.bool_] | None = None) -> F64 | None:
    """The return route from ``position`` on leg ``leg`` of ``points`` to ``recovery`` (module notes).

    Parameters
    ----------
    world : World
        Seabed, obstacles and bounds.
    points : numpy.ndarray
        ``(N, 3)`` mission route (m).
    position : numpy.ndarray
        ``(3,)`` where the vehicle turns back (m).
    leg : int
        The leg it is on.
    recovery : numpy.ndarray
        ``(3,)`` recovery point (m).
    free_from : numpy.ndarray of bool, optional
        ``(N,)`` whether the straight line from each vertex to ``recovery`` is free (computed when omitted).

    Returns
    -------
    numpy.ndarray or None
        ``(K, 3)`` return polyline from ``position`` (m); None when no vertex flown sees ``recovery``.
    """
    if world.path_free(np.stack([position, recovery])):
        return np.stack([position, recovery])
    if free_from is None:
        free_from = np.array([world.path_free(np.stack([q, recovery])) for q in points])
    for j in range(leg, -1, -1):
        if free_from[j]:
            return np.vstack([position, points[leg:j - 1 if j > 0 else None:-1], recovery])
    return None


def _return_energy(world: World, tr: Traverse, model: EnergyModel, s: float, recovery: F64, speed: float,
                   free_from: NDArray[np.bool_], ds: float) -> tuple[float, float, F64, float, int]:
    """E_out(s), E_ret(s) (Wh), the position, time and leg at ``s``; E_ret = inf when no return."""
    pos, t, leg = tr.at(s)
    power = model.power(tr.speeds)
    # energy out: whole legs before plus the part of this leg, at each leg's power
    e_out = float(np.sum(power[:leg] * np.diff(tr.times)[:leg]) + power[leg] * (t - tr.times[leg])) / WH
    back = return_route(world, tr.points, pos, leg, recovery, free_from)
    if back is None:
        return e_out, math.inf, pos, t, leg
    keep = np.r_[True, np.linalg.norm(np.diff(back, axis=0), axis=1) > 1e-9]
    back = back[keep]
    if back.shape[0] < 2:
        return e_out, 0.0, pos, t, leg
    ret = traverse(world, back, speed, t, ds)
    e_ret = float(model.power(speed)) * ret.duration / WH if ret.ok else math.inf
    return e_out, e_ret, pos, t, leg


def point_of_no_return(world: World, tr: Traverse, model: EnergyModel, recovery: ArrayLike | None = None,
                       speed: float | None = None, samples: int = 40, tol: float = 1.0,
                       ds: float = 100.0) -> PointOfNoReturn:
    """Find the point of no return of a mission flown as ``tr`` (module notes).

    Parameters
    ----------
    world : World
        Currents, seabed and obstacles.
    tr : Traverse
        The mission flown through the currents (:func:`~auvplan.endurance.budget.traverse`).
    model : EnergyModel
        Power model and battery.
    recovery : array_like, optional
        ``(3,)`` recovery point (m); the mission's start (home) by default.
    speed : float, optional
        Through-water speed of the return (m/s); the first leg's speed by default.
    samples : int, default 40
        Scan points along the route before the bisection.
    tol : float, default 1.0
        Bisection tolerance along the route (m).
    ds : float, default 100.0
        Longest integration sub-step of the return (m).

    Returns
    -------
    PointOfNoReturn
        The point, its time and energies, or a status saying why there is none.
    """
    home = tr.points[0] if recovery is None else np.asarray(recovery, dtype=float).reshape(3)
    v = float(tr.speeds[0]) if speed is None else float(speed)
    where = "home (the start)" if recovery is None else f"the rally point {np.round(home, 1).tolist()}"
    free_from = np.array([world.path_free(np.stack([q, home])) for q in tr.points])
    total = float(tr.node_s[-1])  # the whole route, or up to where the current blocks it
    budget = model.budget_wh

    def f(s: float) -> tuple[float, tuple[float, float, F64, float, int]]:
        r = _return_energy(world, tr, model, s, home, v, free_from, ds)
        return r[0] + r[1] - budget, r

    grid = np.linspace(0.0, total, max(2, samples) + 1)
    f0, r0 = f(0.0)
    if f0 > 0:
        return _found(home, 0.0, r0, False, f"the vehicle cannot reach {where} with its reserve even from the start",
                      Status.INFEASIBLE)
    lo, r_lo = 0.0, r0
    for s in grid[1:]:
        fs, rs = f(float(s))
        if fs > 0:
            lo, r_lo = _bisect(f, lo, r_lo, float(s), tol)
            return _found(home, lo, r_lo, False, f"turn back for {where} by {lo / 1000:.2f} km along the route (t = "
                          f"{r_lo[3] / 3600:.2f} h, leg {r_lo[4]}): {r_lo[0]:.1f} Wh out, {r_lo[1]:.1f} Wh back")
        lo, r_lo = float(s), rs
    if not tr.ok:
        return _found(home, lo, r_lo, False, f"{where} stays within reach up to where the current blocks the mission")
    return _found(home, lo, r_lo, True, f"{where} stays within reach with the reserve from every point of the mission")


_Return = tuple[float, float, F64, float, int]
"""A turn back at a distance along the route: energy out, energy back (Wh), the position, its time (s), its leg."""


def _bisect(f: Callable[[float], tuple[float, _Return]], lo: float, r_lo: _Return, hi: float,
            tol: float) -> tuple[float, _Return]:
    """The last distance along the route (to ``tol``) in ``[lo, hi]`` from which the return keeps the reserve
    (``f`` ≤ 0 at ``lo``, > 0 at ``hi``), and its return."""
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        fm, rm = f(mid)
        if fm > 0:
            hi = mid
        else:
            lo, r_lo = mid, rm
    return lo, r_lo


def _found(home: F64, s: float, r: _Return, whole: bool, msg: str, status: Status = Status.EXACT) -> PointOfNoReturn:
    """The point of no return at ``s`` along the route (``whole``: the recovery stays within reach throughout)."""
    e_out, e_ret, pos, t, leg = r
    return PointOfNoReturn(status, (float(pos[0]), float(pos[1]), float(pos[2])), t, s, leg, e_out, e_ret,
                           whole, (float(home[0]), float(home[1]), float(home[2])), msg)
