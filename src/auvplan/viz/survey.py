"""The coverage map of a survey (matplotlib; data in, Figure out): the seabed under the area, every line's
swath footprint, the planned lines and the flown track, the gaps in red, and the overlap of every adjacent
pair against the bounds."""

from __future__ import annotations

import base64
import html
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import shapely
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..survey.coverage import Coverage
from ..survey.run import SurveyRun
from ..world import World
from .style import bathymetry_cmap

__all__ = ["coverage_map", "survey_section", "line_table"]


def _fill(ax: Axes, geom: shapely.Geometry, **kw: object) -> None:
    for g in shapely.get_parts(geom):
        if isinstance(g, shapely.Polygon) and not g.is_empty:
            x, y = g.exterior.xy
            ax.fill(np.asarray(x) / 1e3, np.asarray(y) / 1e3, **kw)  # type: ignore[arg-type]


def _panel(ax: Axes, world: World, area: shapely.Polygon, cov: Coverage, track: np.ndarray, title: str) -> None:
    poly = shapely.union_all([f for f in cov.footprints if not f.is_empty])
    x0, y0, x1, y1 = poly.bounds
    gx, gy = np.meshgrid(np.linspace(x0, x1, 160), np.linspace(y0, y1, 160))
    zb = world.seabed(gx, gy)
    lo, hi = float(zb.min()), float(zb.max())
    cmap, norm = bathymetry_cmap(min(lo, -1.0), min(hi, -0.5))
    cf = ax.contourf(gx / 1e3, gy / 1e3, zb, levels=20, cmap=cmap, norm=norm)
    ax.figure.colorbar(cf, ax=ax, label="seabed elevation (m)", shrink=0.8)
    for i, f in enumerate(cov.footprints):
        _fill(ax, f, alpha=0.18, color=("tab:orange" if i % 2 else "tab:blue"), lw=0)
    for g in cov.gaps:
        _fill(ax, g, facecolor="red", edgecolor="red", alpha=0.9, lw=1.5)
    ax.plot(track[:, 0] / 1e3, track[:, 1] / 1e3, color="k", lw=0.6)
    ring = np.asarray(area.exterior.coords)
    ax.plot(ring[:, 0] / 1e3, ring[:, 1] / 1e3, color="crimson", lw=1.0, ls="--")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x east (km)")
    ax.set_ylabel("y north (km)")
    ax.set_aspect("equal")


def coverage_map(world: World, run: SurveyRun, area: shapely.Polygon, overlap: tuple[float, float]) -> Figure:
    """The planned and flown coverage of a survey with the per-pair overlap.

    Parameters
    ----------
    world : World
        The seabed.
    run : SurveyRun
        The planned and flown survey.
    area : shapely.Polygon
        The survey area (drawn dashed).
    overlap : tuple of float
        The overlap bounds (fractions) drawn on the overlap panel.

    Returns
    -------
    matplotlib.figure.Figure
        Two maps (planned, flown) and the overlap of every pair.
    """
    flown = run.flown
    fig = Figure(figsize=(15, 5.2) if flown else (10, 5.2), layout="constrained")
    axes = fig.subplots(1, 3 if flown else 2, width_ratios=[1, 1, 0.8] if flown else [1, 0.8])
    plan = run.plan
    on = plan.labels >= -1
    p = run.planned
    mower = run.lawnmower
    _panel(axes[0], world, area, p, plan.route[on],
           f"planned: {len(plan.lines.lines)} lines, coverage {p.coverage_pct:.2f} %\n"
           f"(fixed lawnmower: {mower.lines} lines for {mower.shallowest_m:.0f} m)")
    if flown is not None and run.record.sim is not None:
        _panel(axes[1], world, area, flown, run.record.sim.position,
               f"flown (closed loop, currents): coverage {flown.coverage_pct:.2f} %, "
               f"{len(flown.gaps)} gaps {flown.gap_area_m2:.0f} m²")
    ax = axes[-1]
    for cov, name, off, col in ((p, "planned", -0.15, "tab:blue"), (flown, "flown", 0.15, "tab:orange")):
        if cov is None:
            continue
        st = cov.pair_stats()
        i = np.array([s["pair"] for s in st]) + 1 + off
        med = np.array([s["median_pct"] for s in st])
        ax.errorbar(i, med, yerr=[med - [s["min_pct"] for s in st], [s["max_pct"] for s in st] - med], fmt="o",
                    ms=3, color=col, label=f"{name} (min/median/max)")
    for b in overlap:
        ax.axhline(100 * b, color="k", ls="--", lw=0.8)
    ax.set_xlabel("adjacent pair")
    ax.set_ylabel("overlap of the narrower swath (%)")
    ax.legend(fontsize=8)
    ax.set_title("overlap per pair, bounds dashed", fontsize=9)
    return fig


