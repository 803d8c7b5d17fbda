"""Scenario files: TOML → frozen dataclasses → :class:`World` + :class:`Mission`.

Every table maps onto one frozen dataclass (see :mod:`auvplan.io.tables`):
unknown keys, wrong types and out-of-range values are :class:`ScenarioError`
naming the file, the table, the key and the value.  :func:`build` then makes
the World (reading the bathymetry and currents) and checks the mission's start
and goal against it.

Layout (all tables optional except ``[mission]``)::

    name = "..."            description = "..."        seed = 1
    [origin]   lat, lon                                     # geographic scenarios
    [bounds]   x = [min, max]  y = [min, max]  z = [min, max]
    [terrain]  builtin | file, variable, positive, box, resample_m, method, nan_policy
    [terrain.synthetic]  kind = flat|plane|hills|ridge, depth, ...
    [currents] uniform = [u, v, w]   vortices = [{x, y, gamma, delta}, ...]   file = "..."
    [land]     builtin = "gshhg-juan-de-fuca" | file = "coast.gpkg", layer   # coastlines: no-go
    [[obstacles]] type = sphere|ellipsoid, center, radius | semi_axes, yaw_deg, pitch_deg, roll_deg
    [[moving]]    type, radius | semi_axes, motion = linear|circle|waypoints|random-walk, ...
    [mission]  start, goal, route, min_altitude_m, min_depth_m, max_depth_m, obstacle_margin_m
    [[vehicles]]  name, role = leader|follower, start, depth_offset_m     # several vehicles ...
    [formation]   shape = line|column|wedge, spacing_m, changes, ...    # ... flying in formation
    [vehicle] [planner] [guidance] [avoidance] [sim]   parameters of those components
"""

from __future__ import annotations

import copy
import math
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import DataError, ScenarioError
from ..guidance.formation import Formation, FormationParams, VehicleSpec
from ..guidance.hybrid import HybridParams
from ..guidance.local import AvoidanceParams
from ..guidance.los import LosParams
from ..planners.base import PlannerSpec
from ..sim import Mission, SimSettings
from ..vehicles import VehicleParams
from ..world import (
    Bounds,
    CircleMotion,
    CurrentField,
    Ellipsoid,
    LambOseenVortices,
    LinearMotion,
    Margins,
    MovingObstacle,
    RandomWalkMotion,
    Sphere,
    Terrain,
    UniformCurrent,
    WaypointMotion,
    World,
)
from . import limits as _limits
from .bathymetry import TerrainSpec, load_terrain
from .coast import LandSpec, read_land
from .currents import CurrentsFileSpec, parse_time, read_currents
from .geo import LocalFrame
from .limits import Limits
from .tables import build_dataclass, table_error
from .tides import load_tidal_current, parse_start_time

__all__ = [
    "Scenario",
    "OriginSpec",
    "BoundsSpec",
    "SyntheticTerrainSpec",
    "CurrentsSpec",
    "VortexSpec",
    "MissionSpec",
    "GuidanceSpec",
    "load",
    "loads",
    "build",
    "builtin_scenarios",
    "resolve",
    "from_dict",
    "SECTIONS",
]


# ---------------------------------------------------------------------- section dataclasses
@dataclass(frozen=True)
class OriginSpec:
    """Geographic position of the local origin (degrees).

    Attributes
    ----------
    lat : float
        Latitude of the origin (degrees, WGS84), in [-90, 90].
    lon : float
        Longitude of the origin (degrees, WGS84), in [-360, 360].
    """

    lat: float
    lon: float

    def __post_init__(self) -> None:
        if not -90.0 <= self.lat <= 90.0:
            raise ValueError(f"lat = {self.lat}: must lie in [-90, 90]")
        if not -360.0 <= self.lon <= 360.0:
            raise ValueError(f"lon = {self.lon}: must lie in [-360, 360]")


@dataclass(frozen=True)
class BoundsSpec:
    """Operating box (m); empty axes are taken from the terrain.

    Attributes
    ----------
    x, y, z : tuple of float
        ``[min, max]`` of each axis in the local frame (m, z up); empty: from the terrain.
    """

    x: tuple[float, ...] = ()
    y: tuple[float, ...] = ()
    z: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        for name in ("x", "y", "z"):
            v = getattr(self, name)
            if v and (len(v) != 2 or not v[0] < v[1]):
                raise ValueError(f"{name} = {list(v)}: must be [min, max] with min < max")


