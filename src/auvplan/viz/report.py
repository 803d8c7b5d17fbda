"""Self-contained interactive HTML report of one mission (plotly, with plotly.js inlined).

Data in, HTML out: :func:`build_report` takes the World, the :class:`~auvplan.sim.RunRecord`,
the scenario text and a metrics dict and returns the page; nothing here reads or writes files
or computes a plan.  Sections: a 3D view (seabed surface coloured by elevation, current cones
at a few depths, static obstacles, global path, key waypoints, the flown track, and a time
slider / play button that moves the vehicle and the moving obstacles), a plan view (with a
lon/lat graticule when ``to_lonlat`` is given), profiles along the track (depth, altitude
above the seabed, cross-track error, speed), the optimiser's convergence, the metrics table
and the resolved scenario.
"""

from __future__ import annotations

import html
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import Status
from ..endurance import Endurance
from ..sim import RunRecord, decimate
from ..world import World
from . import PLOTLY_MISSING

try:
    import plotly.colors as pc
    import plotly.graph_objects as go
    import plotly.io as pio
    from plotly.subplots import make_subplots
except ImportError as exc:  # plotly is the optional `report` extra
    raise ImportError(PLOTLY_MISSING) from exc
from .chart import ToLonLat, figure_plan_view
from .scene3d import figure_3d, thin
from .style import LAND_COLORS, ROLE, plotly_text

__all__ = ["build_report", "build_bench_report", "figure_profiles", "figure_convergence"]


def _clock(t: ArrayLike) -> NDArray[np.datetime64]:
    """Elapsed seconds as datetimes from midnight, so that plotly labels the axis hh:mm:ss."""
    return np.datetime64("2000-01-01T00:00:00") + np.round(np.asarray(t) * 1000).astype("timedelta64[ms]")


def figure_profiles(record: RunRecord, min_altitude_m: float | None = None) -> go.Figure:
    """Draw depth (with the seabed under it), altitude above the seabed (with the altitude limit),
    cross-track error and speed against time.

    Parameters
    ----------
    record : RunRecord
        The flight (its ``sim``); empty panels without one.
    min_altitude_m : float, optional
        The mission's ``min_altitude_m``, drawn as a red line on the altitude panel.

    Returns
    -------
    plotly.graph_objects.Figure
        Four panels (m, m, m, m/s) against the elapsed time (h:mm:ss).
    """
    fig = make_subplots(rows=4, cols=1, shared_xaxes=True, vertical_spacing=0.04,
                        subplot_titles=("depth (m): vehicle and seabed", "altitude above seabed (m)",
                                        "cross-track error (m)", "speed over ground (m/s)"))
    sim = record.sim
    if sim is not None and sim.t.size:
        i = thin(sim.t.size)
        alt = np.where(np.isfinite(sim.altitude), sim.altitude, np.nan)
        clock = _clock(sim.t[i])
        seabed = alt[i] - sim.position[i, 2]  # depth of the seabed under the vehicle: altitude + vehicle depth
        fig.add_trace(go.Scatter(x=clock, y=seabed, mode="lines", name="seabed", showlegend=False,
                                 line=dict(color=LAND_COLORS[3], width=1.5),
                                 hovertemplate="seabed %{y:.1f} m<extra></extra>"), row=1, col=1)
        for row, (y, name) in enumerate(((-sim.position[:, 2], "depth"), (alt, "altitude"),
                                         (sim.route_error, "cross-track"), (sim.speed, "speed")), start=1):
            fig.add_trace(go.Scatter(x=clock, y=y[i], mode="lines", name=name, showlegend=False,
                                     line=dict(color=ROLE["track"], width=1.5)), row=row, col=1)
        if min_altitude_m is not None and np.isfinite(min_altitude_m):
            fig.add_trace(go.Scatter(x=clock[[0, -1]], y=[min_altitude_m] * 2, mode="lines",
                                     name="min_altitude_m", showlegend=False, meta=dict(kind="limit"),
                                     line=dict(color=ROLE["limit"], width=1.5, dash="dash"),
                                     hovertemplate=f"min_altitude_m {min_altitude_m:g} m<extra></extra>"), row=2, col=1)
            fig.add_annotation(x=clock[-1], y=min_altitude_m, xref="x2", yref="y2",
                               text=f"min_altitude_m {min_altitude_m:g}", showarrow=False, xanchor="right",
                               yanchor="bottom", font=dict(color=ROLE["limit"], size=11))
        fig.update_yaxes(autorange="reversed", row=1, col=1)
        fig.update_yaxes(rangemode="tozero", row=2, col=1)
        fig.update_xaxes(tickformat="%H:%M:%S", hoverformat="%H:%M:%S")
    fig.update_xaxes(title_text="elapsed time (h:mm:ss)", row=4, col=1)
    fig.update_layout(height=760, title="profiles along the track", margin=dict(t=60))
    return fig


