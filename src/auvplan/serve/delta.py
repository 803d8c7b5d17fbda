"""Sending the page only what an edit changed: the waypoints as a splice on the revision the page holds.

Every change of the session's waypoints makes a new revision.  A page that says which revision it
holds (``rev`` in its request) and is one revision behind receives ``delta = {start, stop, waypoints}``:
replace its waypoints ``[start:stop]`` by ``waypoints``.  Moving one waypoint of a 1 000-waypoint
mission sends one waypoint instead of a thousand; an insert, a delete or an undo is a splice too.
A page further behind (another tab edited, a re-plan) gets the whole list.
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["changed_slice", "changed_items", "Revisions"]

_F64 = NDArray[np.float64]
"""Array of float64 (m)."""


def changed_slice(old: _F64, new: _F64) -> tuple[int, int, int]:
    """The one slice that turns ``old`` into ``new``: ``new = old[:start] + new[start:stop_new] + old[stop_old:]``.

    Parameters
    ----------
    old, new : numpy.ndarray
        ``(N, 3)`` and ``(M, 3)`` waypoints.

    Returns
    -------
    start, stop_old, stop_new : int
        The common prefix ends at ``start``; the common suffix starts at ``stop_old`` in ``old`` and
        ``stop_new`` in ``new`` (the suffix never overlaps the prefix).
    """
    n, m = old.shape[0], new.shape[0]
    k = min(n, m)
    same = np.all(old[:k] == new[:k], axis=1)
    start = int(np.argmin(same)) if not same.all() else k
    tail = np.all(old[n - k:][::-1] == new[m - k:][::-1], axis=1)[: k - start]
    suffix = int(np.argmin(tail)) if not tail.all() else k - start
    return start, n - suffix, m - suffix


def changed_items(old: list[Any], new: list[Any]) -> tuple[int, int, int]:
    """:func:`changed_slice` of two lists (items compared with ``==``; a changed item is re-sent).

    Parameters
    ----------
    old, new : list
        The previous and the current items (e.g. the violations, in leg order).

    Returns
    -------
    start, stop_old, stop_new : int
        ``new = old[:start] + new[start:stop_new] + old[stop_old:]``.
    """
    n, m = len(old), len(new)
    k = min(n, m)
    start = 0
    while start < k and old[start] == new[start]:
        start += 1
    suffix = 0
    while suffix < k - start and old[n - 1 - suffix] == new[m - 1 - suffix]:
        suffix += 1
    return start, n - suffix, m - suffix


class Revisions:
    """Revision numbers of a session's waypoints and violations, and the splices from the previous ones."""

    def __init__(self) -> None:
        self.rev = 0
        self._current: tuple[_F64, list[dict[str, Any]]] | None = None
        self._previous: tuple[_F64, list[dict[str, Any]]] | None = None
        self._lock = threading.Lock()

    def state(self, waypoints: _F64, violations: list[dict[str, Any]], known: Any = None) -> dict[str, Any]:
        """The waypoints' and violations' part of the page's state.

        Parameters
        ----------
        waypoints : numpy.ndarray
            The session's current ``(N, 3)`` waypoints.
        violations : list of dict
            Their check's violations (in leg order).
        known : int, optional
            The revision the page holds (``rev`` of its last state), if it said.

        Returns
        -------
        dict
            ``rev`` and either ``delta`` (the page is one revision behind, or current and gets empty
            splices: ``start``, ``stop``, ``waypoints`` and ``violations`` = ``{start, stop, items}``) or
            ``waypoints`` (the whole list; the page then reads the whole violations from the check).
        """
        with self._lock:
            cur = self._current
            if cur is None or not np.array_equal(cur[0], waypoints) or cur[1] != violations:
                self._previous = cur
                cur = self._current = (np.array(waypoints, dtype=float, copy=True), list(violations))
                self.rev += 1
            out: dict[str, Any] = {"rev": self.rev}
            valid = isinstance(known, int) and not isinstance(known, bool)
            if valid and known == self.rev:
                out["delta"] = {"start": 0, "stop": 0, "waypoints": np.empty((0, 3)),
                                "violations": {"start": 0, "stop": 0, "items": []}}
            elif valid and known == self.rev - 1 and self._previous is not None:
                (w0, v0), (w1, v1) = self._previous, cur
                start, stop_old, stop_new = changed_slice(w0, w1)
                vs, vstop_old, vstop_new = changed_items(v0, v1)
                out["delta"] = {"start": start, "stop": stop_old, "waypoints": w1[start:stop_new],
                                "violations": {"start": vs, "stop": vstop_old, "items": v1[vs:vstop_new]}}
            else:
                out["waypoints"] = waypoints  # and the violations in the check, whole
            return out
