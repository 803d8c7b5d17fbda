"""``mission check`` as a job: exported mission files re-flown under their format's depth semantics against a
scenario's seabed, obstacles, surface, depth band and bounds, held to the vehicle's limits and energy, and
measured against its charted no-go zones."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from ..guidance.mission.flycheck import MissionCheck
    from ..guidance.mission.terrain_legs import FlownTrack
    from ..io.missions.readback.mission_storage import BoardStorage
    from ..io.scenario.specs import Scenario
    from ..nav import NavCheck, NavParams
    from ..path.flyable import LimitReport
    from ..world import World
    from ..world.zones import ZoneApproach

__all__ = ["FIRMWARE_NOTE", "FileCheck", "check_missions", "navigation_check", "terrain_following_check",
           "zones_measured_on"]


@dataclass(frozen=True)
class FileCheck:
    """One file's checks.

    Attributes
    ----------
    record : dict
        Its JSON record (``mission check --json``): ``ok`` is the file's verdict (every check, as the exit code),
        ``check_ok`` the seabed, obstacles, surface, depth band and bounds alone.
    check : MissionCheck
        The file re-flown under its format's depth semantics.
    vehicle : LimitReport
        The vehicle's pitch, turn and depth limits.
    energy_line : str
        The energy verdict, one line.
    deploy_line : str
        Datum, envelope, payload events and altitude legs, one line (issue 51).
    ok : bool
        Whether every check passed.
    zones : tuple of ZoneApproach
        The closest approach to each charted zone and the legs entering it (empty without zones).
    navigation : tuple of str
        ``[navigation]``: the predicted error of every leg and the verdict, one line each (issue 52).
    terrain_following : str
        A ``.plan``'s terrain-frame legs flown following the seabed: the verdict, one line (empty without).
    speed_line : str
        The legs whose speed the file does not carry, judged at the vehicle's speed, one line (empty when it
        carries every leg's; ``speed_assumed_legs`` in the record).
    """

    record: dict[str, Any]
    check: MissionCheck
    vehicle: LimitReport
    energy_line: str
    deploy_line: str
    ok: bool
    zones: tuple[ZoneApproach, ...] = ()
    navigation: tuple[str, ...] = ()
    terrain_following: str = ""
    speed_line: str = ""


def check_missions(scenario: str, files: list[str], pitch: float,
                   board: BoardStorage | None = None) -> tuple[Scenario, list[FileCheck]]:
    """Check mission files against a scenario.

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file.
    files : list of str
        Mission files (``.moos``, ``.plan``, ``.gpx``, ``.yaml``, ``.geojson``, ``.kml``, ``.csv``).
    pitch : float
        Pitch (deg) at which a depth-holding executor changes depth.
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a ``.plan`` it cannot hold fails (``deploy.mission_storage``).

    Returns
    -------
    scenario : Scenario
        The scenario.
    checks : list of FileCheck
        One per file, in order.
    """
    from ..io.missions.parsed import parse_once
    from ..io.scenario import loader as scenario_io

    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    with parse_once():  # each file's JSON parsed and its items walked once by all the readers below
        return sc, [_check_file(sc, world, mission, name, pitch, board) for name in files]


def _check_file(sc: Any, world: World, mission: Any, name: str, pitch: float,
                board: BoardStorage | None = None) -> FileCheck:
    """One file of :func:`check_missions`."""
    from ..io.missions.energy import file_energy_flight
    from ..io.missions.formats import check_mission_file, read_mission
    from ..io.missions.readback.deploy_read import file_deploy_check
    from ..io.missions.readback.dwell import read_dwells
    from ..io.scenario.defaults import energy_defaults

    points, _, fmt = read_mission(Path(name), world.origin, world.seabed if world.terrain is not None else None)
    follow, track = _terrain_frame(world, Path(name), fmt, points)
    # every leg measured as its executor flies it (a terrain-frame leg on its seabed-following track)
    check, fmt = check_mission_file(Path(name), world, pitch, follow, track)
    vlimits = _file_vehicle_limits(world, mission, points, fmt, follow, track)
    energy, energy_ok, energy_line, held_water, leg_water = file_energy_flight(world, mission, Path(name))
    # issue 51: datum, envelope, payload; the time-out judged against the energy check's duration (one figure)
    deploy, deploy_line = file_deploy_check(name, world.origin, points, fmt, check.min_altitude_m,
                                            float(energy.get("duration_s", 0.0)), board)
    # the legs flown at a speed the file does not hold (a .plan before its first DO_CHANGE_SPEED: WPNAV_SPEED)
    speed_line = energy.pop("speed_assumed_line", "")
    assumed = energy.pop("speed_assumed_legs", [])
    defaults = energy_defaults(sc)  # issue 51: a verdict resting on a default names it
    energy_line += "".join(f"; {d}" for d in defaults)
    energy["defaults"] = defaults
    rec = {"file": name, "format": fmt, **check.as_dict(), "vehicle": vlimits.as_dict(), "energy": energy,
           "deploy": deploy, "speed_assumed_legs": assumed,
           "speed_assumed_mps": mission.vehicle.speed if assumed else None}
    if sc.mission.confidence:  # issue 39: checked against the worst-case seabed at that confidence
        rec["clearance_confidence"] = sc.mission.confidence
    # charted no-go zones: the closest approach to each, and the legs that enter it (exact test), under the
    # format's depth semantics (a held depth: every leg's envelope and the executor's track, as the seabed)
    tf_ok = True
    tf_line = ""
    if follow is not None:
        rec["terrain_following"], tf_ok, tf_line = terrain_following_check(world, points, follow, track)
    # every check on every leg, a .plan's launch too (ArduSub flies from its home to the first item), each leg
    # named by the waypoint it leaves, as the seabed check names it (leg 0 leaves the first waypoint: a .plan's
    # home, its launch; docs/missions.md)
    zones = _zone_approach(world, points, check.semantics, pitch, follow, first=0, flown=track)
    if zones:
        rec["zones"] = [z.as_dict() for z in zones]
        rec["zones_measured_on"] = zones_measured_on(check.semantics, pitch, follow is not None)
    zones_ok = not any(z.entered_legs for z in zones)
    nav_ok = True
    nav_lines: list[str] = []
    if mission.navigation is not None:  # issue 52: the predicted error per leg and the clearance under it
        rec["navigation"], nav_ok, nav_lines = navigation_check(world, mission.navigation, points, Path(name),
                                                                follow, first=0, flown=track,
                                                                held_water_m=held_water, water_m=leg_water,
                                                                dwell_s=read_dwells(Path(name), len(points)))
    ok = check.ok and vlimits.ok and energy_ok and deploy["ok"] and zones_ok and nav_ok and tf_ok
    # the top-level verdict is the exit code's: every check that fails the file (the seabed's alone: check_ok)
    rec["ok"], rec["check_ok"] = bool(ok), bool(check.ok)
    return FileCheck(rec, check, vlimits, energy_line, deploy_line, ok, tuple(zones), tuple(nav_lines), tf_line,
                     speed_line)


def _file_vehicle_limits(world: World, mission: Any, points: np.ndarray, fmt: str, follow: np.ndarray | None,
                         track: FlownTrack | None) -> LimitReport:
    """A mission file judged leg by leg as a helm flies it: every leg's pitch and turns as given, no leg too short
    (issue 49); a terrain-frame leg's pitch and depth are its seabed-following track's (where the vehicle climbs
    and dives); a QGC plan starts from its home on the surface (the launch, not a leg of the mission)."""
    from ..path.legs import helm_check
    from ..sim.pipeline import vehicle_limits

    flown = (None, None) if follow is None else _flown_pitch_depth(world, points, follow, track)
    vlimits = helm_check(points[1:] if fmt == "qgc" else points, vehicle_limits(mission.vehicle),
                         pitch=flown[0], depth=flown[1])
    if fmt == "qgc":  # its legs named as the seabed check, terrain-following legs, zones and navigation do
        vlimits = _from_home(vlimits)
    return vlimits


def _from_home(report: LimitReport) -> LimitReport:
    """A ``.plan``'s helm report (judged after its launch leg) with its legs numbered from the home, leg 0 the launch,
    as every other line of the file's report numbers them."""
    from dataclasses import replace

    def shift(k: int) -> int:
        return k + 1 if k >= 0 else k

    return replace(report, max_pitch_leg=shift(report.max_pitch_leg), tightest_turn_leg=shift(report.tightest_turn_leg),
                   violations=tuple(replace(v, leg=v.leg + 1) for v in report.violations))


