"""``mission check`` of a mission held in memory, re-checking only the legs an edit changed.

The figures are those of ``auvplan mission check`` on the mission's exported file
(:func:`auvplan.guidance.mission.flycheck.fly_check` under the executor's depth semantics,
:func:`auvplan.path.flyable.check_limits` against the ``[vehicle]``, the energy budget of
:func:`auvplan.endurance.mission_budget` from the scenario's start time; in a steady current each
leg's flight is cached too, :mod:`auvplan.app.page.budget`).  Each leg's seabed and
obstacle figures depend on its two ends only (:func:`~auvplan.guidance.mission.flycheck.leg_figures`), and
each segment of the held-depth executor's track on its own ends
(:func:`~auvplan.guidance.mission.flycheck.segment_figures`): both are kept in a cache keyed by the ends'
coordinates, so moving one waypoint re-checks two legs and the few track segments that moved.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ...endurance import EnergyModel
from ...guidance.mission.flycheck import SEMANTICS, MissionCheck, held_track, leg_figures, segment_figures
from ...guidance.mission.limits import waypoint_limits
from ...guidance.mission.zone_legs import held_zone_entries
from ...path.legs import helm_check
from ...sim import Mission
from ...sim.pipeline import vehicle_limits
from ...world import World
from .budget import IncrementalBudget
from .lru import LruCache as _Cache

if TYPE_CHECKING:
    from ...endurance.budget import Budget
    from ...path.flyable import LimitReport

__all__ = ["CheckSettings", "IncrementalCheck", "CheckResult"]

_F64 = NDArray[np.float64]
"""Array of float64 (m unless said)."""


@dataclass(frozen=True)
class CheckSettings:
    """How the mission is checked.

    Attributes
    ----------
    semantics : {'held', 'ramp'}
        The executor's depth semantics (``held``: MOOS-IvP, the strictest; ``ramp``: every other export).
    pitch_deg : float
        Pitch at which a depth-holding executor changes depth (degrees; ``mission check --pitch``).
    """

    semantics: str = "held"
    pitch_deg: float = 15.0

    def __post_init__(self) -> None:
        if self.semantics not in SEMANTICS:
            raise ValueError(f"semantics = {self.semantics!r}: choose one of {', '.join(SEMANTICS)}")
        if not 0.0 < self.pitch_deg <= 90.0:  # also refuses nan
            raise ValueError(f"pitch = {self.pitch_deg}: must be a finite angle in (0, 90] degrees")


@dataclass(frozen=True, eq=False)
class CheckResult:
    """A checked mission: the ``mission check`` verdicts and the violations by leg.

    Attributes
    ----------
    check : MissionCheck
        Seabed, obstacles, surface, depth band and bounds (as ``fly_check``).
    summary : dict
        The figures the page shows (m, degrees, s, Wh).
    violations : list of dict
        ``leg``, ``kind``, ``text`` and ``value`` of every broken rule, by leg.
    rechecked : int
        Legs and track segments computed for this check (the rest came from the cache).
    """

    check: MissionCheck
    summary: dict[str, Any]
    violations: list[dict[str, Any]]
    rechecked: int = 0


def _keys(a: _F64, b: _F64, tag: bytes) -> list[bytes]:
    ends = np.ascontiguousarray(np.concatenate([a, b], axis=1))
    return [tag + row.tobytes() for row in ends]


class IncrementalCheck:
    """``mission check`` of a world and mission, with per-leg figures cached across edits.

    Parameters
    ----------
    world : World
        Seabed, obstacles, currents, margins.
    mission : Mission
        Its ``[vehicle]`` (limits, energy model, speed) and ``[endurance]`` settings.
    """

    def __init__(self, world: World, mission: Mission) -> None:
        self.world, self.mission = world, mission
        self._legs = _Cache()
        self._segments = _Cache()
        self._budget = IncrementalBudget(world, EnergyModel.from_vehicle(mission.vehicle), mission.endurance.ds_m)

    def _leg_figures(self, a: _F64, b: _F64, semantics: str) -> tuple[_F64, NDArray[np.bool_], _F64, int]:
        keys = _keys(a, b, semantics.encode())
        found, missing = self._legs.get_many(keys)
        if missing:
            idx = np.asarray(missing)
            alt, hits, dist = leg_figures(self.world, a[idx], b[idx], semantics)
            for j, i in enumerate(missing):
                value = (float(alt[j]), float(hits[j]), float(dist[j]))
                self._legs.put(keys[i], value)
                found[i] = value
        arr = np.array(found, dtype=float).reshape(-1, 3)
        return arr[:, 0], arr[:, 1] > 0, arr[:, 2], len(missing)

    def _segment_figures(self, a: _F64, b: _F64) -> tuple[_F64, NDArray[np.int64], int]:
        keys = _keys(a, b, b"seg")
        found, missing = self._segments.get_many(keys)
        if missing:
            idx = np.asarray(missing)
            alt, hits = segment_figures(self.world, a[idx], b[idx])
            for j, i in enumerate(missing):
                value = (float(alt[j]), float(hits[j]))
                self._segments.put(keys[i], value)
                found[i] = value
        arr = np.array(found, dtype=float).reshape(-1, 2)
        return arr[:, 0], arr[:, 1].astype(np.int64), len(missing)

    def fly_check(self, waypoints: _F64, settings: CheckSettings) -> tuple[MissionCheck, NDArray[np.bool_], int]:
        """:func:`auvplan.guidance.mission.flycheck.fly_check`, from cached leg figures.

        Parameters
        ----------
        waypoints : numpy.ndarray
            ``(N, 3)`` mission (m), N >= 2.
        settings : CheckSettings
            Semantics and pitch.

        Returns
        -------
        check : MissionCheck
            Equal to ``fly_check(world, waypoints, semantics, pitch)``.
        hits : numpy.ndarray
            ``(N - 1,)`` bool, the legs that meet an obstacle.
        computed : int
            Legs and segments not found in the cache.
        """
        w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
        world, m = self.world, self.world.margins
        alt, hits, dist, computed = self._leg_figures(w[:-1], w[1:], settings.semantics)
        k = int(np.argmin(alt)) if np.isfinite(alt).any() else -1
        extra: dict[str, Any] = {}
        if settings.semantics == "held":
            trk = held_track(w, settings.pitch_deg)
            seg_alt, seg_hits, more = self._segment_figures(trk[:-1], trk[1:])
            computed += more
            extra = {"pitch_deg": float(settings.pitch_deg),
                     "executor_min_altitude_m": float(seg_alt.min()) if world.terrain is not None else math.inf,
                     "executor_obstacle_hits": int(seg_hits.sum())}
        check = MissionCheck(settings.semantics, float(alt.min()), k, float(dist.min()) if dist.size else math.inf,
                             int(hits.sum()), alt, m.min_altitude, m.obstacle, limits=waypoint_limits(world, w),
                             **extra)
        return check, hits, computed

    def run(self, waypoints: _F64, settings: CheckSettings, speeds: float | _F64 | None = None) -> CheckResult:
        """Check the mission: seabed, obstacles, surface, depth band, bounds, vehicle limits and energy.

        Parameters
        ----------
        waypoints : numpy.ndarray
            ``(N, 3)`` mission (m), N >= 2.
        settings : CheckSettings
            Semantics and pitch.
        speeds : float or numpy.ndarray, optional
            Through-water speed per leg (m/s); the vehicle's cruise speed by default.

        Returns
        -------
        CheckResult
            The verdicts, the page's figures and the violations by leg.
        """
        w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
        check, hits, computed = self.fly_check(w, settings)
        vehicle = self.mission.vehicle
        limits = helm_check(w, vehicle_limits(vehicle))  # leg by leg, as a helm flies it (issue 49)
        budget = self._budget.run(w, vehicle.speed if speeds is None else speeds)[0]  # = mission_budget
        violations = _leg_violations(check, hits, limits)
        entered, in_zones = _zone_violations(self.world, w, settings)
        violations += in_zones + _waypoint_violations(check, w)
        violations.sort(key=lambda v: v["leg"])
        return CheckResult(check, _summary(check, limits, budget, settings, w, entered), violations, computed)


def _leg_violations(check: MissionCheck, hits: NDArray[np.bool_], limits: LimitReport) -> list[dict[str, Any]]:
    """The legs under the required altitude, within an obstacle's margin, and past the vehicle's limits."""
    req = check.required_altitude_m
    violations: list[dict[str, Any]] = []
    for leg in np.flatnonzero(check.leg_altitude_m < req - 1e-6):
        a = float(check.leg_altitude_m[leg])
        violations.append({"leg": int(leg), "kind": "altitude", "value": a,
                           "text": f"leg {leg}: altitude {a:.1f} m < min_altitude_m = {req:g}"})
    for leg in np.flatnonzero(hits):
        violations.append({"leg": int(leg), "kind": "obstacle", "value": float("nan"),
                           "text": f"leg {leg}: within obstacle_margin_m = {check.obstacle_margin_m:g} of an "
                                   "obstacle"})
    for v in limits.violations:
        violations.append({"leg": v.leg, "kind": v.limit, "value": v.value, "text": v.text})
    return violations


def _zone_violations(world: World, w: _F64, settings: CheckSettings) -> tuple[int, list[dict[str, Any]]]:
    """The charted zones' entries, leg by leg (as ``mission check``): the straight legs, and for a held depth each
    leg's envelope and the executor's track too; their count and violations."""
    zones = world.zones
    violations: list[dict[str, Any]] = []
    entered = 0
    if zones and len(w) > 1:
        seg, zi = zones.exact.entries(np.stack([w[:-1], w[1:]], axis=1))
        if settings.semantics == "held":
            hl, hz = held_zone_entries(zones.exact, w, settings.pitch_deg)
            pairs = np.unique(np.column_stack([np.r_[seg, hl], np.r_[zi, hz]]), axis=0).reshape(-1, 2)
            seg, zi = pairs[:, 0], pairs[:, 1]
        entered = int(seg.size)
        for leg, k in zip(seg, zi, strict=True):
            name = zones.names[int(k)]
            violations.append({"leg": int(leg), "kind": "zone", "value": float("nan"),
                               "text": f"leg {leg}: enters no-go zone {name!r}"})
    return entered, violations


def _waypoint_violations(check: MissionCheck, w: _F64) -> list[dict[str, Any]]:
    """Waypoints above the surface, outside the depth band or the bounds (on the leg they start, the last on the
    leg it ends)."""
    violations: list[dict[str, Any]] = []
    lim = check.limits
    if lim is not None:
        for kind, idx in (("above_surface", lim.above_surface), ("outside_depth_band", lim.outside_depth_band),
                          ("outside_bounds", lim.outside_bounds)):
            for i in idx:
                at = int(i) if int(i) < len(w) - 1 else len(w) - 2
                violations.append({"leg": at, "kind": kind, "value": float(-w[i, 2]),
                                   "text": f"waypoint {i}: {kind.replace('_', ' ')} (depth {-w[i, 2]:.1f} m)"})
    return violations


def _summary(check: MissionCheck, limits: LimitReport, budget: Budget, settings: CheckSettings, w: _F64,
             entered: int) -> dict[str, Any]:
    """The page's figures of the check, the vehicle's limits and the energy budget."""
    return {
        "ok": bool(check.ok and limits.ok and budget.status.ok and not entered), "zone_entries": entered,
        "check_ok": check.ok, "vehicle_ok": limits.ok, "energy_ok": budget.status.ok,
        "semantics": check.semantics, "pitch_deg": settings.pitch_deg, "waypoints": int(len(w)),
        "legs": int(len(w) - 1),
        "min_altitude_m": check.min_altitude_m,
        "min_altitude_leg": check.min_altitude_leg if check.min_altitude_leg >= 0 else None,
        "executor_min_altitude_m": check.executor_min_altitude_m, "required_altitude_m": check.required_altitude_m,
        "min_obstacle_distance_m": check.min_obstacle_distance_m, "obstacle_hits": check.obstacle_hits,
        "tightest_turn_m": limits.tightest_turn_m,
        "tightest_turn_leg": limits.tightest_turn_leg if limits.tightest_turn_leg >= 0 else None,
        "max_pitch_deg": limits.max_pitch_deg, "max_pitch_leg": limits.max_pitch_leg,
        "deepest_m": limits.max_depth_m,
        "length_m": float(np.linalg.norm(np.diff(w, axis=0), axis=1).sum()),
        "duration_s": budget.duration_s, "energy_wh": budget.energy_wh, "margin_wh": budget.margin_wh,
        "energy_status": budget.status.value, "energy_message": budget.message,
        "vehicle_summary": limits.summary,
    }
