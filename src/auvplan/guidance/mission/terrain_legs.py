"""The track of a waypoint mission whose legs follow the seabed (ArduSub: QGroundControl items in the terrain
frame, ``MAV_FRAME_GLOBAL_TERRAIN_ALT`` = 10).

Between two items such an executor does not fly the straight 3D line: it holds an altitude above the seabed,
going from the altitude it leaves the first item at to the second item's (ArduPilot's terrain-relative
navigation interpolates the altitude target along the leg).  Over a ridge between two items the vehicle climbs
with the seabed and can come shallower than either item — above a charted shallows band, or out of the water —
where the straight line passes below.

On a bilinear seabed the elevation along a horizontal line is a quadratic inside each grid cell, and the
altitude target is linear in the leg's parameter: the track's depth is a quadratic on each piece between two
grid-line crossings.  :func:`terrain_track` therefore places a vertex at every crossing and at the extremum of
each piece's quadratic: the track's shallowest and deepest points are vertices (exact); and it divides each piece
so that the chord between two vertices stays within :data:`SAG_M` of the curve (a quadratic's chord over a
parameter span ``d`` sags ``|q2| d^2 / 4``; across a saddle cell the whole piece's chord sagged metres: a zone over
the middle of the leg entered by the track and missed by its chord, an altitude read metres under the one held).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..._types import BoolArray, FloatArray, IntArray
from ...geometry import as_points
from ...path.flyable import leg_pitch_deg
from ...world import World
from ...world.terrain import Terrain
from .flycheck import MissionCheck, leg_figures
from .limits import waypoint_limits

__all__ = ["SAG_M", "END_MERGE_M", "FlownTrack", "check_as_flown", "flown_pitch_depth", "flown_track",
           "followed_altitude", "terrain_track"]

SAG_M = 0.01
"""The most the track's chords stand off the seabed-following curve they stand for (m)."""


_MERGE = 1e-9
"""Grid-line crossings closer than this (in the leg's parameter) are one: a leg through a grid node crosses its
two lines at parameters a rounding apart, and the sliver between them lies in neither cell the leg flies over."""

END_MERGE_M = 1e-3
"""A grid-line crossing closer than this to a leg's end (m, horizontally) is the end: the files carry positions to
0.1 mm (a ``.plan``'s 1e-9 degree), so a leg the export placed on a grid line reads back a fraction of a
millimetre to either side of it, and the sliver of the next cell would lend the whole leg that cell's slope
(``mariana-nav``'s leg 534 read 24.8 degrees for the 19.98 it flies)."""


def _pieces(terrain: Terrain, a: np.ndarray, b: np.ndarray) -> FloatArray:
    """The leg's parameters (0..1) where it crosses a grid line, with both ends (crossings within :data:`_MERGE`
    of one another, or within :data:`END_MERGE_M` of an end, merged)."""
    s = []
    end = max(_MERGE, END_MERGE_M / max(float(np.hypot(*(b[:2] - a[:2]))), 1e-300))
    for axis, grid in ((0, terrain.x), (1, terrain.y)):
        d = float(b[axis] - a[axis])
        if d != 0.0:
            t = (np.asarray(grid, dtype=float) - a[axis]) / d
            s.append(t[(t > end) & (t < 1.0 - end)])
    inner = np.unique(np.concatenate(s)) if s else np.zeros(0)
    inner = inner[np.r_[True, np.diff(inner) > _MERGE]] if inner.size else inner
    out: FloatArray = np.concatenate([[0.0], inner, [1.0]])
    return out


