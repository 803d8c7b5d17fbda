"""The plan view of a mission report drawn as a chart (plotly): data in, figure out.

Filled depth in the shared bathymetry colours with isobaths at a round interval chosen from the
relief and labelled in metres, the coastline and land as on a chart, a graticule in degrees with
°E/°N labels on the frame, a scale bar and a north arrow, obstacles at their true size (with a
fixed-size symbol where they would be too small to see), moving obstacles' tracks and where each came
closest to the vehicle, start and goal, the global path and labelled key waypoints, and the flown
track coloured by its altitude above the seabed — the safety figure a planner looks at first. No two
labels overlap (:mod:`auvplan.viz.chartmarks`); the legend sits outside the data.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..sim import RunRecord
from ..world import World
from . import PLOTLY_MISSING

try:
    import plotly.graph_objects as go
except ImportError as exc:  # plotly is the optional `report` extra
    raise ImportError(PLOTLY_MISSING) from exc
from .chartmarks import (
    ToLonLat,
    coastline,
    contour_lines,
    degree_label,
    graticule,
    isobath_levels,
    needs_marker,
    nice_step,
    north_arrow,
    place_labels,
    scale_bar,
)
from .scene3d import _terrain_grid, elevation_range, shape_surface, thin
from .style import ALTITUDE_COLORSCALE, ROLE, bathymetry_colorscale, plotly_text

__all__ = ["figure_plan_view", "nice_step", "graticule", "degree_label", "ToLonLat"]



def _graticule_traces(fig: go.Figure, world: World, to_lonlat: ToLonLat) -> None:
    b = world.bounds
    first = True
    for axis, v, seg, step in graticule(world, to_lonlat):
        fig.add_trace(go.Scatter(x=seg[:, 0], y=seg[:, 1], mode="lines", name="graticule", legendgroup="graticule",
                                 showlegend=first, line=dict(color="rgba(60,60,60,0.55)", width=0.8, dash="dot"),
                                 hoverinfo="skip"))
        first = False
        # Longitudes labelled along the top edge, latitudes along the right edge (the bottom and
        # left carry the local metres).
        end = seg[np.argmax(seg[:, 1])] if axis == "lon" else seg[np.argmax(seg[:, 0])]
        fig.add_annotation(x=end[0] if axis == "lon" else b.xmax, y=b.ymax if axis == "lon" else end[1],
                           text=degree_label(v, axis, step), showarrow=False, font=dict(size=11),
                           xanchor="center" if axis == "lon" else "left",
                           yanchor="bottom" if axis == "lon" else "middle",
                           xshift=0 if axis == "lon" else 4, yshift=4 if axis == "lon" else 0,
                           name=f"graticule-{axis}")


def _scale_bar_and_north(fig: go.Figure, world: World, to_lonlat: ToLonLat | None) -> None:
    b = world.bounds
    w, h = b.xmax - b.xmin, b.ymax - b.ymin
    x0, y0, length, label = scale_bar(world)
    fig.add_shape(type="rect", x0=x0 - 0.01 * w, x1=x0 + length + 0.01 * w, y0=y0 - 0.02 * h, y1=y0 + 0.05 * h,
                  fillcolor="rgba(255,255,255,0.8)", line=dict(width=0), layer="above")
    fig.add_shape(type="line", x0=x0, x1=x0 + length, y0=y0, y1=y0, line=dict(color="black", width=4), layer="above",
                  name="scale bar")
    fig.add_annotation(x=x0 + length / 2, y=y0, text=label, showarrow=False, yanchor="bottom", yshift=3,
                       font=dict(size=12), name="scale-bar")
    cx, cy, nx, ny = north_arrow(world, to_lonlat)  # towards increasing latitude where known, else grid north
    arrow = 0.08 * h
    fig.add_annotation(x=cx + nx * arrow, y=cy + ny * arrow, ax=cx, ay=cy, axref="x", ayref="y", xref="x", yref="y",
                       text="N", showarrow=True, arrowhead=2, arrowsize=1.4, arrowwidth=2.5, arrowcolor="black",
                       font=dict(size=15, color="black"), yanchor="bottom", name="north-arrow")


_PLOT_PX = (1000.0, 590.0)
"""Approximate plot area of the chart (px) for placing labels; the browser test measures the real one."""


def _px_per_m(world: World) -> float:
    b = world.bounds
    return min(_PLOT_PX[0] / (b.xmax - b.xmin), _PLOT_PX[1] / (b.ymax - b.ymin))


def _seabed(fig: go.Figure, world: World) -> list[tuple[list[tuple[float, float]], str]]:
    """Filled seabed, labelled isobaths at a round interval and the coastline; returns the isobath
    labels' candidate positions and texts (placed with the other labels)."""
    x, y, z = _terrain_grid(world, 200)
    lo, hi = elevation_range(world)
    tick = nice_step(hi - lo, 6.0)
    fig.add_trace(go.Heatmap(x=x, y=y, z=z, zmin=lo, zmax=hi, colorscale=bathymetry_colorscale(lo, hi), name="seabed",
                             zsmooth="best", colorbar=dict(title="elevation (m)", x=1.08, len=0.9, tick0=0.0,
                                                           dtick=tick, tickformat=".0f"),
                             hovertemplate="x %{x:.0f} m<br>y %{y:.0f} m<br>seabed %{z:.0f} m<extra></extra>"))
    levels, step = isobath_levels(float(np.nanmin(z)), float(np.nanmax(z)))
    labels: list[tuple[list[tuple[float, float]], str]] = []
    first = True
    for level in levels[::-1]:  # shallow first: the shelf's labels are placed before the deep ones
        pieces = contour_lines(x, y, z, level)
        if not pieces:
            continue
        xs = np.concatenate([np.append(p[:, 0], np.nan) for p in pieces])
        ys = np.concatenate([np.append(p[:, 1], np.nan) for p in pieces])
        fig.add_trace(go.Scatter(x=xs, y=ys, mode="lines", name=f"isobaths (every {step:g} m)",
                                 legendgroup="isobaths", showlegend=first,
                                 meta=dict(kind="isobath", level=float(level)),
                                 line=dict(color=ROLE["isobath"], width=0.8), hoverinfo="skip"))
        first = False
        longest = max(pieces, key=len)
        cands = [tuple(longest[int(f * (len(longest) - 1))]) for f in (0.5, 0.3, 0.7, 0.15, 0.85)]
        labels.append(([(float(a), float(b)) for a, b in cands], f"{-level:.0f}"))
    shore = coastline(world, x, y, z)
    if shore:
        xs = np.concatenate([np.append(p[:, 0], np.nan) for p in shore])
        ys = np.concatenate([np.append(p[:, 1], np.nan) for p in shore])
        fig.add_trace(go.Scatter(x=xs, y=ys, mode="lines", name="coastline", meta=dict(kind="coastline"),
                                 line=dict(color=ROLE["coast"], width=1.6), hoverinfo="skip"))
    return labels