@dataclass(frozen=True)
class SyntheticTerrainSpec:
    """Analytic seabed for laboratory scenes.

    ``kind``: ``flat`` (``depth``), ``plane`` (``depth`` at the origin plus
    ``slope = [dz/dx, dz/dy]``), ``hills`` (flat plus Gaussian hills
    ``hills = [[x, y, height, sigma], ...]``) or ``ridge`` (flat plus a ridge of
    ``height`` along x = ``ridge_x`` with half-width ``ridge_width``).

    Attributes
    ----------
    kind : str
        ``flat``, ``plane``, ``hills`` or ``ridge``.
    depth : float
        Water depth at the origin (m, positive).
    cell_m : float
        Grid cell (m); 0 chooses one from the bounds.
    slope : tuple of 2 float
        ``[dz/dx, dz/dy]`` of a ``plane`` (m/m).
    hills : tuple of (x, y, height, sigma)
        Gaussian hills: centre (m), height (m) and width σ (m).
    ridge_x : float
        x of the ridge's crest (m).
    ridge_width : float
        Half-width of the ridge (m).
    height : float
        Height of the ridge above the flat seabed (m).
    """

    kind: str = "flat"
    depth: float = 100.0
    cell_m: float = 0.0
    slope: tuple[float, float] = (0.0, 0.0)
    hills: tuple[tuple[float, float, float, float], ...] = ()
    ridge_x: float = 0.0
    ridge_width: float = 10.0
    height: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in ("flat", "plane", "hills", "ridge"):
            raise ValueError(f"kind = {self.kind!r}: choose flat, plane, hills or ridge")
        if self.depth <= 0:
            raise ValueError(f"depth = {self.depth}: must be positive")
        if self.cell_m < 0 or self.ridge_width <= 0:
            raise ValueError("cell_m must be >= 0 and ridge_width > 0")


@dataclass(frozen=True)
class VortexSpec:
    """One Lamb–Oseen vortex: centre (m), circulation ``gamma`` (m²/s), core radius ``delta`` (m).

    Attributes
    ----------
    x, y : float
        Centre (m).
    gamma : float
        Circulation Γ (m²/s), positive anticlockwise.
    delta : float
        Core radius δ (m), positive.
    """

    x: float
    y: float
    gamma: float
    delta: float

    def __post_init__(self) -> None:
        if self.delta <= 0:
            raise ValueError(f"delta = {self.delta}: the core radius must be positive")


@dataclass(frozen=True)
class CurrentsSpec:
    """Current field: uniform, a sum of Lamb–Oseen vortices, a NetCDF file, or tidal stations
    (``tides`` = a built-in name such as ``"juan-de-fuca"`` or a station JSON file; needs [origin]
    and [mission] start_time).

    Attributes
    ----------
    uniform : tuple of 3 float
        Uniform current east, north, up (m/s).
    vortices : tuple of VortexSpec
        Lamb–Oseen vortices.
    file : str or CurrentsFileSpec or None
        A NetCDF current file (``file = "x.nc"`` or a table with its variable names).
    tides : str
        A built-in tidal station set or a station JSON file.
    """

    uniform: tuple[float, float, float] = (0.0, 0.0, 0.0)
    vortices: tuple[VortexSpec, ...] = ()
    file: str | CurrentsFileSpec | None = None
    tides: str = ""

    def __post_init__(self) -> None:
        if isinstance(self.file, str):  # file = "x.nc" is short for file = { path = "x.nc" }
            object.__setattr__(self, "file", CurrentsFileSpec(path=self.file))
        kinds = int(any(self.uniform)) + int(bool(self.vortices)) + int(self.file is not None) + int(bool(self.tides))
        if kinds > 1:
            raise ValueError("give only one of 'uniform', 'vortices', 'file' and 'tides'")


