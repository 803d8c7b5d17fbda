"""The clearance contract between planner and follower (issue 57 item 2): a route's tracking-error bound.

A planned route keeps a margin from every static obstacle, but the vehicle flies the route through a
path follower, and a vehicle with a finite turn radius leaves the route on its curves and corners
(the follower switches legs ahead of a waypoint, the heading lags the command).  What the plan must
keep is therefore the mission's margin *plus* how far the follower leaves the route.

:func:`route_bound` computes that distance from the vehicle model: the follower flies the route in the
mission's world with its obstacles taken away (the same vehicle, autopilot, time step and currents, no
local avoidance), and the bound is the largest 3-D distance from that track to the route polyline
(:func:`route_deviation`).  The hybrid field adds its stated push
(:attr:`auvplan.guidance.following.hybrid.HybridParams.push_bound_m`): near a static obstacle that a
clear route passes, its repulsion only shifts the line it steers to by at most that much.  The bound is
kept per leg (the points of the track nearest that leg), so a start next to an obstacle on a straight
first leg is not charged with the error of a sharp turn far away.  By the triangle inequality, a route
whose every leg is at least margin + its bound from every static obstacle (exact segment tests) is
flown at least the margin away, as long as the flight stays within the bound.

Why per route and not one figure per vehicle: flying LOS along routes whose every fly-by turn fits the
10 m turn radius (REMUS-100-class defaults), the deviation is 0.9-2.0 m on 270° polygons inscribed in a
circle of radius R with 1-5 m chords and 8.7 m (120°) to 15.1 m (150°) at single sharp corners, so one bound
over every flyable route would refuse every plan near an obstacle; the plan's own route decides
(docs/flow-flown.md).

:func:`auvplan.sim.pipeline.kept_fit` applies the contract; :func:`contract_world` raises the margin.

Limits: the bound is computed, not proven (a disturbance the model does not carry - waves, a current
other than the world's, a navigation error - is not in it); the local avoidance's manoeuvres round
moving obstacles are not covered; the seabed margin is not raised.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..world import World
from .loop import simulate
from .mission import Mission

__all__ = ["TrackingBound", "route_deviation", "route_bound", "contract_world", "route_keeps"]

FOLLOWERS = ("los", "ilos", "hybrid")
"""The path followers a bound is computed for."""


@dataclass(frozen=True)
class TrackingBound:
    """How far a follower leaves one route (m).

    Attributes
    ----------
    follower : str
        ``los``, ``ilos`` or ``hybrid``.
    legs_m : numpy.ndarray
        ``(N - 1,)`` per leg: the largest 3-D distance to the route of the points of the track flown without
        obstacles whose nearest route point lies on that leg (0 for a leg no point is nearest to).
    push_m : float
        The hybrid field's stated push (0 for LOS and ILOS), added to every leg.
    """

    follower: str
    legs_m: NDArray[np.float64]
    push_m: float

    @property
    def flown_m(self) -> float:
        """The largest distance of the flown track from the route (m)."""
        return float(self.legs_m.max()) if self.legs_m.size else 0.0

    @property
    def total_m(self) -> float:
        """The bound over the whole route: ``flown_m + push_m`` (m)."""
        return self.flown_m + self.push_m

    @property
    def per_leg_m(self) -> NDArray[np.float64]:
        """``(N - 1,)`` each leg's bound: ``legs_m + push_m`` (m)."""
        return np.asarray(self.legs_m + self.push_m, dtype=float)


def route_deviation(track: NDArray[np.float64], route: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                                                 NDArray[np.intp]]:
    """Each track point's 3-D distance to the route polyline, and the leg its nearest route point lies on.

    Parameters
    ----------
    track : numpy.ndarray
        ``(M, 3)`` flown positions (m).
    route : numpy.ndarray
        ``(N, 3)`` waypoints (m).

    Returns
    -------
    tuple of numpy.ndarray
        ``(M,)`` distances (m) and ``(M,)`` leg indices.
    """
    a, d = route[:-1], np.diff(route, axis=0)
    dd = np.maximum((d * d).sum(axis=1), 1e-12)
    s = np.clip(np.einsum("mlk,lk->ml", track[:, None, :] - a[None], d) / dd, 0.0, 1.0)
    q = a[None] + s[..., None] * d[None]
    dist = np.linalg.norm(track[:, None, :] - q, axis=2)
    j = dist.argmin(axis=1)
    return dist[np.arange(track.shape[0]), j], j


def route_bound(world: World, mission: Mission, route: ArrayLike, follower: str | None = None) -> TrackingBound:
    """The tracking-error bound of a route under a follower, from the vehicle model (module notes).

    Parameters
    ----------
    world : World
        The mission's world: its currents and seabed are kept, its static and moving obstacles taken away.
    mission : Mission
        Its vehicle, follower settings (``los``, ``hybrid``), leg speeds and time step.
    route : array_like
        ``(N, 3)`` waypoints (m).
    follower : str, optional
        ``los``, ``ilos`` or ``hybrid``; the mission's ``guidance`` by default.

    Returns
    -------
    TrackingBound
        The bound (m).
    """
    name = follower or mission.guidance
    if name not in FOLLOWERS:
        raise ValueError(f"unknown guidance {name!r}; choose hybrid, los or ilos")
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    clear = replace(world, obstacles=(), moving=())
    sim = simulate(clear, mission, route=w, guidance=name, avoidance="none", rng=mission.seed)
    dist, leg = route_deviation(sim.position, w)
    legs = np.zeros(w.shape[0] - 1)
    np.maximum.at(legs, leg, dist)
    push = mission.hybrid.push if name == "hybrid" else 0.0
    return TrackingBound(name, legs, push)


def route_keeps(world: World, route: ArrayLike, clearance: ArrayLike) -> int:
    """The first leg of a route closer than its ``clearance`` to a static obstacle's surface (exact segment
    tests), -1 when every leg keeps it.

    Parameters
    ----------
    world : World
        Its static obstacles.
    route : array_like
        ``(N, 3)`` waypoints (m).
    clearance : array_like
        Required distance from every surface (m): one for all legs or ``(N - 1,)``, one per leg.

    Returns
    -------
    int
        Leg index, or -1.
    """
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    legs = np.stack([w[:-1], w[1:]], axis=1)
    need = np.broadcast_to(np.asarray(clearance, dtype=float), (legs.shape[0],))
    hit = np.zeros(legs.shape[0], dtype=bool)
    for ob in world.obstacles:
        hit |= ob.segments_hit(legs, need)
    return int(np.argmax(hit)) if hit.any() else -1


def contract_world(world: World, bound: float) -> World:
    """The world a plan is made in so that the follower keeps the mission's margin: the static obstacles'
    margin raised by the bound.

    Parameters
    ----------
    world : World
        The mission's world.
    bound : float
        The follower's bound on the route (m; :attr:`TrackingBound.total_m`).

    Returns
    -------
    World
        ``world`` with ``margins.obstacle`` raised by ``bound``.
    """
    m = world.margins
    return replace(world, margins=replace(m, obstacle=m.obstacle + bound))
