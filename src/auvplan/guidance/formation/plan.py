"""Planning for a formation: every slot's swept track against the seabed and obstacles, exactly.

The global plan (or a fixed survey line) is the route of the leader's slot.  The other slots sweep
tracks beside and behind it (the formation's width, its depth spread and the shape changes in
between): :func:`plan_formation` samples every slot's track every ``sample_m`` metres of reference
progress (route vertices and the ends of every shape change included) and tests each of its segments
with :meth:`World.segments_free` — the exact segment-versus-seabed walk, the exact obstacle tests,
the depth band and the bounds (moving obstacles excluded: they are the closed loop's business).

Where a slot's track fails and ``auto_column`` is set, the formation is reshaped to a column over
that stretch — in a column every vehicle flies on the route itself at the route's depth, which is
the checked mission — starting a transition plus one spacing before the first failing route
position and re-forming one spacing after the column's *tail* has passed the last one (the
trailing vehicles reach a route position ``k·spacing`` after the leader).  The tracks are then tested
again (a re-form may fail further on), until every segment is free or ``max_rounds`` is reached; the
result says which stretches were reshaped and why.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..._types import ArrayLike, Status
from ...world import World
from .keeping import Formation
from .route import FormationRoute, Schedule

__all__ = ["FormationPlan", "requested_breaks", "plan_formation", "check_tracks"]


@dataclass(frozen=True, eq=False)
class FormationPlan:
    """The shapes along the route and every slot's checked track.

    Attributes
    ----------
    status : Status
        ``EXACT`` when every slot track passes the exact test, else ``INFEASIBLE``.
    structure : FormationRoute
        The route as a virtual structure (slots at a reference position).
    breaks : tuple of (float, str)
        Shape breakpoints (m along the route, shape) in force, reshapes included.
    reshaped : tuple of (float, float, str)
        Route stretches ``[start, end]`` flown in column because a slot track failed there, and why.
    s : ndarray (M,)
        Reference positions of the track samples (m along the route).
    tracks : ndarray (n, M, 3)
        Every slot's swept track.
    free : ndarray (n, M - 1) of bool
        The exact test of every track segment.
    message : str
        What was found.
    """

    status: Status
    structure: FormationRoute
    breaks: tuple[tuple[float, str], ...]
    reshaped: tuple[tuple[float, float, str], ...]
    s: np.ndarray
    tracks: np.ndarray
    free: np.ndarray
    message: str

    @property
    def route(self) -> np.ndarray:
        """The route (leader's slot track) as waypoints ``(N, 3)``."""
        return self.structure.w


def requested_breaks(formation: Formation, route: ArrayLike) -> list[tuple[float, str]]:
    """The scenario's shape schedule: the initial shape at 0 and each change at its place.

    Parameters
    ----------
    formation : Formation
        The initial shape and the changes (``at_m`` or ``waypoint``).
    route : array_like (N, 3)
        The route (a waypoint's route position is its arc length).

    Returns
    -------
    list of (float, str)
        ``(route position, shape)`` breakpoints.
    """
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    cum = np.r_[0.0, np.cumsum(np.hypot(*np.diff(w[:, :2], axis=0).T))]
    out = [(0.0, formation.params.shape)]
    for ch in formation.params.changes:
        if ch.waypoint >= 0:
            if ch.waypoint >= w.shape[0]:
                raise ValueError(f"shape change at waypoint {ch.waypoint}: the route has {w.shape[0]} waypoints")
            out.append((float(cum[ch.waypoint]), ch.shape))
        else:
            out.append((min(float(ch.at_m), float(cum[-1])), ch.shape))
    return out


def _schedule(formation: Formation, breaks: Sequence[tuple[float, str]]) -> Schedule:
    fp = formation.params
    return Schedule(breaks, formation.n, fp.spacing_m, fp.transition_m,
                    [v.depth_offset_m for v in formation.vehicles])


def check_tracks(world: World, structure: FormationRoute, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every slot track and the exact test of each of its segments (static world).

    Parameters
    ----------
    world : World
        Seabed, obstacles, depth band, bounds, land.
    structure : FormationRoute
        The route with its shapes.
    step : float
        Largest spacing of the track samples (m of reference progress).

    Returns
    -------
    s : ndarray (M,)
        Reference positions.
    tracks : ndarray (n, M, 3)
        The slot tracks.
    free : ndarray (n, M - 1) of bool
        :meth:`World.segments_free` of every segment.
    """
    s, tracks = structure.tracks(step)
    segs = np.stack([tracks[:, :-1], tracks[:, 1:]], axis=2)
    return s, tracks, np.asarray(world.segments_free(segs, moving=False), dtype=bool)


def _windows(bad_route_pos: np.ndarray, n: int, spacing: float, transition: float) -> list[tuple[float, float]]:
    """Reference stretches that must be fully in column for failing route positions."""
    pos = np.sort(bad_route_pos)
    groups: list[list[float]] = []
    for p in pos:
        if groups and p - groups[-1][1] <= transition + 2.0 * spacing:
            groups[-1][1] = float(p)
        else:
            groups.append([float(p), float(p)])
    tail = (n - 1) * spacing
    return [(g0 - spacing, g1 + tail + spacing) for g0, g1 in groups]


def _with_columns(requested: Sequence[tuple[float, str]], windows: Sequence[tuple[float, float]],
                  transition: float, length: float) -> list[tuple[float, str]]:
    """The requested breaks with column windows ``[c0, c1]`` imposed (column from ``c0 − transition``)."""
    merged: list[list[float]] = []
    for c0, c1 in sorted(windows):
        if merged and c0 - transition <= merged[-1][1] + transition:
            merged[-1][1] = max(merged[-1][1], c1)
        else:
            merged.append([c0, c1])
    req = sorted(requested)

    def shape_at(s: float) -> str:
        name = req[0][1]
        for b, sh in req:
            if s >= b:
                name = sh
        return name

    out = [(b, sh) for b, sh in req if not any(c0 - transition <= b <= c1 for c0, c1 in merged)]
    for c0, c1 in merged:
        out.append((max(c0 - transition, 0.0), "column"))
        if c1 < length:
            out.append((c1, shape_at(c1)))
    out.sort()
    if out[0][0] > 0.0:
        out.insert(0, (0.0, req[0][1]))
    # drop breaks that repeat the shape in force
    clean = [out[0]]
    for b, sh in out[1:]:
        if sh != clean[-1][1]:
            clean.append((b, sh))
    return clean


def plan_formation(world: World, route: ArrayLike, formation: Formation, max_rounds: int = 6) -> FormationPlan:
    """Shapes and checked slot tracks of ``formation`` along ``route (N, 3)`` in ``world``.

    Parameters
    ----------
    world : World
        Seabed, obstacles and margins (moving obstacles are not considered).
    route : array_like (N, 3)
        The leader's route (a checked mission or a fixed survey line).
    formation : Formation
        Vehicles and formation parameters.
    max_rounds : int
        Rounds of test-and-reshape before giving up.

    Returns
    -------
    FormationPlan
        ``EXACT`` when every slot track is free; ``INFEASIBLE`` (with the failing vehicle and route
        position in ``message``) when it is not and cannot be reshaped.
    """
    fp = formation.params
    requested = requested_breaks(formation, route)
    breaks = list(requested)
    windows: list[tuple[float, float]] = []
    reasons: list[tuple[float, float, str]] = []
    structure = FormationRoute(route, _schedule(formation, breaks), fp.course_window_m or fp.spacing_m)
    s, tracks, free = check_tracks(world, structure, fp.sample_m)
    for _ in range(max_rounds):
        if free.all() or not fp.auto_column:
            break
        veh, seg = np.nonzero(~free)
        off = structure.schedule.offsets(s[seg])[np.arange(seg.size), veh]
        route_pos = np.clip(s[seg] + off[:, 0], 0.0, structure.length)
        new = [w for w in _windows(route_pos, formation.n, fp.spacing_m, fp.transition_m) if w not in windows]
        if not new:  # the column itself fails there: nothing left to reshape
            break
        for (c0, c1) in new:
            who = sorted({formation.names[v] for v, p in zip(veh, route_pos) if c0 <= p <= c1})
            reasons.append((max(c0 - fp.transition_m, 0.0), min(c1, structure.length),
                            f"slot track of {', '.join(who)} not free"))
        windows += new
        breaks = _with_columns(requested, windows, fp.transition_m, structure.length)
        structure = FormationRoute(route, _schedule(formation, breaks), fp.course_window_m or fp.spacing_m)
        s, tracks, free = check_tracks(world, structure, fp.sample_m)
    if free.all():
        status = Status.EXACT
        msg = "every slot track is free" + (f"; column over {len(reasons)} stretch(es)" if reasons else "")
    else:
        status = Status.INFEASIBLE
        v, j = np.argwhere(~free)[0]
        msg = (f"slot track of {formation.names[v]} not free near reference {s[j]:.0f} m "
               f"({tracks[v, j].round(1).tolist()})" + ("" if fp.auto_column else "; auto_column is off"))
    return FormationPlan(status, structure, tuple(breaks), tuple(reasons), s, tracks, free, msg)
