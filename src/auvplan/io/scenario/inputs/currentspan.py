"""Currents needed outside a file's time span (issue 51): refused unless the scenario states a rule.

A current file covers a time span; a mission that lasts longer needs currents the file does not have.
Before issue 51 the grid's clamping silently held the last field.  Now ``[currents] beyond`` decides:

* ``"refuse"`` (default) — exit 2 naming the file's span and the hours the mission needs: before planning
  when even the fastest possible transit (straight line at ``max_speed`` plus the strongest current) outlasts
  the file, else once the plan and flight say how long the mission lasts;
* ``"hold"`` — the field at the file's last time is held (the grid's clamping), and the run says so;
* ``"zero"`` — no current after the file's last time (a :data:`ZERO_RAMP_S` ramp to zero), and the run says so.
"""

from __future__ import annotations

import numpy as np

from ....errors import DataError
from ....sim import RunRecord
from ....world import World
from ....world.currents.fields import CurrentField, GriddedCurrent

__all__ = ["BEYOND", "ZERO_RAMP_S", "zero_beyond", "file_span", "lower_bound_s", "check_span", "run_note"]

BEYOND = ("refuse", "hold", "zero")
"""Values of ``[currents] beyond``."""
ZERO_RAMP_S = 1.0
"""With ``beyond = "zero"``, the current falls linearly to zero over this time after the file's last time (s)."""
_FAR_S = 1.0e12
"""Time of the last zero slice (s): beyond any mission."""


def zero_beyond(field: GriddedCurrent) -> GriddedCurrent:
    """The field with zero current after its last time (``beyond = "zero"``).

    Parameters
    ----------
    field : GriddedCurrent
        A time-varying grid.

    Returns
    -------
    GriddedCurrent
        The same grid with two zero slices appended, at ``t_end + ZERO_RAMP_S`` and far beyond.
    """
    t = np.asarray(field.t, dtype=float)
    shape = np.asarray(field.u).reshape(t.size, np.size(field.z), np.size(field.y), np.size(field.x)).shape
    zeros = np.zeros((2, *shape[1:]))

    def ext(c: object) -> np.ndarray:
        return np.concatenate([np.asarray(c, dtype=float).reshape(shape), zeros])

    return GriddedCurrent(field.x, field.y, field.z, ext(field.u), ext(field.v),
                          None if field.w is None else ext(field.w), np.r_[t, t[-1] + ZERO_RAMP_S, t[-1] + _FAR_S],
                          field.name)


def file_span(field: CurrentField, beyond: str) -> tuple[float, float] | None:
    """The time span (s from the start) of a time-varying current file; None for other fields.

    Parameters
    ----------
    field : CurrentField
        The world's current.
    beyond : str
        ``[currents] beyond`` (with ``"zero"`` the two appended slices are not the file's).

    Returns
    -------
    tuple of float or None
        ``(first, last)`` times (s).
    """
    if not isinstance(field, GriddedCurrent) or field.t is None or np.size(field.t) < 2:
        return None
    t = np.asarray(field.t, dtype=float)
    if beyond == "zero" and t.size > 3 and t[-1] - t[-3] >= _FAR_S:
        t = t[:-2]
    return float(t[0]), float(t[-1])


def lower_bound_s(world: World, start: np.ndarray, goal: np.ndarray, max_speed: float) -> float:
    """The least time any mission from ``start`` to ``goal`` can take: the straight line at the vehicle's
    top speed plus the strongest current.

    Parameters
    ----------
    world : World
        Its current (its largest speed).
    start, goal : numpy.ndarray
        ``(3,)`` points (m).
    max_speed : float
        The vehicle's top speed through the water (m/s).

    Returns
    -------
    float
        Seconds.
    """
    d = float(np.linalg.norm(np.asarray(goal, dtype=float) - np.asarray(start, dtype=float)))
    return d / max(max_speed + world.currents.max_speed, 1e-9)


def check_span(source: str, beyond: str, span: tuple[float, float] | None, needed_s: float,
               predicted: bool = True, cruise_s: float | None = None) -> str | None:
    """Refuse, or describe, currents needed past the file's span.

    Parameters
    ----------
    source : str
        The scenario file, for the message.
    beyond : str
        ``[currents] beyond``.
    span : tuple of float or None
        :func:`file_span`.
    needed_s : float
        How long the mission lasts (s from the start).
    predicted : bool, optional
        Whether ``needed_s`` is the mission's duration (True) or a lower bound of it (False).
    cruise_s : float, optional
        With a lower bound: the duration at the cruise speed through still water (s), also named.

    Returns
    -------
    str or None
        The note saying which rule was applied, None when the file covers the mission.

    Raises
    ------
    DataError
        With ``beyond = "refuse"``, naming the span and the hours needed.
    """
    if span is None or not np.isfinite(needed_s) or needed_s <= span[1] + 1e-6:
        return None
    what = "lasts" if predicted else "lasts at least"
    cruise = f" ({cruise_s / 3600:.2f} h at the cruise speed in still water)" if cruise_s else ""
    cover = f"covers {span[0] / 3600:.2f} to {span[1] / 3600:.2f} h from the start"
    if beyond == "refuse":
        raise DataError(f"{source}: [currents] the current file {cover}, but the mission {what} "
                        f"{needed_s / 3600:.2f} h{cruise}: {(needed_s - span[1]) / 3600:.2f} h without currents; give "
                        "a longer file or [currents] beyond = \"hold\" (hold the last field) or \"zero\" "
                        "(no current after the file)")
    rule = "the field at its last time held" if beyond == "hold" else "no current"
    return (f"currents: the file {cover}; the last {(needed_s - span[1]) / 3600:.2f} h of the {needed_s / 3600:.2f} h "
            f"mission fly with {rule} ([currents] beyond = \"{beyond}\")")


def run_note(source: str, beyond: str, world: World, record: RunRecord) -> str | None:
    """:func:`check_span` of a run: the mission lasts as long as its flight (else its timed plan, else its
    route at the planned speed is not known: nothing is said).

    Parameters
    ----------
    source : str
        The scenario file.
    beyond : str
        ``[currents] beyond``.
    world : World
        Its current.
    record : RunRecord
        The run.

    Returns
    -------
    str or None
        The note of the rule applied.

    Raises
    ------
    DataError
        With ``beyond = "refuse"`` when the run needed currents past the file.
    """
    if record.sim is not None and record.sim.t.size:
        needed = float(record.sim.t[-1])
    elif record.plan is not None and record.plan.times is not None and len(record.plan.times):
        needed = float(record.plan.times[-1])
    else:
        needed = float(record.plan.cost_terms.get("duration_s", np.nan)) if record.plan is not None else np.nan
    return check_span(source, beyond, file_span(world.currents, beyond), needed)
