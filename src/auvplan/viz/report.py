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
from collections.abc import Callable

import numpy as np

from ..errors import require

require("plotly", "report")
import plotly.graph_objects as go  # noqa: E402
import plotly.io as pio  # noqa: E402
from plotly.subplots import make_subplots  # noqa: E402

from ..sim import RunRecord  # noqa: E402
from ..world import Ellipsoid, Sphere, World  # noqa: E402

__all__ = ["build_report", "build_bench_report", "figure_3d", "figure_plan_view", "figure_profiles",
           "figure_convergence", "shape_surface"]

FRAMES = 60
"""Time-slider frames."""

MAX_POINTS = 3000
"""Longest line drawn (longer tracks are thinned evenly; the ends are kept)."""


def _thin(n: int) -> np.ndarray:
    """Indices of at most ``MAX_POINTS`` evenly spread samples of ``n`` (first and last kept)."""
    return np.unique(np.linspace(0, n - 1, min(n, MAX_POINTS)).round().astype(int))


def shape_surface(shape, n: int = 16) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(x, y, z)`` grids ``(n, n)`` of a sphere's or ellipsoid's surface."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n), np.linspace(0, np.pi, n))
    unit = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)], axis=-1)
    c = np.asarray(shape.center, dtype=float)
    if isinstance(shape, Ellipsoid):
        p = c + (unit * np.asarray(shape.semi_axes)) @ shape._rot.T
    elif isinstance(shape, Sphere):
        p = c + shape.radius * unit
    else:
        p = c + shape.bounding_radius * unit
    return p[..., 0], p[..., 1], p[..., 2]


def _line(p: np.ndarray, name: str, color: str, width: float = 4, dash: str | None = None) -> go.Scatter3d:
    return go.Scatter3d(x=p[:, 0], y=p[:, 1], z=p[:, 2], mode="lines", name=name,
                        line=dict(color=color, width=width, dash=dash))


def _terrain_grid(world: World, max_nodes: int = 120):
    t = world.terrain
    assert t is not None
    b = world.bounds
    ix = np.flatnonzero((t.x >= b.xmin - t.dx) & (t.x <= b.xmax + t.dx))
    iy = np.flatnonzero((t.y >= b.ymin - t.dy) & (t.y <= b.ymax + t.dy))
    ix = ix[:: max(1, int(np.ceil(ix.size / max_nodes)))]
    iy = iy[:: max(1, int(np.ceil(iy.size / max_nodes)))]
    return t.x[ix], t.y[iy], t.z[np.ix_(iy, ix)]  # z is (ny, nx)


def _times(record: RunRecord) -> np.ndarray:
    if record.sim is None or record.sim.t.size == 0:
        return np.empty(0)
    return np.linspace(record.sim.t[0], record.sim.t[-1], min(FRAMES, record.sim.t.size))


def _moving_tracks(world: World, times: np.ndarray) -> np.ndarray:
    """Centres ``(T, M, 3)`` of the moving obstacles at ``times`` (NaN while inactive), one
    vectorised call per obstacle."""
    if not world.moving:
        return np.empty((times.size, 0, 3))
    pts = np.stack([np.asarray(o.motion.position(times), dtype=float) for o in world.moving], axis=1)
    active = np.array([[o.appears <= t < o.disappears for o in world.moving] for t in times])
    return np.where(active[..., None], pts, np.nan)


