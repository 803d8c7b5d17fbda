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
  :func:`auvplan.guidance.hybrid.hybrid_force`, the single-vehicle field itself;
* **repulsion from the other vehicles**: the same eqs. 7–8 term
  (:func:`~auvplan.guidance.formation_steer.vehicle_repulsion`) with its own gain ``k_vehicle`` and
  influence ``vehicle_influence_m`` beyond the separation ``separation_m``,
  acting from the *predicted* relative position at closest approach (the vehicles share positions and
  velocities), so two vehicles on crossing courses open their miss distance early and the same way
  round (no goal factor: the other vehicles move with the formation);
* the resultant is the course; the current turns it into a heading (crab angle) as in
  :class:`~auvplan.guidance.hybrid.HybridGuidance`;
* **speed adjustment** holds the along-track spacing: ``u = u_slot + k_s ε`` (``ε`` the along
  error, positive when behind; ``u_slot`` the slot's own speed: the leader's speed command times the
  slot track's stretch, so outer vehicles speed up in turns and during shape changes), and the
  leader waits for a lagging follower, ``u_L = u₀ − k_w max(0, max ε)``.

Linearised on a straight route (small errors, crab-compensated current) the cross error obeys
``s (s² + 2ζω_n s + ω_n²) + ω_n² U k_H / (k_X Δ) = 0`` (heading autopilot poles ω_n, ζ; ground speed
``U``) and the along error ``T_u s² + s + k_s = 0`` (surge lag ``T_u``; the leader's wait cancels out
of the spacing error because each follower's feed-forward is the leader's command):
:func:`~auvplan.guidance.formation_steer.dominant_pole` (the steering law is computed in
:mod:`auvplan.guidance.formation_steer`).  The defaults put the along poles at a double root ``−1/(2 T_u)``.

Shapes (``spacing_m`` between neighbours): ``line`` (abreast: port, starboard, port … of the
leader), ``column`` (single file behind the leader, every vehicle on the route at the route's
depth), ``wedge`` (each rank ``spacing`` back and ``spacing`` out).  A shape change at a route
position blends the offsets over ``transition_m`` metres (smoothstep).
"""

from __future__ import annotations

import bisect
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TypeAlias

import numpy as np

from .._types import ArrayLike, FloatArray

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

SHAPES = ("line", "column", "wedge")

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


def shape_offsets(shape: str, n: int, spacing: float, depth_offsets: ArrayLike | None = None) -> FloatArray:
    """Slot offsets of a shape; slot 0 is the leader's.

    ``line``: abreast, port then starboard in rising ranks; ``column``: ``k·spacing`` behind;
    ``wedge``: rank ``r`` is ``r·spacing`` behind and ``r·spacing`` out.

    Parameters
    ----------
    shape : str
        ``line``, ``column`` or ``wedge``.
    n : int
        Number of slots.
    spacing : float
        Distance between neighbouring slots (m).
    depth_offsets : array_like (n,), optional
        Depths below the reference (m, positive deeper), for the abreast shapes (a column flies on
        the route).

    Returns
    -------
    ndarray (n, 3)
        (along ahead, to starboard, up) in metres.
    """
    if shape not in SHAPES:
        raise ValueError(f"shape = {shape!r}: choose {', '.join(SHAPES)}")
    k = np.arange(n)
    rank = (k + 1) // 2
    side = np.where(k % 2 == 1, -1.0, 1.0)
    out = np.zeros((n, 3))
    if shape == "column":
        out[:, 0] = -k * spacing
        return out
    out[:, 1] = side * rank * spacing
    if shape == "wedge":
        out[:, 0] = -rank * spacing
    if depth_offsets is not None:
        out[:, 2] = -np.asarray(depth_offsets, dtype=float)
    return out


def _smoothstep(x: ArrayLike) -> FloatArray:
    c = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    out: FloatArray = c * c * (3.0 - 2.0 * c)
    return out


class Schedule:
    """Shapes along the route, each blended in over ``transition`` metres from the shape before it.

    Parameters
    ----------
    breaks : sequence of (float, str)
        ``(route position, shape)`` breakpoints; the first at 0 m.
    n : int
        Number of vehicles.
    spacing : float
        Slot spacing (m).
    transition : float
        Blend length (m).
    depth_offsets : array_like (n,), optional
        The vehicles' depth offsets (m, positive deeper).
    """

    def __init__(self, breaks: Sequence[tuple[float, str]], n: int, spacing: float, transition: float,
                 depth_offsets: ArrayLike | None = None) -> None:
        self.breaks = sorted((float(s), str(sh)) for s, sh in breaks)
        if not self.breaks or self.breaks[0][0] > 0:
            raise ValueError("a schedule starts with the shape at 0 m")
        self.n, self.spacing, self.transition = n, float(spacing), float(transition)
        self.depth = np.zeros(n) if depth_offsets is None else np.asarray(depth_offsets, dtype=float)
        self._offsets = [shape_offsets(sh, n, spacing, self.depth) for _, sh in self.breaks]

    def shape_at(self, s: float) -> str:
        """The shape in force (or being formed) at a route position.

        Parameters
        ----------
        s : float
            Route position (m).

        Returns
        -------
        str
            The shape.
        """
        name = self.breaks[0][1]
        for b, sh in self.breaks:
            if s >= b:
                name = sh
        return name

    def offsets(self, s: ArrayLike) -> FloatArray:
        """Slot offsets at route positions.

        Parameters
        ----------
        s : array_like (...)
            Route positions (m).

        Returns
        -------
        ndarray (..., n, 3)
            (along ahead, to starboard, up) of every slot.
        """
        s = np.asarray(s, dtype=float)
        out = np.broadcast_to(self._offsets[0], s.shape + (self.n, 3)).copy()
        for (b, _), prev, new in zip(self.breaks[1:], self._offsets[:-1], self._offsets[1:]):
            w = _smoothstep((s - b) / self.transition)[..., None, None]
            out = out + w * (new - prev)
        return out


class FormationRoute:
    """The global route as the formation's virtual structure: slots at a reference position ``s``.

    Parameters
    ----------
    route : array_like (N, 3)
        The route the leader flies (the checked mission).
    schedule : Schedule
        Shapes along it.
    course_window : float
        Half-window (m) of the chord that gives the slots' orientation (smooths corners).
    """

    def __init__(self, route: ArrayLike, schedule: Schedule, course_window: float) -> None:
        w = np.asarray(route, dtype=float).reshape(-1, 3)
        d = np.hypot(*np.diff(w[:, :2], axis=0).T)
        keep = np.r_[True, d > 1e-9]
        self.w = w[keep]
        self.cum = np.r_[0.0, np.cumsum(np.hypot(*np.diff(self.w[:, :2], axis=0).T))]
        self.length = float(self.cum[-1])
        self.schedule = schedule
        self.window = float(course_window)
        first, last = self.w[1] - self.w[0], self.w[-1] - self.w[-2]
        self._t0 = first[:2] / np.hypot(*first[:2])
        self._t1 = last[:2] / np.hypot(*last[:2])
        # plain-float copies for the closed loop's scalar queries (one vehicle step = a few of them)
        self._cum = self.cum.tolist()
        self._w = self.w.tolist()
        self._breaks = [(b, shape_offsets(sh, schedule.n, schedule.spacing, schedule.depth).tolist())
                        for b, sh in schedule.breaks]

    def point(self, s: ArrayLike) -> FloatArray:
        """Route points at arc lengths (straight extensions beyond the ends).

        Parameters
        ----------
        s : array_like (...)
            Arc lengths (m).

        Returns
        -------
        ndarray (..., 3)
            The points.
        """
        s = np.asarray(s, dtype=float)
        sc = np.clip(s, 0.0, self.length)
        out = np.stack([np.interp(sc, self.cum, self.w[:, j]) for j in range(3)], axis=-1)
        before, after = np.minimum(s, 0.0), np.maximum(s - self.length, 0.0)
        out[..., 0] += before * self._t0[0] + after * self._t1[0]
        out[..., 1] += before * self._t0[1] + after * self._t1[1]
        return out

    def course(self, s: ArrayLike) -> FloatArray:
        """Smoothed compass course: the chord from ``s − window`` to ``s + window``.

        Parameters
        ----------
        s : array_like (...)
            Arc lengths (m).

        Returns
        -------
        ndarray (...)
            Courses (rad, compass).
        """
        s = np.asarray(s, dtype=float)
        d = self.point(s + self.window) - self.point(s - self.window)
        course: FloatArray = np.arctan2(d[..., 0], d[..., 1])
        return course

    def slots(self, s: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Every slot with the formation's reference at ``s``.

        Parameters
        ----------
        s : array_like (...)
            Reference positions (m along the route).

        Returns
        -------
        positions : ndarray (..., n, 3)
            Slot positions.
        courses : ndarray (..., n)
            The slots' courses (rad, compass).
        """
        s = np.asarray(s, dtype=float)
        off = self.schedule.offsets(s)
        sa = s[..., None] + off[..., 0]
        base = self.point(sa)
        psi = self.course(sa)
        nx, ny = np.cos(psi), -np.sin(psi)
        base[..., 0] += off[..., 1] * nx
        base[..., 1] += off[..., 1] * ny
        base[..., 2] += off[..., 2]
        return base, psi

    def tracks(self, step: float) -> tuple[np.ndarray, np.ndarray]:
        """Every slot's swept track over the whole route.

        Parameters
        ----------
        step : float
            Largest spacing of the reference positions (m); route vertices and shape-change ends are
            included.

        Returns
        -------
        s : ndarray (M,)
            Reference positions.
        tracks : ndarray (n, M, 3)
            The slots at each of them.
        """
        extra = [b for b, _ in self.schedule.breaks] + [b + self.schedule.transition for b, _ in self.schedule.breaks]
        s = np.unique(np.r_[np.linspace(0.0, self.length, max(2, int(math.ceil(self.length / step)) + 1)),
                            self.cum, [e for e in extra if 0 <= e <= self.length]])
        pos, _ = self.slots(s)
        return s, np.swapaxes(pos, 0, 1)

    def point_at(self, s: float) -> tuple[float, float, float]:
        """:meth:`point` for one arc length, in plain floats (the closed loop's fast path).

        Parameters
        ----------
        s : float
            Arc length (m).

        Returns
        -------
        tuple of 3 float
            The point.
        """
        L = self.length
        if s <= 0.0 or s >= L:
            p, e, t = (self._w[0], s, self._t0) if s <= 0.0 else (self._w[-1], s - L, self._t1)
            return p[0] + e * t[0], p[1] + e * t[1], p[2]
        k = bisect.bisect_right(self._cum, s) - 1
        a, b = self._w[k], self._w[k + 1]
        f = (s - self._cum[k]) / (self._cum[k + 1] - self._cum[k])
        return a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])

    def slots_at(self, s: float) -> tuple[list[tuple[float, float, float]], list[float]]:
        """:meth:`slots` for one reference position, in plain floats (the closed loop's fast path).

        Parameters
        ----------
        s : float
            Reference position (m).

        Returns
        -------
        positions : list of (float, float, float)
            Slot positions.
        courses : list of float
            The slots' courses (rad).
        """
        off = [list(o) for o in self._breaks[0][1]]
        tr = self.schedule.transition
        for (b, new), (_, prev) in zip(self._breaks[1:], self._breaks[:-1]):
            x = min(max((s - b) / tr, 0.0), 1.0)
            w = x * x * (3.0 - 2.0 * x)
            if w:
                for o, p, q in zip(off, prev, new):
                    o[0] += w * (q[0] - p[0])
                    o[1] += w * (q[1] - p[1])
                    o[2] += w * (q[2] - p[2])
        pts, psis = [], []
        h = self.window
        for a, c, up in off:
            sa = s + a
            x, y, z = self.point_at(sa)
            x0, y0, _ = self.point_at(sa - h)
            x1, y1, _ = self.point_at(sa + h)
            psi = math.atan2(x1 - x0, y1 - y0)
            pts.append((x + c * math.cos(psi), y - c * math.sin(psi), z + up))
            psis.append(psi)
        return pts, psis

    def project(self, x: float, y: float, s_prev: float, behind: float = 30.0, ahead: float = 120.0) -> float:
        """Arc length of the nearest route point within a window about the previous one.

        Continuous: no jumps at leg switches, no short-cuts to a distant part of the route.

        Parameters
        ----------
        x, y : float
            Horizontal position (m).
        s_prev : float
            The previous arc length (m).
        behind, ahead : float
            The window ``[s_prev − behind, s_prev + ahead]`` (m).

        Returns
        -------
        float
            Arc length (m).
        """
        lo, hi = max(s_prev - behind, 0.0), min(s_prev + ahead, self.length)
        cum, w = self._cum, self._w
        k = max(bisect.bisect_right(cum, lo) - 1, 0)
        best, s_best = math.inf, min(max(s_prev, lo), hi)
        while k < len(cum) - 1 and cum[k] <= hi:
            ax, ay = w[k][0], w[k][1]
            dx, dy = w[k + 1][0] - ax, w[k + 1][1] - ay
            dd = dx * dx + dy * dy
            f = min(max(((x - ax) * dx + (y - ay) * dy) / dd, 0.0), 1.0) if dd > 0 else 0.0
            d = math.hypot(ax + f * dx - x, ay + f * dy - y)
            if d < best:
                best, s_best = d, cum[k] + f * (cum[k + 1] - cum[k])
            k += 1
        return min(max(s_best, lo), hi)
