"""Sending the page only what an edit changed: the waypoints as a splice on the revision the page holds.

Every distinct state of the session's waypoints and violations the server sends gets a revision number
(``rev``, increasing).  A page that says which revision it holds (``rev`` in its request) and is current
or one revision behind receives ``delta = {base, start, stop, waypoints, violations}``: the splice that
turns revision ``base`` into revision ``rev`` (replace its waypoints ``[start:stop]`` by ``waypoints``).
Moving one waypoint of a 1 000-waypoint mission sends one waypoint instead of a thousand; an insert, a
delete or an undo is a splice too.  A page further behind (another tab edited, a re-plan) gets the whole
list.

The protocol holds by construction, whatever order the answers arrive in:

- a splice names the revision it applies to (``base``) and the one it makes (``rev``): the page applies
  it only on exactly that base (:func:`take`), drops an answer older than what it shows, and otherwise
  asks for the whole state;
- an edit names the revision it was made on, and the server refuses it (:class:`StaleRevision`, HTTP
  409) unless that is the session's current state (:meth:`Revisions.require`): an index picked on an old
  picture never moves or deletes another waypoint.

The page's rule is ``static/delta.js``; :func:`take` is the same rule in Python (the tests drive both).
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import AuvplanError

__all__ = ["changed_slice", "changed_items", "Revisions", "StaleRevision", "PageCopy", "take"]

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


class StaleRevision(AuvplanError):
    """An edit made on a revision that is no longer the session's (answered with HTTP 409)."""


class Revisions:
    """Revision numbers of a session's waypoints and violations, and the splices from the previous ones.

    The caller holds the session's lock around :meth:`require` and the edit, and around :meth:`state`
    and the read of the waypoints it is given, so that a revision always names one state.
    """

    def __init__(self) -> None:
        self.rev = 0
        self._current: tuple[_F64, list[dict[str, Any]]] | None = None
        self._previous: tuple[_F64, list[dict[str, Any]]] | None = None
        self._lock = threading.Lock()

    def _stamp(self, waypoints: _F64, violations: list[dict[str, Any]]) -> tuple[_F64, list[dict[str, Any]]]:
        """The current snapshot, a new revision when the waypoints or violations changed (lock held)."""
        cur = self._current
        if cur is None or not np.array_equal(cur[0], waypoints) or cur[1] != violations:
            self._previous = cur
            cur = self._current = (np.array(waypoints, dtype=float, copy=True), list(violations))
            self.rev += 1
        return cur

    def require(self, known: Any, waypoints: _F64, violations: list[dict[str, Any]]) -> None:
        """Refuse an edit made on a revision other than the session's current state.

        Parameters
        ----------
        known : int or None
            The revision the page made its edit on (``rev`` of its request); ``None`` (a script that
            sends no revision) is always accepted.
        waypoints : numpy.ndarray
            The session's current ``(N, 3)`` waypoints.
        violations : list of dict
            Their check's violations.

        Raises
        ------
        StaleRevision
            When ``known`` is not the revision of the current waypoints and violations.
        """
        if known is None:
            return
        with self._lock:
            self._stamp(waypoints, violations)
            if known != self.rev or isinstance(known, bool):
                raise StaleRevision(f"rev {known!r}: the mission changed since (now revision {self.rev}); the edit "
                                    "was not applied and the page shows the current mission")

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
            splices: ``base`` = ``known``, ``start``, ``stop``, ``waypoints`` and ``violations`` =
            ``{start, stop, items}``) or ``waypoints`` (the whole list; the page then reads the whole
            violations from the check).
        """
        with self._lock:
            cur = self._stamp(waypoints, violations)
            out: dict[str, Any] = {"rev": self.rev}
            valid = isinstance(known, int) and not isinstance(known, bool)
            if valid and known == self.rev:
                out["delta"] = {"base": known, "start": 0, "stop": 0, "waypoints": np.empty((0, 3)),
                                "violations": {"start": 0, "stop": 0, "items": []}}
            elif valid and known == self.rev - 1 and self._previous is not None:
                (w0, v0), (w1, v1) = self._previous, cur
                start, stop_old, stop_new = changed_slice(w0, w1)
                vs, vstop_old, vstop_new = changed_items(v0, v1)
                out["delta"] = {"base": known, "start": start, "stop": stop_old, "waypoints": w1[start:stop_new],
                                "violations": {"start": vs, "stop": vstop_old, "items": v1[vs:vstop_new]}}
            else:
                out["waypoints"] = waypoints  # and the violations in the check, whole
            return out


class PageCopy:
    """What the page holds: the server's waypoints and violations at revision ``rev`` (``None``: nothing)."""

    def __init__(self) -> None:
        self.rev: int | None = None
        self.waypoints: list[list[float]] = []
        self.violations: list[Any] = []


def take(page: PageCopy, st: dict[str, Any]) -> str:
    """Apply one answer of the server to the page's copy: the rule of ``static/delta.js``, in Python.

    Parameters
    ----------
    page : PageCopy
        The page's copy, changed in place.
    st : dict
        An answer (JSON data): ``rev`` and ``delta`` or ``waypoints`` (with ``check.violations``).

    Returns
    -------
    str
        ``"ok"`` (applied), ``"stale"`` (older than the copy: dropped whole) or ``"gap"`` (a splice on
        a revision the copy does not hold: the copy is emptied and the page asks for the whole state).
    """
    rev = st.get("rev")
    if page.rev is not None and rev is not None and rev < page.rev:
        return "stale"
    d = st.get("delta")
    if d is not None and rev is not None and page.rev is not None and d["base"] == page.rev:
        page.waypoints[d["start"]:d["stop"]] = [list(p) for p in d["waypoints"]]
        v = d["violations"]
        page.violations[v["start"]:v["stop"]] = list(v["items"])
    elif d is None and "waypoints" in st:
        page.waypoints = [list(p) for p in st["waypoints"]]
        page.violations = list((st.get("check") or {}).get("violations") or [])
    else:
        page.rev = None
        return "gap"
    page.rev = rev
    return "ok"