def figure_3d(world: World, record: RunRecord) -> go.Figure:
    """The 3D scene with the time slider (see the module notes)."""
    fig = go.Figure()
    b = world.bounds
    if world.terrain is not None:
        x, y, z = _terrain_grid(world)
        fig.add_trace(go.Surface(x=x, y=y, z=z, colorscale="Earth", reversescale=True, name="seabed", showscale=True,
                                 colorbar=dict(title="elevation (m)", x=1.02, len=0.7), opacity=0.95,
                                 hovertemplate="x %{x:.0f} m<br>y %{y:.0f} m<br>seabed %{z:.0f} m<extra></extra>"))
    path = record.plan.path if record.plan is not None and record.plan.path.size else record.route
    zs = path[:, 2] if path.size else np.array([b.zmin, b.zmax])
    gx, gy = np.meshgrid(np.linspace(b.xmin, b.xmax, 7), np.linspace(b.ymin, b.ymax, 7))
    cones = []
    for z in np.linspace(zs.min(), zs.max(), 3) if np.ptp(zs) > 0 else [zs[0]]:
        p = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, z)])
        cones.append(np.column_stack([p, world.currents.velocity(p, 0.0)]))
    cone = np.vstack(cones)
    if np.abs(cone[:, 3:]).max() > 0:
        fig.add_trace(go.Cone(x=cone[:, 0], y=cone[:, 1], z=cone[:, 2], u=cone[:, 3], v=cone[:, 4], w=cone[:, 5],
                              name="current", sizemode="scaled", sizeref=0.6, colorscale="Blues", showscale=False,
                              hovertemplate="current %{u:.2f}, %{v:.2f} m/s<extra></extra>"))
    for i, s in enumerate(world.obstacles):
        x, y, z = shape_surface(s)
        fig.add_trace(go.Surface(x=x, y=y, z=z, showscale=False, colorscale=[[0, "firebrick"], [1, "firebrick"]],
                                 opacity=0.6, name=f"obstacle {i}", hoverinfo="name"))
    if record.plan is not None and record.plan.path.size:
        fig.add_trace(_line(record.plan.path, f"global path ({record.plan.planner})", "orange", 5))
    if record.keys.size:
        k = record.keys
        fig.add_trace(go.Scatter3d(x=k[:, 0], y=k[:, 1], z=k[:, 2], mode="markers", name="key waypoints",
                                   marker=dict(size=4, color="gold", symbol="diamond")))
    times = _times(record)
    if times.size and record.sim is not None:
        fig.add_trace(_line(record.sim.position[_thin(record.sim.t.size)], "track", "crimson", 3))
        pos = _positions(record, times)
        mov = _moving_tracks(world, times)
        fig.add_trace(go.Scatter3d(x=[pos[0, 0]], y=[pos[0, 1]], z=[pos[0, 2]], mode="markers", name="vehicle",
                                   marker=dict(size=7, color="black")))
        iv = len(fig.data) - 1
        fig.add_trace(go.Scatter3d(x=mov[0][:, 0], y=mov[0][:, 1], z=mov[0][:, 2], mode="markers",
                                   name="moving obstacles", marker=dict(size=6, color="purple")))
        im = len(fig.data) - 1
        frames, steps = [], []
        for j, t in enumerate(times):
            name = f"t{j}"
            frames.append(go.Frame(name=name, traces=[iv, im], data=[
                go.Scatter3d(x=[pos[j, 0]], y=[pos[j, 1]], z=[pos[j, 2]]),
                go.Scatter3d(x=mov[j][:, 0], y=mov[j][:, 1], z=mov[j][:, 2])]))
            steps.append(dict(method="animate", label=f"{t:.0f}",
                              args=[[name], dict(mode="immediate", frame=dict(duration=0, redraw=True),
                                                 transition=dict(duration=0))]))
        fig.frames = frames
        fig.update_layout(
            sliders=[dict(active=0, steps=steps, currentvalue=dict(prefix="t = ", suffix=" s"), x=0.05, len=0.9)],
            updatemenus=[dict(type="buttons", showactive=False, x=0.0, y=0.0, xanchor="right", buttons=[
                dict(label="▶", method="animate",
                     args=[None, dict(frame=dict(duration=120, redraw=True), fromcurrent=True)]),
                dict(label="❚❚", method="animate",
                     args=[[None], dict(mode="immediate", frame=dict(duration=0, redraw=False))])])])
    span = np.array([b.xmax - b.xmin, b.ymax - b.ymin])
    fig.update_layout(
        scene=dict(xaxis_title="x east (m)", yaxis_title="y north (m)", zaxis_title="z (m)", aspectmode="manual",
                   aspectratio=dict(x=1.0, y=float(span[1] / span[0]), z=0.45)),
        height=720, margin=dict(l=0, r=0, t=30, b=0), legend=dict(x=0.0, y=1.0),
        title=f"{record.scenario} — seed {record.seed}: {record.status.value}")
    return fig


def _positions(record: RunRecord, times: np.ndarray) -> np.ndarray:
    sim = record.sim
    assert sim is not None
    return np.column_stack([np.interp(times, sim.t, sim.position[:, k]) for k in range(3)])


