"""Figure of a departure-time sweep: duration and energy versus departure, beside the straight line
and the steady-current plan flown through the same changing current."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..planners.timeopt.planner import SweepRow

__all__ = ["sweep_figure"]


def sweep_figure(rows: Sequence[SweepRow], title: str = "") -> Figure:
    """Draw duration (h) and energy (kJ) versus the departure (h after the start time) in two panels.

    Parameters
    ----------
    rows : sequence of SweepRow
        One row per departure time, with the timed plan's, the steady-current plan's and the straight
        line's duration (s) and energy (J).
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (never shown).
    """
    from matplotlib.figure import Figure

    d = np.array([r.depart_s for r in rows]) / 3600.0
    fig = Figure(figsize=(8.0, 6.0), layout="constrained")
    ax_t, ax_e = fig.subplots(2, 1, sharex=True)
    series = (("timed plan", "duration_s", "energy_j", "C0", "-"),
              ("steady-current plan", "steady_duration_s", "steady_energy_j", "C1", "--"),
              ("straight line", "straight_duration_s", "straight_energy_j", "C2", ":"))
    for label, dur, en, colour, style in series:
        ax_t.plot(d, [getattr(r, dur) / 3600.0 for r in rows], style, color=colour, marker=".", label=label)
        ax_e.plot(d, [getattr(r, en) / 1e3 for r in rows], style, color=colour, marker=".", label=label)
    ax_t.set_ylabel("duration (h)")
    ax_e.set_ylabel("energy (kJ)")
    ax_e.set_xlabel("departure (h after the mission's start_time, UTC)")
    ax_t.legend(loc="best", fontsize="small")
    ax_t.grid(alpha=0.3)
    ax_e.grid(alpha=0.3)
    if title:
        ax_t.set_title(title)
    return fig
