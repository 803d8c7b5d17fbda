"""A survey as a mission: the lines in flying order, the turns between them, the depth held within the
pitch limit, the exact seabed and obstacle test of every line and turn, and the transits from the launch
point to the first line and from the last line home by the global planner.

Route vertices are labelled: ``k >= 0`` on line ``k`` (flying order), ``TURN`` on a turn, ``TRANSIT`` on a
transit.  A survey may start and end at the same launch/recovery point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from .._types import Status
from ..guidance.mission.legs import merge_short_legs
from ..nav import NavParams
from ..path.legs import shortest_leg
from ..planners.core.base import PlanResult, Progress
from ..runtime.parallel import Runner
from ..sim import Mission, planned_route
from ..sim.pipeline import vehicle_limits
from ..world import World
from .held import held_safe
from .joins import join_bridges, join_transit, turn_between
from .lines.envelope import lower_envelope
from .lines.frame import Frame
from .lines.placement import LineParams, SurveyLines, place_lines
from .lines.swath import Seabed, Sensor
from .ties import crab_margin, tie_lines
from .zones import clip_to_zones

__all__ = ["SurveyParams", "SurveyPlan", "plan_survey", "survey_route", "choose_heading", "nav_spacing", "TURN",
           "TRANSIT", "DEFAULT_TURN_RADIUS_M"]

TURN = -1
TRANSIT = -2
DEFAULT_TURN_RADIUS_M = 10.0
"""Turn radius when ``[vehicle]`` gives none: the REMUS-100-class steady turn at full rudder (~10 m)."""


@dataclass(frozen=True)
class SurveyParams:
    """A survey: the area, the sensor, how the lines are placed, and how the vehicle turns.

    Attributes
    ----------
    area : shapely.Polygon
        The area to cover in the local frame (m).
    sensor : Sensor
        Swath sensor and mounting.
    lines : LineParams
        Overlap bounds, station spacing, bend and pitch limits.
    heading_deg : float or None
        Compass heading of the lines (deg); None chooses the shortest survey (:func:`choose_heading`).
    turn_radius_m : float
        Least turn radius of the vehicle (m).
    run_in_m : float
        Straight run beyond the area at both ends of every line (m), so the vehicle is on the line when
        it enters the area.
    frame : Frame or None
        A corridor's frame along its centre line (:class:`~auvplan.survey.lines.frame.CurveFrame`); None: straight
        lines along ``heading_deg``.
    tie_lines : int
        Tie (cross) lines flown across the main lines after them.
    hold_overlap : bool
        Place the lines with the overlap margin the crab angle in the current takes away
        (:func:`~auvplan.survey.ties.crab_margin`), so the flown overlap keeps ``overlap_min``.
    """

    area: shapely.Polygon
    sensor: Sensor
    lines: LineParams = LineParams()
    heading_deg: float | None = None
    turn_radius_m: float = DEFAULT_TURN_RADIUS_M
    run_in_m: float = 60.0
    frame: Frame | None = None
    tie_lines: int = 0
    hold_overlap: bool = True

    def __post_init__(self) -> None:
        if not self.turn_radius_m > 0:
            raise ValueError(f"turn_radius_m = {self.turn_radius_m}: must be positive")
        if self.run_in_m < 0:
            raise ValueError(f"run_in_m = {self.run_in_m}: must be >= 0")
        if not (self.area.is_valid and self.area.area > 0):
            raise ValueError("the survey area must be a valid polygon with a positive area")


@dataclass(frozen=True)
class SurveyPlan:
    """The planned survey mission.

    Attributes
    ----------
    status : Status
        ``EXACT`` when every line, turn and transit is clear; else why not (``message``).
    message : str
        What failed, naming the line or turn.
    lines : SurveyLines
        The placed lines.
    route : numpy.ndarray
        ``(N, 3)`` the whole mission (m): transit, lines and turns, transit home.
    labels : numpy.ndarray
        ``(N,)`` line number (flying order) of each route vertex, or ``TURN`` / ``TRANSIT``.
    turn_words : tuple of str
        The Dubins word of each turn (CCC words are omega turns).
    transits : tuple of PlanResult
        The global plans of the transits out and home (absent when the launch is on the first line).
    min_turn_radius_m : float
        The tightest turn radius of the survey part of the route (m).
    max_pitch_deg : float
        The steepest climb or dive of the survey part (deg).
    overlap_margin : float
        The margin added to the least overlap where the lines were placed (fraction).
    """

    status: Status
    message: str
    lines: SurveyLines
    route: NDArray[np.float64]
    labels: NDArray[np.int64]
    turn_words: tuple[str, ...]
    transits: tuple[PlanResult, ...]
    min_turn_radius_m: float
    max_pitch_deg: float
    overlap_margin: float = 0.0

    def tie_waypoints(self) -> list[NDArray[np.float64]]:
        """The waypoints of every tie line in flying order (labels after the main lines').

        Returns
        -------
        list of numpy.ndarray
            ``(M, 3)`` waypoints of each tie line (m).
        """
        n = len(self.lines.lines)
        ties = np.unique(self.labels[self.labels >= n])
        return [self.route[self.labels == k] for k in ties]

    def line_waypoints(self) -> list[NDArray[np.float64]]:
        """The waypoints of every line in flying order.

        Returns
        -------
        list of numpy.ndarray
            ``(M, 3)`` waypoints of each line, run-ins included (m).
        """
        return [self.route[self.labels == k] for k in range(len(self.lines.lines))]

    @property
    def survey_length_m(self) -> float:
        """Length of the lines and turns (m), transits excluded."""
        keep = self.labels != TRANSIT
        p = self.route[keep]
        return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) if p.shape[0] > 1 else 0.0

    @property
    def length_m(self) -> float:
        """Length of the whole mission (m)."""
        return float(np.linalg.norm(np.diff(self.route, axis=0), axis=1).sum())


def choose_heading(seabed: Seabed, params: SurveyParams, candidates: int = 12) -> float:
    """The line heading of the shortest survey among evenly spread headings and the isobaths'.

    Every candidate is planned at a coarse station spacing; the length counts the lines (their own length: a line
    bends with the seabed), run-ins and turns, a turn as the U-turn ``π R + D - 2 R`` to the next line ``D`` away
    (``π R`` when closer; as ``π R`` alone it left out the way across, and a 1.6 km x 12 m strip was flown across in
    8 lines, 2.6 km, not along it in one, 1.7 km).

    Parameters
    ----------
    seabed : callable
        ``zb(x, y)`` (m).
    params : SurveyParams
        The survey.
    candidates : int
        Headings tried, evenly spread over 180°, besides the isobaths' at the area's centre.

    Returns
    -------
    float
        Compass heading (rad).
    """
    area = params.area
    c = area.centroid
    h = 0.1 * math.sqrt(area.area)
    gx = float(seabed(np.array([c.x + h]), np.array([c.y]))[0] - seabed(np.array([c.x - h]), np.array([c.y]))[0])
    gy = float(seabed(np.array([c.x]), np.array([c.y + h]))[0] - seabed(np.array([c.x]), np.array([c.y - h]))[0])
    heads = [math.pi * i / candidates for i in range(candidates)]
    if math.hypot(gx, gy) > 0:
        heads.append(math.atan2(-gy, gx) % math.pi)  # compass heading of the isobaths (normal to the gradient)
    coarse = replace(params.lines, station_m=max(params.lines.station_m, math.sqrt(area.area) / 20.0))
    best, best_len = heads[0], math.inf
    for hd in heads:
        lines = place_lines(seabed, area, params.sensor, hd, coarse)
        way = [lines.waypoints(k)[:, :2] for k in range(len(lines.lines))]  # a line's own length: it bends
        total = sum(float(np.hypot(*np.diff(w, axis=0).T).sum()) + 2 * params.run_in_m for w in way)
        ends = [w[-1 if k % 2 == 0 else 0] for k, w in enumerate(way)]  # where each line ends (alternating)
        gaps = [math.dist(a, b) for a, b in zip(ends[:-1], ends[1:], strict=True)]  # each turn's way across, D
        total += sum(math.pi * params.turn_radius_m + max(d - 2.0 * params.turn_radius_m, 0.0) for d in gaps)
        if lines.complete and total < best_len:
            best, best_len = hd, total
    return best


def _line_points(lines: SurveyLines, k: int, forward: bool, run_in: float) -> NDArray[np.float64]:
    """Waypoints of line ``k`` in flying direction, extended by the run-in at both ends."""
    p = lines.waypoints(k)
    if not forward:
        p = p[::-1]
    if run_in > 0 and p.shape[0] >= 2:
        t0 = p[1, :2] - p[0, :2]
        t1 = p[-1, :2] - p[-2, :2]
        a = np.r_[p[0, :2] - run_in * t0 / np.linalg.norm(t0), p[0, 2]]
        b = np.r_[p[-1, :2] + run_in * t1 / np.linalg.norm(t1), p[-1, 2]]
        p = np.vstack([a, p, b])
    return p


def survey_route(world: World, lines: SurveyLines, params: SurveyParams,
                 min_depth: float) -> tuple[NDArray[np.float64], NDArray[np.int64], tuple[str, ...]]:
    """Lines (alternating directions) and turns as one route, with its depth held within the pitch limit.

    Parameters
    ----------
    world : World
        The seabed.
    lines : SurveyLines
        The placed lines.
    params : SurveyParams
        Turn radius, run-in, sensor (its mounting) and pitch limit.
    min_depth : float
        Shallowest depth allowed (m).

    Returns
    -------
    tuple
        ``(N, 3)`` route (m), ``(N,)`` labels, the turns' Dubins words.
    """
    parts, labels, words = [], [], []
    prev: NDArray[np.float64] | None = None
    for k in range(len(lines.lines)):
        pts = _line_points(lines, k, k % 2 == 0, params.run_in_m)
        if prev is not None:
            turn, word = turn_between(prev, pts, params.turn_radius_m)
            parts.append(turn)
            labels.append(np.full(turn.shape[0], TURN))
            words.append(word)
        parts.append(pts)
        labels.append(np.full(pts.shape[0], k))
        prev = pts
    n = len(lines.lines)
    for j, pts in enumerate(tie_lines(lines, params.tie_lines, params.run_in_m,
                                      from_end=n % 2 == 1, step=params.lines.station_m)):
        assert prev is not None
        turn, word = turn_between(prev, pts, params.turn_radius_m)
        parts += [turn, pts]
        labels += [np.full(turn.shape[0], TURN), np.full(pts.shape[0], n + j)]
        words.append(word)
        prev = pts
    route = np.vstack(parts)
    lab = np.concatenate(labels).astype(np.int64)
    if params.sensor.mounting == "auv" and world.terrain is not None:
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(route[:, :2], axis=0).T))])
        target = world.seabed(route[:, 0], route[:, 1]) + params.sensor.altitude_m
        route[:, 2] = np.minimum(lower_envelope(arc, target, math.tan(math.radians(params.lines.pitch_max_deg))),
                                 -min_depth)
    return route, lab, tuple(words)


def _turn_radius(route: NDArray[np.float64]) -> float:
    """Least radius of the circles through consecutive route vertices (m)."""
    a, b, c = route[:-2, :2], route[1:-1, :2], route[2:, :2]
    ab, bc, ca = (np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1), np.linalg.norm(a - c, axis=1))
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(cross > 1e-9 * ab * bc, ab * bc * ca / (2.0 * cross), np.inf)
    return float(r.min()) if r.size else math.inf


def _check(world: World, route: NDArray[np.float64], labels: NDArray[np.int64]) -> str:
    """'' when every segment passes the exact seabed and obstacle test; else which line or turn fails."""
    seg = np.stack([route[:-1], route[1:]], axis=1)
    ok = world.segments_free(seg, moving=False)
    if ok.all():
        return ""
    i = int(np.flatnonzero(~ok)[0])
    what = f"line {labels[i]}" if labels[i] >= 0 else ("a turn" if labels[i] == TURN else "a transit")
    return (f"{int((~ok).sum())} segments fail the seabed/obstacle test; the first on {what} at "
            f"({seg[i, 0, 0]:.0f}, {seg[i, 0, 1]:.0f}, {seg[i, 0, 2]:.0f}): {world.explain(seg[i, 0])}")


@dataclass(frozen=True, eq=False)
class _Transit:
    """What both transits share: the world, the mission, the seed (and the progress, in this process)."""

    world: World
    mission: Mission
    seed: int
    progress: Progress | None


def _transit(shared: _Transit, leg: tuple[Any, Any, str]) -> tuple[PlanResult, NDArray[np.float64] | None]:
    """One transit (out or home) as a task of :meth:`auvplan.runtime.parallel.Runner.map`."""
    a, b, _ = leg
    m = replace(shared.mission, start=(float(a[0]), float(a[1]), float(a[2])),
                goal=(float(b[0]), float(b[1]), float(b[2])), route=())
    planned, path = planned_route(shared.world, m, shared.seed, shared.progress)
    assert planned is not None
    return planned, path


def nav_spacing(nav: NavParams | None, params: SurveyParams) -> tuple[float, float]:
    """``LineParams``' relative navigation error (issue 52): an AUV-mounted sensor dead-reckons, at the drift
    rate of its lock state on the lines (bottom lock when the sensor's altitude is within the DVL's range);
    a surface mounting has GPS (no relative drift).

    Parameters
    ----------
    nav : NavParams or None
        ``[navigation]``.
    params : SurveyParams
        The survey: sensor, run-ins and turn radius.

    Returns
    -------
    tuple of float
        ``nav_rel_per_m`` (confidence × rate; 0: none) and ``nav_turn_m`` (run-ins and the longest turn: 2πR).
    """
    if nav is None or params.sensor.mounting != "auv":
        return 0.0, 0.0
    rate = nav.rate(params.sensor.altitude_m <= nav.dvl_range_m)
    return nav.confidence * rate, 2.0 * params.run_in_m + 2.0 * math.pi * params.turn_radius_m


FLIGHT_SLACK = 1.25
"""The flight's span, over which the crab angle's current is read: its straight length (out, the lines, home) at the
vehicle's speed through the water, times this (transits round the seabed, a head current)."""


MAX_SPAN_H = 24.0 * 60
"""Longest span the crab angle's current is read over (60 days, read hourly; a vehicle creeping along its lines
would be read for years)."""


def _lines_for_flight(world: World, mission: Mission, params: SurveyParams, seabed: Seabed, heading: float
                      ) -> tuple[float, LineParams, SurveyLines, NDArray[np.float64], NDArray[np.int64], Any]:
    """The lines and their route, placed with the crab angle's overlap margin of the current over the whole flight.

    The margin reads the current every hour from the start; the flight's length is known once the lines are placed,
    so a time-varying current is read over 12 h first, then (lines placed again) over the flight's estimated span
    (:data:`FLIGHT_SLACK`) until the span read covers it (strait-corridor flies 12.5 h: a current after 12 h was
    never read).  Returns the margin, the line parameters, the lines, the route, its labels and its words.
    """
    surface_z = -max(world.margins.min_depth, 0.0)
    rel, turn = nav_spacing(mission.navigation, params)  # issue 52: adjacent lines' relative error
    speed, hours = mission.vehicle.speed, 12.0
    for _ in range(4):
        auv = params.sensor.mounting == "auv"  # the current where the sensor flies: at its altitude, or the surface
        margin = crab_margin(world.currents, params.area, surface_z, speed, params.frame, heading,
                             0.5 * (1.0 - params.lines.overlap_min), hours, seabed if auv else None,
                             params.sensor.altitude_m) if params.hold_overlap else 0.0
        line_params = replace(params.lines, surface_z=surface_z, overlap_margin=margin, nav_rel_per_m=rel,
                              nav_turn_m=turn)
        lines = place_lines(seabed, params.area, params.sensor, heading, line_params, params.frame)
        route, labels, words = survey_route(world, lines, replace(params, lines=line_params),
                                            max(world.margins.min_depth, 0.0))
        if not params.hold_overlap or world.currents.steady or not route.size or speed <= 0:
            break
        length = (math.dist(mission.start, route[0]) + float(np.linalg.norm(np.diff(route, axis=0), axis=1).sum())
                  + math.dist(route[-1], mission.goal))
        span_h = FLIGHT_SLACK * length / speed / 3600.0
        if span_h <= hours:
            break
        if hours >= MAX_SPAN_H:
            break
        hours = float(min(math.ceil(span_h), MAX_SPAN_H))
    return margin, line_params, lines, route, labels, words


def plan_survey(world: World, mission: Mission, params: SurveyParams, seed: int = 0,
                progress: Progress | None = None, runner: Runner | None = None) -> SurveyPlan:
    """Plan a survey mission: lines, turns, depth, checks and the transits out and home.

    Parameters
    ----------
    world : World
        Seabed, obstacles and margins.
    mission : Mission
        Launch (``start``) and recovery (``goal``) points, vehicle and planner settings.
    params : SurveyParams
        The survey.
    seed : int
        Seed of the transit planner.
    progress : callable, optional
        Progress of the transit planner (in this process).
    runner : Runner, optional
        Where the two transits (out and home, independent plans with the same seed) are planned
        (:class:`auvplan.runtime.parallel.Runner`; this process by default).

    Returns
    -------
    SurveyPlan
        The mission; a failed check or transit is its status, not an exception.
    """
    if world.terrain is None:
        raise ValueError("a survey needs a seabed ([terrain])")
    seabed = world.seabed
    margin, line_params, lines, route, labels, words = _lines_for_flight(world, mission, params, seabed,
                                                                         _heading(seabed, params))
    p = route[labels != TRANSIT]
    dh = np.hypot(*np.diff(p[:, :2], axis=0).T)
    pitch = float(np.degrees(np.arctan2(np.abs(np.diff(p[:, 2])), np.maximum(dh, 1e-9))).max()) if dh.size else 0.0
    message = "" if lines.complete else f"the area is not covered after {len(lines.lines)} lines (max_lines)"
    transits: list[PlanResult] = []
    if world.zones and not message:  # lines clipped by the no-go zones, the gaps bridged round them
        route, labels, transits, message = clip_to_zones(world, mission, route, labels, TRANSIT, seed, progress,
                                                           params.turn_radius_m)
        route, labels = join_bridges(world, route, labels, TRANSIT, params.turn_radius_m)
    message = message or _check(world, route, labels)
    route, labels, message = _with_transits(world, mission, params, route, labels, message, seed, progress, runner,
                                            transits)
    status = Status.EXACT if not message else Status.INFEASIBLE
    route, labels, held = _helm_legs(world, mission, params, route, labels)
    if held and not message:
        status, message = Status.INFEASIBLE, held
    return SurveyPlan(status, message, lines, route, labels, words, tuple(transits), _turn_radius(p), pitch, margin)


def _heading(seabed: Seabed, params: SurveyParams) -> float:
    """The lines' heading: the frame's, the one given, or the one :func:`choose_heading` picks (rad)."""
    if params.frame is not None:
        return params.frame.heading
    if params.heading_deg is None:
        return choose_heading(seabed, params)
    return math.radians(params.heading_deg)


def _with_transits(world: World, mission: Mission, params: SurveyParams, route: NDArray[np.float64],
                   labels: NDArray[np.int64], message: str, seed: int, progress: Progress | None,
                   runner: Runner | None, transits: list[PlanResult]) -> tuple[NDArray[np.float64], NDArray[np.int64],
                                                                             str]:
    """The survey joined to its transits out (from the launch) and home (to the recovery), each planned
    (``runner``) and appended to ``transits``; the message of the first that fails."""
    parts, labs = [route], [labels]
    legs = [] if message else [(a, b, where) for a, b, where in ((mission.start, route[0], "out"),
                                                               (route[-1], mission.goal, "home"))
                               if math.dist(a, b) > mission.sim.arrival_radius]
    shared = _Transit(world, mission, seed, None if runner is not None and runner.distributed else progress)
    for (_, _, where), (planned, path) in zip(legs, (runner or Runner()).map(_transit, legs, shared=shared).results):
        transits.append(planned)
        if path is None:
            message = f"the transit {where} failed ({planned.status.value}): {planned.message}"
            break
        if where == "out":
            path = np.vstack([path[:-1], join_transit(world, path, route[:2], params.turn_radius_m, home=False)])
            parts.insert(0, path)
            labs.insert(0, np.full(path.shape[0], TRANSIT))
        else:
            path = np.vstack([join_transit(world, route[-2:], path, params.turn_radius_m, home=True), path[1:]])
            parts.append(path)
            labs.append(np.full(path.shape[0], TRANSIT))
    return np.vstack(parts), np.concatenate(labs).astype(np.int64), message


def _helm_legs(world: World, mission: Mission, params: SurveyParams, route: NDArray[np.float64],
               labels: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.int64], str]:
    """The route without legs the helm refuses, and safe under held depth: failing legs split, or said."""
    # a transit's planned path can begin or end millimetres from the launch point: legs the vehicle's helm
    # refuses (shorter than the shortest leg); the transits lose such an end where safe, the survey keeps all
    lim = vehicle_limits(mission.vehicle)
    keep = merge_short_legs(world, route, shortest_leg(lim), fixed=np.flatnonzero(labels != TRANSIT),
                            max_pitch_deg=lim.max_pitch_deg)
    # survey22: every leg also under held depth (MOOS), as `run`'s exports: failing legs split, or said
    return held_safe(world, route[keep], labels[keep], params.lines.pitch_max_deg,
                     shortest_leg(lim), {TURN: "a turn", TRANSIT: "a transit"})
