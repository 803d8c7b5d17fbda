"""Static matplotlib figures for papers (PNG/SVG): data in, Figure out.

* :func:`plan_view` — seabed contours, obstacles, route vs flown track, key waypoints
  (document 001's "route and track with obstacles" figure).
* :func:`profiles` — depth, altitude, cross-track error and speed against time.
* :func:`convergence` — best cost per iteration of one or several optimisers (document 002).
* :func:`algorithm_paths` — the paths of several planners over the seabed (document 002's
  comparison of IABC, ABC, GA and PSO).
* :func:`streamlines` — streamlines from many starts around the obstacles (document 000).

:func:`write_mission_figures` writes the mission figures of a run into a folder.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Rectangle
from numpy.typing import ArrayLike, NDArray

from .._types import Status
from ..path import arc_length
from ..sim import RunRecord
from ..world import Ellipsoid, Sphere, World
from .chartmarks import ToLonLat, coastline, degree_label, graticule, isobath_levels, nice_step, north_arrow, scale_bar
from .scene3d import elevation_range, shape_surface
from .style import ALTITUDE_COLORSCALE, LAND_COLORS, ROLE, bathymetry_cmap, mpl_text

__all__ = ["plan_view", "profiles", "convergence", "algorithm_paths", "streamlines", "write_mission_figures",
           "bench_figures", "SaveFigure"]


SaveFigure = Callable[[Path, Any, int], object]
"""Writes one figure: ``save(path, fig, dpi)``."""


def _savefig(path: Path, fig: Any, dpi: int) -> None:
    fig.savefig(path, dpi=dpi)


STRIP = 4.0
"""Plan views whose data extent is more elongated than this are drawn with the short axis
exaggerated to this ratio (and say so), instead of as an unreadable strip."""


def _subplots(*grid: int, figsize: tuple[float, float], **kw: Any) -> tuple[Figure, Any]:
    """``pyplot.subplots`` without pyplot: a bare :class:`~matplotlib.figure.Figure` (rendered by
    Agg on ``savefig``), so that drawing never selects or switches the user's backend."""
    fig = Figure(figsize=figsize)
    return fig, fig.subplots(*grid, **kw)


def _seabed(ax: Axes, world: World) -> None:
    """Filled seabed in the shared bathymetry colours, isobaths at a round interval labelled with their
    depth, the coastline, and a colour bar with round ticks."""
    if world.terrain is None:
        return
    t = world.terrain
    lo, hi = elevation_range(world)
    cmap, norm = bathymetry_cmap(lo, hi)
    levels = np.linspace(lo, hi, 41)
    cs = ax.contourf(t.x, t.y, t.z, levels=levels, cmap=cmap, norm=norm, extend="both")
    depths, _ = isobath_levels(float(np.nanmin(t.z)), float(np.nanmax(t.z)))
    if depths.size:
        lines = ax.contour(t.x, t.y, t.z, levels=depths, colors="k", linewidths=0.4, alpha=0.45)
        ax.clabel(lines, fmt=lambda v: f"{-v:.0f}", fontsize=6, inline_spacing=2)
    for piece in coastline(world, np.asarray(t.x), np.asarray(t.y), np.asarray(t.z)):
        ax.plot(piece[:, 0], piece[:, 1], color=ROLE["coast"], lw=1.1)
    step = nice_step(hi - lo, 6.0)
    ticks = np.arange(np.ceil(lo / step), np.floor(hi / step) + 1) * step
    ax.figure.colorbar(cs, ax=ax, label="seabed elevation (m)", ticks=ticks, format="%.0f")