def figure_convergence(record: RunRecord) -> go.Figure:
    """Draw the best cost after each optimiser iteration.

    Parameters
    ----------
    record : RunRecord
        Its plan's ``history``; an empty figure without one.

    Returns
    -------
    plotly.graph_objects.Figure
        Best cost (the objective's unit) against the iteration.
    """
    fig = go.Figure()
    if record.plan is not None and record.plan.history.size:
        h = record.plan.history
        fig.add_trace(go.Scatter(x=np.arange(1, h.size + 1), y=h, mode="lines+markers",
                                 name=plotly_text(record.plan.planner)))
    fig.update_layout(xaxis_title="iteration", yaxis_title="best cost", height=380, title="convergence")
    return fig


def _table(metrics: Mapping[str, Any]) -> str:
    def fmt(v: Any) -> str:
        if isinstance(v, float):
            return f"{v:.6g}"
        if isinstance(v, (list, tuple)):
            return ", ".join(fmt(x) for x in v)
        return html.escape(str(v))

    rows = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{fmt(v)}</td></tr>" for k, v in metrics.items())
    return f'<table id="metrics">{rows}</table>'


_CSS = """body{font-family:system-ui,sans-serif;margin:1.5em;max-width:1300px}
table{border-collapse:collapse}th,td{border:1px solid #ccc;padding:3px 8px;text-align:left;font-size:0.9em}
th{background:#f3f3f3}pre{background:#f7f7f7;padding:1em;overflow:auto;font-size:0.85em}"""


def _min_altitude(scenario_text: str) -> float | None:
    """The scenario's ``[mission] min_altitude_m`` (None when the text does not parse or has none)."""
    try:
        value = tomllib.loads(scenario_text).get("mission", {}).get("min_altitude_m")
    except tomllib.TOMLDecodeError:
        return None
    return float(value) if isinstance(value, int | float) else None


