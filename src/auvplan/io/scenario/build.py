"""A parsed :class:`~auvplan.io.scenario.specs.Scenario` → :class:`~auvplan.world.World` +
:class:`~auvplan.sim.Mission`:
read the bathymetry, currents and coastlines it names, make the World, and check the mission's start,
goal, route and vehicles against it (and the simulation's record against the memory budget)."""

from __future__ import annotations

import hashlib
import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ...errors import DataError, ScenarioError
from ...nav.params import NavParams
from ...sim import Mission
from ...world import (
    Bounds,
    CurrentField,
    LambOseenVortices,
    Margins,
    Terrain,
    UniformCurrent,
    World,
)
from ..data.bathymetry import load_terrain
from ..data.cache import cached
from ..data.geo import LocalFrame
from ..files import limits as _limits
from .inputs.currentspan import check_span, file_span, lower_bound_s, zero_beyond
from .inputs.geoinput import apply_altitudes, clip_to_data
from .inputs.uncertainty import seabed_at_confidence
from .specs import BoundsSpec, Scenario, SyntheticTerrainSpec
from .tables import table_error
from .validate import from_dict

if TYPE_CHECKING:
    from ...world.land import Land
    from ...world.zones import Zones

MAX_SUBSTEPS = 1000
"""Most sub-steps of the time-optimal planner's travel-time integration per lattice cell (``substep``)."""

__all__ = ["build", "check_plan_sizes"]


def _synthetic_terrain(spec: SyntheticTerrainSpec, bounds: BoundsSpec, src: str) -> Terrain:
    if not (bounds.x and bounds.y):
        raise ScenarioError(f"{src}: [bounds] x and y are required with [terrain.synthetic]")
    (x0, x1), (y0, y1) = bounds.x, bounds.y
    cell = spec.cell_m or max(x1 - x0, y1 - y0) / 200.0
    x = np.linspace(x0, x1, max(int(round((x1 - x0) / cell)) + 1, 2))
    y = np.linspace(y0, y1, max(int(round((y1 - y0) / cell)) + 1, 2))
    gx, gy = np.meshgrid(x, y)
    z = np.full_like(gx, -spec.depth)
    if spec.kind == "plane":
        z = z + spec.slope[0] * gx + spec.slope[1] * gy
    elif spec.kind == "hills":
        for hx, hy, h, s in spec.hills:
            z = z + h * np.exp(-((gx - hx) ** 2 + (gy - hy) ** 2) / (2.0 * s * s))
    elif spec.kind == "ridge":
        z = z + spec.height * np.clip(1.0 - np.abs(gx - spec.ridge_x) / spec.ridge_width, 0.0, None)
    return Terrain(x, y, z, name=f"synthetic:{spec.kind}")


def _check_point(world: World, point: tuple[float, ...], key: str, src: str) -> None:
    p = np.asarray(point, dtype=float)
    table = "" if key.startswith("[") else "[mission] "
    at = "[" + ", ".join(f"{v + 0.0:.2f}" for v in p) + "] m"  # to the cm: one from degrees had 15 decimals
    if not world.bounds.contains(p):
        b = world.bounds
        raise ScenarioError(
            f"{src}: {table}{key} = {at}: outside the bounds x [{b.xmin:.0f}, {b.xmax:.0f}] "
            f"y [{b.ymin:.0f}, {b.ymax:.0f}] z [{b.zmin:.0f}, {b.zmax:.0f}]"
        )
    if world.clearly_free(p):  # decided in numpy: no compiled kernel loaded for a point well clear (issue 56)
        return
    why = world.explain(p, 0.0)
    if why:
        seabed = float(world.seabed(p[0], p[1]))
        extra = f" (seabed at {seabed:.1f} m)" if np.isfinite(seabed) else ""
        raise ScenarioError(f"{src}: {table}{key} = {at}: not a free point: {why}{extra}")


