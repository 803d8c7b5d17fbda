"""The charted zones a waypoint mission may enter under its executor's depth semantics.

A straight 3D leg is what a ``"ramp"`` executor flies (ArduSub, the polyline formats), and the zones' exact
segment test decides it.  A ``"held"`` executor (MOOS-IvP: one depth per leg) changes depth at a finite pitch
from wherever the previous leg left it: on a leg it lies anywhere in the leg's envelope (the vertical rectangle
between its two ends' depths), and a change not finished when a leg ends carries on into the next, outside that
leg's envelope (:func:`~auvplan.guidance.mission.flycheck.held_track`).  :func:`held_zone_entries` tests both,
as :func:`~auvplan.guidance.mission.flycheck.fly_check` does for the seabed and the obstacles: a mission that
climbs early through a band its straight legs pass under is caught.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..._types import IntArray
from ...geometry import as_points
from ...world.zones import Zones
from .flycheck import held_track

__all__ = ["held_zone_entries"]


def _track_legs(w: np.ndarray, track: np.ndarray) -> IntArray:
    """The leg (from 0) of each segment of :func:`held_track`'s polyline: per leg it adds a corner where a depth
    change ends (when it ends inside the leg) and the leg's end, whose horizontal position is the waypoint's.  A
    corner within a rounding of the leg's end lands on the waypoint itself: the last leg's then stays the last."""
    legs = np.empty(track.shape[0] - 1, dtype=np.intp)
    leg = 0
    for k in range(1, track.shape[0]):
        legs[k - 1] = leg
        if leg + 2 < w.shape[0] and track[k, 0] == w[leg + 1, 0] and track[k, 1] == w[leg + 1, 1]:
            leg += 1
    return legs


def held_zone_entries(zones: Zones, waypoints: ArrayLike, pitch_deg: float) -> tuple[IntArray, IntArray]:
    """Every (leg, zone) pair a depth-holding executor may enter: the leg's envelope meets the zone
    (:meth:`Zones.envelope_entries`), or the executor model's track on that leg does (:meth:`Zones.entries`).

    Parameters
    ----------
    zones : Zones
        The zones to test (``Zones.exact`` for a check of a mission).
    waypoints : array_like
        ``(N, 3)`` mission waypoints (m).
    pitch_deg : float
        Pitch of the executor model's depth changes (degrees).

    Returns
    -------
    leg, zone : numpy.ndarray of int
        The pairs (each once; legs from 0), sorted by leg, then zone.
    """
    w = as_points(waypoints).reshape(-1, 3)
    empty = np.zeros(0, dtype=np.intp)
    if not zones or w.shape[0] < 2:
        return empty, empty
    legs, zi = zones.envelope_entries(w[:-1], w[1:])
    track = held_track(w, pitch_deg)
    seg, tz = zones.entries(np.stack([track[:-1], track[1:]], axis=1))
    pairs = np.unique(np.concatenate([np.column_stack([legs, zi]), np.column_stack([_track_legs(w, track)[seg], tz])]),
                      axis=0).reshape(-1, 2)
    return pairs[:, 0].astype(np.intp), pairs[:, 1].astype(np.intp)
