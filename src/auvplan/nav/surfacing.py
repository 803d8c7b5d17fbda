"""A GPS fix's surfacing: the mission's depth schedule with its climbs and dives, and whether a surfacing can
be flown (``docs/navigation.md``, "Fixes planned with the fewest surfacings").

A surfacing at ``s_f`` along the route's horizontal track lifts the schedule to the upper envelope
``max(z_route(s), −tanθ |s − s_f|)`` (:func:`apply_fixes`).  It can be flown when its climb begins after the
start and its dive ends before the goal (else the envelope would lift the start or the goal: the mission
would neither begin nor end there, and the climb from the start's depth would break the pitch limit), and
when its climb and dive pass the World's exact static segment test (seabed, obstacles, no-go zones, land,
bounds), as the route's own legs did.  Near a static obstacle it allows only the horizontal uncertainty
that keeps its climb and dive clear of the obstacle's margin, near a charted no-go zone only the one that keeps
the zone out of reach at their depths (:func:`surfacing_slack`; :func:`~auvplan.nav.clearance.zone_safe_radius`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from .._types import BoolArray, FloatArray, IntArray
from .clearance import obstacle_safe_radius, zone_safe_radius

if TYPE_CHECKING:  # pragma: no cover - for type checkers only
    from ..world import World
    from .fixes import RouteProfile

__all__ = ["apply_fixes", "surfacing_slack", "surfacing_zone_slack", "surfacing_ok", "surfacing_legs",
           "clear_of_ends", "SHORTEST_FIX_LEG_M", "CLIMB_SLACK_DEG"]

SHORTEST_FIX_LEG_M = 2.5
"""Shortest leg (3D, m) :func:`apply_fixes` leaves where it splits the route: the exported mission's
:data:`auvplan.path.legs.FITTED_LEG_M` (kept equal by a test; ``nav`` does not import ``path``), so that the
rounding of the exported coordinates cannot take a climb or dive at the pitch limit over it."""
CLIMB_SLACK_DEG = 0.05
"""Pitch (degrees) a fix's climb and dive keep below the limit at least: the mission builder's
:data:`auvplan.path.flyable.PITCH_SLACK_DEG` (kept equal by a test), which the millimetre rounding of a leg of
:data:`SHORTEST_FIX_LEG_M` or more cannot use up (0.02°, ``PITCH_SHARE`` of a 20° limit, it could: 19.98° read
20.0008° on a 2.6 m leg)."""

R_MAX = 1.0e5
"""Largest horizontal uncertainty the obstacle slack is searched to (m); beyond it the slack is ``inf``."""


def surfacing_slack(prof: RouteProfile, k: int) -> float:
    """The largest horizontal uncertainty a surfacing at sample ``k`` allows, ``-1`` when it cannot be flown.

    Parameters
    ----------
    prof : RouteProfile
        The route and its World.
    k : int
        The sample of the surfacing.

    Returns
    -------
    float
        ``-1``: it would lift the start or the goal, or its climb or dive fails the World's exact static segment
        test, or a charted zone comes within ``prof.dive_error`` of its dive at the dive's depths (the error just
        after the fix); else the largest ``r`` (m) with its climb and dive clear of every
        static obstacle by the obstacle margin plus ``r`` (``inf`` without obstacles).  Memoised on ``prof``.
    """
    k = int(k)
    if k not in prof._surfacing:
        prof._surfacing[k] = _slack(prof, k)
    return prof._surfacing[k]


def surfacing_ok(prof: RouteProfile, k: int) -> bool:
    """Whether a surfacing at sample ``k`` can be flown (:func:`surfacing_slack` ≥ 0).

    Parameters
    ----------
    prof : RouteProfile
        The route and its World.
    k : int
        The sample of the surfacing.

    Returns
    -------
    bool
        It lifts neither end and its climb and dive pass the World's exact static segment test.
    """
    return surfacing_slack(prof, k) >= 0.0


def clear_of_ends(prof: RouteProfile, k: int) -> bool:
    """A surfacing at sample ``k`` lifts neither the start nor the goal (its climb and dive fit in the route).

    Parameters
    ----------
    prof : RouteProfile
        The route.
    k : int
        The sample of the surfacing.

    Returns
    -------
    bool
        ``−tanθ s_k ≤ z_start`` and ``−tanθ (L − s_k) ≤ z_goal``.
    """
    sk, tan = float(prof.s[k]), prof.tan_pitch
    return bool(-tan * sk <= prof.xyz[0, 2] + 1e-9 and -tan * (float(prof.s[-1]) - sk) <= prof.xyz[-1, 2] + 1e-9)


def _slack(prof: RouteProfile, k: int) -> float:
    if not clear_of_ends(prof, k):
        return -1.0
    world = prof.world
    if world is None:
        return np.inf
    seg = surfacing_legs(prof, k)
    if seg.shape[0] and not world.segments_free(seg, moving=False).all():
        return -1.0
    if world.zones and seg.shape[0]:  # the dive, just after the fix: its error is at most prof.dive_error
        dive = seg[seg[:, 1, 2] < seg[:, 0, 2]]
        if dive.shape[0] and zone_safe_radius(world, dive[:, 0], dive[:, 1], prof.dive_error).min() < prof.dive_error:
            return -1.0
    return _obstacle_slack(world, seg, min(R_MAX, prof.reach))


def surfacing_zone_slack(prof: RouteProfile, k: int) -> float:
    """The largest error on arrival at a surfacing at sample ``k`` that keeps the charted zones out of reach of its
    climb at the climb's depths (:func:`~auvplan.nav.clearance.zone_safe_radius`): the stretch that ends there must
    stay within it (the error only grows along it).  Its dive is judged on :func:`surfacing_slack`.

    Parameters
    ----------
    prof : RouteProfile
        The route and its World.
    k : int
        The sample of the surfacing.

    Returns
    -------
    float
        (m): ``inf`` without a zone within ``prof.reach``.  Memoised on ``prof``.
    """
    k = int(k)
    if k not in prof._zone_slack:
        world, out = prof.world, np.inf
        if world is not None and world.zones:
            seg = surfacing_legs(prof, k)
            climb = seg[seg[:, 1, 2] > seg[:, 0, 2]]
            if climb.shape[0]:
                out = float(zone_safe_radius(world, climb[:, 0], climb[:, 1], min(R_MAX, prof.reach)).min())
        prof._zone_slack[k] = out
    return prof._zone_slack[k]


def surfacing_legs(prof: RouteProfile, k: int) -> FloatArray:
    """The legs of a surfacing's climb and dive at sample ``k``.

    Parameters
    ----------
    prof : RouteProfile
        The route.
    k : int
        The sample of the surfacing.

    Returns
    -------
    numpy.ndarray
        ``(K, 2, 3)`` the mission's legs that lie on the climb or the dive (m).
    """
    sk, tan = float(prof.s[k]), prof.tan_pitch
    reach = float(-prof.xyz[:, 2].min()) / tan  # no climb is longer than this
    lo, hi = np.searchsorted(prof.s, [sk - reach, sk + reach])
    lo, hi = max(int(lo) - 1, 0), min(int(hi) + 1, prof.s.size)
    pts, _ = apply_fixes(prof.xyz[lo:hi], [sk - prof.s[lo]], ("gps",), tan)
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pts[:, :2], axis=0).T))]
    on = np.abs(pts[:, 2] + tan * np.abs(s - (sk - prof.s[lo]))) <= 1e-6  # on the climb or the dive
    legs = on[:-1] & on[1:]
    out: FloatArray = np.stack([pts[:-1][legs], pts[1:][legs]], axis=1)
    return out


def _obstacle_slack(world: World, seg: FloatArray, reach: float) -> float:
    """Largest ``r`` up to ``reach`` with no static obstacle within its margin plus ``r`` of the legs (the route's
    own test, :func:`~auvplan.nav.clearance.obstacle_safe_radius`; ``inf`` when clear at ``reach``)."""
    if not world.obstacles or seg.shape[0] == 0:
        return np.inf
    return float(obstacle_safe_radius(world, seg[:, 0], seg[:, 1], reach).min())


def apply_fixes(route: ArrayLike, s_fix: ArrayLike, kinds: tuple[str, ...],
                tan_pitch: float) -> tuple[FloatArray, tuple[str, ...]]:
    """The mission with its fixes: surfacings (a waypoint at depth 0) and USBL fix waypoints on the track.

    The depth schedule becomes ``max(z_route(s), max_f −tanθ |s − s_f|)`` over the same horizontal
    track: its breakpoints are the route's vertices, the fixes and every crossing of a climb or dive
    with a leg or with another fix's; a route vertex the envelope lifts is kept (its bend stays).

    Parameters
    ----------
    route : array_like
        ``(N, 3)`` waypoints (m).
    s_fix : array_like
        ``(F,)`` the fixes along the horizontal track (m).
    kinds : tuple of str
        ``(F,)`` ``"gps"`` or ``"usbl"``.
    tan_pitch : float
        Slope of the climbs and dives.

    Returns
    -------
    points : numpy.ndarray
        ``(N', 3)`` waypoints.
    kinds : tuple of str
        ``(N',)`` the fix at each (``""`` elsewhere).
    """
    p = np.asarray(route, dtype=float).reshape(-1, 3)
    sf = np.asarray(s_fix, dtype=float).reshape(-1)
    if sf.size == 0:
        return p.copy(), ("",) * p.shape[0]
    h = np.hypot(*np.diff(p[:, :2], axis=0).T)
    sv = np.r_[0.0, np.cumsum(h)]
    sf = _snap(sf, sv, p[:, 2], tan_pitch)
    gps = sf[[k == "gps" for k in kinds]]
    b, leg = _breakpoints(p, h, sv, sf, gps, tan_pitch)
    s = np.r_[sv, b]
    order = np.lexsort((s, np.r_[np.arange(sv.size) - 0.5, leg]))  # vertex i before leg i's inner breakpoints
    s = s[order]
    vertex = order < sv.size
    f_leg = np.clip((b - sv[leg]) / np.where(h[leg] > 0.0, h[leg], 1.0), 0.0, 1.0)[:, None]
    pts = np.vstack([p, p[leg] + f_leg * (p[leg + 1] - p[leg])])[order]
    for f in gps:
        pts[:, 2] = np.maximum(pts[:, 2], -tan_pitch * np.abs(s - f))
    out_kinds = [""] * s.size
    for f, kind in zip(sf, kinds, strict=True):
        out_kinds[int(np.argmin(np.abs(s - f)))] = kind
    keep = _needed(pts, s, vertex, out_kinds)
    pts, out_kinds = pts[keep], [k for k, m in zip(out_kinds, keep, strict=True) if m]
    vertex = vertex[keep]
    pts, vertex, out_kinds = _drop_repeats(pts, vertex, out_kinds)
    kept = _merge_short(pts, vertex | np.array([bool(k) for k in out_kinds]))
    return pts[kept], tuple(out_kinds[i] for i in kept)


def _breakpoints(p: FloatArray, h: FloatArray, sv: FloatArray, sf: FloatArray, gps: FloatArray,
                 tan_pitch: float) -> tuple[FloatArray, IntArray]:
    """The breakpoints :func:`apply_fixes` adds strictly inside the legs, in order, and the leg of each: the fixes,
    every crossing of a climb or dive with a leg, and the midpoints between two surfacings."""
    brk = [sf]
    for f in gps:  # crossings of each climb/dive with each leg
        for sign in (-1.0, 1.0):
            slope_v = -sign * tan_pitch  # V(s) = -tan * |s - f| = tan*(s - f) before f (sign -1), -tan*(s - f) after
            dz = np.diff(p[:, 2])
            with np.errstate(divide="ignore", invalid="ignore"):
                # z_route(s) = z0 + (dz/h)(s - s0) meets V(s) = slope_v (s - f)
                s_cross = (p[:-1, 2] - dz / h * sv[:-1] + slope_v * f) / (slope_v - dz / h)
            brk.append(s_cross[np.isfinite(s_cross) & (s_cross > sv[:-1]) & (s_cross < sv[1:])])
    if gps.size > 1:
        brk.append(0.5 * (gps[1:] + gps[:-1]))
    # per leg, so that a vertical leg (no horizontal length) keeps both its ends: the route's vertices, then
    # each leg's breakpoints strictly inside it
    b = np.unique(np.concatenate(brk))
    leg = np.searchsorted(sv, b, side="right") - 1
    inside = (leg >= 0) & (leg < h.size) & (b - sv[np.clip(leg, 0, sv.size - 1)] > 1e-6)
    b, leg = b[inside], leg[inside]
    inside = sv[leg + 1] - b > 1e-6
    b, leg = b[inside], leg[inside]
    return b, leg


def _drop_repeats(pts: FloatArray, vertex: BoolArray,
                  out_kinds: list[str]) -> tuple[FloatArray, BoolArray, list[str]]:
    """The points without a repeat of the one before (a vertical leg the envelope lifted whole), its fix and its
    being a vertex merged into that one."""
    same = np.r_[False, np.all(np.abs(np.diff(pts, axis=0)) <= 1e-9, axis=1)]  # a vertical leg lifted whole
    for i in np.flatnonzero(same)[::-1]:  # the repeat is merged into the point before it, with its fix
        out_kinds[i - 1] = out_kinds[i - 1] or out_kinds[i]
        vertex[i - 1] |= vertex[i]
    pts, vertex, out_kinds = pts[~same], vertex[~same], [k for k, d in zip(out_kinds, same, strict=True) if not d]
    return pts, vertex, out_kinds


def _snap(sf: FloatArray, sv: FloatArray, z: FloatArray, tan_pitch: float) -> FloatArray:
    """Each fix closer than :data:`SHORTEST_FIX_LEG_M` to a route vertex moved to the nearest place that is a vertex
    or that far from every vertex (a fix and a vertex are both kept: closer, their leg would be shorter than the
    rule) and that lifts neither the start nor the goal higher than the fix did (a move of less than the rule)."""
    out = sf.copy()
    ends = (0, sv.size - 1)
    for i, f in enumerate(sf):
        if not 0.0 < np.abs(sv - f).min() < SHORTEST_FIX_LEG_M:
            continue
        near = sv[np.abs(sv - f) < 2.0 * SHORTEST_FIX_LEG_M]
        cand = np.unique(np.r_[near, near - SHORTEST_FIX_LEG_M, near + SHORTEST_FIX_LEG_M])
        cand = cand[(cand >= sv[0]) & (cand <= sv[-1])]
        gap = np.abs(sv[None, :] - cand[:, None]).min(axis=1)
        ok = (gap == 0.0) | (gap >= SHORTEST_FIX_LEG_M - 1e-9)
        for e in ends:  # the climb or dive reaches no end higher than the fix's own did
            ok &= -tan_pitch * np.abs(sv[e] - cand) <= max(z[e], -tan_pitch * abs(sv[e] - f))
        if ok.any():
            out[i] = cand[ok][np.argmin(np.abs(cand[ok] - f))]
    return out


def _merge_short(pts: FloatArray, fixed: BoolArray) -> list[int]:
    """The points kept so that no leg is shorter than :data:`SHORTEST_FIX_LEG_M` (3D): of a shorter leg, its end
    that is neither a route vertex, a fix nor an end of the mission is dropped.  Such a point is a crossing of a
    climb or dive with a route leg (or two fixes' dives meeting), a kink of the upper envelope of lines over one
    route leg: the chord that replaces it lies on that leg's horizontal track, above the envelope (never nearer
    the seabed), and its pitch lies between those of the two legs it joins (never steeper)."""
    fixed = fixed.copy()
    fixed[[0, -1]] = True
    idx = list(range(pts.shape[0]))
    i = 0
    while i < len(idx) - 1:
        a, b = idx[i], idx[i + 1]
        if np.linalg.norm(pts[b] - pts[a]) >= SHORTEST_FIX_LEG_M or (fixed[a] and fixed[b]):
            i += 1
        elif not fixed[b]:
            del idx[i + 1]
        else:
            del idx[i]
            i = max(i - 1, 0)
    return idx


def _needed(pts: FloatArray, s: FloatArray, vertex: BoolArray, kinds: list[str]) -> BoolArray:
    """Breakpoints to keep: route vertices, fixes, and wherever the depth schedule bends."""
    keep = np.zeros(s.size, dtype=bool)
    keep[[0, -1]] = True
    keep |= vertex | np.array([bool(k) for k in kinds])
    slope = np.diff(pts[:, 2]) / np.maximum(np.diff(s), 1e-12)
    keep[1:-1] |= np.abs(np.diff(slope)) > 1e-9
    return keep