def _check_terrain_size(s: Scenario, extent: tuple[float, float, float, float] | None) -> None:
    """A resampled data grid's node count from the bounds (or the crop box), before reading it."""
    t = s.terrain
    if t is None or not t.resample_m > 0:
        return
    if extent is not None:
        span_x, span_y = extent[1] - extent[0], extent[3] - extent[2]
    elif t.box:
        lat = math.radians(0.5 * (t.box[0] + t.box[1]))
        span_y = (t.box[1] - t.box[0]) * 111_320.0
        span_x = abs(t.box[3] - t.box[2]) * 111_320.0 * max(math.cos(lat), 1e-3)
    else:
        return  # the data's own extent: bounded by the file itself
    nodes = _limits.grid_nodes(span_x, span_y, t.resample_m)
    _limits.check(s.limits, f"{s.source}: [terrain]", f"resample_m = {t.resample_m:g} ({nodes:.3g} nodes)",
                  nodes * _limits.BYTES_PER_TERRAIN_NODE)


def _check_sim_size(s: Scenario) -> None:
    """The simulation preallocates its record for the time limit: check it before any flight."""
    m = s.mission
    pts = [m.start, *m.route, m.goal] if m.route else [m.start, m.goal]
    length = sum(math.dist(a, b) for a, b in zip(pts[:-1], pts[1:]))
    if not m.route:
        length *= 1.5  # a planned path is longer than the straight line
    nbytes = _limits.sim_bytes(length, s.vehicle.speed, s.sim.max_time, s.sim.dt, s.sim.record_every,
                               len(s.obstacles) + len(s.moving))
    _limits.check(s.limits, f"{s.source}: [sim]", f"a record at dt = {s.sim.dt:g} s, record_every = "
                  f"{s.sim.record_every}, for a ~{length:.3g} m mission at [vehicle] speed = {s.vehicle.speed:g}",
                  nbytes)


def _check_endurance_size(s: Scenario) -> None:
    """The energy budget's integration steps (``[endurance] ds_m`` along the mission) against the one estimator."""
    m = s.mission
    pts = [m.start, *m.route, m.goal] if m.route else [m.start, m.goal]
    length = sum(math.dist(a, b) for a, b in zip(pts[:-1], pts[1:])) * (1.0 if m.route else 1.5)
    _limits.check_endurance(s.limits, f"{s.source}: [endurance]", length, max(len(pts) - 1, 1), s.endurance.ds_m)


def check_plan_sizes(s: Scenario, span: tuple[float, float], sweep_s: float = 0.0, timeopt: bool = False) -> None:
    """``[planner.timeopt]`` (lattice and current table) and ``[formation] sample_m`` against the budget.

    Parameters
    ----------
    s : Scenario
        The scenario.
    span : (float, float)
        Horizontal sides of the world's bounds (m; the planners' search box lies inside).
    sweep_s : float, optional
        Span of a departure sweep (s): the table covers it on top of the horizon.
    timeopt : bool, optional
        Check the time-optimal planner even when the scenario names another (a sweep).
    """
    m, p = s.mission, s.planner.timeopt
    pts = [m.start, *m.route, m.goal] if m.route else [m.start, m.goal]
    length = sum(math.dist(a, b) for a, b in zip(pts[:-1], pts[1:])) * (1.0 if m.route else 1.5)
    if timeopt or s.planner.name == "timeopt":
        slowest = s.vehicle.speed * (min(p.speeds) if p.objective == "energy" else 1.0)
        horizon = (p.horizon_s or 1.5 * math.dist(m.start, m.goal) / slowest + 7200.0) + sweep_s
        # the front method's steps: a cell at V + the current, taken as 1.5 V (the built-in tides: ≤ 1.6 V)
        front = 2.5 * s.vehicle.speed if p.method == "front" else 0.0
        nodes, steps, nbytes = _limits.timeopt_size(span[0], span[1], p.cell, p.levels, horizon, p.dt, front)
        _limits.check(s.limits, f"{s.source}: [planner.timeopt]",
                      f"cell = {p.cell:g}, levels = {p.levels}, dt = {p.dt:g} s, horizon_s = {horizon:.6g} s"
                      + (f" (with a {sweep_s:.6g} s departure sweep)" if sweep_s else "")
                      + f": a lattice of {nodes:.3g} nodes × a current table of {steps:.3g} steps, which", nbytes)
        cell = p.cell or max(span) / 100.0  # timeplan.setup's automatic cell
        if p.substep and cell / p.substep > MAX_SUBSTEPS:  # 1e-9 m integrated each edge for ever (> 60 s)
            raise ScenarioError(f"{s.source}: [planner.timeopt] substep = {p.substep:g} m: {cell / p.substep:.3g} "
                                f"sub-steps per cell of {cell:g} m, over the {MAX_SUBSTEPS} allowed (0: cell / 2)")
    if s.formation is not None:
        fp = s.formation.params
        samples = (length / fp.sample_m + 2.0) * s.formation.n
        _limits.check(s.limits, f"{s.source}: [formation]", f"sample_m = {fp.sample_m:g} over a ~{length:.3g} m "
                      f"route for {s.formation.n} vehicles ({samples:.3g} track samples), which",
                      samples * _limits.BYTES_PER_TRACK_SAMPLE)


