"""What a vehicle can fly: pitch, fly-by turns and depth rating of a polyline (plan or mission).

A vehicle following waypoints turns *fly-by*: it leaves leg k before the waypoint on an arc of
radius R tangent to both legs.  Through a heading change Δψ the arc's tangent points lie
``t = R tan(Δψ/2)`` before and after the waypoint, so the turns at both ends of a leg fit when

    R (tan(Δψ_k / 2) + tan(Δψ_{k+1} / 2)) <= L_k          (L_k: the leg's horizontal length)

which is also the curvature limit κ <= 1/R of a densely sampled curve (Δψ ≈ L κ).  A sampled
curve is judged on its track simplified to ``TRACK_FRACTION`` · R horizontally
(:func:`corner_indices`), so that micro-legs of a spline's samples are not taken for turns.  The largest
radius that fits a leg is ``L_k / (tan(Δψ_k/2) + tan(Δψ_{k+1}/2))``; the tightest turn of a
polyline is the least of those.  A leg's pitch is ``atan(|Δz| / L_k)``; the depth rating bounds
every vertex's depth.  :func:`check_limits` reports the largest pitch, the tightest turn and every
violation by leg; :func:`flyby_arcs` returns the turn geometry (tangent points, centres) for
re-flying a mission with its fitted turns.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from .pitch import cone_max, cone_min, pitch_profile

__all__ = ["VehicleLimits", "LimitViolation", "LimitReport", "leg_pitch_deg", "turn_angles", "leg_turn_radius",
           "check_limits", "flyby_arcs", "merge_close", "corner_indices", "MIN_LEG_M", "MERGE_FRACTION",
           "PITCH_SLACK_DEG", "STRAIGHT_M", "TRACK_FRACTION", "cone_max", "cone_min", "pitch_profile"]

_F64 = NDArray[np.float64]
"""Array of float64 (units as documented per parameter)."""

PITCH_SLACK_DEG = 0.05
"""Pitch kept below the limit by the mission builder and the planners' repair, so that the rounding
of exported coordinates (1 mm) cannot take a leg of 2.5 m or more over the limit."""
STRAIGHT_M = 4.0e7
"""A fly-by radius wider than the Earth's circumference (m) is printed as a straight leg: its turn is the rounding
of the file's coordinates (:attr:`LimitReport.summary`)."""
MIN_LEG_M = 1e-6
"""Legs shorter than this horizontally have no heading (a vertical leg: its pitch is 90°)."""
TRACK_FRACTION = 0.1
"""Horizontal tolerance, as a fraction of the turn radius, at which a sampled track's corners are
judged (:func:`corner_indices`): 1 m for a 10 m turn radius."""
MERGE_FRACTION = 0.01
"""Vertices closer than this fraction of the turn radius to the previous one are merged before the
check (:func:`merge_close`): a 1 % kink cannot hide a turn the vehicle cannot make."""


@dataclass(frozen=True)
class VehicleLimits:
    """The limits a plan or mission must respect.

    Attributes
    ----------
    max_pitch_deg : float
        Largest pitch of a leg (degrees, in (0, 90)).
    turn_radius_m : float
        Least fly-by turn radius (m, >= 0; 0 switches the turn check off).
    max_depth_m : float
        Depth rating (m below the surface, positive).
    """

    max_pitch_deg: float = 90.0
    turn_radius_m: float = 0.0
    max_depth_m: float = math.inf

    def __post_init__(self) -> None:
        if not 0.0 < self.max_pitch_deg <= 90.0:
            raise ValueError(f"max_pitch_deg = {self.max_pitch_deg}: must lie in (0, 90]")
        if self.turn_radius_m < 0:
            raise ValueError(f"turn_radius_m = {self.turn_radius_m}: must be >= 0")
        if not self.max_depth_m > 0:
            raise ValueError(f"max_depth_m = {self.max_depth_m}: must be positive")