@dataclass(frozen=True)
class MissionSpec:
    """Start, goal, optional explicit route, and the vehicle's safety margins (m).

    Attributes
    ----------
    start, goal : tuple of 3 float
        End points (x, y, z) in the local frame (m, z up); must be free and in the bounds.
    route : tuple of points
        A fixed route to fly instead of planning (at least two points, no zero-length leg).
    min_altitude_m : float
        Least height above the seabed.
    min_depth_m, max_depth_m : float
        Depth band (m below the surface).
    obstacle_margin_m : float
        Extra clearance around every obstacle.
    surface : bool
        ``false`` removes the sea-surface constraint (laboratory scenes in a document's own
        coordinates, e.g. document 000's goal at z = +30).
    start_time : str
        ISO 8601 UTC time of the start, matched to the current file's time axis or the tides
        (empty: the file's first time).
    """

    start: tuple[float, float, float]
    goal: tuple[float, float, float]
    route: tuple[tuple[float, float, float], ...] = ()
    min_altitude_m: float = 10.0
    min_depth_m: float = 0.0
    max_depth_m: float = math.inf
    obstacle_margin_m: float = 0.0
    surface: bool = True
    start_time: str = ""

    def __post_init__(self) -> None:
        if self.start_time:  # ISO 8601, matched to the current file's CF time or the tides
            try:
                parse_time(self.start_time)
            except ValueError as exc:
                raise ValueError(f"start_time = {self.start_time!r}: {exc}") from exc
        for name in ("min_altitude_m", "min_depth_m", "obstacle_margin_m"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name} = {getattr(self, name)}: must be >= 0")
        if not self.max_depth_m > self.min_depth_m:
            raise ValueError(f"max_depth_m = {self.max_depth_m}: must exceed min_depth_m")
        if any(not math.isfinite(v) for v in self.start + self.goal):
            raise ValueError("start and goal must be finite")


@dataclass(frozen=True)
class GuidanceSpec:
    """Which path follower drives the vehicle, with the parameters of each.

    Attributes
    ----------
    name : str
        ``hybrid``, ``los`` or ``ilos``.
    hybrid : HybridParams
        Document 001's hybrid field.
    los : LosParams
        LOS and ILOS.
    """

    name: str = "hybrid"
    hybrid: HybridParams = field(default_factory=HybridParams)
    los: LosParams = field(default_factory=LosParams)

    def __post_init__(self) -> None:
        if self.name not in ("hybrid", "los", "ilos"):
            raise ValueError(f"name = {self.name!r}: choose hybrid, los or ilos")


@dataclass(frozen=True, eq=False)
class Scenario:
    """A parsed, validated scenario (nothing read from disk yet but the TOML itself).

    Attributes
    ----------
    name, description : str
        Scenario name and one-line description.
    seed : int
        Default random seed.
    source : str
        The file (or ``<string>``).
    base_dir : pathlib.Path or None
        Folder that relative data paths resolve against.
    origin : OriginSpec or None
        Geographic origin of the local frame.
    bounds : BoundsSpec
        Operating box (m).
    terrain : TerrainSpec or None
        Bathymetry source (file or built-in).
    synthetic : SyntheticTerrainSpec or None
        Analytic seabed instead.
    currents : CurrentsSpec
        Current field.
    obstacles : tuple
        Static obstacles (spheres, ellipsoids).
    moving : tuple of MovingObstacle
        Moving obstacles.
    mission : MissionSpec
        Start, goal, route and margins.
    vehicle : VehicleParams
        Vehicle parameters.
    planner : PlannerSpec
        Global planner and its settings.
    guidance : GuidanceSpec
        Path follower.
    avoidance : AvoidanceParams
        Local avoidance.
    sim : SimSettings
        Closed-loop settings.
    raw : dict
        The parsed TOML document.
    limits : Limits
        Resource budget.
    land : LandSpec or None
        Coastline source.
    formation : Formation or None
        Several vehicles in formation (``[formation]`` and ``[[vehicles]]``).
    """

    name: str
    description: str
    seed: int
    source: str
    base_dir: Path | None
    origin: OriginSpec | None
    bounds: BoundsSpec
    terrain: TerrainSpec | None
    synthetic: SyntheticTerrainSpec | None
    currents: CurrentsSpec
    obstacles: tuple[Any, ...]
    moving: tuple[MovingObstacle, ...]
    mission: MissionSpec
    vehicle: VehicleParams
    planner: PlannerSpec
    guidance: GuidanceSpec
    avoidance: AvoidanceParams
    sim: SimSettings
    raw: dict[str, Any] = field(repr=False, default_factory=dict)
    limits: Limits = field(default_factory=Limits)
    land: LandSpec | None = None
    formation: Formation | None = None