def build(scenario: Scenario, terrain: Terrain | None = None) -> tuple[World, Mission]:
    """Read the scenario's data and make its World and Mission.

    ``terrain``, when given, replaces the scenario's terrain source (a results folder's saved
    cut-out: the grid the run used, so a moved folder needs no data file).

    Parameters
    ----------
    scenario : Scenario
        The validated scenario.
    terrain : Terrain, optional
        A terrain replacing the scenario's source.

    Returns
    -------
    world : World
        Seabed, currents, obstacles, bounds and margins.
    mission : Mission
        End points, route and every component's settings.

    Raises
    ------
    ScenarioError
        When the start or goal is outside the bounds or not free, or the
        bounds are missing.
    DataError
        When the bathymetry or current data are unusable or do not cover the area.
    """
    s = scenario
    frame = LocalFrame(s.origin.lat, s.origin.lon) if s.origin else None
    b = s.bounds
    extent = (b.x[0], b.x[1], b.y[0], b.y[1]) if b.x and b.y else None
    _check_terrain_size(s, extent)
    _check_endurance_size(s)  # from the document alone: before any data is read
    if extent is not None:  # before any data is read when the bounds say where
        check_plan_sizes(s, (extent[1] - extent[0], extent[3] - extent[2]))
    with _limits.budget(s.limits):  # every data reader estimates against the scenario's budget
        s, terrain, bounds, currents = _read_data(s, frame, extent, terrain)
    land, zones = _vector_layers(s, frame, terrain, bounds)
    world = _world(s, bounds, terrain, currents, land, zones)
    _check_places(s, world)
    _check_current_span(s, world)
    return world, _mission(s, world)


def _read_data(s: Scenario, frame: LocalFrame | None, extent: tuple[float, float, float, float] | None,
               terrain: Terrain | None) -> tuple[Scenario, Terrain | None, Bounds, CurrentField]:
    """The seabed (bounds clipped to it when derived, altitudes placed on it), the bounds and the currents."""
    b = s.bounds
    if s.geo is not None and s.geo.bounds_derived and extent is not None and (terrain is not None or s.terrain):
        data = terrain if terrain is not None else _terrain(s, frame, None)
        extent = clip_to_data(s.geo, extent, data.extent, f"{s.source}: [terrain] {data.name}")  # type: ignore[union-attr]
        s = replace(s, bounds=replace(b, x=extent[:2], y=extent[2:]))
    if terrain is None:  # (a saved cut-out is the seabed the run used: already at its confidence)
        terrain = seabed_at_confidence(s, _terrain(s, frame, extent), frame, extent)
    if s.geo is not None and s.geo.altitudes:
        s = _place_altitudes(s, terrain)
    bounds = _bounds(s, terrain)
    if extent is None:
        check_plan_sizes(s, (bounds.xmax - bounds.xmin, bounds.ymax - bounds.ymin))
    return s, terrain, bounds, _currents(s, frame, bounds)


