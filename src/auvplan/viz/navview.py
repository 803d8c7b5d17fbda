"""The navigation error in the report (issue 52 item 6): the band the vehicle may be in on the plan view,
with its fixes, and the predicted error against time (with the true error of a flight flown with drift).

Data in, figures out: the band and the times come from :mod:`auvplan.nav.band`.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..nav import ErrorProfile, NavPlan, error_profile
from ..nav.band import error_band, profile_times
from ..sim import RunRecord
from ..world import World
from . import PLOTLY_MISSING

try:
    import plotly.graph_objects as go
except ImportError as exc:  # plotly is the optional `report` extra
    raise ImportError(PLOTLY_MISSING) from exc
from .style import ROLE

__all__ = ["nav_profile", "band_outline", "mark_error_band", "figure_nav_error", "BAND_COLOR"]

BAND_COLOR = "rgba(177, 89, 40, 0.25)"
"""Fill of the error band (``ROLE["nav"]``, light)."""


def nav_profile(world: World, nav: NavPlan) -> ErrorProfile | None:
    """The predicted error along the mission of ``nav`` (None when it carries no error model).

    Parameters
    ----------
    world : World
        The seabed (lock states).
    nav : NavPlan
        The mission's fixes and error model.

    Returns
    -------
    ErrorProfile or None
        The error at every sample.
    """
    if nav.params is None or nav.points.shape[0] < 2:
        return None
    return error_profile(world, nav.points, nav.kinds, nav.params, nav.params.usbl_xy, water_m=nav.leg_water_m,
                         launch_water_m=nav.launch_water_m)


def band_outline(band: shapely.Geometry) -> tuple[np.ndarray, np.ndarray]:
    """The band's rings as one x and one y array, rings separated by NaN (plotly draws them as one trace).

    Parameters
    ----------
    band : shapely.Geometry
        Polygon or MultiPolygon (:func:`auvplan.nav.band.error_band`).

    Returns
    -------
    x, y : numpy.ndarray
        Coordinates (m) with NaN between rings.
    """
    xs: list[np.ndarray] = []
    ys: list[np.ndarray] = []
    for poly in getattr(band, "geoms", [band]):
        for ring in [poly.exterior, *poly.interiors]:
            c = np.asarray(ring.coords)
            xs += [c[:, 0], np.array([np.nan])]
            ys += [c[:, 1], np.array([np.nan])]
    return (np.concatenate(xs), np.concatenate(ys)) if xs else (np.empty(0), np.empty(0))


def mark_error_band(fig: go.Figure, profile: ErrorProfile, nav: NavPlan) -> None:
    """Draw the error band and the fixes on a plan view (local metres).

    Parameters
    ----------
    fig : plotly.graph_objects.Figure
        The plan view (:func:`auvplan.viz.chart.figure_plan_view`).
    profile : ErrorProfile
        The predicted error along the mission.
    nav : NavPlan
        Its fixes (positions and kinds) and confidence.
    """
    conf = nav.params.confidence if nav.params is not None else float("nan")
    x, y = band_outline(error_band(profile))
    fig.add_trace(go.Scatter(x=x, y=y, mode="lines", fill="toself", fillcolor=BAND_COLOR, name=(
        f"navigation error ({conf:g} σ band, up to {nav.check.budget.max_error_m:.0f} m)"),
        line=dict(color=ROLE["nav"], width=0.8), hoverinfo="skip", meta=dict(kind="nav_band")))
    idx = [i for i, k in enumerate(nav.kinds) if k]
    if idx:
        p = nav.points[idx]
        fig.add_trace(go.Scatter(x=p[:, 0], y=p[:, 1], mode="markers", name="position fixes",
                                 marker=dict(symbol="triangle-up", size=11, color=ROLE["nav"],
                                             line=dict(color="white", width=1)),
                                 text=[f"fix {n + 1}: {nav.kinds[i]}, t {t / 3600:.2f} h" for n, (i, t) in
                                       enumerate(zip(idx, nav.times_s, strict=True))],
                                 hovertemplate="%{text}<extra></extra>", meta=dict(kind="nav_fixes")))


def figure_nav_error(profile: ErrorProfile, nav: NavPlan, record: RunRecord | None = None) -> go.Figure:
    """Draw the predicted error (confidence × σ) against the planned time, the budget E and the fixes; with a
    flight flown with drift, its true error against the flown time (both from the arrival at the first waypoint: a
    launch's dive at negative times).

    Parameters
    ----------
    profile : ErrorProfile
        The predicted error along the mission.
    nav : NavPlan
        Its fixes, dwells, budget and cruise speed (the planned time).
    record : RunRecord, optional
        The run: its flight's ``nav_error`` when flown with drift.

    Returns
    -------
    plotly.graph_objects.Figure
        Error (m) against time (h).
    """
    dwell = nav.dwell_s[[i for i, k in enumerate(nav.kinds) if k]]
    t = profile_times(profile, nav.speed, dwell if dwell.size else 0.0, nav.points, nav.vertex_times_s)
    fix = np.flatnonzero(profile.fix)
    held = dict(zip(fix.tolist(), dwell.tolist(), strict=True))
    tx: list[float] = []
    ey: list[float] = []
    for i in range(t.size):  # before a fix at its time, after it once the dwell is over
        tx.append(float(t[i]))
        ey.append(float(profile.before_m[i]))
        if profile.fix[i]:
            tx.append(float(t[i]) + held.get(i, 0.0))
            ey.append(float(profile.after_m[i]))
    fig = go.Figure()
    fig.add_trace(go.Scatter(x=np.asarray(tx) / 3600.0, y=ey, mode="lines", name="predicted error (planned time)",
                             line=dict(color=ROLE["track"], width=1.8), meta=dict(kind="nav_error"),
                             hovertemplate="%{x:.2f} h: %{y:.1f} m<extra></extra>"))
    sim = record.sim if record is not None else None
    if sim is not None and sim.nav_error is not None and sim.t.size:
        # the planned time counts from the arrival at the first waypoint; a flight launched at the surface above it
        # dives first (auvplan.sim.events): its clock is shifted to the same origin, the dive at negative times
        below = np.flatnonzero(sim.position[:, 2] <= nav.points[0, 2] + 1e-6)
        t0 = float(sim.t[below[0]]) if below.size else 0.0
        fig.add_trace(go.Scatter(x=(sim.t - t0) / 3600.0, y=sim.nav_error, mode="lines",
                                 name="true error (flown with drift)",
                                 line=dict(color="gray", width=1), meta=dict(kind="nav_error_flown")))
    if nav.params is not None:
        e = nav.params.max_error_m
        fig.add_trace(go.Scatter(x=[0.0, max(tx) / 3600.0], y=[e, e], mode="lines", name=f"max_error_m {e:g}",
                                 line=dict(color=ROLE["limit"], width=1.5, dash="dash"), meta=dict(kind="limit")))
    if fix.size:
        fig.add_trace(go.Scatter(x=t[fix] / 3600.0, y=profile.before_m[fix], mode="markers", name="fixes",
                                 marker=dict(symbol="triangle-down", size=9, color=ROLE["nav"])))
    conf = nav.params.confidence if nav.params is not None else float("nan")
    fig.update_layout(title=f"navigation error ({conf:g} σ) against time", xaxis_title="time (h)",
                      yaxis_title="horizontal error (m)", height=380, yaxis=dict(rangemode="tozero"))
    return fig