def _place(fig: go.Figure, world: World, labels: list[tuple[list[tuple[float, float]], str, str]]) -> None:
    """Annotate every label at its first position clear of the others (isobath depths, key waypoints,
    start and goal); the scale bar and north arrow corners are kept free."""
    b = world.bounds
    k = _px_per_m(world)
    w, h = b.xmax - b.xmin, b.ymax - b.ymin
    corners = [((b.xmax - 0.36 * w) * k, b.ymin * k, b.xmax * k, (b.ymin + 0.14 * h) * k),
               (b.xmin * k, (b.ymax - 0.2 * h) * k, (b.xmin + 0.11 * w) * k, (b.ymax - 0.06 * h) * k)]
    inside = [[(cx, cy) for cx, cy in cands
               if b.xmin + 30 / k < cx < b.xmax - 30 / k and b.ymin + 12 / k < cy < b.ymax - 12 / k] or cands[:1]
              for cands, _, _ in labels]
    sizes = [(7.0 * len(text) + 4.0, 14.0) for _, text, _ in labels]
    chosen = place_labels(inside, sizes, (k, k), taken=corners)
    for (_, text, kind), pos, c in zip(labels, chosen, inside):
        if pos is None:
            continue
        x, y = c[pos]
        style = dict(size=10, color="rgba(0,0,0,0.8)") if kind == "isobath" else \
            dict(size=11, color="rgb(150,0,95)") if kind == "zone" else dict(size=12, color="black")
        fig.add_annotation(x=x, y=y, text=plotly_text(text), showarrow=False, font=style, name=f"label-{kind}",
                           bgcolor="rgba(255,255,255,0.55)" if kind == "isobath" else "rgba(255,255,255,0.8)",
                           borderpad=1)


def _offsets(x: float, y: float, r: float) -> list[tuple[float, float]]:
    """Label positions round a point, ``r`` away, above first."""
    return [(x + r * dx, y + r * dy) for dx, dy in ((0, 1), (1, 0.6), (-1, 0.6), (0, -1), (1, -0.6), (-1, -0.6),
                                                    (0, 2), (2, 0), (-2, 0), (0, -2))]


