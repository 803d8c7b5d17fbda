"""The HTML report of a formation: every vehicle in the 3D view and on the chart, and the fleet's profiles.

Data in, HTML out, like :mod:`auvplan.viz.report` (whose figures it reuses): the leader's run drawn
by :func:`~auvplan.viz.scene3d.figure_3d` and :func:`~auvplan.viz.chart.figure_plan_view` (seabed,
currents, obstacles, the moving obstacles' tracks, graticule, scale bar), each follower's slot track
and flown track added in its own colour, the stretches reshaped to column marked; then the formation
error of every vehicle, the least distance between two vehicles and the shape being flown against
time; the fleet's and each vehicle's metrics, and the scenario.
"""

from __future__ import annotations

import html
from dataclasses import replace

import numpy as np
import plotly.graph_objects as go
import plotly.io as pio
from plotly.subplots import make_subplots

from ..sim import RunRecord, decimate
from ..sim.formation import FormationRecord
from ..world import World
from .chart import ToLonLat, figure_plan_view
from .report import _CSS, _clock, _table
from .scene3d import figure_3d, thin

__all__ = ["COLOURS", "figure_formation_profiles", "build_formation_report"]

COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2")
"""One colour per vehicle, leader first (the same in every figure)."""


def _add_vehicles(fig: go.Figure, record: FormationRecord, runs: list[RunRecord], three_d: bool) -> None:
    f = record.formation
    for i, (name, run) in enumerate(zip(record.result.names if record.result else (), runs)):
        colour = COLOURS[i % len(COLOURS)]
        slot = f.tracks[i] if f is not None else np.empty((0, 3))
        k = thin(slot.shape[0])
        sim = run.sim
        pts = sim.position[thin(sim.t.size)] if sim is not None and sim.t.size else np.empty((0, 3))
        if three_d:
            fig.add_trace(go.Scatter3d(x=slot[k, 0], y=slot[k, 1], z=slot[k, 2], mode="lines", name=f"{name} slot",
                                       line=dict(color=colour, width=2, dash="dot")))
            fig.add_trace(go.Scatter3d(x=pts[:, 0], y=pts[:, 1], z=pts[:, 2], mode="lines", name=f"{name} track",
                                       line=dict(color=colour, width=5)))
        else:
            fig.add_trace(go.Scatter(x=slot[k, 0], y=slot[k, 1], mode="lines", name=f"{name} slot track",
                                     line=dict(color=colour, width=1, dash="dot")))
            fig.add_trace(go.Scatter(x=pts[:, 0], y=pts[:, 1], mode="lines", name=f"{name} flown",
                                     line=dict(color=colour, width=2)))
    if f is not None and not three_d:
        for a, b, why in f.reshaped:
            p = f.structure.point(np.linspace(a, b, 50))
            fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="lines", name="column (reshaped)",
                                     line=dict(color="black", width=8), opacity=0.25, hovertext=why))


def figure_formation_profiles(record: FormationRecord) -> go.Figure:
    """Draw the formation error of every vehicle, the least vehicle distance and the shape against time.

    Parameters
    ----------
    record : FormationRecord
        The plans and the fleet's run.

    Returns
    -------
    plotly.graph_objects.Figure
        Formation error (m), least distance between two vehicles (m) and the shape, against the
        elapsed time (h:mm:ss).
    """
    fig = make_subplots(rows=3, cols=1, shared_xaxes=True, vertical_spacing=0.06, row_heights=[0.5, 0.3, 0.2],
                        subplot_titles=("formation error: distance to the slot (m)",
                                        "least distance between two vehicles (m)", "shape"))
    res = record.result
    if res is not None:
        for i, (name, run, err) in enumerate(zip(res.names, res.runs, res.error)):
            k = thin(run.t.size)
            fig.add_trace(go.Scatter(x=_clock(run.t[k]), y=err[k], mode="lines", name=name,
                                     line=dict(color=COLOURS[i % len(COLOURS)])), row=1, col=1)
        k = thin(res.t.size)
        d = np.where(np.isfinite(res.vehicle_distance), res.vehicle_distance, np.nan)
        fig.add_trace(go.Scatter(x=_clock(res.t[k]), y=d[k], mode="lines", name="least distance",
                                 line=dict(color="black")), row=2, col=1)
        fig.add_trace(go.Scatter(x=_clock(res.t[k]), y=np.asarray(res.shapes)[k], mode="lines", name="shape",
                                 line=dict(color="grey", shape="hv")), row=3, col=1)
        fig.update_xaxes(tickformat="%H:%M:%S", hoverformat="%H:%M:%S")
    fig.update_xaxes(title_text="elapsed time (h:mm:ss)", row=3, col=1)
    fig.update_layout(height=760, title="formation keeping", margin=dict(t=60))
    return fig


def build_formation_report(world: World, record: FormationRecord, runs: list[RunRecord], scenario_text: str,
                           to_lonlat: ToLonLat | None = None) -> str:
    """The whole formation report as one offline HTML page.

    Parameters
    ----------
    world : World
        Seabed, currents, obstacles.
    record : FormationRecord
        The plans and the fleet's run.
    runs : list of RunRecord
        One single-vehicle record per vehicle, leader first
        (:func:`auvplan.io.missions.formation.vehicle_records`).
    scenario_text : str
        The scenario file.
    to_lonlat : callable, optional
        ``(x, y) -> (lon, lat)`` for the chart's graticule.

    Returns
    -------
    str
        The HTML page (plotly.js inlined once).
    """
    runs = [replace(r, sim=decimate(r.sim)) if r.sim is not None else r for r in runs]
    lead = runs[0]
    view3d = figure_3d(world, lead)
    _add_vehicles(view3d, record, runs, True)
    chart = figure_plan_view(world, lead, to_lonlat)
    _add_vehicles(chart, record, runs, False)
    figs = [("view3d", view3d), ("planview", chart), ("formation", figure_formation_profiles(record))]
    parts = [pio.to_html(fig, include_plotlyjs=(i == 0), full_html=False, div_id=div,
                         config=dict(displaylogo=False), auto_play=False) for i, (div, fig) in enumerate(figs)]
    m = record.result.metrics if record.result is not None else {}
    fleet = {k: v for k, v in m.items() if k != "per_vehicle"}
    per = "".join(f"<h3>{html.escape(name)}</h3>" + _table(v) for name, v in m.get("per_vehicle", {}).items())
    f = record.formation
    shapes = "" if f is None else "<p>" + html.escape(
        " → ".join(f"{s} from {b:.0f} m" for b, s in f.breaks) + f"; {f.message}") + "</p>"
    title = html.escape(f"auvplan — {record.scenario} (formation), seed {record.seed}")
    page: str = (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{title}</title><style>{_CSS}</style>"
            f"</head><body><h1>{title}</h1><p>status <b>{html.escape(record.status.value)}</b></p>{shapes}"
            + parts[0] + "<h2>Plan view</h2>" + parts[1] + "<h2>Formation</h2>" + parts[2]
            + "<h2>Metrics</h2>" + _table(fleet) + per
            + f"<h2>Scenario</h2><pre id='scenario'>{html.escape(scenario_text)}</pre></body></html>")
    return page