@dataclass(frozen=True)
class LimitViolation:
    """One leg that breaks one limit.

    Attributes
    ----------
    leg : int
        Leg index (leg k joins points k and k + 1).
    limit : str
        ``"max_pitch_deg"``, ``"turn_radius_m"``, ``"max_depth_m"`` or ``"min_leg_m"``
        (:func:`auvplan.path.legs.helm_check`).
    value : float
        The leg's figure: its pitch (degrees), the largest radius its turns fit (m), its
        greatest depth (m) or its length (m).
    allowed : float
        The limit.
    """

    leg: int
    limit: str
    value: float
    allowed: float

    @property
    def text(self) -> str:
        """One line naming the leg and the limit.

        Returns
        -------
        str
            E.g. ``leg 3: pitch 31.2° > max_pitch_deg = 20``.
        """
        if self.limit == "max_pitch_deg":
            return f"leg {self.leg}: pitch {self.value:.1f}° > max_pitch_deg = {self.allowed:g}"
        if self.limit == "turn_radius_m":
            return (f"leg {self.leg}: its turns fit a radius of {self.value:.1f} m only < turn_radius_m = "
                    f"{self.allowed:g}")
        if self.limit == "min_leg_m":
            return f"leg {self.leg}: {self.value:.3f} m long < the shortest leg {self.allowed:g} m"
        return f"leg {self.leg}: depth {self.value:.1f} m > max_depth_m = {self.allowed:g}"


def _leg(leg: int) -> int | None:
    """A leg number as JSON has it: None (``null``) for the -1 that says there is none."""
    return leg if leg >= 0 else None


@dataclass(frozen=True, eq=False)
class LimitReport:
    """A polyline checked against :class:`VehicleLimits`.

    Attributes
    ----------
    max_pitch_deg : float
        Largest |pitch| of a leg (degrees; 0 without legs).
    max_pitch_leg : int
        Where (-1 without legs).
    tightest_turn_m : float
        Least over legs of the largest radius their turns fit (m; ``inf`` for a straight line).
    tightest_turn_leg : int
        Where (-1 when straight).
    max_depth_m : float
        Greatest depth of a vertex (m).
    violations : tuple of LimitViolation
        Every leg that breaks a limit, in leg order (pitch, turn, depth).
    limits : VehicleLimits
        The limits checked.
    """

    max_pitch_deg: float
    max_pitch_leg: int
    tightest_turn_m: float
    tightest_turn_leg: int
    max_depth_m: float
    violations: tuple[LimitViolation, ...]
    limits: VehicleLimits

    @property
    def ok(self) -> bool:
        """Whether no leg breaks a limit.

        Returns
        -------
        bool
            True without violations.
        """
        return not self.violations

    def as_dict(self) -> dict[str, object]:
        """Summarise the report as plain JSON (lengths in m, angles in degrees).

        Returns
        -------
        dict
            ``ok``, ``max_pitch_deg``, ``max_pitch_leg``, ``tightest_turn_m``, ``tightest_turn_leg``,
            ``deepest_m``, the ``limits`` and the ``violations`` (leg, limit, value, allowed, text); a leg that
            is not there (no legs, a straight line) is None.
        """
        lim = self.limits
        return {"ok": self.ok, "max_pitch_deg": self.max_pitch_deg, "max_pitch_leg": _leg(self.max_pitch_leg),
                "tightest_turn_m": self.tightest_turn_m, "tightest_turn_leg": _leg(self.tightest_turn_leg),
                "deepest_m": self.max_depth_m,
                "limits": {"max_pitch_deg": lim.max_pitch_deg, "turn_radius_m": lim.turn_radius_m,
                           "max_depth_m": lim.max_depth_m},
                "violations": [{"leg": v.leg, "limit": v.limit, "value": v.value, "allowed": v.allowed,
                                "text": v.text} for v in self.violations]}

    @property
    def summary(self) -> str:
        """One line: largest pitch, tightest turn and greatest depth against the limits.

        Returns
        -------
        str
            E.g. ``largest pitch 12.3° (leg 4; max_pitch_deg 20), tightest turn 41.0 m (leg 7; ...``.
        """
        lim = self.limits
        # a radius wider than the Earth is a straight leg whose ends were rounded (lat/lon in a file)
        turn = (f"{self.tightest_turn_m:.1f} m (leg {self.tightest_turn_leg})" if self.tightest_turn_m <= STRAIGHT_M
                else "none (straight)")
        return (f"largest pitch {self.max_pitch_deg:.1f}° (leg {self.max_pitch_leg}; max_pitch_deg "
                f"{lim.max_pitch_deg:g}), tightest turn {turn} (turn_radius_m {lim.turn_radius_m:g}), deepest "
                f"{self.max_depth_m:.1f} m (max_depth_m {lim.max_depth_m:g})")

    @property
    def message(self) -> str:
        """The first violations as one line (empty when none).

        Returns
        -------
        str
            Up to three violations and how many more.
        """
        if not self.violations:
            return ""
        head = "; ".join(v.text for v in self.violations[:3])
        more = len(self.violations) - 3
        return head + (f" (and {more} more)" if more > 0 else "")