def _flown_pitch_depth(world: World, points: np.ndarray, follow: np.ndarray,
                       flown: FlownTrack | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A ``.plan``'s legs' steepest pitch and greatest depth as flown, after its launch leg (as the helm check)."""
    from ..guidance.mission.terrain_legs import flown_pitch_depth

    assert world.terrain is not None
    pitch, depth = (flown.pitch, flown.depth) if flown is not None else flown_pitch_depth(world.terrain, points, follow)
    return pitch[1:], depth[1:]


def _terrain_frame(world: World, path: Path, fmt: str, points: np.ndarray) -> tuple[np.ndarray | None,
                                                                                   FlownTrack | None]:
    """A ``.plan``'s legs flown at their altitude above the seabed (its terrain-frame items), and their track, made
    once for every check of the file (the seabed's, the helm's pitch and depth, the terrain-following verdict, the
    zones and the navigation); ``(None, None)`` for any other file or without one."""
    if fmt != "qgc" or world.terrain is None:
        return None, None
    from ..guidance.mission.terrain_legs import flown_track
    from ..io.missions.readback.terrain_frame import terrain_legs

    follow = terrain_legs(path)
    return (follow, flown_track(world.terrain, points, follow)) if follow.any() else (None, None)


def zones_measured_on(semantics: str, pitch: float, terrain: bool = False) -> str:
    """What a file's closest approach to the zones is measured on, in words (``zones_measured_on``).

    Parameters
    ----------
    semantics : str
        The format's depth semantics: ``"held"`` (MOOS-IvP) or ``"ramp"``.
    pitch : float
        Pitch (deg) at which a depth-holding executor changes depth.
    terrain : bool, optional
        A ``.plan`` with terrain-frame legs (flown following the seabed).

    Returns
    -------
    str
        ``"the executor's track at 15° pitch"``, ``"the straight legs"`` or ``"the straight legs and the
        seabed-following track of the terrain-frame legs"``.
    """
    if semantics == "held":
        return f"the executor's track at {pitch:g}° pitch"
    return "the straight legs and the seabed-following track of the terrain-frame legs" if terrain else \
        "the straight legs"


def _zone_approach(world: World, points: np.ndarray, semantics: str, pitch: float,
                   follow: np.ndarray | None = None, first: int = 1,
                   flown: FlownTrack | None = None) -> list[ZoneApproach]:
    """The closest approach to each charted zone and the legs entering it (exact), under the format's depth
    semantics: the straight legs (a ramp), or for a held depth (MOOS-IvP) the executor's track at ``pitch`` (deg) —
    the closest approach the least over that track, the entries each leg's envelope's and the track's (and the
    straight leg's, which its envelope holds), as :func:`~auvplan.guidance.mission.zone_legs.held_zone_entries`;
    the legs ``follow`` marks (a ``.plan``'s terrain frame) on their seabed-following track instead of the straight
    line between their items, which ArduSub does not fly.  The leg joining ``points[k]`` and ``points[k + 1]`` is
    named ``k + first``; ``flown`` is the track of ``follow``'s legs when the caller has it."""
    if not world.zones:
        return []
    from dataclasses import replace

    from ..guidance.mission.flycheck import held_track
    from ..guidance.mission.zone_legs import held_zone_entries

    exact = world.zones.exact
    if semantics != "held" and (follow is None or world.terrain is None):  # Zones.approach: legs from 1
        return [replace(z, entered_legs=tuple(k - 1 + first for k in z.entered_legs)) for z in exact.approach(points)]
    seg, si = exact.entries(np.stack([points[:-1], points[1:]], axis=1))  # the straight legs, as every format
    if semantics == "held":
        out = exact.approach(held_track(points, pitch))  # the distance the vehicle keeps, not its straight legs'
        legs, zi = held_zone_entries(exact, points, pitch)
        more = [legs[zi == j] for j in range(len(out))]
    else:
        from ..guidance.mission.terrain_legs import terrain_track

        assert world.terrain is not None and follow is not None
        track, seg_leg = (flown.track, flown.leg) if flown is not None else terrain_track(world.terrain, points, follow)
        out = exact.approach(track)  # the least over what is flown: the straight legs and the following ones
        more = [seg_leg[np.asarray(z.entered_legs, dtype=np.intp) - 1] for z in out]
        straight = ~follow[seg]  # a terrain-frame leg's straight line is not flown: its track alone enters or not
        seg, si = seg[straight], si[straight]
    for j, z in enumerate(out):
        entered = tuple(sorted({*(int(k) + first for k in seg[si == j]), *(int(k) + first for k in more[j])}))
        out[j] = replace(z, closest_m=min(z.closest_m, 0.0) if entered else z.closest_m, entered_legs=entered)
    return out


FIRMWARE_NOTE = ("needs an ArduSub that flies terrain-frame items (its Sub::start_command accepting ABOVE_TERRAIN): "
                 "one accepting only ABOVE_HOME says 'BAD NAV AltFrame' and skips each of them")
"""What the terrain-following line says of the firmware (docs/missions.md, "Terrain-frame items and the firmware")."""


def terrain_following_check(world: World, points: np.ndarray, follow: np.ndarray,
                            flown: FlownTrack | None = None) -> tuple[dict[str, Any], bool, str]:
    """A ``.plan``'s terrain-frame legs flown as ArduSub flies them: at the commanded altitude above the seabed
    between items (:func:`~auvplan.guidance.mission.terrain_legs.terrain_track`), re-flown against the seabed, the
    obstacles, the surface, the depth band and the bounds (the track's shallowest and deepest points are its
    vertices, so the waypoint tests are exact on it).

    Parameters
    ----------
    world : World
        Seabed, obstacles, margins, depth band and bounds.
    points : numpy.ndarray
        ``(N, 3)`` the plan's waypoints, home first (m).
    follow : numpy.ndarray of bool
        ``(N - 1,)`` the legs flown following the seabed.
    flown : FlownTrack, optional
        Their track (:func:`~auvplan.guidance.mission.terrain_legs.flown_track`), when the caller has it.

    Returns
    -------
    record : dict
        ``ok``, ``legs`` (the following legs; leg k joins items k and k + 1, as the zones' legs), ``min_altitude_m``,
        ``shallowest_m``, ``deepest_m``, ``above_surface_legs``, ``outside_depth_band_legs``,
        ``outside_bounds_legs``, ``obstacle_hits``, ``vertices``.
    ok : bool
        Whether the track keeps every limit.
    line : str
        The verdict, one line.
    """
    from dataclasses import replace

    from ..guidance.mission.flycheck import fly_check
    from ..guidance.mission.terrain_legs import followed_altitude, terrain_track

    assert world.terrain is not None
    track, seg_leg = (flown.track, flown.leg) if flown is not None else terrain_track(world.terrain, points, follow)
    c = fly_check(world, track, "ramp", launch=True)
    # a following leg's altitude is the one it holds (exact), not its chords' (a centimetre under it over a crest)
    seg_alt = np.where(follow[seg_leg], followed_altitude(world.terrain, points, follow)[seg_leg], c.leg_altitude_m)
    c = replace(c, leg_altitude_m=seg_alt, min_altitude_m=float(seg_alt.min()),
                min_altitude_leg=int(np.argmin(seg_alt)))
    return _terrain_report(c, track, seg_leg, follow)


def _terrain_report(c: MissionCheck, track: np.ndarray, seg_leg: np.ndarray,
                    follow: np.ndarray) -> tuple[dict[str, Any], bool, str]:
    """:func:`terrain_following_check`'s record, verdict and line of the check ``c`` of the flown ``track``."""
    lim = c.limits
    assert lim is not None

    def legs_of(vertices: tuple[int, ...]) -> list[int]:  # the legs of the track's vertices
        return sorted({int(seg_leg[v - 1]) for v in vertices if v > 0})

    legs = [int(k) for k in np.flatnonzero(follow)]
    bad = {"above_surface_legs": legs_of(lim.above_surface), "outside_depth_band_legs": legs_of(lim.outside_depth_band),
           "outside_bounds_legs": legs_of(lim.outside_bounds)}
    rec: dict[str, Any] = {"ok": bool(c.ok), "legs": legs,
           "min_altitude_m": c.min_altitude_m, "required_altitude_m": c.required_altitude_m,
           "shallowest_m": float(-track[1:, 2].max()), "deepest_m": float(-track[1:, 2].min()),
           **bad, "obstacle_hits": c.obstacle_hits, "vertices": int(track.shape[0])}
    broken = [f"{what} on leg{'s' if len(v) > 1 else ''} {', '.join(map(str, v))}" for what, v in (
        ("above the sea surface", bad["above_surface_legs"]),
        (f"outside the depth band ({lim.min_depth_m:g}-{lim.max_depth_m:g} m)", bad["outside_depth_band_legs"]),
        ("outside the bounds", bad["outside_bounds_legs"])) if v]
    if c.obstacle_hits:
        broken.append(f"{c.obstacle_hits} segments meet an obstacle")
    named = ", ".join(map(str, legs)) if len(legs) <= 5 else f"{len(legs)} legs of {len(follow)}"
    line = (f"terrain-following legs (MAV_FRAME 10: {named}): {'OK' if c.ok else 'FAIL'} — "
            + "".join(f"{b}; " for b in broken)
            + f"flown at the commanded altitude above the seabed: least altitude {c.min_altitude_m:.2f} m (required "
              f"{c.required_altitude_m:g} m), shallowest {rec['shallowest_m']:.2f} m, deepest {rec['deepest_m']:.2f} m"
            + f"; {FIRMWARE_NOTE}")
    return rec, bool(c.ok), line


def navigation_check(world: World, nav: NavParams, points: np.ndarray, mission_file: Path | None = None,
                     follow: np.ndarray | None = None, first: int = 1, flown: FlownTrack | None = None,
                     held_water_m: np.ndarray | None = None,
                     water_m: np.ndarray | None = None,
                     dwell_s: np.ndarray | None = None) -> tuple[dict[str, Any], bool, list[str]]:
    """``mission check`` under ``[navigation]``: the file's surface waypoints are its GPS fixes, and the
    ``fixes.csv`` beside it, when there is one, adds its USBL fixes
    (:func:`auvplan.io.missions.readback.fixes.fix_kinds`).

    Parameters
    ----------
    world : World
        Seabed, obstacles, margins.
    nav : NavParams
        The error model and the budget.
    points : numpy.ndarray
        ``(N, 3)`` the mission's waypoints (m).
    mission_file : pathlib.Path, optional
        The mission file (its folder's ``fixes.csv``).
    follow : numpy.ndarray of bool, optional
        ``(N - 1,)`` the legs flown following the seabed (a ``.plan``'s terrain frame): predicted and tested on
        that track (:func:`~auvplan.guidance.mission.terrain_legs.terrain_track`), not on the straight line between
        their items, which ArduSub does not fly.
    first : int, optional
        The number of the first leg (``mission check``: 0, each leg named by the waypoint it leaves).
    flown : FlownTrack, optional
        The track of ``follow``'s legs, when the caller has it.
    held_water_m : numpy.ndarray, optional
        ``(N,)`` the distance moved through the water holding each waypoint (a ``.plan``'s holds,
        :func:`~auvplan.io.missions.energy.file_energy_flight`): its drift without bottom lock.
    water_m : numpy.ndarray, optional
        ``(N - 1,)`` each leg's horizontal distance through the water as the energy check flew it
        (:func:`~auvplan.io.missions.energy.file_energy_flight`): the drift without bottom lock; default: still water.
    dwell_s : numpy.ndarray, optional
        ``(N,)`` the file's wait at each waypoint (:func:`~auvplan.io.missions.readback.dwell.read_dwells`; None: the
        format carries none): a surface fix that waits less than ``surface_s`` fails (no time for its GPS fix); the
        last waypoint's fix serves no leg and needs no wait.

    Returns
    -------
    record : dict
        ``ok``, ``message``, ``fixes``, ``nav_error_max_m``, ``max_error_m`` and per leg ``nav_error_m``,
        ``lock``, ``uncertain_altitude_m``, ``clear``.
    ok : bool
        Error within the budget and every leg clear under it.
    lines : list of str
        One line per leg and the verdict.
    """
    from ..io.missions.readback.fixes import fix_kinds
    from ..nav import check_navigation, surface_kinds

    kinds, source = (surface_kinds(points), "the surface waypoints") if mission_file is None else \
        fix_kinds(points, mission_file, world.origin)
    c = check_navigation(world, points, kinds, nav, nav.usbl_xy, first_leg=first, held_water_m=held_water_m,
                         water_m=water_m) \
        if follow is None or world.terrain is None else _navigation_as_flown(world, nav, points, kinds, follow, first,
                                                                              flown, held_water_m, water_m)
    return _nav_report(c, kinds, source, points, nav, first, dwell_s)


def _nav_report(c: NavCheck, kinds: tuple[str, ...], source: str, points: np.ndarray, nav: NavParams, first: int,
                dwell_s: np.ndarray | None) -> tuple[dict[str, Any], bool, list[str]]:
    """:func:`navigation_check`'s record, verdict and lines of the check ``c`` of the fixes ``kinds``."""
    usbl = sum(1 for k in kinds if k == "usbl")
    message, ok = _short_waits(kinds, points, dwell_s, nav, c.message, c.ok)
    legs, lines = _nav_legs(c, first)
    b = c.budget
    lines.append(f"navigation: {'OK' if ok else 'FAIL'} — {sum(1 for k in kinds if k) - usbl} surface fixes"
                 f"{f' and {usbl} USBL fixes' if usbl else ''} (from {source}), predicted "
                 f"error at most {b.max_error_m:.1f} m (max_error_m {nav.max_error_m:g} m at {nav.confidence:g} σ)"
                 + (f"; {message}" if message else ""))
    rec = {"ok": ok, "message": message, "fixes": sum(1 for k in kinds if k), "usbl_fixes": usbl,
           "fixes_from": source,
           "nav_error_max_m": round(b.max_error_m, 3), "max_error_m": nav.max_error_m, "legs": legs}
    return rec, ok, lines

def _short_waits(kinds: tuple[str, ...], points: np.ndarray, dwell_s: np.ndarray | None, nav: NavParams,
                 message: str, ok: bool) -> tuple[str, bool]:
    """The check's message and verdict, failed when the file surfaces for a GPS fix but waits there less than
    ``surface_s`` (the last waypoint's fix is no leg's: the mission is over, its wait written by no export)."""
    short = [] if dwell_s is None else [i for i, k in enumerate(kinds[:-1])
                                        if k == "gps" and -points[i, 2] <= 0.5 and dwell_s[i] < nav.surface_s - 0.5]
    if short and dwell_s is not None:  # the file surfaces but does not wait there for its fix
        i = short[0]
        message, ok = (f"waypoint {i}: waits {dwell_s[i]:g} s at the surface, less than surface_s {nav.surface_s:g} s "
                       f"for its GPS fix ({len(short)} surface fix{'es' if len(short) > 1 else ''} so)"
                       + (f"; {message}" if message else "")), False
    return message, ok


def _nav_legs(c: NavCheck, first: int) -> tuple[list[dict[str, Any]], list[str]]:
    """Each leg's predicted error, bottom lock, least altitude within the error and clearance: records and lines."""
    b = c.budget
    legs = [{"leg": k + first, "nav_error_m": round(float(b.leg_error_m[k]), 2), "lock": round(float(b.leg_lock[k]), 3),
             "uncertain_altitude_m": round(float(c.leg_uncertain_altitude_m[k]), 2), "clear": bool(c.leg_clear[k])}
            for k in range(len(b.leg_error_m))]
    lines = [f"leg {r['leg']}: predicted error {r['nav_error_m']:.1f} m, bottom lock {100 * r['lock']:.0f} %, least "
             f"altitude within it {r['uncertain_altitude_m']:.1f} m{'' if r['clear'] else ' — TOUCHES'}" for r in legs]
    return legs, lines


def _navigation_as_flown(world: World, nav: NavParams, points: np.ndarray, kinds: tuple[str, ...],
                         follow: np.ndarray, first: int = 1, flown: FlownTrack | None = None,
                         held_water_m: np.ndarray | None = None, water_m: np.ndarray | None = None) -> Any:
    """:func:`auvplan.nav.check_navigation` on the seabed-following track of the legs ``follow`` marks, its figures
    gathered back per leg: the largest error, the bottom lock over the leg's length, the least clearance."""
    from ..guidance.mission.terrain_legs import terrain_track
    from ..nav import check_navigation
    from ..nav.budget import NavBudget, water_lengths
    from ..nav.mission import NavCheck, clearance_failure

    assert world.terrain is not None
    track, seg = (flown.track, flown.leg) if flown is not None else terrain_track(world.terrain, points, follow)
    ends = np.r_[0, np.flatnonzero(np.r_[seg[1:] != seg[:-1], True]) + 1]  # each waypoint's vertex on the track
    on_track = [""] * len(track)
    for j, kind in zip(ends, kinds, strict=True):
        on_track[j] = kind
    held = None
    if held_water_m is not None:  # each waypoint's hold at its vertex of the track
        held = np.zeros(len(track))
        held[ends] = held_water_m
    # each file leg's water distance shared over its track's segments by their horizontal length
    seg_water = water_lengths(np.hypot(*np.diff(track[:, :2], axis=0).T), seg, water_m)
    c = check_navigation(world, track, tuple(on_track), nav, nav.usbl_xy, held_water_m=held, water_m=seg_water)
    n = len(points) - 1
    err, alt = np.full(n, -np.inf), np.full(n, np.inf)
    np.maximum.at(err, seg, c.budget.leg_error_m)
    np.minimum.at(alt, seg, c.leg_uncertain_altitude_m)
    clear = np.ones(n, dtype=bool)
    np.logical_and.at(clear, seg, c.leg_clear)
    length = np.hypot(*np.diff(track[:, :2], axis=0).T) + 1e-300  # a vertical leg: its one segment's lock
    lock = np.bincount(seg, c.budget.leg_lock * length, n) / np.bincount(seg, length, n)
    msg = ""
    if (over := np.flatnonzero(err > nav.max_error_m * (1.0 + 1e-9))).size:
        msg = f"leg {over[0] + first}: predicted error {err[over[0]]:.1f} m exceeds max_error_m {nav.max_error_m:g} m"
    elif not clear.all():
        k = int(np.flatnonzero(~clear)[0])
        on = np.flatnonzero(seg == k)  # the leg's pieces of the track
        msg = clearance_failure(k + first, float(err[k]), float(alt[k]), world, np.stack([track[on], track[on + 1]], 1))
    elif c.budget.error_m[-1] > nav.max_error_m * (1.0 + 1e-9):  # grown in the last waypoint's hold
        msg = (f"waypoint {n}: predicted error {c.budget.error_m[-1]:.1f} m at the end of its hold exceeds "
               f"max_error_m {nav.max_error_m:g} m")
    budget = NavBudget(c.budget.error_m[ends], err, lock, kinds, c.budget.max_error_m)
    return NavCheck(budget, alt, clear, not msg, msg)