def _following_leg(terrain: Terrain, a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray, float]:
    """The track of one leg following the seabed from ``a`` to ``b``: its vertices' parameters (after 0, up to 1)
    and depths, and its steepest slope ``|dz/dl|`` (the tangent's, exact: largest at the ends of a quadratic piece;
    ``inf`` for a leg with no horizontal length that changes depth)."""
    ha = float(a[2] - terrain.elevation(a[0], a[1]))
    hb = float(b[2] - terrain.elevation(b[0], b[1]))

    def z_at(s: FloatArray) -> FloatArray:
        xy = a[:2] + s[:, None] * (b[:2] - a[:2])
        return np.asarray(terrain.elevation(xy[:, 0], xy[:, 1]), dtype=float) + ha + s * (hb - ha)

    s = _pieces(terrain, a, b)
    s0, s1 = s[:-1], s[1:]
    z0, zm, z1 = z_at(s0), z_at(0.5 * (s0 + s1)), z_at(s1)
    q2 = 2.0 * (z0 - 2.0 * zm + z1)  # z = z0 + q1 t + q2 t^2 on each piece, t in [0, 1]
    q1 = z1 - z0 - q2
    length = float(np.hypot(*(b[:2] - a[:2])))
    if length > 0.0:
        # the tangent from the surface's gradient (linear along a piece: extrapolated from its quarter points to
        # its ends), not from differences of depths, which a short piece divides into noise
        ux, uy = (b[:2] - a[:2]) / length
        quarter = a[:2] + np.concatenate([s0 + 0.25 * (s1 - s0), s0 + 0.75 * (s1 - s0)])[:, None] * (b[:2] - a[:2])
        gx, gy = terrain.gradient(quarter[:, 0], quarter[:, 1])
        ga, gb = np.split(gx * ux + gy * uy + (hb - ha) / length, 2)
        slope = float(np.maximum(np.abs(1.5 * ga - 0.5 * gb), np.abs(1.5 * gb - 0.5 * ga)).max())
    else:
        slope = 0.0 if b[2] == a[2] else np.inf
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(np.abs(q2) > 1e-12, -q1 / (2.0 * q2), -1.0)
    inner = (t > 0.0) & (t < 1.0)
    n = np.clip(np.ceil(np.sqrt(np.abs(q2) / (4.0 * SAG_M))), 1, 100_000).astype(np.intp)  # sag |q2| / (4 n^2)
    k = np.repeat(np.arange(n.size), n - 1)
    sub = s0[k] + (s1 - s0)[k] * (np.arange(k.size) - np.repeat(np.cumsum(n - 1) - (n - 1), n - 1) + 1) / n[k]
    s = np.unique(np.concatenate([s, s0[inner] + t[inner] * (s1 - s0)[inner], sub]))[1:]
    z = z_at(s)
    z[-1] = b[2]  # the item itself, as the file places it
    return s, z, slope


def _flags(waypoints: ArrayLike, follow: ArrayLike) -> tuple[FloatArray, BoolArray]:
    w = as_points(waypoints).reshape(-1, 3)
    f = np.asarray(follow, dtype=bool).reshape(-1)
    if f.size != max(w.shape[0] - 1, 0):
        raise ValueError(f"follow has {f.size} flags for {max(w.shape[0] - 1, 0)} legs")
    return w, f


@dataclass(frozen=True, eq=False)
class FlownTrack:
    """A waypoint mission as flown when the legs ``follow`` marks hold an altitude above the seabed
    (:func:`flown_track`).

    Attributes
    ----------
    track : numpy.ndarray
        ``(M, 3)`` polyline (m), as :func:`terrain_track` returns it.
    leg : numpy.ndarray of int
        ``(M - 1,)``: the leg (from 0) of each segment of the track.
    pitch : numpy.ndarray
        ``(N - 1,)`` each leg's steepest pitch (degrees, absolute): a following leg's steepest tangent, the
        others' straight pitch.
    depth : numpy.ndarray
        ``(N - 1,)`` each leg's greatest depth (m, positive down; the track's deepest vertex, exact).
    """

    track: FloatArray
    leg: IntArray
    pitch: FloatArray
    depth: FloatArray


