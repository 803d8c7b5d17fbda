"""Actions on the mission's waypoints: move, insert, delete, set a depth, undo, the check's settings,
keep a candidate and choose one.

Each edit is bounded before it is checked (a position in the scenario's area:
:func:`~auvplan.serve.bounds.inside_area`) and is made under the session's ``write_lock`` (edits are
short and one at a time); the check runs outside the state lock.
"""

from __future__ import annotations

import numpy as np

from ...app.page.check import CheckResult, CheckSettings
from ...app.page.plans import nearest_leg
from ...errors import AuvplanError
from ..bounds import inside_area, scalar
from ..session import Candidate, Session

__all__ = ["edit", "undo", "set_check", "keep", "choose"]


def edit(session: Session, op: str, index: int | None = None, x: float | None = None, y: float | None = None,
         z: float | None = None) -> CheckResult:
    """Move, insert or delete a waypoint, or set its depth; then re-check.

    Parameters
    ----------
    session : Session
        The page's state.
    op : {'move', 'insert', 'delete', 'depth'}
        ``move`` waypoint ``index`` to ``(x, y)`` (and ``z`` when given); ``insert`` a waypoint at
        ``(x, y)`` into the nearest leg (depth interpolated along it, or ``z``); ``delete`` waypoint
        ``index``; ``depth``: set waypoint ``index``'s ``z``.
    index : int, optional
        The waypoint.
    x, y, z : float, optional
        Local coordinates (m).

    Returns
    -------
    CheckResult
        The check of the edited mission.
    """
    if op not in ("move", "insert", "delete", "depth"):
        raise AuvplanError(f"edit op = {op!r}: choose move, insert, delete or depth")
    with session.write_lock:
        w = session.waypoints.copy()
        n = w.shape[0]
        if op in ("move", "delete", "depth"):
            if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < n:
                raise AuvplanError(f"waypoint {index!r}: no such waypoint (0 to {n - 1})")
        xyz = [None if v is None else scalar(v, f"{op} {k}") for k, v in (("x", x), ("y", y), ("z", z))]
        inside_area(session.require()[0], op, index if op != "insert" else None, xyz)
        if op == "move":
            if xyz[0] is None or xyz[1] is None:
                raise AuvplanError("move: x and y are needed")
            w[index, 0], w[index, 1] = xyz[0], xyz[1]
            if xyz[2] is not None:
                w[index, 2] = xyz[2]
            text = f"moved waypoint {index} to ({xyz[0]:.0f}, {xyz[1]:.0f}, {w[index, 2]:.0f}) m"
        elif op == "depth":
            if xyz[2] is None:
                raise AuvplanError("depth: z is needed")
            w[index, 2] = xyz[2]
            text = f"set waypoint {index} to depth {-xyz[2]:.1f} m"
        elif op == "insert":
            if xyz[0] is None or xyz[1] is None:
                raise AuvplanError("insert: x and y are needed")
            leg, f = nearest_leg(w, np.array([xyz[0], xyz[1]]))
            zi = w[leg, 2] + f * (w[leg + 1, 2] - w[leg, 2]) if xyz[2] is None else xyz[2]
            w = np.insert(w, leg + 1, [xyz[0], xyz[1], zi], axis=0)
            index = leg + 1
            text = f"inserted waypoint {index} at ({xyz[0]:.0f}, {xyz[1]:.0f}, {zi:.0f}) m"
        elif op == "delete":
            if n <= 2:
                raise AuvplanError("delete: a mission needs at least 2 waypoints (a start and a goal)")
            w = np.delete(w, int(index or 0), axis=0)
            text = f"deleted waypoint {index}"
        else:
            raise AuvplanError(f"edit op = {op!r}: choose move, insert, delete or depth")
        return session.apply(w, op, text)


def undo(session: Session) -> CheckResult:
    """Go back to the waypoints before the last edit.

    Parameters
    ----------
    session : Session
        The page's state.

    Returns
    -------
    CheckResult
        The check of the restored mission.
    """
    with session.write_lock:
        if not session.undo_stack:
            raise AuvplanError("undo: nothing to undo")
        session.set_waypoints(session.undo_stack.pop())
        session.record("undo", "undid the last edit")
        assert session.result is not None
        return session.result


def set_check(session: Session, semantics: str, pitch_deg: float) -> CheckResult:
    """Check under another executor's semantics or pitch.

    Parameters
    ----------
    session : Session
        The page's state.
    semantics : {'held', 'ramp'}
        Depth held per leg (MOOS-IvP) or ramped along it (every other export).
    pitch_deg : float
        Pitch of the held executor's depth changes (degrees).

    Returns
    -------
    CheckResult
        The new check.
    """
    if isinstance(pitch_deg, bool) or not isinstance(pitch_deg, (int, float)):
        raise AuvplanError(f"check pitch = {str(pitch_deg)[:80]!r}: expected a number of degrees")
    try:  # each setting named by its own message (a bad semantics was blamed on '--pitch 15': hostile round 20)
        settings = CheckSettings(str(semantics)[:80], float(pitch_deg))
    except (TypeError, ValueError, OverflowError) as exc:
        raise AuvplanError(f"check {exc}") from None
    with session.write_lock:
        session.settings = settings
        return session.commit(session.waypoints)


def keep(session: Session, name: str = "") -> Candidate:
    """Keep the current mission as a candidate.

    Parameters
    ----------
    session : Session
        The page's state.
    name : str, optional
        Its name in the table.

    Returns
    -------
    Candidate
        The kept candidate.
    """
    if name is not None and not isinstance(name, str) or any(not c.isprintable() for c in name or ""):
        # was kept as str(value) ("{'a': 1}"), a newline or U+202E in the candidates' table (hostile round 20)
        raise AuvplanError(f"keep name = {str(name)[:80]!r}: a candidate's name is text without control or "
                           "formatting characters")
    with session.lock:
        label = (name or f"edited {len(session.candidates) + 1}").strip()[:80]
        return session.keep_current(label, "edited", session.plan)


def choose(session: Session, index: int) -> CheckResult:
    """Make candidate ``index`` the current mission.

    Parameters
    ----------
    session : Session
        The page's state.
    index : int
        Row of the candidates table.

    Returns
    -------
    CheckResult
        Its check.
    """
    with session.write_lock:
        if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < len(session.candidates):
            raise AuvplanError(f"candidate {index!r}: no such candidate")
        c = session.candidates[index]
        with session.lock:
            session.plan = c.plan
        return session.apply(c.waypoints, "choose", f"chose candidate {c.name}")
