"""Position fixes planned along a route with the fewest fixes, and the best fixed period to compare.

A GPS fix is a surfacing: from the route the vehicle climbs at its pitch limit to the surface at a
point ``s_f`` of the route's horizontal track, waits ``surface_s`` and dives back at the pitch limit
until it meets the route's depth schedule again.  The new schedule is the upper envelope
``z(s) = max(z_route(s), −tanθ |s − s_f|)`` over the same horizontal track, so the fix never brings the
vehicle nearer the seabed.  A USBL fix (``[navigation] usbl``) is taken where the vehicle is.

Planning (``fixes = "plan"``): candidate fix points every ``spacing`` metres along the track; the
error resets at a fix, so whether the stretch between two consecutive fixes ``i → j`` keeps the error
within E and the uncertain clearance (:mod:`auvplan.nav.clearance`) depends on ``i`` and ``j`` only.
The plan is then a shortest path in the DAG of feasible stretches, with the lexicographic cost
(number of fixes, time): dynamic programming over the candidates in route order gives the fewest
fixes over the candidate set exactly, and among those the least time (climb, dive and
``surface_s``).  Lifting the schedule only raises the altitude, so a fix never gives bottom lock
where the route had none: the error of a stretch is at least that of the route without its end's
climb, which bounds the scan (``docs/navigation.md`` gives the argument).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from .._types import FloatArray, IntArray
from ..world import World
from .budget import DEFAULT_STEP_M, drift_increments, fix_sigma, lock_fraction
from .clearance import hazard_safe_radius
from .params import NavParams
from .surfacing import CLIMB_SLACK_DEG, apply_fixes, clear_of_ends, surfacing_ok, surfacing_slack, surfacing_zone_slack

__all__ = ["RouteProfile", "route_profile", "FixPlan", "plan_fixes", "periodic_fixes", "best_period",
           "apply_fixes", "PITCH_SHARE"]

PITCH_SHARE = 0.999
"""Share of the pitch limit the fix's climb and dive use (the limit itself, kept inside its check's rounding), at
most the limit less :data:`~auvplan.nav.surfacing.CLIMB_SLACK_DEG` (the rounding of the exported coordinates)."""


@dataclass(frozen=True, eq=False)
class RouteProfile:
    """A route sampled along its horizontal track, with what a fix plan needs at each sample.

    Attributes
    ----------
    s : numpy.ndarray
        ``(M,)`` horizontal distance along the track (m).
    xyz : numpy.ndarray
        ``(M, 3)`` the samples (m).
    zb : numpy.ndarray
        ``(M,)`` seabed under them (m; ``-inf`` without terrain).
    r_safe : numpy.ndarray
        ``(M - 1,)`` the largest horizontal uncertainty each interval allows near the seabed, the charted zones and
        the static obstacles (:func:`~.clearance.hazard_safe_radius`).
    t : numpy.ndarray
        ``(M,)`` flying time along the route at the cruise speed (s): through the World's current when the route's
        flight is given (:func:`route_profile`), else in still water.
    wr : numpy.ndarray
        ``(M - 1,)`` each interval's horizontal distance through the water over its ground length (its route
        leg's; 1 in still water): the drift without bottom lock grows with the water distance.
    tan_pitch : float
        Slope of a fix's climb and dive.
    world : World or None
        The World whose exact segment test a surfacing's climb and dive must pass
        (:func:`~auvplan.nav.surfacing.surfacing_slack`).
    d0 : float
        The drift ``D`` at the start: the launch's dive from the surface (:func:`~auvplan.nav.budget.launch_drift`;
        0 when not counted).
    reach : float
        The largest error any stretch may have (the budget E, m): how far the surfacings' zone slack is searched.
    dive_error : float
        A bound of the error along a surfacing's dive (m): confidence × σ after a GPS fix and a dive's longest
        horizontal run without lock at the route's largest water ratio.
    leg : numpy.ndarray or None
        ``(M - 1,)`` the route leg of each interval (nondecreasing): ``mission check`` tests each piece of a mission
        leg (at most ``step`` long) under its own largest error, on arrival at its end, and the mission's legs lie
        within the route's but their pieces need not match the intervals (a surfacing cuts a leg), so an interval must
        allow the error one ``step`` past its end, within its leg and the stretch (:func:`_clear`); None: each
        interval at its own error.
    step : float
        The longest piece of ``mission check``'s test (m; :data:`~auvplan.nav.budget.DEFAULT_STEP_M`).
    _surfacing : dict
        :func:`~auvplan.nav.surfacing.surfacing_slack`'s answers by sample (a memo; not set by callers).
    _zone_slack : dict
        :func:`~auvplan.nav.surfacing.surfacing_zone_slack`'s answers by sample (a memo; not set by callers).
    """

    s: FloatArray
    xyz: FloatArray
    zb: FloatArray
    r_safe: FloatArray
    t: FloatArray
    wr: FloatArray
    tan_pitch: float
    world: World | None = None
    d0: float = 0.0
    reach: float = math.inf
    dive_error: float = 0.0
    leg: IntArray | None = None
    step: float = DEFAULT_STEP_M
    _surfacing: dict[int, float] = field(default_factory=dict, repr=False)
    _zone_slack: dict[int, float] = field(default_factory=dict, repr=False)


def route_profile(world: World, route: ArrayLike, nav: NavParams, max_pitch_deg: float, speed: float,
                  step: float = DEFAULT_STEP_M, water_ratio: ArrayLike | None = None,
                  launch_m: float = 0.0, flight: tuple[ArrayLike, ArrayLike] | None = None) -> RouteProfile:
    """Sample a route for fix planning (:class:`RouteProfile`).

    Parameters
    ----------
    world : World
        Seabed, margins.
    route : array_like
        ``(N, 3)`` waypoints (m).
    nav : NavParams
        The budget E (the search radius of the safe radii).
    max_pitch_deg : float
        The vehicle's pitch limit (degrees).
    speed : float
        Cruise speed (m/s).
    step : float, optional
        Sampling (m).
    water_ratio : array_like, optional
        ``(N - 1,)`` each leg's horizontal distance through the water over its horizontal length; default 1.
    launch_m : float, optional
        The drift ``D`` the launch's dive adds by the start (:func:`~auvplan.nav.budget.launch_drift`, m).
    flight : tuple of array_like, optional
        ``(node_s, node_t)``: distance along the route (3D, m) and time (s) of the route flown through the current at
        the cruise speed (:class:`auvplan.endurance.Traverse`); the samples' times are interpolated in it (the
        periodic fixes' timer).  Default: still water, ``s / speed``.

    Returns
    -------
    RouteProfile
        The samples.
    """
    p = np.asarray(route, dtype=float).reshape(-1, 3)
    keep = np.r_[True, np.any(np.abs(np.diff(p, axis=0)) > 1e-9, axis=1)]  # a repeated waypoint is one
    ratio = np.ones(p.shape[0] - 1) if water_ratio is None else np.asarray(water_ratio, dtype=float).reshape(-1)
    if ratio.shape != (p.shape[0] - 1,) or not np.all(np.isfinite(ratio)):
        raise ValueError(f"{ratio.size} water ratios for {p.shape[0] - 1} legs (finite, one per leg)")
    p, ratio = p[keep], ratio[keep[1:]]
    h = np.hypot(*np.diff(p[:, :2], axis=0).T)  # a vertical leg (h = 0) stays: one interval, no drift
    n = np.maximum(np.ceil(h / step), 1).astype(np.intp)
    leg = np.repeat(np.arange(n.size), n)
    k = np.arange(leg.size) - np.repeat(np.cumsum(n) - n, n)
    xyz = np.vstack([p[leg] + (k / n[leg])[:, None] * (p[leg + 1] - p[leg]), p[-1:]])
    s = np.r_[0.0, np.cumsum((h / n)[leg])]
    zb = world.seabed(xyz[:, 0], xyz[:, 1])
    r_safe = hazard_safe_radius(world, xyz[:-1], xyz[1:], nav.max_error_m)  # seabed, zones, obstacles
    s3 = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(xyz, axis=0), axis=1))]
    t = s3 / speed if flight is None else np.interp(s3, np.asarray(flight[0], dtype=float),
                                                    np.asarray(flight[1], dtype=float))
    tan = math.tan(math.radians(min(PITCH_SHARE * max_pitch_deg, max_pitch_deg - CLIMB_SLACK_DEG)))
    run = float(-xyz[:, 2].min()) / tan * float(max(ratio.max(initial=1.0), 1.0))  # a dive's longest water run
    dive = nav.confidence * math.hypot(nav.fix_error_m, run * max(nav.rate(False), nav.rate(True)))
    return RouteProfile(s, xyz, zb, r_safe, t, ratio[leg], tan, world, float(launch_m), float(nav.max_error_m), dive,
                        leg.astype(np.intp), float(step))


@dataclass(frozen=True)
class _Node:
    """A fix candidate: sample index, kind (``start``, ``goal``, ``gps``, ``usbl``), σ after it (m), cost (s), and
    the drift ``D`` it leaves with (m: the launch's at the start, 0 after a fix)."""

    k: int
    kind: str
    sigma: float
    cost: float
    d: float = 0.0


def _lifted(prof: RouteProfile, k0: int, k1: int, ends: tuple[_Node, _Node]) -> FloatArray:
    """The depth schedule between samples ``k0..k1`` with the surfacings of the two end nodes."""
    z = prof.xyz[k0:k1 + 1, 2].copy()
    s = prof.s[k0:k1 + 1]
    for node in ends:
        if node.kind == "gps":
            z = np.maximum(z, -prof.tan_pitch * np.abs(s - prof.s[node.k]))
    return z


def _surfacings_allow(prof: RouteProfile, a: _Node, b: _Node) -> float:
    """The largest error the surfacings at the ends of a stretch allow near static obstacles and, for the climb to
    its end, near the charted zones (m): its error is largest at its end, so a stretch whose largest error is within
    this keeps them clear."""
    climb = surfacing_zone_slack(prof, b.k) if b.kind == "gps" else math.inf
    return min([climb, *(surfacing_slack(prof, n.k) for n in (a, b) if n.kind == "gps")])


def _clear(prof: RouteProfile, k0: int, err: FloatArray) -> bool:
    """Whether the intervals ``k0, k0 + 1, …`` of a stretch, whose errors on arrival are ``err`` (nondecreasing), keep
    the uncertain clearance as ``mission check`` tests it, piece by piece under each piece's error on arrival at its
    end: a piece of the mission that meets an interval ends at most ``step`` past the interval's end, within its route
    leg (the mission's legs lie within the route's), so each interval is judged at the error one ``step`` past its
    end (the first sample there, capped at its leg's end and the stretch's) within its safe radius."""
    if err.size == 0:
        return True
    if prof.leg is not None:
        n = err.size
        ends = prof.s[k0 + 1:k0 + n + 1]
        ahead = np.searchsorted(ends, ends + prof.step - 1e-9, side="left")  # the first sample a step past the end
        leg = prof.leg[k0:k0 + n]
        err = err[np.minimum(np.minimum(ahead, n - 1), np.searchsorted(leg, leg, side="right") - 1)]
    return bool(np.all(err <= prof.r_safe[k0:k0 + n]))


def _stretch(prof: RouteProfile, nav: NavParams, a: _Node, b: _Node) -> tuple[bool, float]:
    """Whether the stretch between fixes ``a`` and ``b`` keeps the error within E and the uncertain clearance,
    and its largest error (confidence × σ, m)."""
    z = _lifted(prof, a.k, b.k, (a, b))
    alt = z - prof.zb[a.k:b.k + 1]
    ds = np.diff(prof.s[a.k:b.k + 1])
    inc = drift_increments(ds, lock_fraction(alt, nav.dvl_range_m), nav, ds * prof.wr[a.k:b.k])
    err = nav.confidence * np.hypot(a.sigma, a.d + np.cumsum(inc))
    worst = float(err[-1]) if err.size else nav.confidence * float(np.hypot(a.sigma, a.d))
    ok = worst <= min(nav.max_error_m, _surfacings_allow(prof, a, b)) and _clear(prof, a.k, err)
    return ok, worst


def _nominal(prof: RouteProfile, nav: NavParams, a: _Node) -> tuple[FloatArray, FloatArray, int]:
    """From fix ``a`` to the goal without another fix: depth schedule, drift ``D`` at each sample, and the
    first sample past which no stretch from ``a`` can be feasible (lifting the schedule only loses lock)."""
    z = _lifted(prof, a.k, prof.s.size - 1, (a, a))
    ds = np.diff(prof.s[a.k:])
    inc = drift_increments(ds, lock_fraction(z - prof.zb[a.k:], nav.dvl_range_m), nav, ds * prof.wr[a.k:])
    d = a.d + np.r_[0.0, np.cumsum(inc)]
    err = nav.confidence * np.hypot(a.sigma, d[1:])
    bad = np.flatnonzero((err > nav.max_error_m) | (err > prof.r_safe[a.k:]))
    return z, d, prof.s.size if bad.size == 0 else a.k + int(bad[0]) + 1


def _stretch_from(prof: RouteProfile, nav: NavParams, a: _Node, b: _Node,
                  nominal: tuple[FloatArray, FloatArray, int]) -> tuple[bool, float]:
    """:func:`_stretch` from the nominal schedule of ``a``: only ``b``'s climb is recomputed."""
    z, d, stop = nominal
    if b.k >= stop:
        return False, math.inf
    i = b.k - a.k
    if b.kind != "gps":  # the nominal schedule up to b
        return _clear(prof, a.k, nav.confidence * np.hypot(a.sigma, d[1:i + 1])), \
            nav.confidence * float(np.hypot(a.sigma, d[i]))
    reach = float(-z[:i + 1].min()) / prof.tan_pitch  # no climb starts further back than this
    w0 = max(0, int(np.searchsorted(prof.s, prof.s[b.k] - reach)) - 1 - a.k)
    v = -prof.tan_pitch * (prof.s[b.k] - prof.s[a.k + w0:b.k + 1])
    lifted = np.flatnonzero(v <= z[w0:i + 1])
    j0 = w0 + (int(lifted[-1]) if lifted.size else 0)  # the climb leaves the schedule after this sample
    v = v[j0 - w0:]
    zz = np.maximum(z[j0:i + 1], v)
    ds = np.diff(prof.s[a.k + j0:b.k + 1])
    inc = drift_increments(ds, lock_fraction(zz - prof.zb[a.k + j0:b.k + 1], nav.dvl_range_m), nav,
                           ds * prof.wr[a.k + j0:b.k])
    err = nav.confidence * np.hypot(a.sigma, d[j0] + np.cumsum(inc))
    worst = float(err[-1]) if err.size else nav.confidence * float(np.hypot(a.sigma, d[j0]))
    before = nav.confidence * np.hypot(a.sigma, d[1:j0 + 1])  # up to the climb: the nominal schedule's
    ok = worst <= nav.max_error_m and _clear(prof, a.k, np.r_[before, err])
    return ok, worst


def _surface_cost(prof: RouteProfile, nav: NavParams, k: int, speed: float) -> float:
    """Extra time of a surfacing at sample ``k``: the longer climb and dive, and ``surface_s`` (s)."""
    reach = float(-prof.xyz[:, 2].min()) / prof.tan_pitch  # no climb is longer than this
    lo, hi = np.searchsorted(prof.s, [prof.s[k] - reach, prof.s[k] + reach])
    lo, hi = max(int(lo) - 1, 0), min(int(hi) + 1, prof.s.size)
    s, zr = prof.s[lo:hi], prof.xyz[lo:hi, 2]
    z = np.maximum(zr, -prof.tan_pitch * np.abs(s - prof.s[k]))
    ds = np.diff(s)
    extra = np.hypot(ds, np.diff(z)).sum() - np.hypot(ds, np.diff(zr)).sum()
    return float(extra) / speed + nav.surface_s


def _start(prof: RouteProfile, nav: NavParams) -> _Node:
    """The start: the launch's surface fix and the drift of its dive."""
    return _Node(0, "start", nav.fix_error_m, 0.0, prof.d0)


def _nodes(prof: RouteProfile, nav: NavParams, spacing: float, speed: float,
           usbl_xy: tuple[float, float] | None) -> list[_Node]:
    """Start, the candidates (GPS, and USBL when configured) in route order, goal."""
    m = prof.s.size
    every = max(1, int(round(spacing / max(prof.s[-1] / max(m - 1, 1), 1e-9))))
    nodes = [_start(prof, nav)]
    for k in range(every, m - 1, every):
        if surfacing_ok(prof, k):  # a climb that lifts an end or enters a zone is no candidate
            nodes.append(_Node(k, "gps", nav.fix_error_m, _surface_cost(prof, nav, k, speed)))
        if usbl_xy is not None:
            nodes.append(_Node(k, "usbl", fix_sigma(nav, "usbl", prof.xyz[k], usbl_xy), 0.0))
    nodes.append(_Node(m - 1, "goal", 0.0, 0.0))
    return nodes


@dataclass(frozen=True, eq=False)
class FixPlan:
    """Where to take fixes along a route.

    Attributes
    ----------
    ok : bool
        Whether every stretch keeps the error within E and the uncertain clearance.
    s : numpy.ndarray
        ``(F,)`` the fixes' distances along the track (m).
    kinds : tuple of str
        ``(F,)`` ``"gps"`` or ``"usbl"``.
    max_error_m : float
        The largest predicted error (confidence × σ, m).
    time_s : float
        Time the fixes add (climbs, dives, ``surface_s``; s).
    message : str
        Why the plan fails, when it does.
    """

    ok: bool
    s: FloatArray
    kinds: tuple[str, ...]
    max_error_m: float
    time_s: float
    message: str = ""

    @property
    def count(self) -> int:
        """Number of fixes."""
        return int(self.s.size)


def plan_fixes(prof: RouteProfile, nav: NavParams, speed: float, spacing: float = 250.0,
               usbl_xy: tuple[float, float] | None = None) -> FixPlan:
    """The fewest fixes (ties: least time) that keep the error within E and the uncertain clearance.

    Parameters
    ----------
    prof : RouteProfile
        The route (:func:`route_profile`).
    nav : NavParams
        The error model and E.
    speed : float
        Cruise speed (m/s).
    spacing : float, optional
        Distance between candidate fix points along the track (m).
    usbl_xy : tuple of float, optional
        The USBL ship (m): USBL fixes are candidates too.

    Returns
    -------
    FixPlan
        The fixes; ``ok`` False (with the reason) when no choice of candidates keeps the budget.
    """
    if prof.s.size < 2:  # start and goal at one place: nothing is travelled, the launch fix holds
        return FixPlan(True, np.empty(0), (), nav.confidence * math.hypot(nav.fix_error_m, prof.d0), 0.0)
    nodes = _nodes(prof, nav, spacing, speed, usbl_xy)
    best: list[tuple[int, float, float] | None] = [None] * len(nodes)  # (fixes, time, worst error)
    prev = [-1] * len(nodes)
    best[0] = (0, 0.0, nav.confidence * math.hypot(nav.fix_error_m, prof.d0))
    for i, a in enumerate(nodes[:-1]):
        bi = best[i]
        if bi is None:
            continue
        nominal = _nominal(prof, nav, a)
        for j in range(i + 1, len(nodes)):
            b = nodes[j]
            if b.k <= a.k:
                continue
            if b.k >= nominal[2]:
                break
            ok, worst = _stretch_from(prof, nav, a, b, nominal)
            if not ok or worst > _surfacings_allow(prof, a, b):
                continue
            cand = (bi[0] + (b.kind in ("gps", "usbl")), bi[1] + b.cost, max(bi[2], worst))
            bj = best[j]
            if bj is None or cand[:2] < bj[:2]:
                best[j], prev[j] = cand, i
    goal = best[-1]
    if goal is None:
        return FixPlan(False, np.empty(0), (), math.inf, 0.0, _why(prof, nav))
    chain, j = [], prev[-1]
    while j > 0:
        chain.append(nodes[j])
        j = prev[j]
    chain.reverse()
    return FixPlan(True, prof.s[[n.k for n in chain]], tuple(n.kind for n in chain), goal[2], goal[1])


def _why(prof: RouteProfile, nav: NavParams) -> str:
    """Why no plan exists: the first place where even a fix right before cannot keep the uncertain clearance."""
    tight = np.flatnonzero(prof.r_safe < nav.confidence * nav.fix_error_m)
    if tight.size:
        k = int(tight[0])
        return (f"at {prof.s[k] / 1000:.2f} km along the route the seabed, a no-go zone or an obstacle is within "
                f"{prof.r_safe[k]:.0f} m "
                f"horizontally of the leg, less than confidence × fix_error_m = {nav.confidence * nav.fix_error_m:g} m")
    return (f"no choice of fixes every candidate point keeps the error within max_error_m = {nav.max_error_m:g} m "
            "and the uncertain clearance")


def periodic_fixes(prof: RouteProfile, nav: NavParams, period: float, speed: float) -> FixPlan:
    """GPS fixes every ``period`` seconds of flying time along the route (MOOS-IvP's periodic surfacing).

    Parameters
    ----------
    prof : RouteProfile
        The route.
    nav : NavParams
        The error model and E.
    period : float
        Flying time between fixes (s), measured along the route at the cruise speed (through the current when the
        profile has the route's flight, :func:`route_profile`).  A fix whose climb
        would begin before the start or whose dive would end after the goal is skipped.
    speed : float
        Cruise speed (m/s).

    Returns
    -------
    FixPlan
        The fixes and whether they keep the budget (not when a surfacing cannot be flown:
        :func:`~auvplan.nav.surfacing.surfacing_ok`).
    """
    ks: list[int] = []
    t0 = 0.0
    while True:
        k = int(np.searchsorted(prof.t, t0 + period, side="left"))
        if k >= prof.s.size - 1:
            break
        if clear_of_ends(prof, k):  # the timer fires where the vehicle can surface and regain the goal
            ks.append(k)
        t0 = float(prof.t[k])
    blocked = [k for k in ks if not surfacing_ok(prof, k)]
    if blocked:
        return FixPlan(False, prof.s[ks], ("gps",) * len(ks), math.inf, math.nan,
                       f"a fix every {period:.0f} s surfaces at {prof.s[blocked[0]] / 1000:.2f} km along the route "
                       "through the seabed, an obstacle or a no-go zone")
    chain = [_start(prof, nav)] + [_Node(k, "gps", nav.fix_error_m, 0.0) for k in ks] \
        + [_Node(prof.s.size - 1, "goal", 0.0, 0.0)]
    ok, worst = True, 0.0
    for a, b in zip(chain[:-1], chain[1:], strict=True):
        good, w = _stretch(prof, nav, a, b)
        ok, worst = ok and good, max(worst, w)
        if not ok:
            break
    time = sum(_surface_cost(prof, nav, k, speed) for k in ks) if ok else math.nan
    return FixPlan(ok, prof.s[ks] if ks else np.empty(0), ("gps",) * len(ks), worst, time,
                   "" if ok else f"a fix every {period:.0f} s lets the error or the uncertain clearance fail")


def best_period(prof: RouteProfile, nav: NavParams, speed: float, max_error: float,
                resolution: float = 0.0) -> tuple[float, FixPlan] | None:
    """The largest fix period whose fixes keep the error within ``max_error`` and the uncertain clearance.

    Periods are scanned down from the route's flying time in steps of ``resolution`` seconds (default:
    a thousandth of the flying time, at least 10 s).

    Parameters
    ----------
    prof : RouteProfile
        The route.
    nav : NavParams
        The error model.
    speed : float
        Cruise speed (m/s).
    max_error : float
        The largest error allowed (m): the planned fixes' own maximum, for a like-for-like comparison.
    resolution : float, optional
        Step of the scan (s); 0: the default.

    Returns
    -------
    tuple or None
        ``(period_s, plan)``; None when no period down to ``resolution`` keeps it.
    """
    capped = NavParams(nav.drift_pct, nav.drift_pct_no_lock, nav.dvl_range_m, nav.fix_error_m,
                       max(max_error, nav.confidence * nav.fix_error_m * (1 + 1e-9)), nav.confidence, nav.fixes,
                       nav.surface_s, nav.usbl)
    period = float(prof.t[-1])
    resolution = resolution or max(10.0, period / 1000.0)
    while period >= resolution:
        plan = periodic_fixes(prof, capped, period, speed)
        if plan.ok:
            return period, plan
        period -= resolution
    return None