SECTIONS: dict[str, type] = {
    "origin": OriginSpec, "bounds": BoundsSpec, "terrain": TerrainSpec, "currents": CurrentsSpec,
    "mission": MissionSpec, "vehicle": VehicleParams, "planner": PlannerSpec, "guidance": GuidanceSpec,
    "avoidance": AvoidanceParams, "sim": SimSettings, "limits": Limits, "land": LandSpec,
    "formation": FormationParams,
}
"""The tables that map onto one dataclass each (the loader and :mod:`auvplan.io.schema` share it)."""

_TOP_KEYS = {
    "name", "description", "seed", "origin", "bounds", "terrain", "currents", "obstacles", "moving",
    "mission", "vehicle", "planner", "guidance", "avoidance", "sim", "limits", "land", "formation", "vehicles",
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
    return MovingObstacle(shape, motion, name, float(appears), float(disappears))


# ---------------------------------------------------------------------- loading
def builtin_scenarios() -> dict[str, str]:
    """List the built-in scenarios with their one-line descriptions.

    Returns
    -------
    dict of str to str
        Name → description.
    """
    out = {}
    folder = resources.files("auvplan") / "data" / "scenarios"
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".toml"):
            with entry.open("rb") as fh:
                data = tomllib.load(fh)
            out[entry.name[:-5]] = str(data.get("description", "")).strip().splitlines()[0]
    return out


def resolve(scenario: str | Path) -> Path:
    """Return the path of a scenario given as a file path or the name of a built-in scenario.

    Parameters
    ----------
    scenario : str or pathlib.Path
        A TOML file or a built-in name.

    Returns
    -------
    pathlib.Path
        The TOML file.
    """
    p = Path(scenario)
    if p.is_file():
        return p
    builtin = resources.files("auvplan") / "data" / "scenarios" / f"{scenario}.toml"
    if builtin.is_file():
        return Path(str(builtin))
    names = ", ".join(builtin_scenarios())
    raise ScenarioError(f"{scenario}: no such scenario file, and not a built-in scenario ({names})")


def load(scenario: str | Path) -> Scenario:
    """Parse and validate a scenario file (or built-in name) without reading its data files.

    Parameters
    ----------
    scenario : str or pathlib.Path
        A TOML file or a built-in name.

    Returns
    -------
    Scenario
        The validated scenario.
    """
    path = resolve(scenario)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read ({exc.strerror or exc})") from exc
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise ScenarioError(f"{path}: line {line}: not UTF-8 text (byte 0x{data[exc.start]:02x} at offset "
                            f"{exc.start}); save the scenario as UTF-8") from exc
    return loads(text, source=str(path), base_dir=path.parent)


def _section(data: dict[str, Any], key: str, src: str) -> Any:
    table = data.get(key, {})
    return build_dataclass(SECTIONS[key], table, f"{src}: [{key}]")


