"""A waypoint mission fitted to the vehicle: fly-by turns, climbs within the pitch limit, terrain following.

:func:`fit_mission` takes the horizontal track of a mission (the corners of
:func:`auvplan.guidance.mission.waypoints.build_waypoints`, or a fixed route) and gives it a depth schedule
the vehicle can fly:

* **Turns.**  At each corner the vehicle flies a fly-by arc of radius R through the heading
  change Δψ, tangent to both legs ``t = R tan(Δψ/2)`` from the corner (:mod:`auvplan.path.flyable`).
  Distances along the mission are measured along that flown track (the arcs are shorter than the
  corners they cut), and the seabed under each arc joins the floor of the corner's turn region,
  so neither the pitch limit nor ``min_altitude`` is broken at a turn.
* **Pitch.**  The depth profile is :func:`auvplan.path.pitch.pitch_profile` over the flown distance:
  the target where it is flyable; climbs started early (``cone_max`` of the floor) and dives ended
  late, so no leg is steeper than ``max_pitch_deg`` and no vertex is below its floor (the highest
  seabed under its legs + ``min_altitude``), the start and goal kept.
* **Terrain following.**  With ``follow_altitude`` > 0 the target is the seabed under each point
  (in a turn region, the highest seabed under the arc) + that altitude, raised by ``cone_max``
  where the seabed rises faster than the vehicle can climb: the mission holds the altitude
  wherever the pitch limit allows and is higher only there (and where a descent cannot keep up).

The dense profile (points every quarter terrain cell) is then simplified: a chord replaces points
when it stays within ``tolerance`` of the profile and its deeper end clears every floor under it
(the leg's envelope, so that a depth held per leg is safe too; a chord of a profile within the
pitch limit is within it too); points inside a turn region never become waypoints, so
every turn keeps its tangent lengths.  No leg is shorter than 2.5 m (:data:`auvplan.path.legs.FITTED_LEG_M`:
split points closer to a chord's ends are not taken, and near-duplicates left are merged by
:func:`auvplan.guidance.mission.legs.merge_short_legs`), each turn region reaches ``TURN_SLACK`` R past its
tangent points, and the mission keeps its waypoint budget (:func:`auvplan.path.legs.waypoint_budget`: the
tolerance is doubled until it does), so that every leg of every export holds the limits judged on its own
(issue 49).  The exact envelope test (:func:`auvplan.guidance.mission.envelopes.envelopes_free`) then checks the
static obstacles, and :func:`auvplan.path.legs.helm_check` the result leg by leg; where the pitch limit keeps
the schedule off ``follow_altitude ± tolerance`` the :class:`AltitudeBand` says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._types import BoolArray, FloatArray, IntArray
from ...path.flyable import (
    PITCH_SLACK_DEG,
    LimitReport,
    VehicleLimits,
    check_limits,
    leg_turn_radius,
    turn_angles,
)
from ...path.legs import FITTED_LEG_M, helm_check, shortest_leg, waypoint_budget
from ...path.pitch import (
    cone_max,
    pitch_profile,
)
from ...world import World
from .envelopes import envelopes_free
from .legs import merge_short_legs

__all__ = ["MissionFit", "AltitudeBand", "fit_mission", "fit_turns", "flown_distance", "TURN_SLACK"]

TURN_SLACK = 2e-3
"""Each turn region reaches this fraction of R beyond the arc's tangent points (0.4 m for R = 200 m): the
rounding of exported coordinates (about 1 mm, over legs of at least 2.5 m: a heading noise of up to
1.2e-3 rad at a tangent point, i.e. R × 6e-4 of tangent length) cannot then make a fitted turn read
tighter than R leg by leg (:func:`auvplan.path.legs.helm_check`)."""


@dataclass(frozen=True)
class AltitudeBand:
    """How a terrain-following mission holds its commanded altitude (``follow_altitude_m``).

    Attributes
    ----------
    target_m : float
        The commanded altitude (m; 0: not terrain following).
    band_m : float
        The stated band: the scheduled altitude is within ``target ± band`` wherever the pitch limit
        allows (the simplification's tolerance, m).
    held_fraction : float
        Fraction of the mission's length (3D) where the schedule is within the band.
    legs : tuple of int
        Legs where it is not: the pitch limit forces the mission above (a climb started early, a
        descent that cannot keep up with the seabed) or below (joining a start or goal) the band.
    worst_above_m, worst_below_m : float
        Largest excess of the scheduled altitude over ``target + band`` and shortfall under
        ``target - band`` (m, >= 0).
    """

    target_m: float = 0.0
    band_m: float = 0.0
    held_fraction: float = 1.0
    legs: tuple[int, ...] = ()
    worst_above_m: float = 0.0
    worst_below_m: float = 0.0

    @property
    def message(self) -> str:
        """One line: the band and where it is broken (empty when not terrain following)."""
        if self.target_m <= 0.0:
            return ""
        head = (f"altitude {self.target_m:g} ± {self.band_m:g} m held on {100.0 * self.held_fraction:.1f} % of the "
                f"mission")
        if not self.legs:
            return head
        return (f"{head}; the pitch limit breaks the band on {len(self.legs)} legs (first leg {self.legs[0]}): up to "
                f"{self.worst_above_m:.1f} m above and {self.worst_below_m:.1f} m below it")


@dataclass(frozen=True, eq=False)
class MissionFit:
    """A mission fitted to a vehicle's limits.

    Attributes
    ----------
    waypoints : numpy.ndarray
        ``(N, 3)`` the fitted mission (m).
    report : LimitReport
        Its largest pitch, tightest turn and violations by leg.
    ok : bool
        Within every limit, above the floors, clear of the static obstacles.
    message : str
        Why not (empty when ``ok``).
    band : AltitudeBand
        How the schedule holds ``follow_altitude_m`` (reported, not a failure, where the pitch limit
        breaks the band).
    """

    waypoints: FloatArray
    report: LimitReport
    ok: bool
    message: str
    band: AltitudeBand = AltitudeBand()


def _corner_geometry(w: FloatArray, radius: float) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Per vertex: polyline distance, heading change, tangent length (clipped to half of each leg)
    and the flown length of its turn arc."""
    leg = np.hypot(*np.diff(w[:, :2], axis=0).T)
    s = np.r_[0.0, np.cumsum(leg)]
    dpsi = turn_angles(w)
    half = np.tan(np.minimum(dpsi, math.pi - 1e-9) / 2.0)
    room = np.minimum(np.r_[0.0, leg], np.r_[leg, 0.0]) / 2.0
    t = np.minimum(radius * half, room)
    t[[0, -1]] = 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        arc = np.where(half > 1e-12, t / np.where(half > 1e-12, half, 1.0) * dpsi, 0.0)
    # the region reaches TURN_SLACK R past the tangent points (the flown distance is then shortened by at
    # most 2 TURN_SLACK R per turn: the profile is checked on a shorter distance, so conservatively)
    t = np.where(t > 0.0, np.minimum(t + TURN_SLACK * radius, room), t)
    return s, dpsi, t, arc


def flown_distance(s_poly: FloatArray, s_corner: FloatArray, t: FloatArray, arc: FloatArray) -> FloatArray:
    """Map distances along a polyline to distances along its fly-by track.

    Parameters
    ----------
    s_poly : numpy.ndarray
        Distances along the polyline (m).
    s_corner, t, arc : numpy.ndarray
        Per corner: its distance along the polyline, its tangent length and its arc's length (m).

    Returns
    -------
    numpy.ndarray
        Distances along the flown track (m): straight parts unchanged, each ``[s - t, s + t]``
        replaced by the arc.
    """
    xs, ys = [0.0], [0.0]
    for sc, tc, ac in zip(s_corner, t, arc):
        if tc <= 0.0:
            continue
        a = max(sc - tc, xs[-1])
        ys.append(ys[-1] + (a - xs[-1]))
        xs.append(a)
        ys.append(ys[-1] + ac)
        xs.append(max(sc + tc, a))
    end = float(max(float(np.max(s_poly, initial=0.0)), xs[-1])) + 1.0
    ys.append(ys[-1] + (end - xs[-1]))
    xs.append(end)
    out: FloatArray = np.interp(s_poly, np.asarray(xs), np.asarray(ys))
    return out


def _flat_max_seabed(world: World, a: FloatArray, b: FloatArray) -> FloatArray:
    """Highest seabed along each horizontal segment ``a -> b`` (exact; ``-inf`` without terrain)."""
    if world.terrain is None:
        return np.full(len(a), -np.inf)
    fa, fb = a.copy(), b.copy()
    fa[:, 2] = fb[:, 2] = 0.0
    out: FloatArray = -world.terrain.min_altitude_between(fa, fb)
    return out


def _dense(w: FloatArray, spacing: float, s: FloatArray, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Points every ``spacing`` along ``w`` plus each turn region's two ends: (points, polyline
    distance, index of the corner whose turn region holds the point or -1; corners themselves -2)."""
    pts, dist, region = [w[:1]], [np.zeros(1)], [np.array([-2.0])]
    for i in range(len(w) - 1):
        a, b = w[i], w[i + 1]
        length = s[i + 1] - s[i]
        n = max(int(math.ceil(length / spacing)), 1)
        u = list(np.arange(1, n) / n * length)
        u += [v for v in (t[i], length - t[i + 1]) if 0.0 < v < length]
        u = sorted(set(u)) + [length]
        f = np.asarray(u) / max(length, 1e-300)
        p = a + (b - a) * f[:, None]
        d = s[i] + np.asarray(u)
        reg = np.full(len(u), -1.0)
        reg[np.asarray(u) < t[i] - 1e-9] = i
        reg[np.asarray(u) > length - t[i + 1] + 1e-9] = i + 1
        reg[-1] = -2.0
        pts.append(p)
        dist.append(d)
        region.append(reg)
    return np.vstack(pts), np.concatenate(dist), np.concatenate(region)


def _floors(world: World, p: FloatArray, region: FloatArray, arcs: FloatArray, height: float) -> FloatArray:
    """Highest seabed under each point's two legs and, in a turn region, under its arc; + ``height``."""
    leg = _flat_max_seabed(world, p[:-1], p[1:])
    out = np.maximum(np.r_[leg, -np.inf], np.r_[-np.inf, leg])
    for i, zb in enumerate(arcs):
        if np.isfinite(zb):
            out[region == i] = np.maximum(out[region == i], zb)
    res: FloatArray = out + height
    return res


def _arc_seabed(world: World, w: FloatArray, radius: float, t: FloatArray, dpsi: FloatArray) -> FloatArray:
    """Highest seabed under each corner's fly-by arc (32 chords; ``-inf`` where straight)."""
    out = np.full(len(w), -np.inf)
    if world.terrain is None:
        return out
    for i in range(1, len(w) - 1):
        if t[i] <= 0.0 or dpsi[i] < 1e-12:
            continue
        u = (w[i, :2] - w[i - 1, :2]) / np.hypot(*(w[i, :2] - w[i - 1, :2]))
        v = (w[i + 1, :2] - w[i, :2]) / np.hypot(*(w[i + 1, :2] - w[i, :2]))
        r = t[i] / math.tan(dpsi[i] / 2.0)  # R, or less where the legs are too short for R
        entry, exit_ = w[i, :2] - t[i] * u, w[i, :2] + t[i] * v
        side = 1.0 if u[0] * v[1] - u[1] * v[0] > 0 else -1.0
        c = entry + side * r * np.array([-u[1], u[0]])
        a0, a1 = math.atan2(*(entry - c)[::-1]), math.atan2(*(exit_ - c)[::-1])
        da = (a1 - a0 + math.pi) % (2.0 * math.pi) - math.pi
        ang = a0 + da * np.linspace(0.0, 1.0, 33)
        q = np.column_stack([c[0] + r * np.cos(ang), c[1] + r * np.sin(ang), np.zeros(33)])
        out[i] = float(_flat_max_seabed(world, q[:-1], q[1:]).max())
    return out


def _simplify(s: FloatArray, z: FloatArray, floor: FloatArray, allowed: BoolArray, fixed: IntArray,
              tol: float, min_leg: float = 0.0) -> IntArray:
    """Indices kept: ``fixed`` (the corners and ends), and between them a chord replaces points when
    it stays within ``tol`` of ``z`` and its deeper end is above every ``floor`` between them (the
    leg's envelope, so a depth held per leg is safe too); only ``allowed`` points at least ``min_leg``
    along the track from the chord's ends may be kept."""
    keep = np.zeros(len(s), dtype=bool)
    keep[fixed] = True
    idx = np.flatnonzero(keep)
    stack = list(zip(idx[:-1].tolist(), idx[1:].tolist()))
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        span = max(s[j] - s[i], 1e-300)
        chord = z[i] + (z[j] - z[i]) * (s[i + 1:j] - s[i]) / span
        dev = np.abs(chord - z[i + 1:j])
        # held depth (MOOS): the leg flown flat at its deeper end must clear every floor under it
        low = floor[i + 1:j] - min(z[i], z[j])
        if dev.max() <= tol and low.max() <= 1e-9:
            continue
        far = (s[i + 1:j] - s[i] >= min_leg) & (s[j] - s[i + 1:j] >= min_leg)
        cand = np.flatnonzero(allowed[i + 1:j] & far)
        if cand.size == 0:
            continue  # inside a turn region: its ends clear its (constant) floor
        score = np.maximum(dev, 1e3 * np.maximum(low, 0.0))[cand]
        k = i + 1 + int(cand[int(np.argmax(score))])
        keep[k] = True
        stack += [(i, k), (k, j)]
    return np.flatnonzero(keep)


def _plumb_kept(w: FloatArray, reach: float) -> IntArray:
    """Indices of ``w`` kept: the ends, and the interior vertices but those less than ``reach`` horizontally
    from the vertex kept before them or, at the end, from the last (a vertical or near-vertical leg, as a
    floor lifted above a survey line's start makes).  The fitted schedule changes depth along the track within
    the pitch limit, so two vertices at one horizontal place would become one point: a leg shorter than the
    shortest leg, which no merge may remove (both are the mission's corners); ``reach`` is the horizontal
    span whose leg at the profile's steepest is the shortest leg, so a mission that fits keeps every vertex."""
    keep = [0]
    for i in range(1, len(w) - 1):
        if float(np.hypot(*(w[i, :2] - w[keep[-1], :2]))) >= reach:
            keep.append(i)
    while len(keep) > 1 and float(np.hypot(*(w[keep[-1], :2] - w[-1, :2]))) < reach:
        keep.pop()
    out: IntArray = np.asarray([*keep, len(w) - 1], dtype=np.intp)
    return out


def fit_mission(waypoints: FloatArray, world: World, limits: VehicleLimits, follow_altitude: float = 0.0,
                tolerance: float = 1.0, slack: float = 0.05) -> MissionFit:
    """Fit a mission's depth schedule to a vehicle's pitch limit and turns, optionally following the terrain.

    Parameters
    ----------
    waypoints : numpy.ndarray
        ``(N, 3)`` mission (m); its corners fix the horizontal track and its first and last points
        the start and goal.
    world : World
        Seabed, static obstacles and margins (``min_altitude``, depth band).
    limits : VehicleLimits
        ``max_pitch_deg``, ``turn_radius_m`` and ``max_depth_m``.
    follow_altitude : float, optional
        Altitude above the seabed to hold (m); 0 keeps the mission's own depths where flyable.
    tolerance : float, optional
        Largest vertical deviation of the simplified mission from the dense profile (m).
    slack : float, optional
        Altitude kept above ``min_altitude`` (m), against the rounding of exported coordinates.

    Returns
    -------
    MissionFit
        The fitted waypoints and their check.
    """
    w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
    if len(w) < 2:
        return MissionFit(w.copy(), check_limits(w, limits), True, "")
    slope = math.tan(math.radians(max(limits.max_pitch_deg - PITCH_SLACK_DEG, 0.5 * limits.max_pitch_deg)))
    min_leg = max(shortest_leg(limits), FITTED_LEG_M if limits.max_pitch_deg < 90.0 else 0.0)
    w = w[_plumb_kept(w, min_leg / math.hypot(1.0, slope))]
    radius = limits.turn_radius_m
    s, dpsi, t, arc = _corner_geometry(w, radius)
    # a conservative seabed is lifted cell by cell: its peaks lie anywhere in a cell, so sample finely
    spacing = min(world.terrain.dx, world.terrain.dy) / 16.0 if world.terrain is not None else max(s[-1], 1.0)
    p, d, region = _dense(w, spacing, s, t)
    sf = flown_distance(d, s, t, arc)
    arcs = _arc_seabed(world, w, radius, t, dpsi)
    m = world.margins
    floor = _floors(world, p, region, arcs, m.min_altitude + slack)
    floor[[0, -1]] = -np.inf
    seabed, target = _target(world, p, region, arcs, sf, floor, slope, follow_altitude)
    z, ok = pitch_profile(sf, target, floor, slope, float(w[0, 2]), float(w[-1, 2]), ceiling=-m.min_depth,
                          deepest=-min(m.max_depth, limits.max_depth_m))
    z[[0, -1]] = w[[0, -1], 2]
    keep, out, tolerance = _within_budget(world, p, sf, z, floor, region, limits, tolerance, min_leg)
    band = _band(keep, sf, z, seabed + follow_altitude, follow_altitude, tolerance) if follow_altitude > 0.0 \
        else AltitudeBand()
    report = helm_check(out, limits)
    why = _why_not(world, out, limits, ok, report)
    return MissionFit(out, report, not why, "; ".join(why), band)


def _target(world: World, p: FloatArray, region: FloatArray, arcs: FloatArray, sf: FloatArray, floor: FloatArray,
            slope: float, follow_altitude: float) -> tuple[FloatArray, FloatArray]:
    """The seabed under the dense points and the depths to hold there: ``follow_altitude`` above the seabed, or the
    mission's own depths (``follow_altitude`` 0, the seabed then zeros)."""
    if follow_altitude > 0.0:
        # hold at least the altitude: climbs the vehicle cannot follow start early (cone_max)
        # (the seabed under the point, or the highest under its turn's arc: not the conservative floor)
        seabed = world.terrain.elevation(p[:, 0], p[:, 1]) if world.terrain is not None else np.full(len(p), -np.inf)
        for i, zb in enumerate(arcs):
            if np.isfinite(zb):
                seabed[region == i] = np.maximum(seabed[region == i], zb)
        target = cone_max(sf, np.maximum(seabed + follow_altitude, floor), slope)
    else:
        seabed = np.zeros(len(p))
        target = p[:, 2]
    return seabed, target


def _within_budget(world: World, p: FloatArray, sf: FloatArray, z: FloatArray, floor: FloatArray, region: FloatArray,
                   limits: VehicleLimits, tolerance: float, min_leg: float) -> tuple[IntArray, FloatArray, float]:
    """The dense profile simplified (short legs merged) within the waypoint budget: a coarser tolerance (a wider
    band) until the mission fits it, up to 64 m; the points kept, the waypoints and the tolerance."""
    corners = np.flatnonzero(region == -2)  # the mission's own vertices (its ends and corners)
    while True:
        keep = _simplify(sf, z, floor, region < 0, corners, tolerance, min_leg)
        fixed = np.flatnonzero(np.isin(keep, corners))
        keep = keep[merge_short_legs(world, np.column_stack([p[keep, :2], z[keep]]), min_leg, fixed,
                                     limits.max_pitch_deg)]
        out = np.column_stack([p[keep, :2], z[keep]])
        if len(out) <= waypoint_budget(out) or tolerance >= 64.0:
            return keep, out, tolerance
        tolerance *= 2.0


def _why_not(world: World, out: FloatArray, limits: VehicleLimits, ok: bool, report: LimitReport) -> list[str]:
    """Why the fitted mission is not flyable: no depth profile, the helm's limits, or a leg's envelope not free."""
    m = world.margins
    why = []
    if not ok:
        why.append(f"no depth profile within max_pitch_deg = {limits.max_pitch_deg:g} joins the start and the goal "
                   f"above min_altitude {m.min_altitude:g} m and below min_depth {m.min_depth:g} m")
    if not report.ok:
        why.append(report.message)
    free = envelopes_free(world, out[:-1], out[1:])
    if not free.all():
        why.append(f"leg {int(np.flatnonzero(~free)[0])}: its envelope (depth held at either end) breaks "
                   "min_altitude, the depth band, the bounds or an obstacle's margin")
    return why


def _band(keep: IntArray, sf: FloatArray, z: FloatArray, target: FloatArray, altitude: float,
          band: float) -> AltitudeBand:
    """Where the schedule (the profile ``z`` at the dense points, distance ``sf``) leaves ``target ± band``,
    by leg of the mission (its vertices the dense points ``keep``)."""
    dev = z - target
    above, below = np.maximum(dev - band - 1e-6, 0.0), np.maximum(-dev - band - 1e-6, 0.0)
    off = (above > 0.0) | (below > 0.0)
    ds = np.r_[0.0, np.diff(sf)]
    total = float(sf[-1] - sf[0]) or 1.0
    held = 1.0 - float(ds[off].sum()) / total
    legs = np.clip(np.searchsorted(keep, np.arange(len(z)), side="right") - 1, 0, max(len(keep) - 2, 0))
    bad = tuple(int(k) for k in np.unique(legs[off]))
    return AltitudeBand(altitude, band, held, bad, float(above.max(initial=0.0)), float(below.max(initial=0.0)))


def fit_turns(waypoints: FloatArray, world: World, radius: float, rounds: int = 200) -> FloatArray:
    """Drop the corners whose fly-by turns do not fit, where the leg that replaces them is free.

    For a planned mission (not a route the operator wrote): while some leg's turns need more than
    its length (:func:`auvplan.path.flyable.leg_turn_radius` below ``radius``), the sharper interior
    corner at its ends is removed when the new leg's envelope is free
    (:func:`auvplan.guidance.mission.envelopes.envelopes_free`); a corner that cannot go stays, and the check
    of :func:`fit_mission` then names it.

    Parameters
    ----------
    waypoints : numpy.ndarray
        ``(N, 3)`` mission (m).
    world : World
        Seabed, static obstacles and margins.
    radius : float
        Turn radius R (m).
    rounds : int, optional
        Most corners removed.

    Returns
    -------
    numpy.ndarray
        The mission with its unflyable corners removed where possible.
    """
    w = np.asarray(waypoints, dtype=float).reshape(-1, 3).copy()
    if radius <= 0.0:
        return w
    stuck: set[tuple[float, float]] = set()
    for _ in range(rounds):
        if len(w) < 3:
            break
        bad = np.flatnonzero(leg_turn_radius(w) < radius)
        dpsi = turn_angles(w)
        done = True
        for k in bad:
            cands = [i for i in (int(k), int(k) + 1) if 0 < i < len(w) - 1 and tuple(w[i, :2]) not in stuck]
            for i in sorted(cands, key=lambda i: -dpsi[i]):
                a, b = w[i - 1], w[i + 1]
                if envelopes_free(world, a[None], b[None])[0]:
                    w = np.delete(w, i, axis=0)
                    done = False
                    break
                stuck.add(tuple(w[i, :2]))
            if not done:
                break
        if done:
            break
    return w