def _chart_marks(ax: Axes, world: World, to_lonlat: ToLonLat | None) -> None:
    """Graticule (°E/°N on the frame), a scale bar and a north arrow, as on the report's chart."""
    b = world.bounds
    w, h = b.xmax - b.xmin, b.ymax - b.ymin
    if to_lonlat is not None:
        for axis, v, seg, step in graticule(world, to_lonlat):
            ax.plot(seg[:, 0], seg[:, 1], ":", color="0.25", lw=0.6, alpha=0.7)
            end = seg[np.argmax(seg[:, 1])] if axis == "lon" else seg[np.argmax(seg[:, 0])]
            # labelled just inside the frame (top edge: longitudes, right edge: latitudes), clear of the
            # title and the colour bars
            box = dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.7)
            if axis == "lon" and b.xmin + 0.05 * w < end[0] < b.xmax - 0.05 * w:
                ax.text(end[0], b.ymax - 0.005 * h, degree_label(v, axis, step), ha="center", va="top", fontsize=6,
                        bbox=box)
            elif axis == "lat" and b.ymin + 0.05 * h < end[1] < b.ymax - 0.05 * h:
                ax.text(b.xmax - 0.005 * w, end[1], degree_label(v, axis, step), ha="right", va="center", fontsize=6,
                        bbox=box)
    x0, y0, length, label = scale_bar(world)
    ax.add_patch(Rectangle((x0 - 0.01 * w, y0 - 0.02 * h), length + 0.02 * w, 0.08 * h, color="white", alpha=0.8))
    ax.plot([x0, x0 + length], [y0, y0], color="black", lw=3, solid_capstyle="butt")
    ax.text(x0 + length / 2, y0 + 0.012 * h, label, ha="center", va="bottom", fontsize=8)
    cx, cy, nx, ny = north_arrow(world, to_lonlat)
    arrow = 0.08 * h
    ax.annotate("N", xy=(cx + nx * arrow, cy + ny * arrow), xytext=(cx, cy), ha="center", va="top", fontsize=10,
                arrowprops=dict(arrowstyle="-|>", color="black", lw=1.5))


def _fit_aspect(ax: Axes, points: NDArray[np.float64]) -> None:
    """Equal scales unless the drawn extent is a strip; then exaggerate the short axis."""
    span = np.ptp(points[:, :2], axis=0) if len(points) else np.ones(2)
    span = np.maximum(span, 1e-9)
    ratio = span.max() / span.min()
    if ratio <= STRIP:
        ax.set_aspect("equal")
        return
    factor = ratio / STRIP
    ax.set_aspect(factor if span[1] < span[0] else 1.0 / factor)
    ax.set_title(f"{ax.get_title()}\n({'y' if span[1] < span[0] else 'x'} exaggerated ×{factor:.3g})", fontsize=9)


def _obstacles(ax: Axes, world: World, t: float | None = None) -> None:
    for s in world.obstacles:
        x, y, _ = shape_surface(s, 60)
        ax.fill(x[30], y[30], color=ROLE["static"], alpha=0.6, lw=0)
    if t is not None:
        for o in world.moving:
            if o.active(t):
                c = o.center(t)
                ax.add_patch(Circle((float(c[0]), float(c[1])), o.shape.bounding_radius, color=ROLE["moving"],
                                    alpha=0.4))


def _zones(ax: Axes, world: World) -> None:
    """The charted no-go zones, filled in chart magenta and named."""
    if not world.zones:
        return
    b = world.bounds
    box = shapely.box(b.xmin, b.ymin, b.xmax, b.ymax)
    for i, z in enumerate(world.zones.exact.zones):
        shown = shapely.intersection(z.footprint, box)
        for part in shapely.get_parts(shown):
            if shapely.get_type_id(part) == 3:
                xy = np.asarray(part.exterior.coords)
                ax.fill(xy[:, 0], xy[:, 1], color="#be0078", alpha=0.3, lw=1.0, ec="#be0078",
                        label="no-go zones" if i == 0 else None)
                i = 1
        if not shown.is_empty:
            c = shapely.get_coordinates(shapely.point_on_surface(shown))[0]
            ax.annotate(mpl_text(z.name), (float(c[0]), float(c[1])), fontsize=7, color="#96005f", ha="center",
                        bbox=dict(boxstyle="round,pad=0.1", fc="white", alpha=0.6, lw=0))