def _vector_layers(s: Scenario, frame: LocalFrame | None, terrain: Terrain | None,
                   bounds: Bounds) -> tuple[Land | None, Zones | None]:
    """The ``[land]`` polygons and the ``[[zones]]`` within the bounds (their readers imported only when used)."""
    land = None
    if s.land is not None:  # the readers a scenario uses are imported when it does (issue 56)
        from ..data.vector.coast import read_land

        if frame is None:
            raise ScenarioError(f"{s.source}: [land] needs [origin] lat/lon (the polygons are geographic)")
        try:
            land = read_land(s.land, frame, (bounds.xmin, bounds.xmax, bounds.ymin, bounds.ymax), base_dir=s.base_dir)
        except DataError as exc:
            raise DataError(f"{s.source}: [land] {exc}") from exc
    zones = None
    if s.zones:
        from ..data.vector.zones import read_zones

        zones = read_zones(s.zones, frame, terrain, (bounds.xmin, bounds.xmax, bounds.ymin, bounds.ymax),
                           base_dir=s.base_dir)
    return land, zones


def _margins(s: Scenario) -> Margins:
    """The depth band (clipped by the vehicle's depth rating; a glider's yo must fit in it) and the margins."""
    src, m = s.source, s.mission
    min_depth = m.min_depth_m if m.surface else -math.inf
    rating = s.vehicle.max_depth_m  # the vehicle's depth rating clips the mission's depth band
    if not rating > max(min_depth, 0.0):
        raise table_error(f"{src}: [vehicle]", "max_depth_m", rating, f"the depth rating must exceed [mission] "
                          f"min_depth_m = {m.min_depth_m:g}")
    margins = Margins(m.min_altitude_m, min_depth, min(m.max_depth_m, rating), m.obstacle_margin_m)
    dive = s.vehicle.glider.dive_depth_m if s.vehicle.type == "glider" else 0.0
    if dive > margins.max_depth:  # the yo's bottom is not clipped: say so
        raise table_error(f"{src}: [vehicle.glider]", "dive_depth_m", dive, f"deeper than the depth band's "
                          f"{margins.max_depth:g} m ([mission] max_depth_m, [vehicle] max_depth_m)")
    return margins


def _world(s: Scenario, bounds: Bounds, terrain: Terrain | None, currents: CurrentField, land: Land | None,
           zones: Zones | None) -> World:
    """The World of the scenario's parts (a data error named by the scenario)."""
    margins = _margins(s)
    try:
        return World(
            bounds=bounds,
            terrain=terrain,
            currents=currents,
            obstacles=s.obstacles,
            moving=s.moving,
            margins=margins,
            origin=(s.origin.lat, s.origin.lon) if s.origin else None,
            name=s.name,
            land=land,
            zones=zones,
        )
    except DataError as exc:
        raise DataError(f"{s.source}: {exc}") from exc


def _check_places(s: Scenario, world: World) -> None:
    """Start, goal, route, the fleet's slots and rally points inside the world and free (and the record's size)."""
    src, m = s.source, s.mission
    _check_point(world, m.start, "start", src)
    _check_point(world, m.goal, "goal", src)
    _check_sim_size(s)
    for i, wp in enumerate(m.route):
        if not world.bounds.contains(np.asarray(wp)):
            raise table_error(f"{src}: [mission]", f"route[{i}]", list(wp), "outside the bounds")
    for spec in s.formation.vehicles if s.formation is not None else ():
        span = world.bounds.zmax - world.bounds.zmin
        if abs(spec.depth_offset_m) >= span:  # no slot could fly there: refused, not silently flown in column
            raise table_error(f"{src}: [[vehicles]] {spec.name!r}", "depth_offset_m", spec.depth_offset_m,
                              f"puts the vehicle outside the world's {span:g} m of depth ([bounds] z)")
        if spec.start:
            _check_point(world, spec.start, f"[[vehicles]] {spec.name!r} start", src)
    for rally in s.endurance.rally:
        _check_point(world, rally.point, f"[endurance] rally {rally.name!r} point", src)