def flown_track(terrain: Terrain, waypoints: ArrayLike, follow: ArrayLike) -> FlownTrack:
    """Return the track, and each leg's steepest pitch and greatest depth, flown when the legs ``follow`` marks
    hold an altitude above the seabed (each leg's track computed once; :func:`terrain_track` and
    :func:`flown_pitch_depth` are its parts).

    Parameters
    ----------
    terrain : Terrain
        The seabed.
    waypoints : array_like
        ``(N, 3)`` mission waypoints (m).
    follow : array_like of bool
        ``(N - 1,)``: the legs flown following the seabed.

    Returns
    -------
    FlownTrack
        The track, its segments' legs, and per leg the steepest pitch and the greatest depth.
    """
    w, f = _flags(waypoints, follow)
    pts: list[FloatArray] = [w[:1]]
    legs: list[IntArray] = []
    pitch = np.abs(leg_pitch_deg(w)) if w.shape[0] > 1 else np.zeros(0)
    for k in range(w.shape[0] - 1):
        a, b = w[k], w[k + 1]
        if not f[k]:
            pts.append(b[None, :])
            legs.append(np.array([k]))
            continue
        s, z, slope = _following_leg(terrain, a, b)
        pitch[k] = max(float(np.degrees(np.arctan(slope))), pitch[k])
        xy = a[:2] + s[:, None] * (b[:2] - a[:2])
        pts.append(np.column_stack([xy, z]))
        legs.append(np.full(s.size, k))
    track = np.vstack(pts)
    leg = (np.concatenate(legs) if legs else np.zeros(0, dtype=np.intp)).astype(np.intp)
    low = np.full(max(w.shape[0] - 1, 0), np.inf)  # each leg's deepest vertex: its segments' ends
    np.minimum.at(low, leg, track[:-1, 2])
    np.minimum.at(low, leg, track[1:, 2])
    return FlownTrack(track, leg, pitch, -low)


def terrain_track(terrain: Terrain, waypoints: ArrayLike, follow: ArrayLike) -> tuple[FloatArray, IntArray]:
    """Return the track flown when the legs ``follow`` marks hold an altitude above the seabed.

    Leg ``k`` (waypoint ``k`` to ``k + 1``) marked in ``follow`` is flown at an altitude above ``terrain`` going
    linearly (in the leg's horizontal parameter) from waypoint ``k``'s altitude to waypoint ``k + 1``'s; an
    unmarked leg is the straight 3D line.

    Parameters
    ----------
    terrain : Terrain
        The seabed.
    waypoints : array_like
        ``(N, 3)`` mission waypoints (m).
    follow : array_like of bool
        ``(N - 1,)``: the legs flown following the seabed.

    Returns
    -------
    track : numpy.ndarray
        ``(M, 3)`` polyline (m): the waypoints, and on each following leg a vertex at every grid-line crossing and
        at every extremum of the depth between two crossings, and between them within :data:`SAG_M` of the curve.
    leg : numpy.ndarray of int
        ``(M - 1,)``: the leg (from 0) of each segment of the track.
    """
    flown = flown_track(terrain, waypoints, follow)
    return flown.track, flown.leg