def build_report(world: World, record: RunRecord, scenario_text: str, metrics: Mapping[str, Any],
                 to_lonlat: ToLonLat | None = None, endurance: Endurance | None = None,
                 ensemble: Mapping[str, Any] | None = None, sections: Sequence[tuple[str, str]] = ()) -> str:
    """Build the whole report as one HTML page that needs no network (plotly.js is inlined once).

    The flight is drawn from its decimated samples (:func:`auvplan.sim.decimate`: one every 20 m
    or 30 s, with the extremes of altitude and obstacle distance).

    Parameters
    ----------
    world : World
        The mission's world.
    record : RunRecord
        The run: plan, key waypoints and flight.
    scenario_text : str
        The resolved scenario, shown verbatim.
    metrics : mapping of str to object
        Metric name → value (units in the names), shown as a table.
    to_lonlat : callable, optional
        ``(x, y) -> (lon, lat)`` (m → degrees); with it the plan view has a graticule.
    endurance : Endurance, optional
        The energy budget: with it an Energy section (charge against time, energy per leg) and the
        point of no return on the plan view (:mod:`auvplan.viz.energy`).
    ensemble : mapping, optional
        The mission flown in every current member (``plan --json``'s ``arrival_p50_s``,
        ``arrival_p90_s``, ``success_probability``, ``members``): with it a Current ensemble section,
        the spread and each member's arrival and energy (:mod:`auvplan.viz.ensemble_view`).
    sections : sequence of (str, str)
        Further sections ``(title, html)`` after the 3D view (a survey's coverage map and line table,
        :func:`auvplan.viz.survey.survey_section`).

    Returns
    -------
    str
        The HTML page.
    """
    if record.sim is not None:
        record = replace(record, sim=decimate(record.sim))
    plan_view = figure_plan_view(world, record, to_lonlat)
    nav_html = _nav_section(world, record, plan_view)
    figs = [("view3d", figure_3d(world, record)), ("planview", plan_view),
            ("profiles", figure_profiles(record, _min_altitude(scenario_text))),
            ("convergence", figure_convergence(record))]
    spread = _budget_figures(figs, plan_view, endurance, ensemble)
    parts: list[str] = []
    for i, (div, fig) in enumerate(figs):
        parts.append(pio.to_html(fig, include_plotlyjs=(i == 0), full_html=False, div_id=div,
                                 config=dict(displaylogo=False), auto_play=False))
    title = html.escape(f"auvplan — {record.scenario}, seed {record.seed}")
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{title}</title><style>{_CSS}</style>"
            f"</head><body><h1>{title}</h1><p>status <b>{html.escape(record.status.value)}</b></p>"
            + parts[0] + "".join(f"<h2>{html.escape(t)}</h2>{body}" for t, body in sections)
            + "<h2>Plan view</h2>" + parts[1] + "<h2>Profiles</h2>" + parts[2] + nav_html
            + "".join("<h2>Energy</h2>" + p for p in parts[4:len(parts) - bool(spread)])
            + (spread + parts[-1] if spread else "")
            + "<h2>Optimiser</h2>" + parts[3] + "<h2>Metrics</h2>" + _table(metrics)
            + f"<h2>Scenario</h2><pre id='scenario'>{html.escape(scenario_text)}</pre></body></html>")


def _nav_section(world: World, record: RunRecord, plan_view: go.Figure) -> str:
    """The Navigation section (issue 52: the error against time), its error band drawn on the plan view; "" when
    the run has no navigation plan or profile."""
    if record.nav is None:
        return ""
    from .navview import figure_nav_error, mark_error_band, nav_profile

    profile = nav_profile(world, record.nav)
    if profile is None:
        return ""
    mark_error_band(plan_view, profile, record.nav)
    error: str = pio.to_html(figure_nav_error(profile, record.nav, record), include_plotlyjs=False, full_html=False,
                             div_id="naverror", config=dict(displaylogo=False))
    return "<h2>Navigation</h2>" + error


def _budget_figures(figs: list[tuple[str, go.Figure]], plan_view: go.Figure, endurance: Endurance | None,
                    ensemble: Mapping[str, Any] | None) -> str:
    """Append the energy figure (its point of no return on the plan view) and the current ensemble's to ``figs``;
    the ensemble's table ("" without one)."""
    if endurance is not None:
        from .energy import figure_energy, mark_pnr

        mark_pnr(plan_view, endurance)
        figs.append(("energy", figure_energy(endurance)))
    if ensemble and ensemble.get("members"):
        from .ensemble_view import ensemble_table, figure_ensemble

        figs.append(("ensemble", figure_ensemble(ensemble)))
        return "<h2>Current ensemble</h2>" + ensemble_table(ensemble)
    return ""