def _check_current_span(s: Scenario, world: World) -> None:
    """The current data cover the mission's time (issue 51: a file too short for any mission)."""
    m = s.mission
    pts = np.asarray([m.start, *m.route, m.goal], dtype=float)
    least = sum(lower_bound_s(world, a, b, s.vehicle.max_speed) for a, b in zip(pts[:-1], pts[1:]))
    cruise = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()) / s.vehicle.speed
    check_span(s.source, s.currents.beyond, file_span(world.currents, s.currents.beyond), least, False, cruise)


def _mission(s: Scenario, world: World) -> Mission:
    """The Mission: end points, route and every component's settings."""
    m = s.mission
    return Mission(
        name=s.name,
        start=m.start,
        goal=m.goal,
        route=m.route,
        seed=s.seed,
        vehicle=s.vehicle,
        planner=s.planner,
        guidance=s.guidance.name,
        hybrid=s.guidance.hybrid,
        los=s.guidance.los,
        avoidance=s.avoidance,
        sim=s.sim,
        formation=s.formation,
        follow_altitude_m=m.follow_altitude_m,
        endurance=s.endurance,
        navigation=_navigation(s, world),
    )


def _navigation(s: Scenario, world: World) -> NavParams | None:
    """``[navigation]`` with its USBL ship placed in the local frame; its surfacings need ``min_depth_m = 0``."""
    nav = s.navigation
    if nav is None:
        return None
    src = s.source
    if nav.fixes != "none" and world.margins.min_depth > 0.0:
        raise table_error(f"{src}: [mission]", "min_depth_m", s.mission.min_depth_m,
                          f"[navigation] fixes = {nav.fixes!r} surfaces the vehicle: min_depth_m must be 0")
    if nav.usbl is None:
        return nav
    if world.origin is None:
        raise table_error(f"{src}: [navigation]", "usbl", {"lat": nav.usbl.lat, "lon": nav.usbl.lon},
                          "a USBL position needs the scenario's [origin] (or geographic mission points)")
    x, y = LocalFrame(*world.origin).forward(nav.usbl.lon, nav.usbl.lat)
    return replace(nav, _usbl_xy=(float(x), float(y)))


def _place_altitudes(s: Scenario, terrain: Terrain | None) -> Scenario:
    """Positions given as ``altitude`` above the seabed, placed on the terrain (:mod:`.inputs.geoinput`)."""
    assert s.geo is not None
    if terrain is None:
        ref = s.geo.altitudes[0]
        raise table_error(ref.where, ref.key, {"altitude": ref.altitude}, "an altitude needs a [terrain] (give a "
                          "depth instead)")
    x0, x1, y0, y1 = terrain.extent

    def seabed(x: float, y: float) -> float:
        return float(terrain.elevation(x, y)) if x0 <= x <= x1 and y0 <= y <= y1 else math.nan

    # the compiled seabed's values (they are printed and planned from, to the bit), kept in the readers' cache
    # under the grid's and the points' bits: a second validate or plan loads no compiled kernel for them (#56)
    points = tuple((float(ref.x), float(ref.y)) for ref in s.geo.altitudes)
    coef, *origin = terrain.kernel_data[:5]
    grid = hashlib.sha256(coef.tobytes() + repr((coef.shape, origin)).encode()).hexdigest()
    z = cached("seabed-at", (grid, points), (), lambda: np.array([seabed(x, y) for x, y in points]),
               lambda a: ({"z": a}, {}), lambda arrays, _: arrays["z"])
    at = dict(zip(points, z.tolist()))
    placed = from_dict(apply_altitudes(s.geo, lambda x, y: at[(x, y)] if (x, y) in at else seabed(x, y)),
                       s.source, s.base_dir)
    return replace(s, mission=placed.mission, obstacles=placed.obstacles, moving=placed.moving,
                   formation=placed.formation)