def _points(points: ArrayLike) -> _F64:
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    return p


def leg_pitch_deg(points: ArrayLike) -> _F64:
    """Return the pitch of each leg, ``atan2(Δz, horizontal length)`` (degrees, nose-up positive).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` polyline (m, z up).

    Returns
    -------
    numpy.ndarray
        ``(N - 1,)`` pitch of each leg (degrees, in [-90, 90]).
    """
    d = np.diff(_points(points), axis=0)
    return np.degrees(np.arctan2(d[:, 2], np.hypot(d[:, 0], d[:, 1])))


def turn_angles(points: ArrayLike) -> _F64:
    """Return the horizontal heading change at each vertex (radians, in [0, π]).

    Vertical legs (shorter than :data:`MIN_LEG_M` horizontally) carry the heading across; the
    ends turn by 0.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` polyline (m).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` heading change Δψ at each vertex.
    """
    p = _points(points)
    d = np.diff(p[:, :2], axis=0)
    length = np.hypot(d[:, 0], d[:, 1])
    out = np.zeros(len(p))
    prev = -1
    for k in np.flatnonzero(length > MIN_LEG_M):
        if prev >= 0:
            a, b = d[prev] / length[prev], d[k] / length[k]
            out[k] = math.atan2(abs(a[0] * b[1] - a[1] * b[0]), float(a @ b))  # at the vertex where leg k starts
        prev = int(k)
    return out


def leg_turn_radius(points: ArrayLike) -> _F64:
    """Return the largest fly-by radius the turns at both ends of each leg fit.

    ``L_k / (tan(Δψ_k/2) + tan(Δψ_{k+1}/2))``, ``inf`` for a leg between two straight vertices
    and 0 for a vertical leg between turns or a reversal.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` polyline (m).

    Returns
    -------
    numpy.ndarray
        ``(N - 1,)`` radius (m).
    """
    p = _points(points)
    length = np.hypot(*np.diff(p[:, :2], axis=0).T)
    half = np.tan(np.minimum(turn_angles(p), math.pi - 1e-12) / 2.0)
    need = half[:-1] + half[1:]
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(need > 1e-15, length / np.where(need > 1e-15, need, 1.0), np.inf)
    return r


def check_limits(points: ArrayLike, limits: VehicleLimits) -> LimitReport:
    """Check a polyline against a vehicle's pitch, turn radius and depth rating.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` plan or mission (m, z up).
    limits : VehicleLimits
        The vehicle's limits.

    Returns
    -------
    LimitReport
        Largest pitch, tightest turn, greatest depth and each violation by leg.
    """
    full = _points(points)
    if len(full) < 2:
        return LimitReport(0.0, -1, math.inf, -1, float(-full[:, 2].min()) if len(full) else 0.0, (), limits)
    idx = merge_close(full, max(MERGE_FRACTION * limits.turn_radius_m, MIN_LEG_M))
    p = full[idx]
    pitch = np.abs(leg_pitch_deg(p))
    depth = -np.minimum(p[:-1, 2], p[1:, 2])
    turns = corner_indices(full, TRACK_FRACTION * limits.turn_radius_m)
    radius = leg_turn_radius(full[turns])
    bad: list[LimitViolation] = []
    tol = 1e-9
    for k in range(len(p) - 1):
        leg = int(idx[k])  # numbered on the polyline given
        if pitch[k] > limits.max_pitch_deg + tol:
            bad.append(LimitViolation(leg, "max_pitch_deg", float(pitch[k]), limits.max_pitch_deg))
        if depth[k] > limits.max_depth_m + tol:
            bad.append(LimitViolation(leg, "max_depth_m", float(depth[k]), limits.max_depth_m))
    bad += [LimitViolation(int(turns[k]), "turn_radius_m", float(radius[k]), limits.turn_radius_m)
            for k in np.flatnonzero(radius < limits.turn_radius_m * (1.0 - tol))]
    bad.sort(key=lambda v: v.leg)
    kp, kr = int(np.argmax(pitch)), int(np.argmin(radius))
    return LimitReport(float(pitch[kp]), int(idx[kp]), float(radius[kr]), int(turns[kr]) if np.isfinite(radius[kr])
                       else -1, float(depth.max()), tuple(bad), limits)


