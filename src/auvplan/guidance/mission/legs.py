"""Near-duplicate waypoints merged, so that every leg of an exported mission is long enough to fly (issue 49).

A mission built from a dense path or a dense depth profile can hold waypoints millimetres apart (a turn
region's end next to a profile sample, a leg halved ten times next to an obstacle): a helm judges each
leg on its own (:func:`auvplan.path.legs.helm_check`), and such a leg reads a pitch of many degrees once its
ends are rounded, or a turn no vehicle makes.  :func:`merge_short_legs` drops one end of every leg
shorter than the shortest leg allowed, never the mission's ends or its fixed vertices (an operator's
corners), and only where the leg that replaces the two is safe:

* the straight leg is free by the exact test every export's check applies (:meth:`World.segments_free` without
  the moving obstacles: the seabed's exact walk, the static obstacles' margins, land, the charted zones'
  segment-vs-prism test), or one of the two straight legs it replaces was not (the check refuses that mission
  whatever is merged): a vertex moved by a few centimetres can cut a corner into the seabed over a crest or
  into a zone, and a ramp executor flies the straight leg, so a merge in a mission whose envelopes are not
  free (a climb over a crest) must be proven by this test, not by the envelope's;
* its envelope (depth held at either end, :func:`auvplan.guidance.mission.envelopes.envelopes_free`) is free,
  or one of the two legs it replaces was not free already (the merge loses no safety the mission had);
* its pitch is at most the larger of the limit and the steeper of the two legs it replaces.

A short leg whose ends cannot go stays, and the check names it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..._types import FloatArray, IntArray
from ...path.flyable import leg_pitch_deg
from ...world import World
from .envelopes import envelopes_free

__all__ = ["merge_short_legs"]


def _droppable(world: World, q: FloatArray, j: int, max_pitch_deg: float) -> bool:
    """Whether vertex ``j`` of ``q`` (interior) may go: the new leg is safe (module notes)."""
    a, b = q[j - 1], q[j + 1]
    if float(np.linalg.norm(b - a)) <= 0.0:
        return True
    old = q[j - 1:j + 2]
    new_pitch = abs(float(leg_pitch_deg(np.stack([a, b]))[0]))
    if new_pitch > max(max_pitch_deg, float(np.abs(leg_pitch_deg(old)).max())) + 1e-9:
        return False
    # the straight legs: the exact test (the ends are the mission's own, so their point limits are unchanged)
    segs = np.stack([np.stack([a, b]), old[:2], old[1:]])
    free = world.segments_free(segs, moving=False, ends_free=True)
    if not free[0] and free[1:].all():
        return False
    if bool(envelopes_free(world, a[None], b[None])[0]):
        return True
    return not bool(envelopes_free(world, old[:-1], old[1:]).all())


def merge_short_legs(world: World, waypoints: ArrayLike, min_leg: float, fixed: ArrayLike | None = None,
                     max_pitch_deg: float = 90.0) -> IntArray:
    """Drop waypoints so that no leg is shorter than ``min_leg`` where that is safe (module notes).

    Parameters
    ----------
    world : World
        Seabed, static obstacles and margins (the envelope test).
    waypoints : array_like
        ``(N, 3)`` mission (m).
    min_leg : float
        Shortest leg allowed (m, 3D; :func:`auvplan.path.legs.shortest_leg`).
    fixed : array_like of int, optional
        Indices that must stay (the mission's corners); the first and the last always stay.
    max_pitch_deg : float, default 90.0
        The vehicle's pitch limit.

    Returns
    -------
    numpy.ndarray
        Indices of the waypoints kept (increasing, from 0 to N - 1): the short legs' droppable ends removed.
    """
    w = np.asarray(waypoints, dtype=float).reshape(-1, 3)
    n = len(w)
    if n < 3 or min_leg <= 0.0:
        return np.arange(n, dtype=np.intp)
    pinned = np.zeros(n, dtype=bool)
    pinned[[0, -1]] = True
    if fixed is not None:
        pinned[np.asarray(fixed, dtype=np.intp)] = True
    keep = np.ones(n, dtype=bool)
    stuck: set[tuple[int, int]] = set()
    for _ in range(n):
        idx = np.flatnonzero(keep)
        q = w[idx]
        length = np.linalg.norm(np.diff(q, axis=0), axis=1)
        short = [int(k) for k in np.flatnonzero(length < min_leg) if (int(idx[k]), int(idx[k + 1])) not in stuck]
        if not short:
            break
        k = short[0]
        # drop the end whose removal leaves the longer new leg first (the leg's far side), never a pinned one
        for j in sorted((k, k + 1), key=lambda j: -float(np.linalg.norm(q[min(j + 1, len(q) - 1)] - q[max(j - 1, 0)]))):
            if 0 < j < len(q) - 1 and not pinned[idx[j]] and _droppable(world, q, j, max_pitch_deg):
                keep[idx[j]] = False
                break
        else:
            stuck.add((int(idx[k]), int(idx[k + 1])))
    out: IntArray = np.flatnonzero(keep)
    return out
