"""The through-water speed of each leg: least energy by a deadline, or least time within the battery.

Both objectives are the same family.  With a price λ ≥ 0 (W) on time, each leg's speed minimises

    (P(V) + λ) T_i(V, t_i)        over V in [min_speed, max_speed]

where T_i(V, t_i) is the leg's duration flown from its start time t_i through the time-varying
current (:func:`~auvplan.endurance.budget.traverse`).  λ = 0 is least energy; λ → ∞ least time.
The legs are chosen in order, each from the time the previous one ends, and λ is found by
bisection: for ``"energy"`` the smallest λ whose arrival meets the deadline (λ = 0 without one),
for ``"time"`` the largest λ whose energy keeps the reserve.

This is the Lagrangian of ``min Σ P(V_i) T_i`` subject to ``Σ T_i ≤ deadline`` (or of
``min Σ T_i`` subject to ``Σ P(V_i) T_i ≤ budget``): the problem separates by leg, so in a steady
current the choice is exactly optimal; in a current that changes with time the legs are coupled
through their start times, which the in-order choice follows but does not optimise.  In still
water the λ = 0 speed is v* = (P_hotel / (2 k))^(1/3) on every leg (minimum of P(V)/V).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..world import World
from .budget import traverse
from .power import WH, EnergyModel

__all__ = ["SpeedPlan", "choose_speeds", "leg_speeds"]

F64 = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class SpeedPlan:
    """The chosen leg speeds.

    Attributes
    ----------
    objective : str
        ``"fixed"``, ``"energy"`` or ``"time"``.
    speeds : numpy.ndarray
        ``(L,)`` through-water speed of each leg (m/s).
    price_w : float
        The price of time λ (W) the speeds minimise ``(P + λ) T`` for (0 for ``"fixed"``).
    duration_s, energy_wh : float
        The mission's duration (s) and energy (Wh) at these speeds (``inf`` when not flyable).
    message : str
        What was met or why it could not be.
    """

    objective: str
    speeds: F64
    price_w: float
    duration_s: float
    energy_wh: float
    message: str = ""


def _leg_time(world: World, a: F64, b: F64, v: float, t: float, ds: float, tail: bool = False) -> float:
    tr = traverse(world, np.stack([a, b]), v, t, ds, [tail])
    return tr.duration if tr.ok else math.inf


def leg_speeds(world: World, route: ArrayLike, model: EnergyModel, price_w: float, depart: float = 0.0,
               ds: float = 100.0, xtol: float = 1e-6, tail: ArrayLike | None = None) -> tuple[F64, float, float]:
    """Each leg's speed minimising ``(P(V) + λ) T_i(V, t_i)``, leg after leg (module notes).

    Parameters
    ----------
    world : World
        Its currents.
    route : array_like
        ``(N, 3)`` waypoints (m).
    model : EnergyModel
        Power model and speed range.
    price_w : float
        λ, the price of time (W).
    depart : float, default 0.0
        Departure (s after the start time).
    ds : float, default 100.0
        Longest integration sub-step (m).
    xtol : float, default 1e-6
        Speed tolerance of the bounded scalar minimisation (m/s).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first (:func:`~auvplan.endurance.budget.traverse`).

    Returns
    -------
    speeds : numpy.ndarray
        ``(N - 1,)`` (m/s).
    duration_s, energy_wh : float
        The mission at those speeds (``inf`` when a leg cannot be flown in the range).
    """
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    lo, hi = model.min_speed, model.max_speed
    speeds = np.empty(w.shape[0] - 1)
    back = np.zeros(speeds.size, dtype=bool) if tail is None else np.asarray(tail, dtype=bool).reshape(-1)
    t, energy = depart, 0.0
    for i in range(w.shape[0] - 1):
        a, b, k = w[i], w[i + 1], bool(back[i])

        def cost(v: float, a: F64 = a, b: F64 = b, t: float = t, k: bool = k) -> float:
            dur = _leg_time(world, a, b, v, t, ds, k)
            return (float(model.power(v)) + price_w) * dur if math.isfinite(dur) else 1e300

        if lo == hi:
            v = lo
        else:
            from scipy.optimize import minimize_scalar  # imported when used (#56)

            res = minimize_scalar(cost, bounds=(lo, hi), method="bounded", options={"xatol": xtol})
            v = float(res.x)
            if cost(hi) < cost(v):  # the bounded search keeps inside the interval: check the fast end
                v = hi
        dur = _leg_time(world, a, b, v, t, ds, k)
        speeds[i] = v
        if not math.isfinite(dur):
            return speeds, math.inf, math.inf
        t += dur
        energy += float(model.power(v)) * dur / WH
    return speeds, t - depart, energy


def choose_speeds(world: World, route: ArrayLike, model: EnergyModel, cruise: float, objective: str = "fixed",
                  deadline_s: float = 0.0, depart: float = 0.0, ds: float = 100.0,
                  iterations: int = 24, tail: ArrayLike | None = None) -> SpeedPlan:
    """Choose the speed of every leg for an objective (module notes).

    Parameters
    ----------
    world : World
        Its currents.
    route : array_like
        ``(N, 3)`` waypoints (m).
    model : EnergyModel
        Power model, battery and speed range.
    cruise : float
        The vehicle's speed, for ``"fixed"`` (m/s).
    objective : {'fixed', 'energy', 'time'}
        Every leg at ``cruise``; least energy (by ``deadline_s`` when positive); least time within
        the battery's budget.
    deadline_s : float, default 0.0
        Latest arrival (s after the start time) for ``"energy"``; 0 = none.
    depart : float, default 0.0
        Departure (s after the start time).
    ds : float, default 100.0
        Longest integration sub-step (m).
    iterations : int, default 24
        Most bisection steps on the price of time (it stops when λ is known to 0.01 %).
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first (:func:`~auvplan.endurance.budget.traverse`).

    Returns
    -------
    SpeedPlan
        The speeds and what they achieve; when the deadline or the budget cannot be met, the
        fastest (``"energy"``) or the least-energy (``"time"``) speeds with a message saying so.
    """
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    if objective == "fixed":
        return _fixed(world, w, model, cruise, depart, ds, tail)
    if objective not in ("energy", "time"):
        raise ValueError(f"objective = {objective!r}: choose 'fixed', 'energy' or 'time'")

    def at(price_w: float) -> _Speeds:
        return leg_speeds(world, w, model, price_w, depart, ds, tail=tail)

    def ok(res: _Speeds) -> bool:
        if objective == "energy":
            return deadline_s <= 0 or depart + res[1] <= deadline_s
        return res[2] <= model.budget_wh

    base = at(0.0)
    if objective == "energy" and ok(base):
        return SpeedPlan("energy", base[0], 0.0, base[1], base[2], "least energy" + (
            f", arrives {deadline_s - depart - base[1]:.0f} s before the deadline" if deadline_s > 0 else ""))
    lam_hi, fast = _top_speed_price(at, model)
    at_an_end = _at_an_end(objective, ok, base, fast, lam_hi, depart)
    if at_an_end is not None:
        return at_an_end
    best, best_lam = _bisect_price(at, ok, objective == "energy", base, fast, lam_hi, iterations)
    what = "least energy by the deadline" if objective == "energy" else "least time within the battery"
    return SpeedPlan(objective, best[0], best_lam, best[1], best[2], what)


_Speeds = tuple[F64, float, float]
""":func:`leg_speeds`' answer: the speeds, the duration (s) and the energy (Wh)."""


