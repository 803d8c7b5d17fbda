"""A survey's route made safe under held depth (MOOS-IvP), as ``run``'s mission builder makes its exports.

A survey's route is checked along its straight 3D legs (:meth:`World.segments_free`), but a depth-holding
executor changes depth at the start of a leg and then holds it: on a long climbing turn, bridge or transit
leg it flies level at the deeper end's depth under rising seabed.  :func:`held_safe` re-checks every leg's
envelope (:func:`~auvplan.guidance.mission.flycheck.leg_figures`, the exact test ``auvplan mission check``
applies: depth anywhere between the two ends') and splits each failing leg in halves along its 3D line
until every piece's envelope clears the seabed, the obstacles and the no-go zones' depth bands (a leg that
changes depth; a level leg in a band cannot be mended so), or the pieces would be shorter than the vehicle's
shortest leg; the executor's own track (:func:`~auvplan.guidance.mission.flycheck.held_track`) is then flown
too, and the zones checked on both (:func:`~auvplan.guidance.mission.zone_legs.held_zone_entries`).  What
cannot be fixed is said, naming the leg, so the survey is not reported exact.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..guidance.mission.flycheck import held_track, leg_figures, segment_figures
from ..guidance.mission.zone_legs import held_zone_entries
from ..world import World

__all__ = ["held_safe", "held_failures"]

_TURN = -1
"""Label of a point inserted between two labels that differ (a join: turn or transit); as ``mission.TURN``."""


def held_failures(world: World, route: NDArray[np.float64]) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """The legs whose held-depth envelope breaks ``min_altitude`` or an obstacle's margin.

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    route : numpy.ndarray
        ``(N, 3)`` waypoints (m).

    Returns
    -------
    bad : numpy.ndarray
        ``(N - 1,)`` bool, the leg fails.
    altitude : numpy.ndarray
        ``(N - 1,)`` least altitude of each leg's envelope (m).
    """
    alt, hits, _ = leg_figures(world, route[:-1], route[1:], "held")
    return (alt < world.margins.min_altitude - 1e-6) | hits, alt


def _zone_legs(world: World, route: NDArray[np.float64]) -> NDArray[np.bool_]:
    """``(N - 1,)`` bool: the leg's held-depth envelope (any depth between its ends') enters a zone's depth band."""
    out = np.zeros(max(route.shape[0] - 1, 0), dtype=bool)
    if world.zones and route.shape[0] >= 2:
        out[world.zones.exact.envelope_entries(route[:-1], route[1:])[0]] = True
    return out


