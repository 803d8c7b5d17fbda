"""The report's current-ensemble section: the spread of the mission over the members (issue 39).

Data in, HTML out: the ``plan --json`` / ``ensemble.json`` fields ``arrival_p50_s``, ``arrival_p90_s``,
``success_probability`` and ``members`` (each ``name``, ``arrival_s``, ``status``, ``success``,
``energy_wh``, ``heading_deg``) become a table of the spread, one row per member, and a figure of
each member's arrival time and energy with the P50 and P90 lines.  Every number is also in a
``data-value`` attribute (seconds, Wh, the raw value) so that a reader or a test can take it from the page.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping
from typing import Any

import plotly.graph_objects as go
from plotly.subplots import make_subplots

from .style import plotly_text

__all__ = ["ensemble_table", "figure_ensemble"]


def _num(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def _hours(v: Any) -> str:
    x = _num(v)
    return "does not arrive" if x == math.inf else ("—" if not math.isfinite(x) else f"{x / 3600:.2f} h")


def _cell(cls: str, value: Any, text: str) -> str:
    raw = "" if value is None else str(value)
    return f"<td class='{cls}' data-value='{html.escape(raw)}'>{html.escape(text)}</td>"


def ensemble_table(fields: Mapping[str, Any]) -> str:
    """The spread as HTML: P50, P90 and the success probability, then one row per member.

    Parameters
    ----------
    fields : mapping
        ``arrival_p50_s``, ``arrival_p90_s``, ``success_probability``, ``members`` and optionally
        ``robust``, ``robust_candidate`` and ``nominal`` (``plan --json``'s names).

    Returns
    -------
    str
        Two tables: ``#ensemble-spread`` and ``#ensemble-members`` (``tr[data-member]`` per member).
    """
    p = _num(fields.get("success_probability"))
    rows = [("arrival P50", _cell("arrival_p50_s", fields.get("arrival_p50_s"), _hours(fields.get("arrival_p50_s")))),
            ("arrival P90", _cell("arrival_p90_s", fields.get("arrival_p90_s"), _hours(fields.get("arrival_p90_s")))),
            ("success probability", _cell("success_probability", fields.get("success_probability"),
                                          f"{100 * p:.0f} %" if math.isfinite(p) else "—"))]
    if fields.get("robust"):
        rows.append(("robust objective", _cell("robust", fields.get("robust"),
                                               f"{fields['robust']} (kept: {fields.get('robust_candidate', '')})")))
    nominal = fields.get("nominal")
    if isinstance(nominal, Mapping):
        rows.append(("nominal plan's P50 / P90", _cell("nominal_p90_s", nominal.get("arrival_p90_s"),
                                                        f"{_hours(nominal.get('arrival_p50_s'))} / "
                                                        f"{_hours(nominal.get('arrival_p90_s'))}")))
    spread = "".join(f"<tr><th>{html.escape(k)}</th>{v}</tr>" for k, v in rows)
    members = []
    for m in fields.get("members") or []:
        e, h = _num(m.get("energy_wh")), _num(m.get("heading_deg"))
        members.append(
            f"<tr data-member='{html.escape(str(m.get('name', '')))}'><td>{html.escape(str(m.get('name', '')))}</td>"
            + _cell("arrival_s", m.get("arrival_s"), _hours(m.get("arrival_s")))
            + _cell("energy_wh", m.get("energy_wh"), f"{e:.1f} Wh" if math.isfinite(e) else "—")
            + _cell("status", m.get("status"), str(m.get("status", "")))
            + _cell("success", m.get("success"), "yes" if m.get("success") else "no")
            + _cell("heading_deg", m.get("heading_deg"), f"{h:.0f}°" if math.isfinite(h) else "—") + "</tr>")
    return (f"<table id='ensemble-spread' style='margin-bottom:10px'>{spread}</table>"
            "<table id='ensemble-members' style='margin-bottom:10px'>"
            "<tr><th>member</th><th>arrival</th><th>energy</th><th>status</th>"
            "<th>success</th><th>heading (first leg)</th></tr>" + "".join(members) + "</table>")


def figure_ensemble(fields: Mapping[str, Any]) -> go.Figure:
    """Each member's arrival time (h) and energy (Wh), with the P50 and P90 arrival lines.

    Parameters
    ----------
    fields : mapping
        As :func:`ensemble_table`.

    Returns
    -------
    plotly.graph_objects.Figure
        Two bar panels side by side; members that do not arrive have no bar and a red name.
    """
    members = list(fields.get("members") or [])
    names = [plotly_text(str(m.get("name", ""))) for m in members]
    arrival = [_num(m.get("arrival_s")) / 3600 for m in members]
    energy = [_num(m.get("energy_wh")) for m in members]
    colour = ["seagreen" if m.get("success") else "firebrick" for m in members]
    fig = make_subplots(rows=1, cols=2, subplot_titles=("arrival time (h)", "energy (Wh)"), horizontal_spacing=0.12)
    fig.add_trace(go.Bar(x=names, y=[a if math.isfinite(a) else None for a in arrival], marker_color=colour,
                         name="arrival", hovertemplate="%{x}: %{y:.2f} h<extra></extra>"), row=1, col=1)
    fig.add_trace(go.Bar(x=names, y=[e if math.isfinite(e) else None for e in energy], marker_color=colour,
                         name="energy", hovertemplate="%{x}: %{y:.1f} Wh<extra></extra>"), row=1, col=2)
    for key, dash, label in (("arrival_p50_s", "dot", "P50"), ("arrival_p90_s", "dash", "P90")):
        v = _num(fields.get(key))
        if math.isfinite(v):
            fig.add_hline(y=v / 3600, line_dash=dash, line_color="black", annotation_text=f"{label} {v / 3600:.2f} h",
                          row=1, col=1)
    fig.update_layout(height=360, showlegend=False, margin=dict(l=50, r=20, t=80, b=40),
                      title=f"success probability {100 * _num(fields.get('success_probability')):.0f} % "
                            f"over {len(members)} members")
    return fig