def _fixed(world: World, w: F64, model: EnergyModel, cruise: float, depart: float, ds: float,
           tail: ArrayLike | None) -> SpeedPlan:
    """Every leg at ``cruise``."""
    tr = traverse(world, w, cruise, depart, ds, tail)
    dur = tr.duration if tr.ok else math.inf
    return SpeedPlan("fixed", np.full(w.shape[0] - 1, cruise), 0.0, dur, float(model.power(cruise)) * dur / WH)


def _at_an_end(objective: str, ok: Callable[[_Speeds], bool], base: _Speeds, fast: _Speeds, lam_hi: float,
               depart: float) -> SpeedPlan | None:
    """The answer when the fastest speeds miss the deadline or keep the budget, or the least-energy ones break it
    (no price of time to search for); None otherwise."""
    if objective == "energy" and not ok(fast):
        return SpeedPlan("energy", fast[0], lam_hi, fast[1], fast[2],
                         f"the deadline cannot be met: the fastest arrival is {depart + fast[1]:.0f} s")
    if objective == "time" and ok(fast):
        return SpeedPlan("time", fast[0], lam_hi, fast[1], fast[2], "least time: every leg at its fastest")
    if objective == "time" and not ok(base):
        return SpeedPlan("time", base[0], 0.0, base[1], base[2],
                         "even the least-energy speeds break the reserve")
    return None


def _top_speed_price(at: Callable[[float], _Speeds], model: EnergyModel) -> tuple[float, _Speeds]:
    """λ large enough to fly at the top speed, and those speeds: P'(v) T = ... grows with k v_max³; bracket by
    doubling."""
    lam_hi = max(model.hotel_w, 1.0)
    fast = at(lam_hi)
    for _ in range(30):
        if bool(np.all(fast[0] >= model.max_speed - 1e-4)):
            break
        lam_hi *= 4.0
        fast = at(lam_hi)
    return lam_hi, fast


def _bisect_price(at: Callable[[float], _Speeds], ok: Callable[[_Speeds], bool], energy: bool, base: _Speeds,
                  fast: _Speeds, lam_hi: float, iterations: int) -> tuple[_Speeds, float]:
    """Bisect the price of time in ``[0, lam_hi]``: the smallest λ meeting the deadline (``energy``), else the
    largest keeping the battery's budget; its speeds and λ."""
    lo, hi, best = 0.0, lam_hi, (fast if energy else base)
    best_lam = hi if energy else lo
    for _ in range(iterations):
        if hi - lo <= 1e-4 * max(hi, 1.0):  # λ to 0.01 %: the speeds to about 1e-5 of their range
            break
        mid = 0.5 * (lo + hi)
        res = at(mid)
        if energy:  # smallest λ meeting the deadline
            if ok(res):
                hi, best, best_lam = mid, res, mid
            else:
                lo = mid
        elif ok(res):  # "time": largest λ keeping the budget
            lo, best, best_lam = mid, res, mid
        else:
            hi = mid
    return best, best_lam
