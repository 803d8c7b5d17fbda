"""The scenario's tables as frozen dataclasses (``[origin]``, ``[bounds]``, ``[mission]``, ...) and the
parsed :class:`Scenario` they make up; :mod:`auvplan.io.scenario` reads a TOML file into them and
:mod:`auvplan.io.scenario.build` turns a Scenario into a World and a Mission."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ...endurance.params import EnduranceParams
from ...guidance.avoidance.params import AvoidanceParams
from ...guidance.following.hybrid import HybridParams
from ...guidance.following.los import LosParams
from ...guidance.formation.keeping import Formation, FormationParams
from ...nav.params import NavParams
from ...planners.core.base import PlannerSpec
from ...sim import SimParams
from ...survey.spec import SurveySpec
from ...vehicles import VehicleParams
from ...world import MovingObstacle
from ..data.bathymetry import TerrainSpec
from ..data.ocean.currents import CurrentsFileSpec, parse_time
from ..data.ocean.tides import BUILTIN_TIDES
from ..data.vector.coast import LandSpec
from ..data.vector.zones import ZoneSpec
from ..files.limits import Limits
from .inputs.geoinput import GeoInput
from .inputs.members import MemberSpec

__all__ = [
    "Scenario",
    "OriginSpec",
    "BoundsSpec",
    "SyntheticTerrainSpec",
    "CurrentsSpec",
    "MAX_VORTICES",
    "VortexSpec",
    "MissionSpec",
    "GuidanceSpec",
    "SECTIONS",
    "named_files",
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
    uncertainty_m : float
        One-sigma vertical uncertainty of the whole seabed (m), used with ``[mission] confidence``.
    """

    kind: str = "flat"
    depth: float = 100.0
    cell_m: float = 0.0
    slope: tuple[float, float] = (0.0, 0.0)
    hills: tuple[tuple[float, float, float, float], ...] = ()
    ridge_x: float = 0.0
    ridge_width: float = 10.0
    height: float = 0.0
    uncertainty_m: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in ("flat", "plane", "hills", "ridge"):
            raise ValueError(f"kind = {self.kind!r}: choose flat, plane, hills or ridge")
        if self.depth <= 0:
            raise ValueError(f"depth = {self.depth}: must be positive")
        if self.cell_m < 0 or self.ridge_width <= 0:
            raise ValueError("cell_m must be >= 0 and ridge_width > 0")
        if self.uncertainty_m < 0:
            raise ValueError(f"uncertainty_m = {self.uncertainty_m}: must be >= 0")


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