def plan_view(world: World, record: RunRecord, to_lonlat: ToLonLat | None = None) -> Figure:
    """Draw the route (global path) against the flown track, with obstacles and key waypoints, on a
    chart framed on the scenario's bounds (isobaths, coastline, graticule, scale bar, north arrow).

    Parameters
    ----------
    world : World
        Seabed, static and moving obstacles.
    record : RunRecord
        Route, key waypoints and the flight (track coloured by altitude above the seabed, m).
    to_lonlat : callable, optional
        ``(x, y) -> (lon, lat)`` (m → degrees); with it a graticule and a true-north arrow.

    Returns
    -------
    matplotlib.figure.Figure
        Plan view, x east and y north in metres.
    """
    fig, ax = _subplots(figsize=(7.5, 6.5))
    _seabed(ax, world)
    _zones(ax, world)
    _obstacles(ax, world)
    if record.route.size:
        ax.plot(record.route[:, 0], record.route[:, 1], "--", color=ROLE["path"], lw=1.5, label="route")
    if record.keys.size:
        ax.plot(record.keys[:, 0], record.keys[:, 1], "D", color=ROLE["keys"], mec="k", ms=5, label="key waypoints")
    if record.sim is not None and record.sim.t.size:
        p = record.sim.position
        _track_by_altitude(ax, p, record.sim.altitude)
        for m, o in enumerate(world.moving):
            c = np.array([o.center(t) for t in record.sim.t[:: max(1, record.sim.t.size // 200)]])
            ax.plot(c[:, 0], c[:, 1], ":", color=ROLE["moving"], lw=0.8, label="moving obstacles" if m == 0 else None)
    ax.set_xlabel("x east (m)")
    ax.set_ylabel("y north (m)")
    ax.set_title(mpl_text(f"{record.scenario}: {record.status.value}"))
    b = world.bounds
    drawn = [record.route] if record.route.size else []
    if record.sim is not None and record.sim.t.size:
        drawn.append(record.sim.position)
    # framed on the map when the mission spans it, else on the mission (a strip is exaggerated and says so)
    corners = np.array([[b.xmin, b.ymin, 0.0], [b.xmax, b.ymax, 0.0]])
    frame = corners if not drawn or _strip_ratio(np.vstack(drawn)) <= STRIP else np.vstack(drawn)
    _fit_aspect(ax, frame)
    if frame is corners:
        ax.set_xlim(b.xmin, b.xmax)
        ax.set_ylim(b.ymin, b.ymax)
        _chart_marks(ax, world, to_lonlat)
    ax.legend(loc="upper left", bbox_to_anchor=(0.0, -0.12), ncol=2, fontsize=8, frameon=False)
    fig.tight_layout()
    return fig


def _strip_ratio(points: NDArray[np.float64]) -> float:
    span = np.maximum(np.ptp(points[:, :2], axis=0), 1e-9)
    return float(span.max() / span.min())


def _track_by_altitude(ax: Axes, p: NDArray[np.float64], altitude: NDArray[np.float64]) -> None:
    """The flown track coloured by its altitude above the seabed (dark red low, pale yellow high); its
    legend entry shows the colour of the track's median altitude."""
    alt = np.where(np.isfinite(altitude), altitude, np.nan)
    segments = np.stack([p[:-1, :2], p[1:, :2]], axis=1)
    finite = alt[np.isfinite(alt)]
    if finite.size == 0:
        ax.plot(p[:, 0], p[:, 1], color=ROLE["track"], lw=1.2, label="track")
        return
    top = max(float(np.percentile(finite, 95)), 1.0)
    norm = Normalize(0.0, top)
    lc = LineCollection(list(segments), cmap=ALTITUDE_COLORSCALE, norm=norm, linewidths=1.8)
    values = np.nan_to_num(0.5 * (alt[:-1] + alt[1:]), nan=top)
    lc.set_array(values)
    ax.add_collection(lc)
    median = float(values[np.argsort(values)[values.size // 2]])  # a colour the track is drawn in
    ax.plot([], [], color=lc.get_cmap()(norm(median)), lw=1.8, label="track (colour: altitude)")
    ax.autoscale_view()
    ax.figure.colorbar(lc, ax=ax, label="track altitude above seabed (m)", pad=0.01)


def profiles(record: RunRecord, min_altitude_m: float | None = None) -> Figure:
    """Draw depth (with the seabed under it), altitude above the seabed (with the altitude limit),
    cross-track error and speed against time.

    Parameters
    ----------
    record : RunRecord
        The flight (its ``sim``); empty panels without one.
    min_altitude_m : float, optional
        The mission's ``min_altitude_m``, a red dashed line on the altitude panel.

    Returns
    -------
    matplotlib.figure.Figure
        Four panels: depth (m), altitude (m), cross-track error (m), speed (m/s) against time (s).
    """
    fig, axes = _subplots(4, 1, figsize=(7.5, 8), sharex=True)
    sim = record.sim
    if sim is not None and sim.t.size:
        series = ((-sim.position[:, 2], "depth (m)"), (sim.altitude, "altitude (m)"),
                  (sim.route_error, "cross-track (m)"), (sim.speed, "speed (m/s)"))
        axes[0].plot(sim.t, sim.altitude - sim.position[:, 2], lw=1.2, color=LAND_COLORS[3], label="seabed")
        for ax, (y, label) in zip(axes, series):
            ax.plot(sim.t, y, lw=1, color=ROLE["track"], label="vehicle" if ax is axes[0] else None)
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
        axes[0].invert_yaxis()
        axes[0].legend(fontsize=7, loc="best")
        if min_altitude_m is not None and np.isfinite(min_altitude_m) and min_altitude_m > 0:
            axes[1].axhline(min_altitude_m, color=ROLE["limit"], ls="--", lw=1,
                            label=f"min_altitude_m {min_altitude_m:g}")
            axes[1].set_ylim(bottom=0.0)
            axes[1].legend(fontsize=7, loc="best")
    axes[-1].set_xlabel("time (s)")
    fig.tight_layout()
    return fig


def convergence(histories: Mapping[str, ArrayLike]) -> Figure:
    """Draw the best cost per iteration, one line per optimiser.

    Parameters
    ----------
    histories : mapping of str to array_like
        ``{name: best cost after each iteration}``.

    Returns
    -------
    matplotlib.figure.Figure
        Best cost (the objective's unit) against the iteration.
    """
    fig, ax = _subplots(figsize=(6.5, 4))
    for name, h in histories.items():
        h = np.asarray(h, dtype=float)
        if h.size:
            ax.plot(np.arange(1, h.size + 1), h, label=name)
    ax.set_xlabel("iteration")
    ax.set_ylabel("best cost")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


def algorithm_paths(world: World, paths: Mapping[str, ArrayLike]) -> Figure:
    """Draw the plan view and depth profile of several planners' paths.

    Parameters
    ----------
    world : World
        Seabed and static obstacles.
    paths : mapping of str to array_like
        ``{planner name: (N, 3) path}`` in the local frame (m).

    Returns
    -------
    matplotlib.figure.Figure
        Plan view (m) and elevation (m) against the distance along each path (km).
    """
    fig, (ax, bx) = _subplots(1, 2, figsize=(12, 5), gridspec_kw=dict(width_ratios=[1.2, 1]))
    _seabed(ax, world)
    _obstacles(ax, world)
    for name, p in paths.items():
        p = np.asarray(p)
        if p.size:
            ax.plot(p[:, 0], p[:, 1], lw=1.5, label=name)
            s = arc_length(p)
            bx.plot(s / 1000, p[:, 2], lw=1.2, label=name)
            if world.terrain is not None:
                bx.plot(s / 1000, world.terrain.elevation(p[:, 0], p[:, 1]), color="k", lw=0.5, alpha=0.3)
    ax.set_aspect("equal")
    ax.set_xlabel("x east (m)")
    ax.set_ylabel("y north (m)")
    ax.legend(fontsize=8)
    bx.set_xlabel("distance along path (km)")
    bx.set_ylabel("z (m) — thin black: seabed under each path")
    bx.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def _silhouette(ax: Axes, shape: Sphere | Ellipsoid, i: int, j: int, **kw: Any) -> None:
    """Fill the projection of a sphere or ellipsoid on axes ``(i, j)`` (convex: its hull)."""
    from scipy.spatial import ConvexHull

    p = np.stack([g.ravel() for g in shape_surface(shape, 40)], axis=1)[:, [i, j]]
    hull = p[ConvexHull(p).vertices]
    ax.fill(hull[:, 0], hull[:, 1], **kw)


def streamlines(world: World, paths: Iterable[NDArray[np.float64]], goal: Sequence[float] | NDArray[np.float64],
                status: Sequence[object] | None = None) -> Figure:
    """Draw streamlines from many starts (document 000) in plan (x–y) and side (x–z) views.

    Parameters
    ----------
    world : World
        Its static obstacles are drawn as silhouettes.
    paths : iterable of numpy.ndarray
        ``(N, 3)`` streamlines in the local frame (m).
    goal : sequence of 3 float
        Goal point (m).
    status : sequence, optional
        One status per streamline; those other than ``"arrived"`` / ``"EXACT"`` are drawn in red.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels at equal scale (m).
    """
    fig, axes = _subplots(1, 2, figsize=(12, 5.5))
    for ax, (i, j, labels) in zip(axes, ((0, 1, ("x (m)", "y (m)")), (0, 2, ("x (m)", "z (m)")))):
        for s in world.obstacles:
            _silhouette(ax, s, i, j, color=ROLE["static"], alpha=0.45, lw=0)
        for k, p in enumerate(paths):
            ok = status is None or str(status[k]) in ("arrived", "EXACT")
            ax.plot(p[:, i], p[:, j], lw=0.6, color="steelblue" if ok else "red", alpha=0.8)
        ax.plot(goal[i], goal[j], "*", color="gold", mec="k", ms=14)
        ax.set_aspect("equal")
        ax.set_xlabel(labels[0])
        ax.set_ylabel(labels[1])
    fig.tight_layout()
    return fig


def write_mission_figures(folder: Path, world: World, record: RunRecord,
                          formats: Sequence[str] = ("png", "svg"), save: SaveFigure | None = None,
                          to_lonlat: ToLonLat | None = None) -> list[Path]:
    """Write the plan view, profiles and convergence of a run as image files into ``folder``.

    Parameters
    ----------
    folder : pathlib.Path
        Output folder, created if missing.
    world : World
        The mission's world.
    record : RunRecord
        The run.
    formats : sequence of str, optional
        File formats matplotlib can write (``png``, ``svg``, ``pdf`` …).
    save : callable, optional
        ``save(path, fig, dpi)`` writes one figure (the command line's atomic, recorded write);
        default ``fig.savefig(path, dpi=dpi)``.
    to_lonlat : callable, optional
        ``(x, y) -> (lon, lat)``: a graticule and a true-north arrow on the plan view.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    figs = {"plan_view": plan_view(world, record, to_lonlat),
            "profiles": profiles(record, world.margins.min_altitude)}
    if record.plan is not None and record.plan.history.size:
        figs["convergence"] = convergence({mpl_text(record.plan.planner): record.plan.history})
    written = []
    for name, fig in figs.items():
        for fmt in formats:
            path = folder / f"{name}.{fmt}"
            (save or _savefig)(path, fig, 150)
            written.append(path)
    return written


def bench_figures(rows: Sequence[Mapping[str, Any]], folder: Path, save: SaveFigure | None = None) -> list[Path]:
    """Write box plots of the cost per planner and success rates per cell of a sweep's rows.

    Parameters
    ----------
    rows : sequence of mapping
        Rows of ``rows.csv`` (:data:`auvplan.app.bench.rows.COLUMNS`), values as read from the file.
    folder : pathlib.Path
        Output folder (exists).
    save : callable, optional
        ``save(path, fig, dpi)`` writes the figure; default ``fig.savefig(path, dpi=dpi)``.

    Returns
    -------
    list of pathlib.Path
        ``[folder / "bench.png"]``, or empty without rows.
    """
    folder = Path(folder)
    cells: dict[str, list[Mapping[str, Any]]] = {}
    for r in rows:
        cells.setdefault(f"{r['scenario']}\n{r['planner']}/{r['guidance']}", []).append(r)
    if not cells:
        return []
    names = sorted(cells)

    def num(v: Any) -> float:
        try:
            return float(v)
        except (TypeError, ValueError):
            return np.nan

    fig, (ax, bx) = _subplots(1, 2, figsize=(max(8, 2.2 * len(names)), 4.5))
    costs = [np.array([num(r["cost"]) for r in cells[n]]) for n in names]
    ax.boxplot([c[np.isfinite(c)] for c in costs], tick_labels=names)
    ax.set_ylabel("plan cost")
    ax.tick_params(axis="x", labelsize=7)
    ok = [np.mean([Status(r["status"]).ok for r in cells[n]]) for n in names]
    bx.bar(range(len(names)), ok, color="seagreen")
    bx.set_xticks(range(len(names)), names, fontsize=7)
    bx.set_ylim(0, 1.05)
    bx.set_ylabel("success rate")
    fig.tight_layout()
    path = folder / "bench.png"
    (save or _savefig)(path, fig, 130)
    return [path]