def figure_plan_view(world: World, record: RunRecord, to_lonlat: Callable | None = None) -> go.Figure:
    """Map of the mission: seabed contours, obstacles, path, key waypoints, track, and a lon/lat
    graticule (contours of longitude and latitude) when ``to_lonlat`` is given."""
    fig = go.Figure()
    b = world.bounds
    if world.terrain is not None:
        x, y, z = _terrain_grid(world, 200)
        fig.add_trace(go.Contour(x=x, y=y, z=z, colorscale="Earth", name="seabed", ncontours=25,
                                 colorbar=dict(title="elevation (m)"), line=dict(width=0.5)))
    if to_lonlat is not None:
        gx, gy = np.meshgrid(np.linspace(b.xmin, b.xmax, 60), np.linspace(b.ymin, b.ymax, 60))
        lon, lat = to_lonlat(gx, gy)
        for field, label in ((lon, "lon"), (lat, "lat")):
            fig.add_trace(go.Contour(x=gx[0], y=gy[:, 0], z=field, showscale=False, name=f"{label} graticule",
                                     contours=dict(coloring="none", showlabels=True,
                                                   labelfont=dict(size=10, color="dimgray")),
                                     line=dict(color="dimgray", width=0.8, dash="dot"), ncontours=8,
                                     hoverinfo="skip"))
    for i, s in enumerate(world.obstacles):
        x, y, _ = shape_surface(s, 40)
        fig.add_trace(go.Scatter(x=x[len(x) // 2], y=y[len(y) // 2], mode="lines", fill="toself",
                                 name=f"obstacle {i}", line=dict(color="firebrick")))
    if record.plan is not None and record.plan.path.size:
        p = record.plan.path
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="lines", name="global path", line=dict(color="orange")))
    if record.keys.size:
        fig.add_trace(go.Scatter(x=record.keys[:, 0], y=record.keys[:, 1], mode="markers", name="key waypoints",
                                 marker=dict(color="gold", symbol="diamond", size=9, line=dict(width=1))))
    if record.sim is not None and record.sim.t.size:
        p = record.sim.position[_thin(record.sim.t.size)]
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="lines", name="track", line=dict(color="crimson")))
    fig.update_layout(xaxis_title="x east (m)", yaxis_title="y north (m)", height=600, title="plan view",
                      yaxis=dict(scaleanchor="x", scaleratio=1))
    return fig


def figure_profiles(record: RunRecord) -> go.Figure:
    """Depth, altitude above the seabed, cross-track error and speed against time."""
    fig = make_subplots(rows=4, cols=1, shared_xaxes=True, vertical_spacing=0.04,
                        subplot_titles=("depth (m)", "altitude above seabed (m)", "cross-track error (m)",
                                        "speed over ground (m/s)"))
    sim = record.sim
    if sim is not None and sim.t.size:
        i = _thin(sim.t.size)
        alt = np.where(np.isfinite(sim.altitude), sim.altitude, np.nan)
        for row, (y, name) in enumerate(((-sim.position[:, 2], "depth"), (alt, "altitude"),
                                         (sim.route_error, "cross-track"), (sim.speed, "speed")), start=1):
            fig.add_trace(go.Scatter(x=sim.t[i], y=y[i], mode="lines", name=name, showlegend=False), row=row, col=1)
        fig.update_yaxes(autorange="reversed", row=1, col=1)
    fig.update_xaxes(title_text="time (s)", row=4, col=1)
    fig.update_layout(height=760, title="profiles along the track", margin=dict(t=60))
    return fig


def figure_convergence(record: RunRecord) -> go.Figure:
    """Best cost after each optimiser iteration."""
    fig = go.Figure()
    if record.plan is not None and record.plan.history.size:
        h = record.plan.history
        fig.add_trace(go.Scatter(x=np.arange(1, h.size + 1), y=h, mode="lines+markers", name=record.plan.planner))
    fig.update_layout(xaxis_title="iteration", yaxis_title="best cost", height=380, title="convergence")
    return fig


def _table(metrics: dict) -> str:
    def fmt(v):
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


