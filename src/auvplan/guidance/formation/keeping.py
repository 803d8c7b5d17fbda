"""Formation keeping for several under-actuated vehicles in document 001's hybrid potential field.

Document 001 (Wang et al. 2020, "path planning *and formation* method for UUVs based on a hybrid
potential field") gives the single-vehicle field (docs/methods.md §3) and no formation law; this module
builds the formation from the same terms, one heading command per vehicle:

* **virtual structure along the global route** (leader–follower in path coordinates): the
  formation's reference is the leader's arc length ``s`` along the route (its continuous projection);
  slot ``i`` sits at ``P(s + a_i) + c_i n̂ + h_i ẑ`` — ``a_i`` metres along the route ahead (negative:
  behind), ``c_i`` to starboard of the *smoothed* route course at that point, ``h_i`` up.  Slot 0 is
  the leader's: the route itself.
* **route attraction to the slot** (eqs. 3–4): ``k_H·e`` towards the line through the slot along
  the slot's course (``e`` the follower's cross error to it); **heading attraction** (eqs. 5–6):
  ``k_X·Δ`` along that course; **repulsion from obstacles** (eqs. 7–8) — all three through
  :func:`auvplan.guidance.following.hybrid.hybrid_force`, the single-vehicle field itself;
* **repulsion from the other vehicles**: the same eqs. 7–8 term
  (:func:`~auvplan.guidance.formation.steer.vehicle_repulsion`) with its own gain ``k_vehicle`` and
  influence ``vehicle_influence_m`` beyond the separation ``separation_m``,
  acting from the *predicted* relative position at closest approach (the vehicles share positions and
  velocities), so two vehicles on crossing courses open their miss distance early and the same way
  round (no goal factor: the other vehicles move with the formation);
* the resultant is the course; the current turns it into a heading (crab angle) as in
  :class:`~auvplan.guidance.following.hybrid.HybridGuidance`;
* **speed adjustment** holds the along-track spacing: ``u = u_slot + k_s ε`` (``ε`` the along
  error, positive when behind; ``u_slot`` the slot's own speed: the leader's speed command times the
  slot track's stretch, so outer vehicles speed up in turns and during shape changes), and the
  leader waits for a lagging follower, ``u_L = u₀ − k_w max(0, max ε)``.

Linearised on a straight route (small errors, crab-compensated current) the cross error obeys
``s (s² + 2ζω_n s + ω_n²) + ω_n² U k_H / (k_X Δ) = 0`` (heading autopilot poles ω_n, ζ; ground speed
``U``) and the along error ``T_u s² + s + k_s = 0`` (surge lag ``T_u``; the leader's wait cancels out
of the spacing error because each follower's feed-forward is the leader's command):
:func:`~auvplan.guidance.formation.steer.dominant_pole` (the steering law is computed in
:mod:`auvplan.guidance.formation.steer`).  The defaults put the along poles at a double root ``−1/(2 T_u)``.

Shapes (``spacing_m`` between neighbours): ``line`` (abreast: port, starboard, port … of the
leader), ``column`` (single file behind the leader, every vehicle on the route at the route's
depth), ``wedge`` (each rank ``spacing`` back and ``spacing`` out).  A shape change at a route
position blends the offsets over ``transition_m`` metres (smoothstep); the shapes along the route are
:mod:`auvplan.guidance.formation.route`'s (re-exported here).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TypeAlias

from ..._types import FloatArray
from .route import SHAPES, FormationRoute, Schedule, shape_offsets

Vec: TypeAlias = "Sequence[float] | FloatArray"
"""A point or vector ``(x, y[, z])`` (m or m/s) as a sequence or an array."""

__all__ = [
    "SHAPES",
    "ShapeChange",
    "FormationParams",
    "VehicleSpec",
    "VEHICLE_NAME",
    "Formation",
    "shape_offsets",
    "Schedule",
    "FormationRoute",
]


VEHICLE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}")
"""A vehicle name (a folder of the results): no '.', '..', separators, spaces, control characters or NUL."""


@dataclass(frozen=True)
class ShapeChange:
    """A shape change starting at a route position or at a route waypoint.

    Attributes
    ----------
    shape : str
        The new shape: ``line``, ``column`` or ``wedge``.
    at_m : float
        Route position (m along the route) where the blend starts; -1 when ``waypoint`` is given.
    waypoint : int
        Index of the route waypoint where the blend starts; -1 when ``at_m`` is given.
    """

    shape: str
    at_m: float = -1.0
    waypoint: int = -1

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise ValueError(f"shape = {self.shape!r}: choose {', '.join(SHAPES)}")
        if (self.at_m >= 0) == (self.waypoint >= 0):
            raise ValueError("give exactly one of 'at_m' (>= 0) and 'waypoint' (>= 0)")


@dataclass(frozen=True)
class FormationParams:
    """Formation geometry and gains (SI units).

    Attributes
    ----------
    shape : str
        Initial shape: ``line`` (abreast), ``column`` or ``wedge``.
    spacing_m : float
        Distance between neighbouring slots.
    transition_m : float
        Route distance over which a shape change blends the slots.
    changes : tuple of ShapeChange
        Scheduled shape changes (route positions or waypoints).
    auto_column : bool
        Reshape to column wherever a slot track of the shape fails the exact seabed/obstacle test.
    separation_m : float
        Centre distance the vehicle repulsion keeps (its zero of distance).
    vehicle_influence_m : float
        Influence of the vehicle repulsion beyond ``separation_m`` (below ``spacing_m −
        separation_m``: a settled formation feels none).
    k_vehicle : float
        Gain of the vehicle repulsion (eqs. 7–8 form).
    horizon_s : float
        Look-ahead of the predicted closest approach between vehicles (s).
    contact_m : float
        Centre distance at which two hulls touch (a collision).
    k_speed : float
        Along-track spacing gain k_s (1/s).
    k_wait : float
        Leader's slow-down per metre of the largest follower lag k_w (1/s).
    min_speed_ratio : float
        Least speed command as a fraction of the cruise speed.
    course_window_m : float
        Half-window of the route course smoothing that orients the slots (m; 0: ``spacing_m``, so the
        slots of a wide formation turn smoothly round a corner).
    sample_m : float
        Spacing of the slot-track samples tested against the seabed (m).
    start_sigma_m : float
        Launch scatter: standard deviation of each vehicle's initial horizontal position error about
        its slot (or its ``start``), per axis (m; 0: exactly on it).  Drawn from the run's seed.
    start_heading_sigma_deg : float
        Standard deviation of each vehicle's initial heading error (degrees), drawn from the run's seed.
    """

    shape: str = "line"
    spacing_m: float = 30.0
    transition_m: float = 200.0
    changes: tuple[ShapeChange, ...] = ()
    auto_column: bool = True
    separation_m: float = 6.0
    vehicle_influence_m: float = 12.0
    k_vehicle: float = 2.0e4
    horizon_s: float = 30.0
    contact_m: float = 2.0
    k_speed: float = 0.05
    k_wait: float = 0.01
    min_speed_ratio: float = 0.5
    course_window_m: float = 0.0
    sample_m: float = 10.0
    start_sigma_m: float = 0.0
    start_heading_sigma_deg: float = 0.0

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise ValueError(f"shape = {self.shape!r}: choose {', '.join(SHAPES)}")
        for k in ("spacing_m", "transition_m", "separation_m", "vehicle_influence_m", "contact_m", "sample_m",
                  "horizon_s"):
            if not getattr(self, k) > 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be positive")
        for k in ("k_vehicle", "k_speed", "k_wait", "course_window_m", "start_sigma_m", "start_heading_sigma_deg"):
            if getattr(self, k) < 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be >= 0")
        if not 0 < self.min_speed_ratio <= 1:
            raise ValueError(f"min_speed_ratio = {self.min_speed_ratio}: must lie in (0, 1]")
        if self.spacing_m <= self.separation_m + self.vehicle_influence_m:
            raise ValueError(f"spacing_m = {self.spacing_m}: must exceed separation_m + vehicle_influence_m = "
                             f"{self.separation_m + self.vehicle_influence_m} (or a settled formation repels itself)")
        if self.separation_m < self.contact_m:
            raise ValueError(f"separation_m = {self.separation_m}: must be >= contact_m = {self.contact_m}")


@dataclass(frozen=True)
class VehicleSpec:
    """One vehicle of the formation.

    Attributes
    ----------
    name : str
        Its name, a folder of the results: matches :data:`VEHICLE_NAME` (1-64 of ``A-Za-z0-9._-``,
        starting with a letter or digit).
    role : str
        ``leader`` (exactly one) or ``follower``.
    start : tuple of float
        Start ``(x, y, z)`` (m); empty: its slot at the route's start.
    depth_offset_m : float
        Depth below the formation's reference in the abreast shapes (m, positive deeper; a column
        flies at the route's depth).
    """

    name: str
    role: str = "follower"
    start: tuple[float, ...] = ()
    depth_offset_m: float = 0.0

    def __post_init__(self) -> None:
        if self.role not in ("leader", "follower"):
            raise ValueError(f"role = {self.role!r}: choose leader or follower")
        if self.start and len(self.start) != 3:
            raise ValueError(f"start = {list(self.start)}: expected [x, y, z]")
        if not isinstance(self.name, str) or not VEHICLE_NAME.fullmatch(self.name):
            raise ValueError(f"name = {self.name!r}: a vehicle name is a folder of the results: 1-64 ASCII letters, "
                             "digits, '.', '_' or '-', starting with a letter or digit")


@dataclass(frozen=True)
class Formation:
    """The vehicles and the formation parameters.

    Attributes
    ----------
    params : FormationParams
        Geometry and gains.
    vehicles : tuple of VehicleSpec
        The vehicles, reordered leader first, then the followers in slot order.
    """

    params: FormationParams
    vehicles: tuple[VehicleSpec, ...]

    def __post_init__(self) -> None:
        if len(self.vehicles) < 2:
            raise ValueError("a formation needs at least two [[vehicles]]")
        roles = [v.role for v in self.vehicles]
        if roles.count("leader") != 1:
            raise ValueError(f"exactly one [[vehicles]] entry must have role = 'leader' "
                             f"(found {roles.count('leader')})")
        names = [v.name for v in self.vehicles]
        if len(set(names)) != len(names):
            raise ValueError(f"vehicle names must be unique, got {names}")
        lead = roles.index("leader")
        if lead:  # the leader takes slot 0
            v = list(self.vehicles)
            object.__setattr__(self, "vehicles", (v[lead], *v[:lead], *v[lead + 1:]))

    @property
    def n(self) -> int:
        """Number of vehicles."""
        return len(self.vehicles)

    @property
    def names(self) -> tuple[str, ...]:
        """Vehicle names in slot order."""
        return tuple(v.name for v in self.vehicles)