def _split(route: NDArray[np.float64], labels: NDArray[np.int64],
           legs: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Insert the 3D midpoint of each leg in ``legs``; its label is the leg's, or ``TURN``/``TRANSIT`` at a join."""
    mid = 0.5 * (route[legs] + route[legs + 1])
    la, lb = labels[legs], labels[legs + 1]
    lab = np.where(la == lb, la, np.minimum(np.minimum(la, lb), _TURN))
    return np.insert(route, legs + 1, mid, axis=0), np.insert(labels, legs + 1, lab)


def held_safe(world: World, route: NDArray[np.float64], labels: NDArray[np.int64], pitch_deg: float,
              min_leg: float, describe: dict[int, str] | None = None,
              ) -> tuple[NDArray[np.float64], NDArray[np.int64], str]:
    """Split the legs whose held-depth envelope fails until it clears; say what cannot be fixed.

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins.
    route : numpy.ndarray
        ``(N, 3)`` waypoints (m) whose straight legs pass the exact test.
    labels : numpy.ndarray
        ``(N,)`` labels (line number, or negative for a turn or transit).
    pitch_deg : float
        Pitch of the executor's depth changes (degrees; the survey's pitch limit).
    min_leg : float
        Shortest leg the vehicle's helm accepts (m): no piece is made shorter.
    describe : dict, optional
        Names of the negative labels (``{-1: "a turn", -2: "a transit"}``).

    Returns
    -------
    route, labels : numpy.ndarray
        The route with the inserted points (every inserted point on its leg's 3D line).
    message : str
        ``''`` when every leg's envelope and the executor's track clear; else which leg fails.
    """
    names = describe or {}
    route, labels = np.asarray(route, dtype=float), np.asarray(labels, dtype=np.int64)
    if route.shape[0] < 2:
        return route, labels, ""
    route, labels, bad, alt, length = _split_until_clear(world, route, labels, min_leg)
    return route, labels, _held_message(world, route, labels, bad, alt, length, pitch_deg, names)


def _split_until_clear(world: World, route: NDArray[np.float64], labels: NDArray[np.int64], min_leg: float
                       ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.bool_], NDArray[np.float64],
                                  NDArray[np.float64]]:
    """Split every leg whose held-depth envelope fails (or, changing depth, enters a zone's band) while its halves
    are no shorter than ``min_leg``: the route, its labels, the legs still failing, their least altitudes and the
    legs' horizontal lengths."""
    while True:
        bad, alt = held_failures(world, route)
        zoned = _zone_legs(world, route)  # a depth-changing leg's envelope in a zone's band: split, as for the seabed
        length = np.hypot(*np.diff(route[:, :2], axis=0).T)
        fixable = bad | (zoned & (np.abs(np.diff(route[:, 2])) > 1e-6))
        fix = np.flatnonzero(fixable & (0.5 * np.linalg.norm(np.diff(route, axis=0), axis=1) >= max(min_leg, 1e-3)))
        if not fix.size:
            return route, labels, bad, alt, length
        route, labels = _split(route, labels, fix)


def _held_message(world: World, route: NDArray[np.float64], labels: NDArray[np.int64], bad: NDArray[np.bool_],
                  alt: NDArray[np.float64], length: NDArray[np.float64], pitch_deg: float,
                  names: dict[int, str]) -> str:
    """``''`` when every leg's envelope and the executor's track clear; else which leg fails, and how."""
    m = world.margins
    if bad.any():
        i = int(np.flatnonzero(bad)[np.argmin(alt[bad])])
        lab = int(labels[i])
        what = f"line {lab}" if lab >= 0 else names.get(lab, "a join")
        return (f"leg {i} ({what}, {length[i]:.0f} m from ({route[i, 0]:.0f}, {route[i, 1]:.0f}, "
                f"{route[i, 2]:.0f})) fails the held-depth check: least altitude {alt[i]:.2f} m < "
                f"min_altitude {m.min_altitude:g} m or an obstacle's margin")
    if world.zones:  # every leg's envelope and the executor's track, as `mission check` of the mission.moos
        legs, zi = held_zone_entries(world.zones.exact, route, pitch_deg)
        if legs.size:
            i, lab = int(legs[0]), int(labels[int(legs[0])])
            what = f"line {lab}" if lab >= 0 else names.get(lab, "a join")
            return (f"leg {i} ({what}, {length[i]:.0f} m from ({route[i, 0]:.0f}, {route[i, 1]:.0f}, "
                    f"{route[i, 2]:.0f})) enters no-go zone {world.zones.names[int(zi[0])]!r} when "
                    f"flown with depth held at {pitch_deg:g}° pitch (the zone's depth band holds it)")
    trk = held_track(route, pitch_deg)
    seg_alt, seg_hits = segment_figures(world, trk[:-1], trk[1:])
    low = seg_alt < m.min_altitude - 1e-6
    if low.any() or seg_hits.any():
        j = int(np.flatnonzero(low | (seg_hits > 0))[0])
        return (f"flown with depth held at {pitch_deg:g}° pitch, the track near ({trk[j, 0]:.0f}, "
                f"{trk[j, 1]:.0f}, {trk[j, 2]:.0f}) breaks min_altitude {m.min_altitude:g} m or an "
                f"obstacle's margin (least altitude {float(seg_alt.min()):.2f} m)")
    return ""