MAX_VORTICES = 100
"""Most ``[currents] vortices`` (hostile round 22: 100 000 of them validated in 5 s, then ``plan`` ran for hours —
every current sample sums them all)."""


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
    members : tuple of MemberSpec
        A forecast ensemble (issue 39, :mod:`auvplan.io.scenario.inputs.members`): plans are scored in
        every member; the nominal field is the one above, or the first member when none is given.
    beyond : str
        What a mission lasting longer than the current file's time span does (issue 51,
        :mod:`auvplan.io.scenario.inputs.currentspan`): ``"refuse"`` (exit 2, the default), ``"hold"`` (the last
        field held) or ``"zero"`` (no current after the file).
    """

    uniform: tuple[float, float, float] = (0.0, 0.0, 0.0)
    vortices: tuple[VortexSpec, ...] = ()
    file: str | CurrentsFileSpec | None = None
    tides: str = ""
    members: tuple[MemberSpec, ...] = ()
    beyond: str = "refuse"

    def __post_init__(self) -> None:
        if self.beyond not in ("refuse", "hold", "zero"):
            raise ValueError(f"beyond = {self.beyond!r}: choose 'refuse', 'hold' or 'zero'")
        if isinstance(self.file, str):  # file = "x.nc" is short for file = { path = "x.nc" }
            object.__setattr__(self, "file", CurrentsFileSpec(path=self.file))
        kinds = int(any(self.uniform)) + int(bool(self.vortices)) + int(self.file is not None) + int(bool(self.tides))
        if len(self.vortices) > MAX_VORTICES:  # each is summed at every point asked: 10⁵ planned for hours
            raise ValueError(f"vortices: {len(self.vortices):,} vortices, over the {MAX_VORTICES} a scenario may hold "
                             "(each is summed at every point the planners and the flight ask for the current: 1 000 "
                             "took 45 s to plan a 5-iteration swarm, 100 000 hours); give a richer field as a current "
                             "file")
        if kinds > 1:
            raise ValueError("give only one of 'uniform', 'vortices', 'file' and 'tides'")
        named = [m.name for m in self.members if m.name]
        if len(set(named)) < len(named):  # two members of one name: bench --members picked the first alone
            twice = next(n for n in named if named.count(n) > 1)
            raise ValueError(f"members: two members are named {twice!r}; each needs its own name")


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
    follow_altitude_m : float
        Terrain following: fly the route or plan at this altitude above the seabed (m, at least
        ``min_altitude_m``), climbs started early enough for ``[vehicle] max_pitch_deg``; 0: off.
    confidence : float
        Plan and check against the worst-case seabed at this confidence, in (0.5, 1) (issue 39: the
        ``[terrain]`` uncertainty raised by Φ⁻¹(confidence) σ); 0: the nominal seabed.
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
    follow_altitude_m: float = 0.0
    confidence: float = 0.0

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
        if self.confidence and not 0.5 < self.confidence < 1.0:
            raise ValueError(f"confidence = {self.confidence}: must lie in (0.5, 1) (or 0: the nominal seabed)")
        if self.follow_altitude_m and not self.follow_altitude_m >= self.min_altitude_m:
            raise ValueError(f"follow_altitude_m = {self.follow_altitude_m}: must be 0 (off) or at least "
                             f"min_altitude_m = {self.min_altitude_m:g}")


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
    sim : SimParams
        Closed-loop settings.
    raw : dict
        The parsed TOML document.
    limits : Limits
        Resource budget.
    land : LandSpec or None
        Coastline source.
    formation : Formation or None
        Several vehicles in formation (``[formation]`` and ``[[vehicles]]``).
    geo : GeoInput or None
        What its geographic positions left for the build (:mod:`auvplan.io.scenario.inputs.geoinput`).
    endurance : EnduranceParams
        Recovery point, rally points and the speed choice of the energy budget (``[endurance]``).
    survey : SurveySpec or None
        A coverage survey of an area (``[survey]``).
    zones : tuple of ZoneSpec
        Charted no-go zones (``[[zones]]``, :mod:`auvplan.io.data.vector.zones`).
    navigation : NavParams or None
        The navigation error budget and its fixes (``[navigation]``, issue 52).
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
    sim: SimParams
    raw: dict[str, Any] = field(repr=False, default_factory=dict)
    limits: Limits = field(default_factory=Limits)
    land: LandSpec | None = None
    formation: Formation | None = None
    geo: GeoInput | None = None
    endurance: EnduranceParams = field(default_factory=EnduranceParams)
    survey: SurveySpec | None = None
    zones: tuple[ZoneSpec, ...] = ()
    navigation: NavParams | None = None


SECTIONS: dict[str, type] = {
    "origin": OriginSpec, "bounds": BoundsSpec, "terrain": TerrainSpec, "currents": CurrentsSpec,
    "mission": MissionSpec, "vehicle": VehicleParams, "planner": PlannerSpec, "guidance": GuidanceSpec,
    "avoidance": AvoidanceParams, "sim": SimParams, "limits": Limits, "land": LandSpec,
    "formation": FormationParams, "endurance": EnduranceParams,
    "survey": SurveySpec, "navigation": NavParams,
}
"""The tables that map onto one dataclass each (the loader and :mod:`auvplan.io.scenario.schema` share it)."""


def named_files(sc: Scenario) -> list[tuple[str, str]]:
    """Every data file a scenario names, as ``(key, name as written)`` — what ``serve`` confines to its
    folders and what a departure sweep's checkpoints are keyed on.

    Parameters
    ----------
    sc : Scenario
        The scenario.

    Returns
    -------
    list of (str, str)
        ``[terrain] file``, ``[currents] file``, a tide station file, each member's file, ``[land] file``,
        each ``[[zones]] file``, ``[survey] file`` and ``centerline_file``, in that order.
    """
    def name(f: str | CurrentsFileSpec) -> str:
        return f if isinstance(f, str) else f.path

    out: list[tuple[str, str]] = []
    if sc.terrain is not None and sc.terrain.file:
        out.append(("[terrain] file", sc.terrain.file))
    c = sc.currents
    if c.file is not None:
        out.append(("[currents] file", name(c.file)))
    if c.tides and c.tides not in BUILTIN_TIDES:
        out.append(("[currents] tides", c.tides))
    out += [(f"[currents] members[{i}] file", name(m.file)) for i, m in enumerate(c.members) if m.file is not None]
    if sc.land is not None and sc.land.file:
        out.append(("[land] file", sc.land.file))
    out += [(f"[[zones]] #{i + 1} file", z.file) for i, z in enumerate(sc.zones) if z.file]
    if sc.survey is not None:
        out += [(f"[survey] {key}", f) for key, f in (("file", sc.survey.file),
                                                       ("centerline_file", sc.survey.centerline_file)) if f]
    return out