def flown_pitch_depth(terrain: Terrain, waypoints: ArrayLike, follow: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Each leg's steepest pitch and greatest depth as flown: on a leg ``follow`` marks, the seabed-following
    track's (:func:`flown_track`; the pitch of its steepest tangent, where the vehicle must climb or dive with
    the seabed, and its deepest vertex, exact); on the others the straight leg's.

    Parameters
    ----------
    terrain : Terrain
        The seabed.
    waypoints : array_like
        ``(N, 3)`` mission waypoints (m).
    follow : array_like of bool
        ``(N - 1,)``: the legs flown following the seabed.

    Returns
    -------
    pitch : numpy.ndarray
        ``(N - 1,)`` steepest pitch (degrees, absolute), for :func:`auvplan.path.legs.helm_check`.
    depth : numpy.ndarray
        ``(N - 1,)`` greatest depth (m, positive down).
    """
    flown = flown_track(terrain, waypoints, follow)
    return flown.pitch, flown.depth


def followed_altitude(terrain: Terrain, waypoints: ArrayLike, follow: ArrayLike) -> FloatArray:
    """Each leg's least altitude above the seabed as flown, exactly, where ``follow`` marks it: the altitude held
    goes linearly from one item's to the next's, so its least is the lesser of the two (the track's chords read
    up to :data:`SAG_M` under it over a crest: a leg held at ``min_altitude_m`` failed by a centimetre).

    Parameters
    ----------
    terrain : Terrain
        The seabed.
    waypoints : array_like
        ``(N, 3)`` mission waypoints (m).
    follow : array_like of bool
        ``(N - 1,)``: the legs flown following the seabed.

    Returns
    -------
    numpy.ndarray
        ``(N - 1,)`` the least altitude (m) of each marked leg; ``inf`` on the others.
    """
    w, f = _flags(waypoints, follow)
    held = w[:, 2] - np.asarray(terrain.elevation(w[:, 0], w[:, 1]), dtype=float)  # each item's altitude
    out: FloatArray = np.where(f, np.minimum(held[:-1], held[1:]), np.inf)
    return out


def check_as_flown(world: World, waypoints: ArrayLike, follow: ArrayLike, launch: bool = True, *,
                   flown: FlownTrack | None = None) -> MissionCheck:
    """:func:`~auvplan.guidance.mission.flycheck.fly_check` (``"ramp"``) with the legs ``follow`` marks measured as
    they are flown: on the seabed-following track (:func:`terrain_track`), not on the straight line between their
    items, which such an executor does not fly.

    Each marked leg's least altitude is the altitude it holds (:func:`followed_altitude`, exact), its obstacle
    contact and least obstacle distance those of its track's segments (exact on each segment, as for a straight
    leg); unmarked legs are the straight 3D legs.  The surface,
    depth band and bounds are tested at the waypoints (``limits``), as ``fly_check`` does; the track's own
    extremes between items are ``mission check``'s terrain-following verdict.

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    waypoints : array_like
        ``(N, 3)`` mission waypoints (m).
    follow : array_like of bool
        ``(N - 1,)``: the legs flown following the seabed (without a seabed none is).
    launch : bool, optional
        Waypoint 0 is a launch point on the surface (exempt from the depth band).
    flown : FlownTrack, optional
        :func:`flown_track` of these waypoints and flags, when the caller has it (not computed again).

    Returns
    -------
    MissionCheck
        Per leg as flown; ``semantics`` ``"ramp"``.
    """
    w, f = _flags(waypoints, follow)
    if world.terrain is None or not f.any():
        f = np.zeros_like(f)
    n = max(w.shape[0] - 1, 0)
    alt, hits, dist = np.full(n, np.inf), np.zeros(n, dtype=bool), np.full(n, np.inf)
    alt[~f], hits[~f], dist[~f] = leg_figures(world, w[:-1][~f], w[1:][~f], "ramp")  # the straight legs flown
    if f.any():
        assert world.terrain is not None
        track, seg_leg = (flown.track, flown.leg) if flown is not None else terrain_track(world.terrain, w, f)
        on = f[seg_leg]
        _, t_hits, t_dist = leg_figures(world, track[:-1][on], track[1:][on], "ramp")
        alt[f] = followed_altitude(world.terrain, w, f)[f]  # the altitude held, not its chords' (under a crest)
        np.logical_or.at(hits, seg_leg[on], t_hits)
        np.minimum.at(dist, seg_leg[on], t_dist)
    m = world.margins
    k = int(np.argmin(alt)) if np.isfinite(alt).any() else -1
    return MissionCheck("ramp", float(alt.min()), k, float(dist.min()) if dist.size else np.inf, int(hits.sum()), alt,
                        m.min_altitude, m.obstacle, limits=waypoint_limits(world, w, launch))
