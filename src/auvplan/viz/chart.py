"""The plan view of a mission report drawn as a chart (plotly): data in, figure out.

Filled depth in the shared bathymetry colours with isobaths labelled in metres, a graticule in
degrees with °E/°N labels on the frame, a scale bar and a north arrow, obstacles at their true
size, start and goal, the global path and key waypoints, and the flown track coloured by its
altitude above the seabed — the safety figure a planner looks at first. The legend sits outside
the data.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import contourpy
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..sim import RunRecord
from ..world import World
from . import PLOTLY_MISSING

try:
    import plotly.graph_objects as go
except ImportError as exc:  # plotly is the optional `report` extra
    raise ImportError(PLOTLY_MISSING) from exc
from .scene3d import _terrain_grid, elevation_range, shape_surface, thin
from .style import bathymetry_colorscale

__all__ = ["figure_plan_view", "nice_step", "graticule", "degree_label", "ToLonLat"]

ToLonLat = Callable[[Any, Any], tuple[ArrayLike, ArrayLike]]
"""Map from local ``(x, y)`` (m, arrays) to ``(lon, lat)`` (degrees): a pyproj transform."""


def nice_step(span: float, count: float = 5.0) -> float:
    """A round step (1, 2, 2.5, 5 × 10^k) that cuts ``span`` into about ``count`` parts.

    Parameters
    ----------
    span : float
        Positive length.
    count : float
        Wanted number of parts.

    Returns
    -------
    float
        The step, in the unit of ``span``.
    """
    raw = span / count
    if not (np.isfinite(raw) and raw > 0):
        return 1.0
    decade = 10.0 ** np.floor(np.log10(raw))
    return float(min((n * decade for n in (1.0, 2.0, 2.5, 5.0, 10.0)), key=lambda s: abs(s - raw)))


def degree_label(value: float, axis: str, step: float) -> str:
    """``'158.5°E'``, ``'14°N'``: a longitude (``axis='lon'``) or latitude with the decimals of ``step``.

    Parameters
    ----------
    value : float
        Degrees.
    axis : {'lon', 'lat'}
        Which coordinate ``value`` is.
    step : float
        Graticule step, sets the number of decimals.

    Returns
    -------
    str
        The label, hemisphere letter after the absolute value.
    """
    decimals = max(0, int(np.ceil(-np.log10(step) - 1e-9))) if step < 1 else 0
    if step < 1 and abs(step * 10 ** decimals - round(step * 10 ** decimals)) > 1e-9:
        decimals += 1
    hemi = ("E", "W") if axis == "lon" else ("N", "S")
    return f"{abs(value):.{decimals}f}°{hemi[0] if value >= 0 else hemi[1]}"


def graticule(world: World, to_lonlat: ToLonLat, n: int = 80) -> list[tuple[str, float, NDArray[np.float64], float]]:
    """Lines of constant longitude and latitude across the bounds.

    Parameters
    ----------
    world : World
        Its bounds.
    to_lonlat : callable
        ``(x, y) -> (lon, lat)`` in degrees.
    n : int
        Sampling grid size.

    Returns
    -------
    list of (axis, value, polyline, step)
        ``axis`` is ``'lon'`` or ``'lat'``, ``value`` its degrees, ``polyline`` ``(M, 2)`` local x, y (m),
        ``step`` the graticule step (degrees).
    """
    b = world.bounds
    gx, gy = np.meshgrid(np.linspace(b.xmin, b.xmax, n), np.linspace(b.ymin, b.ymax, n))
    lon, lat = (np.asarray(a, dtype=float) for a in to_lonlat(gx, gy))
    lines = []
    for axis, field in (("lon", lon), ("lat", lat)):
        step = nice_step(float(np.ptp(field)), 4.0)
        gen = contourpy.contour_generator(gx, gy, field)
        for v in np.arange(np.ceil(field.min() / step), np.floor(field.max() / step) + 1) * step:
            for seg in gen.lines(float(v)):
                if len(seg) > 1:
                    lines.append((axis, float(v), np.asarray(seg), step))
    return lines


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
    length = nice_step(w / 5.0, 1.0)
    x0, y0 = b.xmax - 0.06 * w - length, b.ymin + 0.06 * h
    label = f"{length / 1000:g} km" if length >= 1000 else f"{length:g} m"
    fig.add_shape(type="rect", x0=x0 - 0.01 * w, x1=x0 + length + 0.01 * w, y0=y0 - 0.02 * h, y1=y0 + 0.05 * h,
                  fillcolor="rgba(255,255,255,0.8)", line=dict(width=0), layer="above")
    fig.add_shape(type="line", x0=x0, x1=x0 + length, y0=y0, y1=y0, line=dict(color="black", width=4), layer="above",
                  name="scale bar")
    fig.add_annotation(x=x0 + length / 2, y=y0, text=label, showarrow=False, yanchor="bottom", yshift=3,
                       font=dict(size=12), name="scale-bar")
    # North arrow: towards increasing latitude where a graticule is known, else grid north (+y).
    nx, ny = 0.0, 1.0
    cx, cy = b.xmin + 0.06 * w, b.ymax - 0.16 * h
    if to_lonlat is not None:
        d = 1e-3 * max(w, h)
        lat = [float(np.asarray(to_lonlat(np.array([cx + dx]), np.array([cy + dy]))[1])[0])
               for dx, dy in ((d, 0.0), (-d, 0.0), (0.0, d), (0.0, -d))]
        gxy = np.array([lat[0] - lat[1], lat[2] - lat[3]])
        if np.linalg.norm(gxy) > 0:
            nx, ny = gxy / np.linalg.norm(gxy)
    arrow = 0.08 * h
    fig.add_annotation(x=cx + nx * arrow, y=cy + ny * arrow, ax=cx, ay=cy, axref="x", ayref="y", xref="x", yref="y",
                       text="N", showarrow=True, arrowhead=2, arrowsize=1.4, arrowwidth=2.5, arrowcolor="black",
                       font=dict(size=15, color="black"), yanchor="bottom", name="north-arrow")


def _seabed(fig: go.Figure, world: World) -> None:
    x, y, z = _terrain_grid(world, 200)
    lo, hi = elevation_range(world)
    step = nice_step(hi - lo, 8.0)
    fig.add_trace(go.Contour(x=x, y=y, z=z, zmin=lo, zmax=hi, colorscale=bathymetry_colorscale(lo, hi), name="seabed",
                             contours=dict(start=np.ceil(lo / step) * step, end=hi, size=step, showlabels=True,
                                           labelfont=dict(size=10, color="rgba(0,0,0,0.75)"), labelformat=".0f"),
                             line=dict(width=0.6, color="rgba(0,0,0,0.35)"),
                             colorbar=dict(title="elevation (m)", x=1.08, len=0.9),
                             hovertemplate="x %{x:.0f} m<br>y %{y:.0f} m<br>seabed %{z:.0f} m<extra></extra>"))


def _mission(fig: go.Figure, world: World, record: RunRecord) -> None:
    for i, s in enumerate(world.obstacles):
        x, y, _ = shape_surface(s, 40)
        fig.add_trace(go.Scatter(x=x[len(x) // 2], y=y[len(y) // 2], mode="lines", fill="toself",
                                 name="static obstacles", legendgroup="obstacles", showlegend=i == 0,
                                 line=dict(color="firebrick"), fillcolor="rgba(178,34,34,0.5)"))
    if record.sim is not None and record.sim.t.size and world.moving:
        t = record.sim.t[thin(record.sim.t.size, 400)]
        for m, o in enumerate(world.moving):
            c = np.asarray(o.motion.position(t), dtype=float).reshape(t.size, 3)
            fig.add_trace(go.Scatter(x=c[:, 0], y=c[:, 1], mode="lines", name="moving obstacles (tracks)",
                                     legendgroup="moving", showlegend=m == 0,
                                     line=dict(color="purple", width=1, dash="dot")))
    if record.plan is not None and record.plan.path.size:
        p = record.plan.path
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="lines", name="global path",
                                 line=dict(color="orange", width=2)))
    if record.keys.size:
        fig.add_trace(go.Scatter(x=record.keys[:, 0], y=record.keys[:, 1], mode="markers", name="key waypoints",
                                 marker=dict(color="gold", symbol="diamond", size=9, line=dict(width=1))))
    if record.sim is not None and record.sim.t.size:
        kept = thin(record.sim.t.size)
        p, alt = record.sim.position[kept], record.sim.altitude[kept]
        shown = alt[np.isfinite(alt)]
        top = float(np.percentile(shown, 95)) if shown.size else 1.0
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="lines", line=dict(color="rgba(40,40,40,0.5)", width=1),
                                 showlegend=False, hoverinfo="skip"))
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="markers", name="track (colour: altitude)",
                                 marker=dict(size=4, color=np.where(np.isfinite(alt), alt, top), colorscale="RdYlGn",
                                             cmin=0.0, cmax=max(top, 1.0),
                                             colorbar=dict(title="track altitude (m)", x=1.22, len=0.9)),
                                 customdata=alt, hovertemplate="altitude %{customdata:.1f} m<extra></extra>"))
    route = record.plan.path if record.plan is not None and record.plan.path.size else record.route
    if route.size:
        fig.add_trace(go.Scatter(x=route[[0, -1], 0], y=route[[0, -1], 1], mode="markers+text", name="start / goal",
                                 text=["start", "goal"], textposition="top center",
                                 textfont=dict(color="white", size=13),
                                 marker=dict(size=12, color=["limegreen", "black"], symbol=["circle", "x"],
                                             line=dict(width=1, color="white"))))


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
    if world.terrain is not None:
        _seabed(fig, world)
    if to_lonlat is not None:
        _graticule_traces(fig, world, to_lonlat)
    _mission(fig, world, record)
    _scale_bar_and_north(fig, world, to_lonlat)
    fig.update_layout(
        xaxis=dict(title="x east (m)", range=[b.xmin, b.xmax], constrain="domain", showgrid=False),
        yaxis=dict(title="y north (m)", range=[b.ymin, b.ymax], scaleanchor="x", scaleratio=1, constrain="domain",
                   showgrid=False),
        height=720, title="plan view", plot_bgcolor="white", margin=dict(l=70, r=20, t=70, b=60),
        legend=dict(orientation="h", x=0.0, y=-0.12, yanchor="top"))
    return fig