def corner_indices(points: ArrayLike, tolerance: float) -> NDArray[np.intp]:
    """The corners of a polyline's horizontal track at a scale: Douglas–Peucker to ``tolerance`` (shapely).

    A densely sampled curve is a turn, not a sequence of micro-legs: its fly-by fit is judged on
    the track simplified to within ``tolerance`` horizontally (the vehicle then flies within
    ``tolerance`` plus the fillet's offset of the given track).  Waypoint missions, whose legs are
    long against ``tolerance``, keep every corner.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` polyline (m).
    tolerance : float
        Horizontal tolerance (m); 0 keeps every vertex.

    Returns
    -------
    numpy.ndarray
        Indices of the vertices kept, from 0 to N - 1.
    """
    p = _points(points)
    if tolerance <= 0.0 or len(p) < 3:
        return np.arange(len(p), dtype=np.intp)
    line = shapely.LineString(np.column_stack([p[:, :2], np.arange(len(p), dtype=float)]))
    kept = np.asarray(line.simplify(tolerance, preserve_topology=False).coords)[:, 2]
    return np.unique(np.r_[0, np.rint(kept).astype(np.intp), len(p) - 1])


def merge_close(points: ArrayLike, tol: float) -> NDArray[np.intp]:
    """Indices of a polyline's vertices with those closer than ``tol`` (3D) to the last kept one dropped.

    Sampled curves repeat points to within micrometres (a spline's clamped ends, a lattice path's
    refinement); a heading change over such a leg is noise, not a turn.  The ends are kept.

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` polyline (m).
    tol : float
        Distance below which a vertex joins the previous kept one (m).

    Returns
    -------
    numpy.ndarray
        Indices kept, increasing, starting at 0 and ending at N - 1.
    """
    p = _points(points)
    keep = [0]
    rows = p.tolist()  # a loop over Python floats: ~10x faster than over numpy rows, same sums
    kx, ky, kz = rows[0]
    for i in range(1, len(rows)):
        x, y, z = rows[i]
        if math.sqrt((x - kx) * (x - kx) + (y - ky) * (y - ky) + (z - kz) * (z - kz)) >= tol:
            keep.append(i)
            kx, ky, kz = x, y, z
    if keep[-1] != len(p) - 1:
        if len(keep) > 1:
            keep[-1] = len(p) - 1
        else:
            keep.append(len(p) - 1)
    return np.asarray(keep, dtype=np.intp)


def flyby_arcs(points: ArrayLike, radius: float) -> tuple[_F64, _F64, _F64]:
    """Return the fly-by turn of radius ``radius`` at each interior vertex (horizontal geometry).

    Parameters
    ----------
    points : array_like
        ``(N, 3)`` polyline (m); only x and y are used.
    radius : float
        Turn radius R (m).

    Returns
    -------
    entry, exit, centre : numpy.ndarray
        ``(N, 2)`` each: the tangent points ``R tan(Δψ/2)`` before and after each vertex on its
        two legs and the arc's centre (the vertex itself at the ends and where the path is
        straight).
    """
    p = _points(points)[:, :2]
    n = len(p)
    entry, exit_, centre = p.copy(), p.copy(), p.copy()
    dpsi = turn_angles(np.column_stack([p, np.zeros(n)]))
    for i in range(1, n - 1):
        if dpsi[i] < 1e-12:
            continue
        u = p[i] - p[i - 1]
        v = p[i + 1] - p[i]
        u, v = u / np.linalg.norm(u), v / np.linalg.norm(v)
        t = radius * math.tan(dpsi[i] / 2.0)
        entry[i], exit_[i] = p[i] - t * u, p[i] + t * v
        side = 1.0 if u[0] * v[1] - u[1] * v[0] > 0 else -1.0  # left turn: centre to the left of u
        centre[i] = entry[i] + side * radius * np.array([-u[1], u[0]])
    return entry, exit_, centre