def line_table(run: SurveyRun, seabed: Any) -> list[dict[str, Any]]:
    """One row per line (main lines in flying order, then the tie lines): its kind, length, the depth under
    it, its swath and its overlap with the next main line (planned and flown, min / median %).

    Parameters
    ----------
    run : SurveyRun
        The survey.
    seabed : callable
        ``zb(x, y)`` (m).

    Returns
    -------
    list of dict
        ``line``, ``kind``, ``length_m``, ``depth_min_m``, ``depth_max_m``, ``swath_min_m``, ``swath_max_m``,
        ``overlap_min_pct``, ``overlap_median_pct``, ``flown_overlap_min_pct``.
    """
    plan = run.plan
    main = plan.line_waypoints()
    rows = []
    pairs = run.planned.pair_stats()
    flown = run.flown.pair_stats() if run.flown is not None else []
    for k, p in enumerate(main + plan.tie_waypoints()):
        depth = -seabed(p[:, 0], p[:, 1])
        row: dict[str, Any] = {"line": k, "kind": "main" if k < len(main) else "tie",
                               "length_m": float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()),
                               "depth_min_m": float(depth.min()), "depth_max_m": float(depth.max())}
        if k < len(main):
            ln = plan.lines.lines[k]
            w = (ln.left + ln.right)[ln.active]
            row.update(swath_min_m=float(np.nanmin(w)), swath_max_m=float(np.nanmax(w)))
            pair = pairs[k] if k < len(pairs) else None
            row.update(overlap_min_pct=pair["min_pct"] if pair else math.nan,
                       overlap_median_pct=pair["median_pct"] if pair else math.nan,
                       flown_overlap_min_pct=flown[k]["min_pct"] if k < len(flown) else math.nan)
        rows.append(row)
    return rows


def _cell(v: Any) -> str:
    if isinstance(v, float):
        return "" if math.isnan(v) else f"{v:,.1f}"
    return html.escape(str(v))


def survey_section(png: bytes, rows: Sequence[Mapping[str, Any]], summary: Mapping[str, Any]) -> str:
    """The report's survey section: the coverage map (inlined PNG), the headline figures and the line table.

    Parameters
    ----------
    png : bytes
        ``coverage.png``.
    rows : sequence of mapping
        :func:`line_table`.
    summary : mapping
        Headline figures (name → value).

    Returns
    -------
    str
        HTML (needs no network).
    """
    img = base64.b64encode(png).decode("ascii")
    head = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{_cell(v)}</td></tr>" for k, v in summary.items())
    cols = ["line", "kind", "length_m", "depth_min_m", "depth_max_m", "swath_min_m", "swath_max_m",
            "overlap_min_pct", "overlap_median_pct", "flown_overlap_min_pct"]
    body = "".join("<tr>" + "".join(f"<td>{_cell(r.get(c, ''))}</td>" for c in cols) + "</tr>" for r in rows)
    return (f"<img id='coverage' alt='coverage map' style='max-width:100%' src='data:image/png;base64,{img}'>"
            f"<table id='survey-summary'>{head}</table><h3>Lines</h3><table id='survey-lines'><tr>"
            + "".join(f"<th>{c}</th>" for c in cols) + f"</tr>{body}</table>"
            "<p>overlap: share of the narrower swath across the track, with the next main line</p>")