def build_report(world: World, record: RunRecord, scenario_text: str, metrics: dict,
                 to_lonlat: Callable | None = None) -> str:
    """The whole report as one HTML page that needs no network (plotly.js is inlined once)."""
    figs = [("view3d", figure_3d(world, record)), ("planview", figure_plan_view(world, record, to_lonlat)),
            ("profiles", figure_profiles(record)), ("convergence", figure_convergence(record))]
    parts = []
    for i, (div, fig) in enumerate(figs):
        parts.append(pio.to_html(fig, include_plotlyjs=(i == 0), full_html=False, div_id=div,
                                 config=dict(displaylogo=False), auto_play=False))
    title = html.escape(f"auvplan — {record.scenario}, seed {record.seed}")
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{title}</title><style>{_CSS}</style>"
            f"</head><body><h1>{title}</h1><p>status <b>{html.escape(record.status.value)}</b></p>"
            + parts[0] + "<h2>Plan view</h2>" + parts[1] + "<h2>Profiles</h2>" + parts[2]
            + "<h2>Optimiser</h2>" + parts[3] + "<h2>Metrics</h2>" + _table(metrics)
            + f"<h2>Scenario</h2><pre id='scenario'>{html.escape(scenario_text)}</pre></body></html>")


def _num(v) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


def build_bench_report(rows: list[dict], summary: list[dict], histories: list[dict]) -> str:
    """One offline HTML page for a sweep: cost box plots per cell, success rates, the median
    convergence curve per cell (with the 25–75 % band), and the summary table."""
    cells: dict[str, list[dict]] = {}
    for r in rows:
        cells.setdefault(f"{r['scenario']} {r['planner']}/{r['guidance']}", []).append(r)
    box = go.Figure()
    for name, rs in sorted(cells.items()):
        c = np.array([_num(r["cost"]) for r in rs])
        box.add_trace(go.Box(y=c[np.isfinite(c)], name=name, boxpoints="outliers"))
    box.update_layout(title="plan cost per cell", yaxis_title="cost", height=450)
    names = sorted(cells)
    rate = [np.mean([r["status"] in ("EXACT", "APPROXIMATE") for r in cells[n]]) for n in names]
    bars = go.Figure(go.Bar(x=names, y=rate, marker_color="seagreen"))
    bars.update_layout(title="success rate", yaxis=dict(range=[0, 1.05]), height=380)
    conv = go.Figure()
    by_cell: dict[str, list[np.ndarray]] = {}
    for h in histories:
        s, p, g, _ = h["key"]
        if h["history"]:
            by_cell.setdefault(f"{s} {p}/{g}", []).append(np.asarray(h["history"], dtype=float))
    for name, hs in sorted(by_cell.items()):
        n = max(len(h) for h in hs)
        m = np.array([np.pad(h, (0, n - len(h)), mode="edge") for h in hs])
        q25, q50, q75 = np.percentile(m, [25, 50, 75], axis=0)
        it = np.arange(1, n + 1)
        conv.add_trace(go.Scatter(x=np.r_[it, it[::-1]], y=np.r_[q75, q25[::-1]], fill="toself", opacity=0.2,
                                  line=dict(width=0), showlegend=False, hoverinfo="skip", name=name))
        conv.add_trace(go.Scatter(x=it, y=q50, mode="lines", name=f"{name} (median of {len(hs)})"))
    conv.update_layout(title="convergence (best cost per iteration)", xaxis_title="iteration",
                       yaxis_title="best cost", height=450)
    parts = [pio.to_html(f, include_plotlyjs=(i == 0), full_html=False, div_id=d, config=dict(displaylogo=False))
             for i, (d, f) in enumerate((("costs", box), ("success", bars), ("convergence", conv)))]
    table = ""
    if summary:
        cols = list(summary[0])
        head = "".join(f"<th>{html.escape(c)}</th>" for c in cols)
        def cell(v):
            return f"<td>{v:.6g}</td>" if isinstance(v, float) else f"<td>{html.escape(str(v))}</td>"

        body = "".join("<tr>" + "".join(cell(r[c]) for c in cols) + "</tr>" for r in summary)
        table = f'<table id="summary"><tr>{head}</tr>{body}</table>'
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>auvplan bench</title><style>{_CSS}</style>"
            f"</head><body><h1>auvplan bench: {len(rows)} runs</h1>" + "".join(parts)
            + "<h2>Summary</h2>" + table + "</body></html>")
