"""Figures of a mission's endurance (issue 38): charge against time with the reserve, energy per leg
(predicted and flown), and the point of no return marked on the plan view.  Data in, figures out."""

from __future__ import annotations

import numpy as np

from ..endurance import Endurance
from . import PLOTLY_MISSING

try:
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots
except ImportError as exc:  # plotly is the optional `report` extra
    raise ImportError(PLOTLY_MISSING) from exc

__all__ = ["figure_energy", "mark_pnr"]


def figure_energy(e: Endurance) -> go.Figure:
    """Charge against time (predicted, flown, the reserve line, the point of no return) and energy per leg.

    Parameters
    ----------
    e : Endurance
        The mission's budget, point of no return and (optionally) its flight.

    Returns
    -------
    plotly.graph_objects.Figure
        Two panels: usable charge left (Wh) against time (h), and each leg's energy (Wh).
    """
    b, m = e.budget, e.budget.model
    fig = make_subplots(rows=1, cols=2, column_widths=[0.6, 0.4], horizontal_spacing=0.08,
                        subplot_titles=("usable charge left (Wh)", "energy per leg (Wh)"))
    t, left = b.charge()
    fig.add_trace(go.Scatter(x=t / 3600.0, y=left, mode="lines", name="predicted", line=dict(color="#1f77b4")),
                  row=1, col=1)
    if e.flown is not None:
        f = e.flown.energy
        keep = np.unique(np.linspace(0, f.t.size - 1, min(f.t.size, 600)).astype(int))
        fig.add_trace(go.Scatter(x=f.t[keep] / 3600.0, y=m.usable_wh - f.cumulative_wh[keep], mode="lines",
                                 name="flown (closed loop)", line=dict(color="#ff7f0e", dash="dot")), row=1, col=1)
    span = [float(t[0]) / 3600.0, float(t[-1]) / 3600.0] if t.size else [0.0, 1.0]
    fig.add_trace(go.Scatter(x=span, y=[m.reserve_wh] * 2, mode="lines", name=f"reserve {m.reserve_wh:.0f} Wh",
                             line=dict(color="firebrick", dash="dash")), row=1, col=1)
    p = e.pnr
    if not p.whole_mission and np.isfinite(p.t_s):
        fig.add_trace(go.Scatter(x=[p.t_s / 3600.0], y=[m.usable_wh - p.energy_out_wh], mode="markers+text",
                                 text=["point of no return"], textposition="top right", name="point of no return",
                                 marker=dict(symbol="x", size=12, color="black")), row=1, col=1)
    legs = np.arange(b.energy_leg_wh.size)
    fig.add_trace(go.Bar(x=legs, y=b.energy_leg_wh, name="leg, predicted", marker_color="#1f77b4"), row=1, col=2)
    if e.flown is not None:
        fig.add_trace(go.Bar(x=legs, y=e.flown.energy_wh, name="leg, flown", marker_color="#ff7f0e"), row=1, col=2)
    fig.update_xaxes(title_text="time after the start (h)", row=1, col=1)
    fig.update_xaxes(title_text="leg", row=1, col=2)
    fig.update_layout(height=420, title=f"energy — {b.message}", barmode="group", margin=dict(t=80),
                      title_font=dict(size=13))
    return fig


def mark_pnr(fig: go.Figure, e: Endurance) -> go.Figure:
    """Add the point of no return and the recovery point to a plan view (x east, y north in m).

    Parameters
    ----------
    fig : plotly.graph_objects.Figure
        The plan view (:func:`auvplan.viz.chart.figure_plan_view`).
    e : Endurance
        The analysis.

    Returns
    -------
    plotly.graph_objects.Figure
        ``fig``, with the two markers added.
    """
    p = e.pnr
    label = "point of no return" + (" (none: home in reach all along)" if p.whole_mission else "")
    fig.add_trace(go.Scatter(x=[p.position[0]], y=[p.position[1]], mode="markers+text", name=label,
                             text=["PNR"], textposition="bottom center", textfont=dict(color="white"),
                             marker=dict(symbol="x-thin-open" if p.whole_mission else "x", size=14, color="#e7298a",
                                         line=dict(width=3, color="#e7298a")),
                             hovertext=p.message, hoverinfo="text"))
    fig.add_trace(go.Scatter(x=[p.recovery[0]], y=[p.recovery[1]], mode="markers", name="recovery point",
                             marker=dict(symbol="star", size=12, color="deepskyblue", line=dict(width=1))))
    return fig