def _obstacles(fig: go.Figure, world: World, record: RunRecord) -> None:
    """Static obstacles at true size (plus a fixed-size symbol where too small to see); moving
    obstacles' tracks and their position when closest to the vehicle, marked the same way."""
    k = _px_per_m(world)
    small: list[tuple[float, float, str]] = []
    for i, s in enumerate(world.obstacles):
        x, y, _ = shape_surface(s, 40)
        fig.add_trace(go.Scatter(x=x[len(x) // 2], y=y[len(y) // 2], mode="lines", fill="toself",
                                 name="static obstacles", legendgroup="obstacles", showlegend=i == 0,
                                 line=dict(color=ROLE["static"]), fillcolor="rgba(95,95,95,0.55)"))
        if needs_marker(2 * s.bounding_radius, k):
            small.append((float(s.center[0]), float(s.center[1]), f"obstacle {i}, radius {s.bounding_radius:.0f} m"))
    if small:
        fig.add_trace(go.Scatter(x=[p[0] for p in small], y=[p[1] for p in small], mode="markers",
                                 name="static obstacles (small)", legendgroup="obstacles", showlegend=False,
                                 text=[p[2] for p in small], hoverinfo="text",
                                 marker=dict(symbol="circle", size=8, color=ROLE["static"], line=dict(width=1,
                                                                                                     color="white"))))
    if record.sim is None or not record.sim.t.size or not world.moving:
        return
    t = record.sim.t[thin(record.sim.t.size, 400)]
    vehicle = record.sim.position[thin(record.sim.t.size, 400)]
    near = []
    for m, o in enumerate(world.moving):
        c = np.asarray(o.motion.position(t), dtype=float).reshape(t.size, 3)
        fig.add_trace(go.Scatter(x=c[:, 0], y=c[:, 1], mode="lines", name="moving obstacles (tracks)",
                                 legendgroup="moving", showlegend=m == 0,
                                 line=dict(color=ROLE["moving"], width=1, dash="dot")))
        alive = (o.appears <= t) & (t < o.disappears)
        d = np.where(alive, np.linalg.norm(c - vehicle, axis=1), np.inf)
        j = int(np.argmin(d))
        if np.isfinite(d[j]):
            near.append((c[j], float(o.shape.bounding_radius), o.name or f"moving obstacle {m}", float(t[j])))
    for n, (c, r, _, _) in enumerate(near):
        ang = np.linspace(0, 2 * np.pi, 33)
        fig.add_trace(go.Scatter(x=c[0] + r * np.cos(ang), y=c[1] + r * np.sin(ang), mode="lines", fill="toself",
                                 name="moving obstacles (closest to the vehicle)", legendgroup="moving-near",
                                 showlegend=n == 0, line=dict(color=ROLE["moving"], width=1),
                                 fillcolor="rgba(123,50,148,0.5)", meta=dict(kind="moving", radius=r),
                                 hoverinfo="skip"))
    fig.add_trace(go.Scatter(x=[c[0] for c, *_ in near], y=[c[1] for c, *_ in near], mode="markers",
                             name="moving obstacles (closest to the vehicle)", legendgroup="moving-near",
                             showlegend=False, hoverinfo="text",
                             text=[plotly_text(f"{nm}, radius {r:g} m, closest at {tj:.0f} s")
                                   for _, r, nm, tj in near],
                             marker=dict(symbol="circle-open", size=9, color=ROLE["moving"], line=dict(width=2))))


def _zones(fig: go.Figure, world: World) -> list[tuple[list[tuple[float, float]], str, str]]:
    """The charted no-go zones inside the bounds, filled in chart magenta; returns their name labels."""
    if not world.zones:
        return []
    b = world.bounds
    box = shapely.box(b.xmin, b.ymin, b.xmax, b.ymax)
    labels: list[tuple[list[tuple[float, float]], str, str]] = []
    first = True
    for z in world.zones.exact.zones:
        shown = shapely.intersection(z.footprint, box)
        rings = [np.asarray(r.coords) for p in shapely.get_parts(shown) if shapely.get_type_id(p) == 3
                 for r in (p.exterior, *p.interiors)]
        if not rings:
            continue
        xs = np.concatenate([np.append(r[:, 0], np.nan) for r in rings])
        ys = np.concatenate([np.append(r[:, 1], np.nan) for r in rings])
        fig.add_trace(go.Scatter(x=xs, y=ys, mode="lines", fill="toself", name="no-go zones", legendgroup="zones",
                                 showlegend=first, meta=dict(kind="zone", name=z.name), hoverinfo="text",
                                 text=plotly_text(f"{z.name}: {z.band}"), line=dict(color="rgb(190,0,120)", width=1.2),
                                 fillcolor="rgba(190,0,120,0.25)"))
        first = False
        c = shapely.get_coordinates(shapely.point_on_surface(shown))[0]
        labels.append(([(float(c[0]), float(c[1]))], z.name, "zone"))
    return labels


def _mission(fig: go.Figure, world: World, record: RunRecord) -> list[tuple[list[tuple[float, float]], str, str]]:
    """Zones, obstacles, path, key waypoints, the track coloured by altitude, start and goal; returns the
    labels of the zones, the key waypoints, start and goal for :func:`_place`."""
    labels = _zones(fig, world)
    _obstacles(fig, world, record)
    r = 14.0 / _px_per_m(world)
    route = record.plan.path if record.plan is not None and record.plan.path.size else record.route
    if route.size:
        labels += [(_offsets(float(route[0, 0]), float(route[0, 1]), r), "start", "end"),
                   (_offsets(float(route[-1, 0]), float(route[-1, 1]), r), "goal", "end")]
    if record.plan is not None and record.plan.path.size:
        p = record.plan.path
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="lines", name="global path",
                                 line=dict(color=ROLE["path"], width=2)))
    if record.keys.size:
        fig.add_trace(go.Scatter(x=record.keys[:, 0], y=record.keys[:, 1], mode="markers", name="key waypoints",
                                 text=[f"K{i}" for i in range(len(record.keys))], hoverinfo="text",
                                 marker=dict(color=ROLE["keys"], symbol="diamond", size=9, line=dict(width=1))))
        labels += [(_offsets(float(q[0]), float(q[1]), r), f"K{i}", "key") for i, q in enumerate(record.keys)]
    if record.sim is not None and record.sim.t.size:
        kept = thin(record.sim.t.size)
        p, alt = record.sim.position[kept], record.sim.altitude[kept]
        shown = alt[np.isfinite(alt)]
        top = float(np.percentile(shown, 95)) if shown.size else 1.0
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="lines", line=dict(color=ROLE["track"], width=1),
                                 showlegend=False, hoverinfo="skip"))
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="markers", name="track (colour: altitude)",
                                 marker=dict(size=4, color=np.where(np.isfinite(alt), alt, top),
                                             colorscale=ALTITUDE_COLORSCALE, cmin=0.0, cmax=max(top, 1.0),
                                             colorbar=dict(title="track altitude (m)", x=1.22, len=0.9)),
                                 customdata=alt, hovertemplate="altitude %{customdata:.1f} m<extra></extra>"))
    if route.size:
        fig.add_trace(go.Scatter(x=route[[0, -1], 0], y=route[[0, -1], 1], mode="markers", name="start / goal",
                                 marker=dict(size=12, color=[ROLE["start"], ROLE["goal"]], symbol=["circle", "x"],
                                             line=dict(width=1.5, color="black"))))
    return labels


