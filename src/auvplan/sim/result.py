"""What a run produced: the closed loop's :class:`SimResult` (time series, events, :class:`SimMetrics`),
a mission's :class:`RunRecord` (plan, route, key waypoints, run), and :func:`decimate` for exports."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import Status
from ..path import arc_length, polyline_length
from ..planners.core.base import PlanResult

if TYPE_CHECKING:  # a run's navigation plan; the plan of `plan` has none (issue 56)
    from ..guidance.following.route import RoutePoint
    from ..nav.mission import NavPlan
    from ..vehicles import VehicleState

__all__ = ["SimResult", "SimMetrics", "RunRecord", "decimate"]


class SimMetrics(TypedDict):
    """Summary figures of a run (:attr:`SimResult.metrics`; DESIGN.md §4 simulate JSON fields).

    Attributes
    ----------
    status : str
        The run's :class:`~auvplan._types.Status` value.
    arrived : bool
        Whether the vehicle reached the last waypoint.
    duration_s : float
        Time flown (s).
    distance_m : float
        Distance flown (m).
    min_altitude_m : float
        Least height above the seabed (m).
    min_clearance_m : float
        Smaller of ``min_altitude_m`` and ``min_obstacle_distance_m`` (m; margins not subtracted).
    min_obstacle_distance_m : float
        Least distance to an obstacle surface, static or moving (m).
    obstacle_min_distances_m : list of float
        Least distance to each obstacle, static then moving (m).
    collisions : int
        Contacts (``collision`` and ``unavoidable`` events).
    unavoidable : int
        Contacts with an obstacle faster than the vehicle that was closing in.
    cross_track_rms_m, cross_track_max_m : float
        RMS and largest distance to the route (m).
    escapes : int
        Local-minimum escapes.
    wall_time_s : float
        Wall-clock time of the run (s).
    """

    status: str
    arrived: bool
    duration_s: float
    distance_m: float
    min_altitude_m: float
    min_clearance_m: float
    min_obstacle_distance_m: float
    obstacle_min_distances_m: list[float]
    collisions: int
    unavoidable: int
    cross_track_rms_m: float
    cross_track_max_m: float
    escapes: int
    wall_time_s: float


@dataclass(frozen=True, eq=False)
class SimResult:
    """Time series and outcome of one closed-loop run.

    Arrays have one row per recorded step: ``t (N,)``, ``position (N, 3)``, ``heading (N,)``
    (compass, rad), ``speed (N,)`` (over ground), ``rudder (N,)`` (rad), ``cross_track (N,)``
    (signed, to the active leg, m), ``route_error (N,)`` (distance to the whole route, m),
    ``progress (N,)`` (m along the route), ``altitude (N,)`` (m above the seabed; inf without
    terrain), ``obstacle_distance (N, M)`` (m to each static then moving obstacle surface).

    Attributes
    ----------
    status : Status
        ``EXACT`` on arrival, else ``COLLISION``, ``UNAVOIDABLE``, ``DEADLOCK`` or ``TIMEOUT``.
    arrived : bool
        Whether the vehicle reached the last waypoint.
    t, position, heading, speed, rudder, cross_track, route_error, progress, altitude, obstacle_distance : ndarray
        The recorded time series (see above).
    events : tuple of (float, str, str)
        ``(time, kind, message)`` of arrival, collision, unavoidable, deadlock or timeout.
    guidance, avoidance : str
        The path follower and the local avoidance used.
    wall_time_s : float
        Wall-clock time of the run.
    escapes, decision_steps, decision_time_s
        Local-minimum escapes, APF decision steps and their total time (s).
    minimum_escapes : int
        Of the escapes, those fired by document 004's local-minimum count (the others by the stalled
        route progress).
    nav_error : ndarray or None
        ``(N,)`` the true horizontal error of the navigation estimate the vehicle steered by (m); None
        with perfect navigation (:mod:`auvplan.sim.drift`).
    """

    status: Status
    arrived: bool
    t: NDArray[np.float64]
    position: NDArray[np.float64]
    heading: NDArray[np.float64]
    speed: NDArray[np.float64]
    rudder: NDArray[np.float64]
    cross_track: NDArray[np.float64]
    route_error: NDArray[np.float64]
    progress: NDArray[np.float64]
    altitude: NDArray[np.float64]
    obstacle_distance: NDArray[np.float64]
    events: tuple[tuple[float, str, str], ...]
    guidance: str
    wall_time_s: float
    escapes: int = 0
    avoidance: str = "none"
    decision_steps: int = 0
    decision_time_s: float = 0.0
    minimum_escapes: int = 0
    nav_error: NDArray[np.float64] | None = None

    @property
    def metrics(self) -> SimMetrics:
        """Summary figures of the run (DESIGN.md §4 simulate JSON fields).

        ``min_altitude_m`` is the least height above the seabed, ``min_obstacle_distance_m`` the
        least distance to an obstacle surface (static or moving), ``min_clearance_m`` the smaller
        of the two (the geometric clearance, as in a plan's cost terms; margins not subtracted),
        ``collisions`` the contacts (``collision`` and ``unavoidable`` events).
        """
        d = polyline_length(self.position) if self.t.size > 1 else 0.0
        per_obs = self.obstacle_distance.min(axis=0) if self.obstacle_distance.size else np.empty(0)
        altitude = float(self.altitude.min()) if self.t.size else float("inf")
        obstacle = float(per_obs.min()) if per_obs.size else float("inf")
        return {
            "status": self.status.value,
            "arrived": self.arrived,
            "duration_s": float(self.t[-1]) if self.t.size else 0.0,
            "distance_m": float(d),
            "min_altitude_m": altitude,
            "min_clearance_m": min(altitude, obstacle),
            "min_obstacle_distance_m": obstacle,
            "obstacle_min_distances_m": per_obs.tolist(),
            "collisions": sum(1 for e in self.events if e[1] in ("collision", "unavoidable")),
            "unavoidable": sum(1 for e in self.events if e[1] == "unavoidable"),
            "cross_track_rms_m": float(np.sqrt(np.mean(self.route_error**2))) if self.t.size else 0.0,
            "cross_track_max_m": float(self.route_error.max()) if self.t.size else 0.0,
            "escapes": self.escapes,
            "wall_time_s": self.wall_time_s,
        }


@dataclass(frozen=True, eq=False)
class RunRecord:
    """Everything one mission produced: the plan, the route flown, its key waypoints, the run.

    ``seed`` is the integer seed the run used (the mission's unless another was given; -1 when a
    ``numpy.random.Generator`` was passed instead of a seed).

    Attributes
    ----------
    scenario : str
        Scenario name.
    seed : int
        Seed of the run (-1 for a generator).
    plan : PlanResult or None
        The global plan (None for a mission with a fixed route).
    route, keys : ndarray, shape (N, 3) and (K, 3)
        Waypoints flown and their key waypoints (document 004).
    sim : SimResult or None
        The closed-loop run (None when the plan failed).
    nav : NavPlan or None
        The navigation budget and its fixes (``[navigation]``; :mod:`auvplan.nav`).
    altitude : dict or None
        A terrain-following mission's altitude against its commanded band, planned and flown
        (:func:`auvplan.sim.band.altitude_band_metrics`; None when not terrain following).
    """

    scenario: str
    seed: int
    plan: PlanResult | None
    route: NDArray[np.float64]
    keys: NDArray[np.float64]
    sim: SimResult | None
    nav: NavPlan | None = None
    altitude: Mapping[str, float | int] | None = None

    @property
    def status(self) -> Status:
        """The mission's outcome: the plan's failure if it failed, then the navigation budget's, else the
        simulation's."""
        if self.plan is not None and not self.plan.status.ok:
            return self.plan.status
        if self.nav is not None and not self.nav.ok:
            return Status.INFEASIBLE
        return self.sim.status if self.sim is not None else Status.INFEASIBLE


def decimate(result: SimResult, every_m: float = 20.0, every_s: float = 30.0) -> SimResult:
    """Thin a run's recorded samples for exports and reports.

    One sample every ``every_m`` metres or ``every_s`` seconds (whichever comes first), plus the
    first and last samples and those of least altitude and least obstacle distance (the
    full-resolution result stays in ``run.npz``).

    Parameters
    ----------
    result : SimResult
        The run.
    every_m : float, optional
        Distance between kept samples along the track (m).
    every_s : float, optional
        Time between kept samples (s).

    Returns
    -------
    SimResult
        The same run with fewer samples (``result`` itself when it has two or fewer).
    """
    n = result.t.size
    if n <= 2:
        return result
    s = arc_length(result.position)
    keep = np.zeros(n, dtype=bool)
    keep[np.unique(np.searchsorted(s, np.arange(0.0, s[-1], every_m)))] = True
    keep[np.unique(np.searchsorted(result.t, np.arange(0.0, result.t[-1], every_s)))] = True
    keep[[0, n - 1, int(np.argmin(result.altitude))]] = True
    if result.obstacle_distance.size:
        keep[int(np.argmin(result.obstacle_distance.min(axis=1)))] = True
    arrays = ("t", "position", "heading", "speed", "rudder", "cross_track", "route_error", "progress", "altitude",
              "obstacle_distance")
    return replace(result, **{k: getattr(result, k)[keep] for k in arrays})


class _Recorder:
    """Preallocated time series of the run, one row per recorded step (:class:`~auvplan.sim.result.SimResult`)."""

    def __init__(self, n_rec: int, n_obs: int) -> None:
        self.n = 0
        self.t, self.h, self.v, self.d, self.e, self.pr, self.alt, self.ne = (np.empty(n_rec) for _ in range(8))
        self.p = np.empty((n_rec, 3))
        self.obs = np.empty((n_rec, n_obs))

    def add(self, t: float, pos: ArrayLike, s: VehicleState, vel: tuple[float, float, float], rp: RoutePoint,
            alt: float, dists: ArrayLike, nav_error: float = 0.0) -> None:
        """Record one step: time, position, heading, rudder, speed over ground, route point, altitude, distances
        and the navigation estimate's error."""
        n = self.n
        self.ne[n] = nav_error
        self.t[n], self.p[n], self.h[n], self.d[n] = t, pos, s.psi, s.delta
        self.v[n] = math.hypot(vel[0], vel[1])
        self.e[n], self.pr[n], self.alt[n] = rp.cross, rp.progress, alt
        self.obs[n] = dists
        self.n += 1
