"""Scenario documents validated: the dict ``tomllib`` parses from a scenario file becomes a frozen
:class:`~auvplan.io.scenario.specs.Scenario` (:func:`from_dict`); unknown keys, wrong types and out-of-range
values are :class:`ScenarioError` naming the file, the table, the key and the value.  Reading the file is
:mod:`auvplan.io.scenario.loader`'s; building the World and Mission, :mod:`auvplan.io.scenario.build`'s (which
re-validates a scenario here once its altitudes are placed on the terrain).
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...errors import ScenarioError
from ...guidance.formation.keeping import Formation, VehicleSpec
from ...planners.core import registry
from ...planners.core.base import PlannerSpec
from ...sim import SimParams
from ...world import (
    CircleMotion,
    Ellipsoid,
    LinearMotion,
    MovingObstacle,
    RandomWalkMotion,
    Sphere,
    WaypointMotion,
)
from ..data.bathymetry import TerrainSpec
from ..data.vector.zones import parse_zones
from ..files import limits as _limits
from ..files.limits import Limits
from .defaults import apply_preset
from .inputs.geoinput import resolve_positions
from .names import check_scenario_name, check_vehicle_folders
from .specs import SECTIONS, BoundsSpec, MissionSpec, Scenario, SyntheticTerrainSpec
from .tables import build_dataclass, table_error

if TYPE_CHECKING:
    from ...endurance.params import EnduranceParams
    from ...vehicles import VehicleParams
    from ..data.vector.coast import LandSpec
    from .specs import CurrentsSpec, OriginSpec

__all__ = ["from_dict"]

_TOP_KEYS = {
    "name", "description", "seed", "origin", "bounds", "terrain", "currents", "obstacles", "moving",
    "mission", "vehicle", "planner", "guidance", "avoidance", "sim", "limits", "land", "formation", "vehicles",
    "endurance",
    "survey", "zones", "navigation",
}



# ---------------------------------------------------------------------- obstacles
@dataclass(frozen=True)
class _SphereSpec:
    type: str
    center: tuple[float, float, float]
    radius: float


@dataclass(frozen=True)
class _EllipsoidSpec:
    type: str
    center: tuple[float, float, float]
    semi_axes: tuple[float, float, float]
    yaw_deg: float = 0.0
    pitch_deg: float = 0.0
    roll_deg: float = 0.0


def _shape(table: dict[str, Any], where: str, *, moving: bool) -> Any:
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: expected a table (type, center, radius, ...), got {table!r:.80}")
    if moving:  # a moving shape is placed by its motion; its other keys belong to the motion
        t = {k: v for k, v in table.items() if k in _SHAPE_KEYS}
        t["center"] = [0.0, 0.0, 0.0]
    else:
        t = dict(table)
    kind = t.setdefault("type", "sphere")
    if kind == "sphere":
        s = build_dataclass(_SphereSpec, t, where)
        try:
            return Sphere(s.center, s.radius)
        except ValueError as exc:
            raise table_error(where, "radius", s.radius, str(exc)) from exc
    if kind == "ellipsoid":
        s = build_dataclass(_EllipsoidSpec, t, where)
        try:
            return Ellipsoid(s.center, s.semi_axes, math.radians(s.yaw_deg), math.radians(s.pitch_deg),
                             math.radians(s.roll_deg))
        except ValueError as exc:
            raise table_error(where, "semi_axes", list(s.semi_axes), str(exc)) from exc
    raise table_error(where, "type", kind, "choose 'sphere' or 'ellipsoid'")


@dataclass(frozen=True)
class _LinearSpec:
    start: tuple[float, float, float]
    velocity: tuple[float, float, float]


@dataclass(frozen=True)
class _CircleSpec:
    center: tuple[float, float, float]
    orbit_radius: float
    period: float
    phase_deg: float = 0.0


@dataclass(frozen=True)
class _WaypointsSpec:
    points: tuple[tuple[float, float, float], ...]
    speed: float
    loop: bool = True


@dataclass(frozen=True)
class _RandomWalkSpec:
    start: tuple[float, float, float]
    speed: float
    turn_sigma: float = 0.05
    heading_deg: float = 0.0
    duration: float = 7200.0
    dt: float = 1.0
    seed: int = 0


_SHAPE_KEYS = ("type", "radius", "semi_axes", "yaw_deg", "pitch_deg", "roll_deg")
_MOVING_KEYS = ("name", "motion", "appears", "disappears")


def _moving(table: dict[str, Any], where: str, bounds_xy: tuple[float, float, float, float] | None,
            limits: Limits) -> MovingObstacle:
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}: expected a table, got {table!r:.80}")
    shape = _shape(table, where, moving=True)
    motion_name = table.get("motion")
    if motion_name is None:
        raise ScenarioError(f"{where} missing required key 'motion'")
    rest = {k: v for k, v in table.items() if k not in _SHAPE_KEYS + _MOVING_KEYS}
    motion: LinearMotion | CircleMotion | WaypointMotion | RandomWalkMotion
    try:
        if motion_name == "linear":
            s = build_dataclass(_LinearSpec, rest, where)
            motion = LinearMotion(s.start, s.velocity)
        elif motion_name == "circle":
            s = build_dataclass(_CircleSpec, rest, where)
            motion = CircleMotion(s.center, s.orbit_radius, s.period, math.radians(s.phase_deg))
        elif motion_name == "waypoints":
            s = build_dataclass(_WaypointsSpec, rest, where)
            for i in range(1, len(s.points)):
                if math.dist(s.points[i - 1], s.points[i]) <= 1e-9:
                    raise table_error(where, f"points[{i}]", list(s.points[i]), f"repeats points[{i - 1}]: a "
                                      "zero-length leg")
            motion = WaypointMotion(np.asarray(s.points), s.speed, s.loop)
        elif motion_name == "random-walk":
            s = build_dataclass(_RandomWalkSpec, rest, where)
            if s.dt > 0 and s.duration > 0:  # the track is precomputed: check its size first
                _limits.check(limits, where, f"duration / dt = {s.duration:g} / {s.dt:g} (a precomputed track)",
                              s.duration / s.dt * _limits.BYTES_PER_WALK_STEP)
            motion = RandomWalkMotion(s.start, s.speed, s.turn_sigma, math.radians(s.heading_deg), s.duration,
                                      s.dt, s.seed, bounds_xy)
        else:
            raise table_error(where, "motion", motion_name, "choose linear, circle, waypoints or random-walk")
    except ValueError as exc:
        if isinstance(exc, ScenarioError):
            raise
        raise ScenarioError(f"{where} {exc}") from exc
    appears = table.get("appears", 0.0)
    disappears = table.get("disappears", math.inf)
    for key, val in (("appears", appears), ("disappears", disappears)):
        if isinstance(val, bool) or not isinstance(val, (int, float)):
            raise table_error(where, key, val, "expected a number of seconds")
        if key in table and not math.isfinite(val):
            raise table_error(where, key, val, "must be finite (omit 'disappears' for never)")
    if not disappears > appears:
        raise table_error(where, "disappears", disappears, "must be later than 'appears'")
    name = table.get("name", "")
    if not isinstance(name, str):
        raise table_error(where, "name", name, "expected a string")
    if len(name) > 128 or any(not c.isprintable() for c in name):  # U+202E reversed every message naming it
        raise table_error(where, "name", name[:80], "a moving obstacle's name is up to 128 characters without "
                          "control or formatting characters (messages name it on one line)")
    return MovingObstacle(shape, motion, name, float(appears), float(disappears))


def _section(data: dict[str, Any], key: str, src: str) -> Any:
    table = data.get(key, {})
    return build_dataclass(SECTIONS[key], table, f"{src}: [{key}]")


def _planner(table: Any, src: str) -> PlannerSpec:
    """``[planner]``, with the ``[planner.<name>]`` table of a planner registered from outside the package
    read into its registered settings type (:func:`auvplan.planners.core.registry.register`)."""
    where = f"{src}: [planner]"
    builtin = {f.name for f in dataclasses.fields(PlannerSpec)}
    outside = {k: v for k, v in table.items() if isinstance(v, dict) and k not in builtin and registry.known(k)} \
        if isinstance(table, dict) else {}
    spec: PlannerSpec = build_dataclass(PlannerSpec, table, where, skip=tuple(outside))
    plugins = []
    for name, sub in outside.items():
        cls = registry.get(name).settings_type
        if cls is None:
            raise ScenarioError(f"{src}: [planner.{name}] planner {name!r} takes no settings")
        plugins.append((name, build_dataclass(cls, sub, f"{src}: [planner.{name}]")))
    return dataclasses.replace(spec, _plugins=tuple(plugins)) if plugins else spec


def from_dict(data: dict[str, Any], source: str = "<string>", base_dir: Path | None = None) -> Scenario:
    """Validate a parsed scenario document (the dict ``tomllib`` returns) into a :class:`Scenario`.

    Parameters
    ----------
    data : dict
        The parsed TOML document.
    source : str, optional
        Its name, for messages.
    base_dir : pathlib.Path, optional
        Folder that relative data paths resolve against.

    Returns
    -------
    Scenario
        The validated scenario.
    """
    name, description, seed = _header(data, source)
    raw = data
    geo = resolve_positions(data, source, base_dir)  # {lat, lon, depth | altitude} -> metre triples
    if geo is not None:
        data = geo.metric
    limits = _section(data, "limits", source)
    origin, bounds, terrain, synthetic, currents, land = _world_sections(data, source)
    obstacles, moving = _obstacles(data, source, bounds, limits)
    mission = _section(data, "mission", source)
    planner = _planner(data.get("planner", {}), source)
    sim = _section(data, "sim", source)
    _check_sizes(source, limits, bounds, synthetic, planner)
    _limits.check_members(f"{source}: [currents] members", [m.count for m in currents.members])
    survey = _section(data, "survey", source) if "survey" in data else None
    if survey is None:  # a survey may start and end at the same launch/recovery point
        _check_geometry(source, mission, sim)
    formation = _formation(data, source, mission)
    zones = parse_zones(data.get("zones", []), source)
    vehicle, endurance = _vehicle_endurance(data, source)
    return Scenario(
        name=name, description=description.strip(), seed=seed, source=source, base_dir=base_dir, origin=origin,
        bounds=bounds, terrain=terrain, synthetic=synthetic, currents=currents, obstacles=obstacles, moving=moving,
        mission=mission, vehicle=vehicle, planner=planner, guidance=_section(data, "guidance", source),
        avoidance=_section(data, "avoidance", source), sim=sim, raw=copy.deepcopy(raw), limits=limits, land=land,
        formation=formation, geo=geo, endurance=endurance, survey=survey, zones=zones,
        navigation=_section(data, "navigation", source) if "navigation" in data else None,
    )


def _world_sections(data: dict[str, Any], source: str) -> tuple[OriginSpec | None, BoundsSpec, TerrainSpec | None,
                                                                 SyntheticTerrainSpec | None, CurrentsSpec,
                                                                 LandSpec | None]:
    """``[origin]``, ``[bounds]``, ``[terrain]`` (data or synthetic), ``[currents]`` and ``[land]``, with what a real
    terrain and land need (an origin; a terrain to burn the land into)."""
    origin = _section(data, "origin", source) if "origin" in data else None
    bounds = _section(data, "bounds", source)
    terrain, synthetic = _terrain(data, source)
    if (terrain is not None) and origin is None:
        raise ScenarioError(f"{source}: [origin] lat/lon is required with a real terrain (for its projection)")
    currents = _section(data, "currents", source)
    land = _section(data, "land", source) if "land" in data else None
    if land is not None and (origin is None or terrain is None and synthetic is None):
        raise ScenarioError(f"{source}: [land] needs [origin] lat/lon and a [terrain] to burn the land into")
    return origin, bounds, terrain, synthetic, currents, land


def _obstacles(data: dict[str, Any], source: str, bounds: Any,
               limits: Limits) -> tuple[tuple[Any, ...], tuple[MovingObstacle, ...]]:
    """``[[obstacles]]`` and ``[[moving]]`` (a moving one's random walk kept within the bounds)."""
    obstacles = tuple(_shape(t, f"{source}: [[obstacles]] #{i + 1}", moving=False)
                      for i, t in enumerate(_array(data, "obstacles", source)))
    bxy = (bounds.x + bounds.y) if bounds.x and bounds.y else None
    moving = tuple(_moving(t, f"{source}: [[moving]] #{i + 1}", bxy, limits)
                   for i, t in enumerate(_array(data, "moving", source)))
    return obstacles, moving


def _vehicle_endurance(data: dict[str, Any], source: str) -> tuple[VehicleParams, EnduranceParams]:
    """``[vehicle]`` (its preset applied) and ``[endurance]``, whose return speed must be one the vehicle flies."""
    vehicle = build_dataclass(SECTIONS["vehicle"], apply_preset(data.get("vehicle", {}), f"{source}: [vehicle]"),
                              f"{source}: [vehicle]")
    endurance = _section(data, "endurance", source)
    ret = endurance.return_speed
    if ret and not vehicle.min_speed <= ret <= vehicle.max_speed:  # 100 m/s or 1e-300 m/s: a return costed at it
        raise table_error(f"{source}: [endurance]", "return_speed", ret, f"outside the vehicle's speeds [min_speed "
                          f"{vehicle.min_speed:g}, max_speed {vehicle.max_speed:g}] m/s (0: its cruise speed)")
    return vehicle, endurance

def _header(data: Any, source: str) -> tuple[str, str, int]:
    """The document's top level: a table of known sections with ``[mission]``; name, description, seed."""
    if not isinstance(data, dict):
        raise ScenarioError(f"{source}: expected a table of sections, got {type(data).__name__}")
    for key in data:
        if key not in _TOP_KEYS:
            raise ScenarioError(f"{source}: unknown key {key!r} (allowed: {', '.join(sorted(_TOP_KEYS))})")
    if "mission" not in data:
        raise ScenarioError(f"{source}: missing required table [mission]")
    name = data.get("name", Path(source).stem)
    description = data.get("description", "")
    seed = data.get("seed", 0)
    if not isinstance(name, str):
        raise table_error(f"{source}:", "name", name, "expected a string")
    if "name" in data:  # an explicit name (the file's own stem, the default, is the user's choice)
        check_scenario_name(source, name)
    if not isinstance(description, str):
        raise table_error(f"{source}:", "description", description, "expected a string")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise table_error(f"{source}:", "seed", seed, "expected a non-negative integer")
    if seed >= 2**63:
        raise table_error(f"{source}:", "seed", seed, "must be < 2^63")
    return name, description, seed


def _terrain(data: dict[str, Any], source: str) -> tuple[TerrainSpec | None, SyntheticTerrainSpec | None]:
    """``[terrain]`` (a data source) or ``[terrain.synthetic]`` (an analytic seabed), not both."""
    if "terrain" not in data:
        return None, None
    t = dict(data["terrain"]) if isinstance(data["terrain"], dict) else data["terrain"]
    if isinstance(t, dict) and "synthetic" in t:
        if len(t) > 1:
            extra = sorted(k for k in t if k != "synthetic")
            raise ScenarioError(f"{source}: [terrain] {extra[0]!r} cannot be combined with [terrain.synthetic]")
        return None, build_dataclass(SyntheticTerrainSpec, t["synthetic"], f"{source}: [terrain.synthetic]")
    return _section(data, "terrain", source), None


def _array(data: dict[str, Any], key: str, source: str) -> list[Any]:
    """An array of tables (``[[obstacles]]``, ``[[moving]]``), empty when absent."""
    raw = data.get(key, [])
    if not isinstance(raw, list):
        raise table_error(f"{source}:", key, raw, f"expected an array of tables [[{key}]]")
    return raw


def _formation(data: dict[str, Any], src: str, mission: MissionSpec) -> Formation | None:
    """``[[vehicles]]`` and ``[formation]``: both or neither."""
    if "vehicles" not in data and "formation" not in data:
        return None
    raw = data.get("vehicles", [])
    if not isinstance(raw, list) or not raw:
        raise table_error(f"{src}:", "vehicles", raw, "expected an array of tables [[vehicles]] (name, role, ...)")
    vehicles = tuple(build_dataclass(VehicleSpec, v, f"{src}: [[vehicles]] #{i + 1}") for i, v in enumerate(raw))
    check_vehicle_folders(src, [v.name for v in vehicles])
    params = _section(data, "formation", src)
    for i, ch in enumerate(params.changes):
        if ch.waypoint >= 0 and ch.waypoint >= max(len(mission.route), 1):
            raise table_error(f"{src}: [formation]", f"changes[{i}].waypoint", ch.waypoint,
                              f"the [mission] route has {len(mission.route)} waypoints" if mission.route else
                              "a waypoint needs a [mission] route (use at_m with a planned route)")
    try:
        return Formation(params, vehicles)
    except ValueError as exc:
        raise ScenarioError(f"{src}: [[vehicles]] {exc}") from exc


def _check_sizes(src: str, limits: Limits, bounds: BoundsSpec, synthetic: SyntheticTerrainSpec | None,
                 planner: PlannerSpec) -> None:
    """Sizes known from the document alone, against the budget (before anything is allocated)."""
    if synthetic is not None and bounds.x and bounds.y:
        (x0, x1), (y0, y1) = bounds.x, bounds.y
        cell = synthetic.cell_m or max(x1 - x0, y1 - y0) / 200.0
        nodes = _limits.grid_nodes(x1 - x0, y1 - y0, cell)
        _limits.check(limits, f"{src}: [terrain.synthetic]", f"cell_m = {cell:g} over the bounds ({nodes:.3g} nodes)",
                      nodes * _limits.BYTES_PER_TERRAIN_NODE)
    pts = float(planner.population) * float(planner.samples)
    _limits.check(limits, f"{src}: [planner]", f"population × samples = {planner.population} × {planner.samples}",
                  pts * _limits.BYTES_PER_SAMPLE)
    _limits.check_plan_work(f"{src}: [planner]", planner.population, planner.iterations, planner.budget,
                            planner.samples)  # after the memory: a population bomb names its memory first
    grid = planner.grid
    if grid.cell > 0 and bounds.x and bounds.y and bounds.z:
        nodes = min(_limits.grid_nodes(bounds.x[1] - bounds.x[0], bounds.y[1] - bounds.y[0], grid.cell)
                    * ((bounds.z[1] - bounds.z[0]) / (grid.cell_z or grid.cell) + 1.0), grid.max_nodes)
    else:
        nodes = grid.target_nodes
    _limits.check(limits, f"{src}: [planner.grid]", f"a reference lattice of ~{nodes:.3g} nodes",
                  _limits.lattice_bytes(nodes))


def _check_geometry(src: str, m: MissionSpec, sim: SimParams) -> None:
    """Zero-length and degenerate missions: start on the goal, repeated or too few route points."""
    where = f"{src}: [mission]"
    if not m.route:
        gap = math.dist(m.start, m.goal)
        if gap <= sim.arrival_radius:
            raise table_error(where, "goal", list(m.goal), f"is {gap:.3g} m from start, within [sim] arrival_radius "
                              f"({sim.arrival_radius:g} m): nothing to plan")
        return
    if len(m.route) < 2:
        raise table_error(where, "route", [list(p) for p in m.route], "needs at least two points")
    for i in range(1, len(m.route)):
        a, b = m.route[i - 1], m.route[i]
        if math.hypot(b[0] - a[0], b[1] - a[1]) <= 1e-6:
            raise table_error(where, f"route[{i}]", list(b), f"no horizontal distance from route[{i - 1}] "
                              f"({list(a)}): a leg the vehicle cannot steer along")