def _terrain(s: Scenario, frame: LocalFrame | None,
             extent: tuple[float, float, float, float] | None) -> Terrain | None:
    """The scenario's seabed: a data grid (cropped to the bounds), a synthetic one, or none."""
    try:
        if s.terrain is not None:
            return load_terrain(s.terrain, frame, base_dir=s.base_dir, extent_m=extent)
        if s.synthetic is not None:
            return _synthetic_terrain(s.synthetic, s.bounds, s.source)
    except DataError as exc:
        raise DataError(f"{s.source}: [terrain] {exc}") from exc
    return None


def _bounds(s: Scenario, terrain: Terrain | None) -> Bounds:
    """The operating box: ``[bounds]``, completed from the terrain's extent and depth."""
    b = s.bounds
    if terrain is not None:
        x0, x1, y0, y1 = terrain.extent
        xr, yr = (b.x or (x0, x1)), (b.y or (y0, y1))
        zr = b.z or (float(terrain.z.min()) - 1.0, 0.0)
    else:
        if not (b.x and b.y and b.z):
            raise ScenarioError(f"{s.source}: [bounds] x, y and z are required when there is no terrain")
        xr, yr, zr = b.x, b.y, b.z
    return Bounds(xr[0], xr[1], yr[0], yr[1], zr[0], zr[1])


def _currents(s: Scenario, frame: LocalFrame | None, bounds: Bounds) -> CurrentField:
    """The current field (vortices, a data file, tides or uniform), checked to cover the bounds."""
    c, src = s.currents, s.source
    box = (bounds.xmin, bounds.xmax, bounds.ymin, bounds.ymax)
    currents: CurrentField
    try:
        if c.vortices:
            v = c.vortices
            currents = LambOseenVortices(np.array([(q.x, q.y) for q in v]), np.array([q.gamma for q in v]),
                                         np.array([q.delta for q in v]))
        elif c.file is not None:
            from ..data.ocean.currents import read_currents  # the readers a scenario uses, when it does (issue 56)

            currents = read_currents(c.file, frame, base_dir=s.base_dir, extent_m=box,  # type: ignore[arg-type]
                                     start_time=s.mission.start_time)
            if c.beyond == "zero" and file_span(currents, "hold") is not None:  # issue 51: no current after it
                currents = zero_beyond(currents)
        elif c.tides:
            if frame is None or not s.mission.start_time:
                raise ScenarioError(f"{src}: [currents] tides = {c.tides!r} needs [origin] lat/lon and "
                                    "[mission] start_time (ISO 8601, UTC)")
            from ..data.ocean.tides import load_tidal_current, parse_start_time

            currents = load_tidal_current(c.tides, frame, parse_start_time(s.mission.start_time),
                                          base_dir=s.base_dir)
        elif c.members and not any(c.uniform):  # an ensemble alone: its first member is the nominal field
            from .inputs.members import member_fields

            return member_fields(c.members, UniformCurrent(), frame, box, source=src, base_dir=s.base_dir,
                                 start_time=s.mission.start_time, first_only=True)[0][1]
        else:
            currents = UniformCurrent(c.uniform)
    except DataError as exc:
        if c.members and str(exc).startswith(f"{src}: [currents]"):
            raise
        raise DataError(f"{src}: [currents] {exc}") from exc
    if not currents.covers(*box):
        what = f"file {c.file.path!r}" if c.file is not None else "field"  # type: ignore[union-attr]
        raise DataError(f"{src}: [currents] the current {what} does not cover the bounds x [{bounds.xmin:.0f}, "
                        f"{bounds.xmax:.0f}] y [{bounds.ymin:.0f}, {bounds.ymax:.0f}] m")
    return currents