def _num(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


def build_bench_report(rows: Sequence[Mapping[str, Any]], summary: Sequence[Mapping[str, Any]],
                       histories: Sequence[Mapping[str, Any]]) -> str:
    """Build one offline HTML page for a sweep.

    Cost box plots per cell, success rates, the median convergence curve per cell (with the
    25–75 % band), and the summary table.

    Parameters
    ----------
    rows : sequence of mapping
        Rows of ``rows.csv`` (:data:`auvplan.app.bench.rows.COLUMNS`).
    summary : sequence of mapping
        One row per cell (:func:`auvplan.app.bench.rows.summarise`).
    histories : sequence of mapping
        Convergence records (:func:`auvplan.app.bench.rows.read_histories`): ``key``, ``history`` and
        optionally ``trace`` (evaluations, best cost).

    Returns
    -------
    str
        The HTML page.
    """
    cells: dict[str, list[Mapping[str, Any]]] = {}
    for r in rows:
        cells.setdefault(f"{r['scenario']} {r['planner']}/{r['guidance']}", []).append(r)
    palette = pc.qualitative.Plotly + pc.qualitative.D3
    colour = {name: palette[i % len(palette)] for i, name in enumerate(sorted(cells))}
    box = go.Figure()
    for name, rs in sorted(cells.items()):
        c = np.array([_num(r["cost"]) for r in rs])
        box.add_trace(go.Box(y=c[np.isfinite(c)], name=name, boxpoints="outliers", marker_color=colour[name]))
    box.update_layout(title="plan cost per cell", yaxis_title="cost", height=450)
    names = sorted(cells)
    rate = [np.mean([Status(r["status"]).ok for r in cells[n]]) for n in names]
    bars = go.Figure(go.Bar(x=names, y=rate, marker_color=[colour[n] for n in names]))
    bars.update_layout(title="success rate", yaxis=dict(range=[0, 1.05]), height=380)
    conv = _convergence_figure(histories, colour)
    parts = [pio.to_html(f, include_plotlyjs=(i == 0), full_html=False, div_id=d, config=dict(displaylogo=False))
             for i, (d, f) in enumerate((("costs", box), ("success", bars), ("convergence", conv)))]
    table = ""
    if summary:
        cols = list(summary[0])
        head = "".join(f"<th>{html.escape(c)}</th>" for c in cols)
        def cell(v: Any) -> str:
            return f"<td>{v:.6g}</td>" if isinstance(v, float) else f"<td>{html.escape(str(v))}</td>"

        body = "".join("<tr>" + "".join(cell(r[c]) for c in cols) + "</tr>" for r in summary)
        table = f'<table id="summary"><tr>{head}</tr>{body}</table>'
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>auvplan bench</title><style>{_CSS}</style>"
            f"</head><body><h1>auvplan bench: {len(rows)} runs</h1>" + "".join(parts)
            + "<h2>Summary</h2>" + table + "</body></html>")


def _convergence_figure(histories: Sequence[Mapping[str, Any]], colour: Mapping[str, str]) -> go.Figure:
    """Median and interquartile band of the best cost per cell, against objective evaluations
    when the records carry a trace (comparable between optimisers), else against iterations."""
    conv = go.Figure()
    by_cell: dict[str, list[NDArray[np.float64]]] = {}
    traced = all(h.get("trace") for h in histories if h["history"])
    for h in histories:
        s, p, g, _ = h["key"]
        if h["history"]:
            curve = np.asarray(h["trace"], dtype=float) if traced else np.asarray(h["history"], dtype=float)
            by_cell.setdefault(f"{s} {p}/{g}", []).append(curve)
    for name, hs in sorted(by_cell.items()):
        if traced:
            x = np.linspace(0.0, max(t[-1, 0] for t in hs), 200)[1:]
            m = np.array([t[np.maximum(np.searchsorted(t[:, 0], x, side="right") - 1, 0), 1] for t in hs])
        else:
            n = max(len(h) for h in hs)
            m = np.array([np.pad(h, (0, n - len(h)), mode="edge") for h in hs])
            x = np.arange(1, n + 1)
        q25, q50, q75 = np.percentile(m, [25, 50, 75], axis=0)
        c = colour.get(name, "gray")
        conv.add_trace(go.Scatter(x=np.r_[x, x[::-1]], y=np.r_[q75, q25[::-1]], fill="toself", opacity=0.2,
                                  line=dict(width=0), showlegend=False, hoverinfo="skip", name=name, fillcolor=c))
        conv.add_trace(go.Scatter(x=x, y=q50, mode="lines", name=f"{name} (median of {len(hs)})",
                                  line=dict(color=c)))
    what = "objective evaluations" if traced else "iteration"
    conv.update_layout(title=f"convergence (best cost against {what})", xaxis_title=what, yaxis_title="best cost",
                       height=450)
    return conv