def figure_plan_view(world: World, record: RunRecord, to_lonlat: ToLonLat | None = None) -> go.Figure:
    """The mission as a chart (see the module notes).

    Parameters
    ----------
    world : World
        Seabed, obstacles, bounds.
    record : RunRecord
        Plan, key waypoints and the flight.
    to_lonlat : callable, optional
        ``(x, y) -> (lon, lat)``; with it the graticule and a true-north arrow are drawn.

    Returns
    -------
    plotly.graph_objects.Figure
        The plan view, x east and y north in metres at equal scale.
    """
    fig = go.Figure()
    b = world.bounds
    depths = _seabed(fig, world) if world.terrain is not None else []
    if to_lonlat is not None:
        _graticule_traces(fig, world, to_lonlat)
    marks = _mission(fig, world, record)
    # the mission's own labels first, then as many isobath depths as fit between them
    _place(fig, world, marks + [(c, t, "isobath") for c, t in depths])
    _scale_bar_and_north(fig, world, to_lonlat)
    fig.update_layout(
        xaxis=dict(title="x east (m)", range=[b.xmin, b.xmax], constrain="domain", showgrid=False),
        yaxis=dict(title="y north (m)", range=[b.ymin, b.ymax], scaleanchor="x", scaleratio=1, constrain="domain",
                   showgrid=False),
        height=720, title="plan view", plot_bgcolor="white", margin=dict(l=70, r=20, t=70, b=60),
        legend=dict(orientation="h", x=0.0, y=-0.12, yanchor="top"))
    return fig
