"""The 3D scene of a mission report (plotly): data in, figure out.

Seabed surface in the shared bathymetry colours (:mod:`auvplan.viz.style`), the sea surface,
current arrows coloured by speed and scaled into the scene, static and moving obstacles as meshes
of their true shape and size, the global path, start / goal / key waypoints labelled, the flown
track, and a time slider (hh:mm:ss) with a play button that moves the vehicle and the moving
obstacles' meshes. The axes are fixed to the scenario bounds with a stated vertical exaggeration,
so nothing drawn can stretch the scene beyond the operating box.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..sim import RunRecord
from ..world import Ellipsoid, Sphere, World
from . import MissingPlotly

if TYPE_CHECKING:
    import plotly.graph_objects as go
else:
    try:
        import plotly.graph_objects as go
    except ImportError:  # plotly is the optional `report` extra; the geometry helpers here work without it
        go = MissingPlotly()
from .style import ROLE, bathymetry_colorscale, plotly_text, speed_colorscale

__all__ = ["figure_3d", "shape_surface", "shape_mesh", "vertical_exaggeration", "z_range", "hms", "FRAMES",
           "MAX_POINTS"]

FRAMES = 60
"""Time-slider frames."""

MAX_POINTS = 3000
"""Longest line drawn (longer tracks are thinned evenly; the ends are kept)."""

_NICE = (1.0, 2.0, 5.0)


def thin(n: int, most: int = MAX_POINTS) -> NDArray[np.intp]:
    """Indices of at most ``most`` evenly spread samples of ``n`` (first and last kept)."""
    return np.unique(np.linspace(0, n - 1, min(n, most)).round().astype(int))


def hms(t: float) -> str:
    """``h:mm:ss`` of a time in seconds (negative times get a leading minus).

    Parameters
    ----------
    t : float
        Time (s).

    Returns
    -------
    str
        The time as hours, minutes and seconds.
    """
    sign = "-" if t < 0 else ""
    s = int(round(abs(float(t))))
    return f"{sign}{s // 3600:d}:{s // 60 % 60:02d}:{s % 60:02d}"


def vertical_exaggeration(world: World, target: float = 0.35, z_range: tuple[float, float] | None = None) -> float:
    """The round vertical exaggeration (1, 2, 5, 10, 20 …) nearest (in ratio) to the one that
    makes the scene's height ``target`` of its larger horizontal side.

    Parameters
    ----------
    world : World
        Its bounds set the box.
    target : float
        Wanted height / width ratio of the drawn box.
    z_range : (float, float), optional
        The vertical range drawn; the bounds' by default.

    Returns
    -------
    float
        At least 1.
    """
    b = world.bounds
    lo, hi = (b.zmin, b.zmax) if z_range is None else z_range
    ratio = target * max(b.xmax - b.xmin, b.ymax - b.ymin) / (hi - lo)
    if ratio <= 1.0:
        return 1.0
    decade = 10.0 ** np.floor(np.log10(ratio))
    return float(min((n * decade for n in (*_NICE, 10.0)), key=lambda v: abs(np.log(v / ratio))))


def shape_surface(shape: Sphere | Ellipsoid, n: int = 16) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                                  NDArray[np.float64]]:
    """``(x, y, z)`` grids ``(n, n)`` of a sphere's or ellipsoid's surface.

    Parameters
    ----------
    shape : Sphere or Ellipsoid
        Any other shape is drawn as its bounding sphere.
    n : int
        Grid size in each surface parameter.

    Returns
    -------
    x, y, z : numpy.ndarray
        ``(n, n)`` each, in the shape's frame (m).
    """
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


def shape_mesh(shape: Sphere | Ellipsoid, n: int = 11) -> tuple[NDArray[np.float64], NDArray[np.int_]]:
    """Vertices ``(V, 3)`` and triangles ``(F, 3)`` of a shape's surface (a closed mesh).

    Parameters
    ----------
    shape : Sphere or Ellipsoid
        The shape, at its own centre.
    n : int
        Grid size of :func:`shape_surface`; odd, so that every vertex has its antipode and the
        poles and the equator are vertices (the mesh's box is the shape's).

    Returns
    -------
    vertices : numpy.ndarray
        ``(V, 3)`` vertex positions (m).
    triangles : numpy.ndarray
        ``(F, 3)`` vertex indices, int.
    """
    x, y, z = shape_surface(shape, n)
    vertices = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    r, c = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (r * n + c).ravel()
    tri = np.concatenate([np.column_stack([a, a + 1, a + n]), np.column_stack([a + 1, a + n + 1, a + n])])
    return vertices, tri


def _mesh(vertices: NDArray[np.float64], tri: NDArray[np.int_], name: str, color: str, opacity: float) -> go.Mesh3d:
    return go.Mesh3d(x=vertices[:, 0], y=vertices[:, 1], z=vertices[:, 2], i=tri[:, 0], j=tri[:, 1], k=tri[:, 2],
                     color=color, opacity=opacity, name=name, showlegend=True, flatshading=True,
                     hoverinfo="name")


def _terrain_grid(world: World, max_nodes: int = 120) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                              NDArray[np.float64]]:
    t = world.terrain
    assert t is not None
    b = world.bounds
    ix = np.flatnonzero((t.x >= b.xmin - t.dx) & (t.x <= b.xmax + t.dx))
    iy = np.flatnonzero((t.y >= b.ymin - t.dy) & (t.y <= b.ymax + t.dy))
    ix = ix[:: max(1, int(np.ceil(ix.size / max_nodes)))]
    iy = iy[:: max(1, int(np.ceil(iy.size / max_nodes)))]
    return t.x[ix], t.y[iy], t.z[np.ix_(iy, ix)]  # z is (ny, nx)


def elevation_range(world: World) -> tuple[float, float]:
    """Elevation range of the seabed inside the bounds (m), for a shared colour scale.

    Parameters
    ----------
    world : World
        Its terrain and bounds.

    Returns
    -------
    zmin, zmax : float
        Lowest and highest seabed elevation (m); the bounds' vertical range without a terrain.
    """
    if world.terrain is None:
        return world.bounds.zmin, world.bounds.zmax
    z = _terrain_grid(world, 400)[2]
    return float(np.nanmin(z)), float(np.nanmax(z))


def z_range(world: World, record: RunRecord) -> tuple[float, float]:
    """The vertical range worth drawing: the seabed, the path, the track and the obstacles with a
    tenth of their span around them, clipped to the scenario's bounds (never beyond them).

    Parameters
    ----------
    world : World
        Seabed, obstacles and bounds.
    record : RunRecord
        Route, plan and flight.

    Returns
    -------
    zmin, zmax : float
        Vertical range (m), inside the bounds.
    """
    b = world.bounds
    zs = [np.array([np.nan])]
    if world.terrain is not None:
        zs.append(np.array(elevation_range(world)))
    for p in (record.route, record.plan.path if record.plan is not None else np.empty((0, 3)),
              record.sim.position if record.sim is not None else np.empty((0, 3))):
        if p.size:
            zs.append(p[:, 2])
    for o in world.obstacles:
        zs.append(np.array([o.center[2] - o.bounding_radius, o.center[2] + o.bounding_radius]))
    z = np.concatenate(zs)
    z = z[np.isfinite(z)]
    if z.size == 0:
        return b.zmin, b.zmax
    pad = max(0.1 * float(np.ptp(z)), 1.0)
    lo, hi = max(b.zmin, float(z.min()) - pad), min(b.zmax, float(z.max()) + pad)
    if hi - lo < 1e-6:
        return b.zmin, b.zmax
    if b.zmax - hi < 0.15 * (hi - lo):  # close to the surface: show it
        hi = b.zmax
    return lo, hi


def _seabed(world: World, zlo: float, zhi: float) -> list[go.Surface]:
    x, y, z = _terrain_grid(world)
    lo, hi = elevation_range(world)
    seabed = go.Surface(x=x, y=y, z=np.clip(z, zlo, zhi), surfacecolor=z, cmin=lo, cmax=hi,
                        colorscale=bathymetry_colorscale(lo, hi), name="seabed", showscale=True,
                        colorbar=dict(title="elevation (m)", x=1.0, len=0.6, y=0.45),
                        hovertemplate="x %{x:.0f} m<br>y %{y:.0f} m<br>seabed %{surfacecolor:.0f} m<extra></extra>")
    return [seabed]


def _sea_surface(world: World) -> go.Surface:
    b = world.bounds
    z0 = min(0.0, b.zmax)
    return go.Surface(x=[b.xmin, b.xmax], y=[b.ymin, b.ymax], z=np.full((2, 2), z0), showscale=False,
                      colorscale=[[0, "#7fb8d8"], [1, "#7fb8d8"]], opacity=0.15, name="sea surface",
                      hoverinfo="name", showlegend=True)


def _currents(world: World, path: NDArray[np.float64]) -> list[go.Cone]:
    b = world.bounds
    zs = path[:, 2] if path.size else np.array([b.zmin, b.zmax])
    # a sparse grid (5 × 5 at two depths) of small cones: the current's pattern without hiding the path;
    # a click on "current" in the legend hides them
    gx, gy = np.meshgrid(np.linspace(b.xmin, b.xmax, 7)[1:-1], np.linspace(b.ymin, b.ymax, 7)[1:-1])
    levels = np.linspace(zs.min(), zs.max(), 2) if np.ptp(zs) > 0 else zs[:1]
    p = np.vstack([np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, z)]) for z in levels])
    v = np.asarray(world.currents.velocity(p, 0.0), dtype=float)
    speed = np.linalg.norm(v, axis=1)
    if not np.isfinite(speed).all() or speed.max() <= 0:
        return []
    # The axes are fixed to the bounds, so arrows cannot stretch the scene; "scaled" sizes them
    # to the spacing of the arrow grid (the fastest about half a cell).
    return [go.Cone(x=p[:, 0], y=p[:, 1], z=p[:, 2], u=v[:, 0], v=v[:, 1], w=v[:, 2], customdata=speed,
                    name="current", sizemode="scaled", sizeref=0.3, anchor="tail", cmin=0.0, opacity=0.6,
                    cmax=float(speed.max()), colorscale=speed_colorscale(), showscale=True, showlegend=True,
                    colorbar=dict(title="current (m/s)", x=1.08, len=0.6, y=0.45),
                    hovertemplate="current %{customdata:.2f} m/s<extra></extra>")]


def _labels(record: RunRecord) -> list[go.Scatter3d]:
    route = record.plan.path if record.plan is not None and record.plan.path.size else record.route
    traces = []
    if route.size:
        ends = route[[0, -1]]
        traces.append(go.Scatter3d(x=ends[:, 0], y=ends[:, 1], z=ends[:, 2], mode="markers+text", name="start / goal",
                                   text=["start", "goal"], textposition="top center",
                                   marker=dict(size=6, color=[ROLE["start"], ROLE["goal"]], symbol=["circle", "x"],
                                               line=dict(width=1, color="black"))))
    if record.keys.size:
        k = record.keys
        # label a key waypoint only where it stands clear of the last one labelled (3 % of the scene's
        # width): crowded keys keep their names on hover instead of piling text on each other
        span = float(np.ptp(k[:, :2], axis=0).max()) if len(k) > 1 else 1.0
        shown, last = [], None
        for i, q in enumerate(k):
            clear = last is None or np.hypot(*(q[:2] - last[:2])) > 0.03 * max(span, 1.0)
            shown.append(f"K{i}" if clear or i == len(k) - 1 else "")
            last = q if clear else last
        traces.append(go.Scatter3d(x=k[:, 0], y=k[:, 1], z=k[:, 2], mode="markers+text", name="key waypoints",
                                   text=shown, hovertext=[f"K{i}" for i in range(len(k))], hoverinfo="text",
                                   textposition="top center", textfont=dict(size=10),
                                   marker=dict(size=4, color=ROLE["keys"], symbol="diamond")))
    return traces


def _moving_meshes(world: World, times: NDArray[np.float64], n: int = 11) -> tuple[list[go.Mesh3d],
                                                                                    list[list[NDArray[np.float64]]]]:
    """One mesh trace per moving obstacle at ``times[0]`` and its vertices at every time
    (empty while the obstacle does not exist)."""
    traces, frames = [], []
    for m, o in enumerate(world.moving):
        vertices, tri = shape_mesh(o.shape.moved_to(np.zeros(3)), n)
        centres = np.asarray(o.motion.position(times), dtype=float).reshape(times.size, 3)
        alive = (o.appears <= times) & (times < o.disappears)
        per_time = [vertices + c if a else np.empty((0, 3)) for c, a in zip(centres, alive)]
        trace = _mesh(per_time[0], tri, plotly_text(o.name or f"moving obstacle {m}"), ROLE["moving"], 0.55)
        trace.update(meta=dict(kind="moving", radius=float(o.shape.bounding_radius)))
        traces.append(trace)
        frames.append(per_time)
    return traces, frames


def _current_frames(fig: go.Figure, world: World,
                    times: NDArray[np.float64]) -> tuple[int, NDArray[np.float64]] | None:
    """``(trace index, velocities (T, N, 3))`` of the current cones at the slider's times when the
    current changes with time (tides), else None; the colour scale spans every frame."""
    cone = next((i for i, d in enumerate(fig.data) if d.type == "cone"), None)
    if cone is None:
        return None
    c = fig.data[cone]
    v = np.asarray(world.currents.sample(np.column_stack([c.x, c.y, c.z]), times), dtype=float)
    if not np.isfinite(v).all() or np.ptp(v, axis=0).max() <= 1e-9:
        return None
    c.update(cmax=float(np.linalg.norm(v, axis=2).max()))
    return cone, v


def _slider(fig: go.Figure, record: RunRecord, world: World) -> None:
    sim = record.sim
    assert sim is not None
    times = np.linspace(sim.t[0], sim.t[-1], min(FRAMES, sim.t.size))
    pos = np.column_stack([np.interp(times, sim.t, sim.position[:, k]) for k in range(3)])
    fig.add_trace(go.Scatter3d(x=[pos[0, 0]], y=[pos[0, 1]], z=[pos[0, 2]], mode="markers", name="vehicle",
                               marker=dict(size=7, color=ROLE["vehicle"], line=dict(width=2, color="white"))))
    moving, verts = _moving_meshes(world, times)
    first = len(fig.data)
    for t in moving:
        fig.add_trace(t)
    ids = [first - 1] + list(range(first, first + len(moving)))
    flow = _current_frames(fig, world, times)
    if flow is not None:
        ids.append(flow[0])
    frames, steps = [], []
    for j, t in enumerate(times):
        data = [go.Scatter3d(x=[pos[j, 0]], y=[pos[j, 1]], z=[pos[j, 2]])]
        data += [go.Mesh3d(x=v[j][:, 0], y=v[j][:, 1], z=v[j][:, 2]) for v in verts]
        if flow is not None:
            vj = flow[1][j]
            data.append(go.Cone(u=vj[:, 0], v=vj[:, 1], w=vj[:, 2], customdata=np.linalg.norm(vj, axis=1)))
        frames.append(go.Frame(name=f"t{j}", traces=ids, data=data))
        steps.append(dict(method="animate", label=hms(t),
                          args=[[f"t{j}"], dict(mode="immediate", frame=dict(duration=0, redraw=True),
                                                transition=dict(duration=0))]))
    fig.frames = frames
    fig.update_layout(
        sliders=[dict(active=0, steps=steps, currentvalue=dict(prefix="t = ", font=dict(size=13)), x=0.06, len=0.9,
                      y=0.02, pad=dict(t=30, b=10), font=dict(size=9))],
        updatemenus=[dict(type="buttons", showactive=False, x=0.05, y=0.02, xanchor="right", yanchor="top", buttons=[
            dict(label="▶", method="animate",
                 args=[None, dict(frame=dict(duration=120, redraw=True), fromcurrent=True)]),
            dict(label="❚❚", method="animate",
                 args=[[None], dict(mode="immediate", frame=dict(duration=0, redraw=False))])])])


def figure_3d(world: World, record: RunRecord, exaggeration: float | None = None) -> go.Figure:
    """The 3D scene with the time slider (see the module notes).

    Parameters
    ----------
    world : World
        Seabed, currents, obstacles and bounds.
    record : RunRecord
        Plan, route, key waypoints and the flight.
    exaggeration : float, optional
        Vertical exaggeration; by default :func:`vertical_exaggeration`.

    Returns
    -------
    plotly.graph_objects.Figure
        The scene: x east, y north, z up (m), vertical exaggeration in ``layout.meta``.
    """
    b = world.bounds
    zlo, zhi = z_range(world, record)
    ve = vertical_exaggeration(world, z_range=(zlo, zhi)) if exaggeration is None else float(exaggeration)
    fig = go.Figure()
    if world.terrain is not None:
        for t in _seabed(world, zlo, zhi):
            fig.add_trace(t)
    if b.zmax >= 0.0 and zhi >= min(0.0, b.zmax):
        fig.add_trace(_sea_surface(world))
    path = record.plan.path if record.plan is not None and record.plan.path.size else record.route
    for t in _currents(world, path):
        fig.add_trace(t)
    for i, s in enumerate(world.obstacles):
        trace = _mesh(*shape_mesh(s, 21), f"obstacle {i}", ROLE["static"], 0.7)
        trace.update(meta=dict(kind="static", radius=float(s.bounding_radius)))
        fig.add_trace(trace)
        if 2 * s.bounding_radius < 0.008 * max(b.xmax - b.xmin, b.ymax - b.ymin):  # too small to see: a symbol too
            c = np.asarray(s.center, dtype=float)
            fig.add_trace(go.Scatter3d(x=[c[0]], y=[c[1]], z=[c[2]], mode="markers", name=f"obstacle {i} (mark)",
                                       showlegend=False, hovertext=f"obstacle {i}, radius {s.bounding_radius:g} m",
                                       hoverinfo="text", marker=dict(size=4, color=ROLE["static"])))
    if record.plan is not None and record.plan.path.size:
        p = record.plan.path
        fig.add_trace(go.Scatter3d(x=p[:, 0], y=p[:, 1], z=p[:, 2], mode="lines",
                                   name=plotly_text(f"global path ({record.plan.planner})"),
                                   line=dict(color=ROLE["path"], width=5)))
    for t in _labels(record):
        fig.add_trace(t)
    if record.sim is not None and record.sim.t.size:
        p = record.sim.position[thin(record.sim.t.size)]
        fig.add_trace(go.Scatter3d(x=p[:, 0], y=p[:, 1], z=p[:, 2], mode="lines", name="track",
                                   line=dict(color=ROLE["track"], width=3)))
        _slider(fig, record, world)
    sx, sy, sz = b.xmax - b.xmin, b.ymax - b.ymin, zhi - zlo
    big = max(sx, sy)
    fig.update_layout(
        scene=dict(xaxis=dict(title="x east (m)", range=[b.xmin, b.xmax]),
                   yaxis=dict(title="y north (m)", range=[b.ymin, b.ymax]),
                   zaxis=dict(title=f"z (m), vertical ×{ve:g}", range=[zlo, zhi]),
                   aspectmode="manual", aspectratio=dict(x=sx / big, y=sy / big, z=sz * ve / big)),
        meta=dict(vertical_exaggeration=ve),
        height=760, margin=dict(l=0, r=0, t=40, b=0), legend=dict(x=0.0, y=1.0, bgcolor="rgba(255,255,255,0.7)"),
        title=plotly_text(f"{record.scenario} — seed {record.seed}: {record.status.value} (vertical exaggeration "
                          f"×{ve:g})"))
    return fig
