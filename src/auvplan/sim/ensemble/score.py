"""A route flown and scored in every member of a current ensemble.

Each member flies the route as :func:`auvplan.endurance.mission_budget` does: the vehicle holds
each leg's track at its through-water speed V, crabbing into the cross current c⊥, so its ground
speed along the leg is ``c∥ + √(V² − c⊥²)`` and its heading through the water is the leg's course
plus ``asin(−c⊥ / V)`` (the heading reported for the first leg).  A member **succeeds** when the
vehicle arrives (no leg where the current beats it), keeps its battery reserve (``[vehicle]
battery_wh``, ``usable_fraction``, ``reserve``) and the route meets no seabed or obstacle (the
world's exact segment test).  Arrival times of the members that do not arrive count as +∞ in the
percentiles, which interpolate linearly between order statistics (numpy's default ``linear``
method): with two members T₁ ≤ T₂, P50 = (T₁ + T₂)/2 and P90 = 0.1 T₁ + 0.9 T₂.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..._types import Status
from ...endurance import EnergyModel, mission_budget
from ...vehicles import VehicleParams
from ...world import CurrentField, World

__all__ = ["MemberScore", "EnsembleScore", "percentile", "score_route", "crab_heading"]


@dataclass(frozen=True)
class MemberScore:
    """The route flown in one member.

    Attributes
    ----------
    name : str
        The member.
    arrival_s : float
        Time from the start to the goal (s); ``inf`` when the vehicle does not arrive.
    status : Status
        ``EXACT`` (success), ``RESERVE_BROKEN``, ``INFEASIBLE`` (the current beats the vehicle) or
        ``COLLISION`` (the route meets the seabed or an obstacle).
    energy_wh : float
        Energy drawn (Wh; ``inf`` when it does not arrive).
    heading_deg : float
        Heading through the water on the first leg (compass degrees).
    message : str
        The verdict in words.
    """

    name: str
    arrival_s: float
    status: Status
    energy_wh: float
    heading_deg: float
    message: str = ""

    @property
    def success(self) -> bool:
        """Arrived with the reserve kept and no collision."""
        return self.status is Status.EXACT

    def as_dict(self) -> dict[str, Any]:
        """The member's JSON fields.

        Returns
        -------
        dict
            ``name``, ``arrival_s``, ``status``, ``success``, ``energy_wh``, ``heading_deg``.
        """
        return {"name": self.name, "arrival_s": self.arrival_s, "status": self.status.value, "success": self.success,
                "energy_wh": self.energy_wh, "heading_deg": self.heading_deg}


@dataclass(frozen=True)
class EnsembleScore:
    """A route scored in every member.

    Attributes
    ----------
    members : tuple of MemberScore
        One per member, in order.
    arrival_p50_s, arrival_p90_s : float
        Median and 90th percentile of the arrival times (s; ``inf`` when too few arrive).
    success_probability : float
        Share of the members in which the mission succeeds.
    """

    members: tuple[MemberScore, ...]
    arrival_p50_s: float
    arrival_p90_s: float
    success_probability: float

    def as_dict(self) -> dict[str, Any]:
        """The ``plan --json`` fields.

        Returns
        -------
        dict
            ``arrival_p50_s``, ``arrival_p90_s``, ``success_probability`` and ``members``.
        """
        return {"arrival_p50_s": self.arrival_p50_s, "arrival_p90_s": self.arrival_p90_s,
                "success_probability": self.success_probability, "members": [m.as_dict() for m in self.members]}


def percentile(values: ArrayLike, q: float) -> float:
    """The q-th percentile with linear interpolation between order statistics, +∞ allowed.

    Parameters
    ----------
    values : array_like
        Values (``inf`` for a member that does not arrive).
    q : float
        Percentile in [0, 100].

    Returns
    -------
    float
        As :func:`numpy.percentile` (``linear``) on finite data; ``inf`` when the interpolation
        reaches an infinite value with a positive weight.
    """
    v = np.sort(np.asarray(values, dtype=float).reshape(-1))
    if v.size == 0:
        return math.nan
    pos = q / 100.0 * (v.size - 1)
    lo = int(math.floor(pos))
    hi = min(lo + 1, v.size - 1)
    w = pos - lo
    if w == 0.0 or hi == lo:
        return float(v[lo])
    if not math.isfinite(v[hi]) or not math.isfinite(v[lo]):
        return math.inf
    return float(v[lo] + w * (v[hi] - v[lo]))


def crab_heading(current: ArrayLike, a: ArrayLike, b: ArrayLike, speed: float) -> float:
    """Heading through the water that holds the track from a to b in a current (compass degrees).

    Parameters
    ----------
    current : array_like
        Current ``(3,)`` (m/s); only its horizontal part is used.
    a, b : array_like
        Ends of the leg ``(3,)`` (m).
    speed : float
        Horizontal through-water speed (m/s).

    Returns
    -------
    float
        ``course + asin(−c⊥ / V)`` in [0, 360), c⊥ the current's component to the right of the
        course; ``nan`` when |c⊥| > V.
    """
    d = np.asarray(b, dtype=float)[:2] - np.asarray(a, dtype=float)[:2]
    c = np.asarray(current, dtype=float)[:2]
    course = math.atan2(d[0], d[1])
    right = np.array([math.cos(course), -math.sin(course)])  # unit vector 90° clockwise of the course
    ratio = -float(c @ right) / speed
    if abs(ratio) > 1.0:
        return math.nan
    return math.degrees(course + math.asin(ratio)) % 360.0


def score_route(world: World, members: Sequence[tuple[str, CurrentField]], route: ArrayLike,
                vehicle: VehicleParams, speeds: ArrayLike | float | None = None, ds: float = 100.0) -> EnsembleScore:
    """Fly a route in every member and score it (module notes).

    Parameters
    ----------
    world : World
        Seabed, obstacles and margins (its own currents are not used).
    members : sequence of (str, CurrentField)
        Name and field of each member.
    route : array_like
        ``(N, 3)`` mission waypoints (m).
    vehicle : VehicleParams
        Speed, power model and battery.
    speeds : array_like or float, optional
        Through-water speed per leg or for all (m/s); the vehicle's ``speed`` by default.
    ds : float, default 100.0
        Longest integration sub-step (m).

    Returns
    -------
    EnsembleScore
        Per-member arrival, status and heading; P50, P90 and the success probability.
    """
    p = np.asarray(route, dtype=float).reshape(-1, 3)
    v = vehicle.speed if speeds is None else speeds
    model = EnergyModel.from_vehicle(vehicle)
    free = world.path_free(p)
    v0 = float(np.broadcast_to(np.asarray(v, dtype=float), (p.shape[0] - 1,))[0])
    scores = []
    for name, field in members:
        budget = mission_budget(replace(world, currents=field), p, model, v, 0.0, ds)
        heading = crab_heading(field.velocity(p[0], 0.0), p[0], p[1], v0)
        arrived = budget.status is not Status.INFEASIBLE
        status = budget.status if free else Status.COLLISION
        message = budget.message if free else "the route meets the seabed or an obstacle"
        scores.append(MemberScore(name, budget.duration_s if arrived else math.inf, status,
                                  budget.energy_wh, heading, message))
    times = [s.arrival_s for s in scores]
    success = sum(s.success for s in scores) / len(scores) if scores else 0.0
    return EnsembleScore(tuple(scores), percentile(times, 50.0), percentile(times, 90.0), success)
