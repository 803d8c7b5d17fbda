"""Survey lines clipped by the charted ``[[zones]]``: the route's vertices inside a zone's convex hull grown
by the turn radius are dropped (the part of a line over a zone, or in a concave notch of one, is not
surveyed) and each gap is bridged by a transit round the zones: straight when the straight leg is free,
else along the convex hull of the grown hulls it meets (arcs of the turn radius round their corners),
else by the global planner.

The zones are the world's (padded: the planners' margin); the bridged route then goes through the same
exact seabed, obstacle and zone test as every survey (:func:`auvplan.survey.mission.plan_survey`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import shapely
from numpy.typing import NDArray

from ..planners.core.base import PlanResult, Progress
from ..sim import Mission, planned_route
from ..world import World, Zone, Zones

__all__ = ["clip_to_zones"]


def _hull_detour(world: World, a: NDArray[np.float64], b: NDArray[np.float64], grown: list[shapely.Geometry]
                 ) -> NDArray[np.float64] | None:
    """The shorter way from ``a`` to ``b`` along the convex hull of the grown footprints the straight leg
    meets (and of ``a`` and ``b``), depth ramped along it; None when it is not free."""
    trace = shapely.LineString([a[:2], b[:2]])
    hit = [g for g in grown if shapely.intersects(g, trace)]
    if not hit:
        return None
    hull = shapely.convex_hull(shapely.union_all([*hit, shapely.MultiPoint([a[:2], b[:2]])]))
    ring = np.asarray(hull.exterior.coords)[:-1]
    ia = int(np.argmin(np.hypot(*(ring - a[:2]).T)))
    ib = int(np.argmin(np.hypot(*(ring - b[:2]).T)))
    if not (np.allclose(ring[ia], a[:2]) and np.allclose(ring[ib], b[:2])):
        return None
    n = ring.shape[0]
    ways = [ring[[(ia + k) % n for k in range((ib - ia) % n + 1)]],
            ring[[(ia - k) % n for k in range((ia - ib) % n + 1)]]]
    for xy in sorted(ways, key=lambda w: float(np.hypot(*np.diff(w, axis=0).T).sum())):
        arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
        z = a[2] + (b[2] - a[2]) * arc / max(arc[-1], 1e-9)
        path = np.column_stack([xy, z])
        path[0], path[-1] = a, b
        if world.segments_free(np.stack([path[:-1], path[1:]], axis=1), moving=False).all():
            return path
    return None


def clip_to_zones(world: World, mission: Mission, route: NDArray[np.float64], labels: NDArray[np.int64],
                  transit: int, seed: int = 0, progress: Progress | None = None, radius: float = 10.0
                  ) -> tuple[NDArray[np.float64], NDArray[np.int64], list[PlanResult], str]:
    """Clip a survey route by the world's zones.

    Parameters
    ----------
    world : World
        Seabed, obstacles and zones.
    mission : Mission
        Vehicle and planner of the bridging transits.
    route : numpy.ndarray
        ``(N, 3)`` lines and turns (m).
    labels : numpy.ndarray of int
        ``(N,)`` their labels (line number, or the turn label).
    transit : int
        The label of a bridging transit's vertices.
    seed : int, default 0
        Seed of the transit planner.
    progress : callable, optional
        Progress of the transit planner.
    radius : float, default 10.0
        The vehicle's turn radius (m): the zones are grown by it for the clipping and the detours.

    Returns
    -------
    tuple
        The clipped route ``(M, 3)``, its labels ``(M,)``, the transits' plans, and ``''`` or why a
        transit failed.
    """
    zones = world.zones
    if not zones or route.shape[0] < 2:
        return route, labels, [], ""
    hulls, inside, seg_in = _entries(zones, route, radius)
    if not inside.any() and not seg_in.any():
        return route, labels, [], ""
    keep = np.flatnonzero(~inside)
    if keep.size < 2:
        return route, labels, [], "every survey line lies inside a no-go zone"
    grown = [shapely.buffer(z.footprint, zones.pad + radius) for z in hulls]
    parts, labs, plans = [route[keep[:1]]], [labels[keep[:1]]], []
    for a, b in zip(keep[:-1], keep[1:], strict=True):
        if b == a + 1 and not seg_in[a] or world.segments_free(np.stack([route[a], route[b]])[None], moving=False)[0]:
            parts.append(route[b:b + 1])
            labs.append(labels[b:b + 1])
            continue
        path, planned = _bridge(world, mission, route[a], route[b], grown, seed, progress)
        if planned is not None:
            plans.append(planned)
        if path is None:
            assert planned is not None
            return route, labels, plans, (f"the transit round a no-go zone from ({route[a, 0]:.0f}, {route[a, 1]:.0f}) "
                                          f"failed ({planned.status.value}): {planned.message}")
        parts += [path[1:-1], route[b:b + 1]]
        labs += [np.full(path.shape[0] - 2, transit, dtype=np.int64), labels[b:b + 1]]
    return np.vstack(parts), np.concatenate(labs).astype(np.int64), plans, ""


def _bridge(world: World, mission: Mission, pa: NDArray[np.float64], pb: NDArray[np.float64],
            grown: list[shapely.Geometry], seed: int, progress: Progress | None
            ) -> tuple[NDArray[np.float64] | None, PlanResult | None]:
    """A way from ``pa`` to ``pb`` round the zones: the detour along their grown hulls, else a transit planned by
    the mission's planner (its plan too; no way when it fails)."""
    detour = _hull_detour(world, pa, pb, grown)
    if detour is not None:
        return detour, None
    ends = replace(mission, start=(float(pa[0]), float(pa[1]), float(pa[2])),
                   goal=(float(pb[0]), float(pb[1]), float(pb[2])), route=())
    planned, path = planned_route(world, ends, seed, progress)
    assert planned is not None
    return path, planned


def _entries(zones: Zones, route: NDArray[np.float64], radius: float
             ) -> tuple[tuple[Zone, ...], NDArray[np.bool_], NDArray[np.bool_]]:
    """The zones' convex hulls, the vertices within ``radius`` of a hull, and the legs that enter a zone.

    A vertex within the turn radius of a zone's convex hull is dropped: a line's end left in a concave notch would
    sit inside the hull the detours follow, and the way out of the notch has sharp corners."""
    hulls = tuple(replace(z, footprint=shapely.convex_hull(z.footprint)) for z in zones.zones)
    wide = Zones(hulls, zones.terrain, zones.pad + radius)
    inside = wide.segments_enter(np.stack([route, route], axis=1))
    seg_in = zones.segments_enter(np.stack([route[:-1], route[1:]], axis=1))
    return hulls, inside, seg_in