def loads(text: str, source: str = "<string>", base_dir: Path | None = None) -> Scenario:
    """Parse and validate scenario TOML text.

    Parameters
    ----------
    text : str
        The TOML.
    source : str, optional
        Its name, for messages.
    base_dir : pathlib.Path, optional
        Folder that relative data paths resolve against.

    Returns
    -------
    Scenario
        The validated scenario.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{source}: invalid TOML ({exc})") from exc
    except RecursionError as exc:
        raise ScenarioError(f"{source}: invalid TOML (arrays or tables nested too deeply)") from exc
    try:
        return from_dict(data, source, base_dir)
    except RecursionError as exc:
        raise ScenarioError(f"{source}: a value is nested too deeply") from exc


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
    if not isinstance(description, str):
        raise table_error(f"{source}:", "description", description, "expected a string")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise table_error(f"{source}:", "seed", seed, "expected a non-negative integer")
    if seed >= 2**63:
        raise table_error(f"{source}:", "seed", seed, "must be < 2^63")
    limits = _section(data, "limits", source)
    origin = _section(data, "origin", source) if "origin" in data else None
    bounds = _section(data, "bounds", source)
    terrain = synthetic = None
    if "terrain" in data:
        t = dict(data["terrain"]) if isinstance(data["terrain"], dict) else data["terrain"]
        if isinstance(t, dict) and "synthetic" in t:
            if len(t) > 1:
                extra = sorted(k for k in t if k != "synthetic")
                raise ScenarioError(f"{source}: [terrain] {extra[0]!r} cannot be combined with [terrain.synthetic]")
            synthetic = build_dataclass(SyntheticTerrainSpec, t["synthetic"], f"{source}: [terrain.synthetic]")
        else:
            terrain = _section(data, "terrain", source)
    if (terrain is not None) and origin is None:
        raise ScenarioError(f"{source}: [origin] lat/lon is required with a real terrain (for its projection)")
    currents = _section(data, "currents", source)
    land = _section(data, "land", source) if "land" in data else None
    if land is not None and (origin is None or terrain is None and synthetic is None):
        raise ScenarioError(f"{source}: [land] needs [origin] lat/lon and a [terrain] to burn the land into")
    obstacles_raw = data.get("obstacles", [])
    if not isinstance(obstacles_raw, list):
        raise table_error(f"{source}:", "obstacles", obstacles_raw, "expected an array of tables [[obstacles]]")
    obstacles = tuple(_shape(t, f"{source}: [[obstacles]] #{i + 1}", moving=False) for i, t in enumerate(obstacles_raw))
    bxy = (bounds.x + bounds.y) if bounds.x and bounds.y else None
    moving_raw = data.get("moving", [])
    if not isinstance(moving_raw, list):
        raise table_error(f"{source}:", "moving", moving_raw, "expected an array of tables [[moving]]")
    moving = tuple(_moving(t, f"{source}: [[moving]] #{i + 1}", bxy, limits) for i, t in enumerate(moving_raw))
    mission = _section(data, "mission", source)
    planner = _section(data, "planner", source)
    sim = _section(data, "sim", source)
    _check_sizes(source, limits, bounds, synthetic, planner)
    _check_geometry(source, mission, sim)
    formation = _formation(data, source, mission)
    return Scenario(
        name=name,
        description=description.strip(),
        seed=seed,
        source=source,
        base_dir=base_dir,
        origin=origin,
        bounds=bounds,
        terrain=terrain,
        synthetic=synthetic,
        currents=currents,
        obstacles=obstacles,
        moving=moving,
        mission=mission,
        vehicle=_section(data, "vehicle", source),
        planner=planner,
        guidance=_section(data, "guidance", source),
        avoidance=_section(data, "avoidance", source),
        sim=sim,
        raw=copy.deepcopy(data),
        limits=limits,
        land=land,
        formation=formation,
    )


def _formation(data: dict[str, Any], src: str, mission: MissionSpec) -> Formation | None:
    """``[[vehicles]]`` and ``[formation]``: both or neither."""
    if "vehicles" not in data and "formation" not in data:
        return None
    raw = data.get("vehicles", [])
    if not isinstance(raw, list) or not raw:
        raise table_error(f"{src}:", "vehicles", raw, "expected an array of tables [[vehicles]] (name, role, ...)")
    vehicles = tuple(build_dataclass(VehicleSpec, v, f"{src}: [[vehicles]] #{i + 1}") for i, v in enumerate(raw))
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
    grid = planner.grid
    if grid.cell > 0 and bounds.x and bounds.y and bounds.z:
        nodes = min(_limits.grid_nodes(bounds.x[1] - bounds.x[0], bounds.y[1] - bounds.y[0], grid.cell)
                    * ((bounds.z[1] - bounds.z[0]) / (grid.cell_z or grid.cell) + 1.0), grid.max_nodes)
    else:
        nodes = grid.target_nodes
    _limits.check(limits, f"{src}: [planner.grid]", f"a reference lattice of ~{nodes:.3g} nodes",
                  nodes * _limits.BYTES_PER_LATTICE_NODE)


def _check_geometry(src: str, m: MissionSpec, sim: SimSettings) -> None:
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


# ---------------------------------------------------------------------- building
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
    table = "" if key.startswith("[[") else "[mission] "
    if not world.bounds.contains(p):
        b = world.bounds
        raise ScenarioError(
            f"{src}: {table}{key} = {list(point)}: outside the bounds x [{b.xmin:.0f}, {b.xmax:.0f}] "
            f"y [{b.ymin:.0f}, {b.ymax:.0f}] z [{b.zmin:.0f}, {b.zmax:.0f}]"
        )
    why = world.explain(p, 0.0)
    if why:
        seabed = float(world.seabed(p[0], p[1]))
        extra = f" (seabed at {seabed:.1f} m)" if np.isfinite(seabed) else ""
        raise ScenarioError(f"{src}: {table}{key} = {list(point)}: not a free point: {why}{extra}")


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
    src = s.source
    frame = LocalFrame(s.origin.lat, s.origin.lon) if s.origin else None
    b = s.bounds
    extent = (b.x[0], b.x[1], b.y[0], b.y[1]) if b.x and b.y else None
    _check_terrain_size(s, extent)
    try:
        if terrain is not None:
            pass
        elif s.terrain is not None:
            terrain = load_terrain(s.terrain, frame, base_dir=s.base_dir, extent_m=extent)
        elif s.synthetic is not None:
            terrain = _synthetic_terrain(s.synthetic, b, src)
    except DataError as exc:
        raise DataError(f"{src}: [terrain] {exc}") from exc
    if terrain is not None:
        x0, x1, y0, y1 = terrain.extent
        xr, yr = (b.x or (x0, x1)), (b.y or (y0, y1))
        zr = b.z or (float(terrain.z.min()) - 1.0, 0.0)
    else:
        if not (b.x and b.y and b.z):
            raise ScenarioError(f"{src}: [bounds] x, y and z are required when there is no terrain")
        xr, yr, zr = b.x, b.y, b.z
    bounds = Bounds(xr[0], xr[1], yr[0], yr[1], zr[0], zr[1])
    c = s.currents
    currents: CurrentField
    try:
        if c.vortices:
            v = c.vortices
            currents = LambOseenVortices(np.array([(q.x, q.y) for q in v]), np.array([q.gamma for q in v]),
                                         np.array([q.delta for q in v]))
        elif c.file is not None:
            currents = read_currents(c.file, frame, base_dir=s.base_dir, extent_m=(xr[0], xr[1], yr[0], yr[1]),  # type: ignore[arg-type]
                                     start_time=s.mission.start_time)
        elif c.tides:
            if frame is None or not s.mission.start_time:
                raise ScenarioError(f"{src}: [currents] tides = {c.tides!r} needs [origin] lat/lon and "
                                    "[mission] start_time (ISO 8601, UTC)")
            currents = load_tidal_current(c.tides, frame, parse_start_time(s.mission.start_time),
                                          base_dir=s.base_dir)
        else:
            currents = UniformCurrent(c.uniform)
    except DataError as exc:
        raise DataError(f"{src}: [currents] {exc}") from exc
    if not currents.covers(bounds.xmin, bounds.xmax, bounds.ymin, bounds.ymax):
        what = f"file {c.file.path!r}" if c.file is not None else "field"  # type: ignore[union-attr]
        raise DataError(f"{src}: [currents] the current {what} does not cover the bounds x [{bounds.xmin:.0f}, "
                        f"{bounds.xmax:.0f}] y [{bounds.ymin:.0f}, {bounds.ymax:.0f}] m")
    land = None
    if s.land is not None:
        if frame is None:
            raise ScenarioError(f"{src}: [land] needs [origin] lat/lon (the polygons are geographic)")
        try:
            land = read_land(s.land, frame, (bounds.xmin, bounds.xmax, bounds.ymin, bounds.ymax), base_dir=s.base_dir)
        except DataError as exc:
            raise DataError(f"{src}: [land] {exc}") from exc
    m = s.mission
    min_depth = m.min_depth_m if m.surface else -math.inf
    margins = Margins(m.min_altitude_m, min_depth, m.max_depth_m, m.obstacle_margin_m)
    try:
        world = World(
            bounds=bounds,
            terrain=terrain,
            currents=currents,
            obstacles=s.obstacles,
            moving=s.moving,
            margins=margins,
            origin=(s.origin.lat, s.origin.lon) if s.origin else None,
            name=s.name,
            land=land,
        )
    except DataError as exc:
        raise DataError(f"{src}: {exc}") from exc
    _check_point(world, m.start, "start", src)
    _check_point(world, m.goal, "goal", src)
    _check_sim_size(s)
    for i, wp in enumerate(m.route):
        if not world.bounds.contains(np.asarray(wp)):
            raise table_error(f"{src}: [mission]", f"route[{i}]", list(wp), "outside the bounds")
    for spec in s.formation.vehicles if s.formation is not None else ():
        if spec.start:
            _check_point(world, spec.start, f"[[vehicles]] {spec.name!r} start", src)
    mission = Mission(
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
    )
    return world, mission
