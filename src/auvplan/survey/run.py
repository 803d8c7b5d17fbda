"""A survey end to end: plan it (:func:`~auvplan.survey.mission.plan_survey`), fly it in the closed loop
with the currents (:func:`auvplan.sim.simulate`), and measure the coverage of the plan and of the flight
against the fixed-lane lawnmower."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
import shapely
from numpy.typing import NDArray

from ..planners.core.base import Progress
from ..runtime.parallel import Runner
from ..sim import Mission, RunRecord, simulate
from ..world import World
from .coverage import Coverage, Lawnmower, fan_right, footprints, lawnmower, measure
from .mission import SurveyParams, SurveyPlan, plan_survey

__all__ = ["SurveyRun", "run_survey", "track_labels", "planned_coverage", "flown_coverage", "no_go_area"]


@dataclass(frozen=True)
class SurveyRun:
    """A planned and flown survey.

    Attributes
    ----------
    plan : SurveyPlan
        The mission.
    record : RunRecord
        The closed-loop flight of the mission (``sim`` None when the plan failed).
    planned, flown : Coverage or None
        Coverage of the planned lines and of the flown track (None without a flight).
    lawnmower : Lawnmower
        The fixed-lane lawnmower over the same area.
    survey_time_s : float
        Time from entering the first line to leaving the last (s); NaN without a flight.
    """

    plan: SurveyPlan
    record: RunRecord
    planned: Coverage
    flown: Coverage | None
    lawnmower: Lawnmower
    survey_time_s: float


def track_labels(route: NDArray[np.float64], labels: NDArray[np.int64],
                 progress: NDArray[np.float64]) -> NDArray[np.int64]:
    """The route label (line number, turn or transit) of each track sample from its progress along the route.

    A sample is on line ``k`` when the route segment it has reached joins two vertices of line ``k``.

    Parameters
    ----------
    route : numpy.ndarray
        ``(N, 3)`` route (m).
    labels : numpy.ndarray
        ``(N,)`` labels of its vertices.
    progress : numpy.ndarray
        ``(M,)`` distance along the route of each sample (m).

    Returns
    -------
    numpy.ndarray
        ``(M,)`` labels (-1 off the lines).
    """
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(route, axis=0), axis=1))])
    seg = np.clip(np.searchsorted(arc, progress, side="right") - 1, 0, route.shape[0] - 2)
    same = labels[seg] == labels[seg + 1]
    return np.where(same, labels[seg], -1).astype(np.int64)


def no_go_area(world: World, plan: SurveyPlan | None = None) -> shapely.Geometry | None:
    """The footprints of the world's charted zones (unpadded) that the survey keeps out of, left out of the
    coverage; None without.

    A zone whose depth band the survey lines pass over or under (a cable's band near the seabed under lines
    flown higher, a band below the seabed the lines follow) is flown over: its part of the area is surveyed,
    so it is neither left out of the coverage nor counted in ``no_go_m2``.

    Parameters
    ----------
    world : World
        Its zones.
    plan : SurveyPlan, optional
        The survey: a zone one of its lines' legs crosses (in plan view) is not a no-go area of it (without a
        plan, every zone is).

    Returns
    -------
    shapely geometry or None
        Their union.
    """
    if not world.zones:
        return None
    zones = [z.footprint for z in world.zones.exact.zones]
    if plan is not None and plan.route.shape[0] > 1:
        lab = plan.labels
        on = (lab[:-1] >= 0) & (lab[:-1] == lab[1:])  # the legs of the survey lines (not turns, not transits)
        legs = shapely.linestrings(np.stack([plan.route[:-1, :2], plan.route[1:, :2]], axis=1)[on])
        zones = [z for z in zones if not shapely.intersects(legs, z).any()]
    return shapely.union_all(zones) if zones else None


def planned_coverage(world: World, plan: SurveyPlan, params: SurveyParams) -> Coverage:
    """Coverage of the planned lines, fans across the nominal heading (the planner's model).

    Parameters
    ----------
    world : World
        The seabed.
    plan : SurveyPlan
        The mission.
    params : SurveyParams
        The survey.

    Returns
    -------
    Coverage
        Coverage, per-pair overlaps and gaps of the plan.
    """
    lab = plan.labels
    fr = plan.lines.geom
    right = fr.right(fr.to_sn(plan.route[:, 0], plan.route[:, 1])[0])
    fps = footprints(world.seabed, params.sensor, plan.route, right, lab, len(plan.lines.lines),
                     params.lines.step_m)
    return measure(params.area, plan.lines, fps, no_go=no_go_area(world, plan))


def flown_coverage(world: World, plan: SurveyPlan, params: SurveyParams, record: RunRecord,
                   spacing: float = 5.0) -> tuple[Coverage, float]:
    """Coverage of the flown track (fans across the vehicle's heading) and the time on the lines.

    Parameters
    ----------
    world : World
        The seabed.
    plan : SurveyPlan
        The mission flown.
    params : SurveyParams
        The survey.
    record : RunRecord
        The flight.
    spacing : float
        Track samples are kept every ``spacing`` metres (m).

    Returns
    -------
    tuple
        The :class:`Coverage` and the time from entering the first line to leaving the last (s).
    """
    sim = record.sim
    assert sim is not None
    lab = track_labels(plan.route, plan.labels, sim.progress)
    dist = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(sim.position, axis=0), axis=1))])
    keep = np.r_[True, np.diff(np.floor(dist / spacing)) > 0]
    keep |= np.r_[lab[1:] != lab[:-1], True] | np.r_[True, lab[1:] != lab[:-1]]
    fps = footprints(world.seabed, params.sensor, sim.position[keep], fan_right(sim.heading[keep]), lab[keep],
                     len(plan.lines.lines), params.lines.step_m)
    on = np.flatnonzero(lab >= 0)
    t = float(sim.t[on[-1]] - sim.t[on[0]]) if on.size else math.nan
    return measure(params.area, plan.lines, fps, no_go=no_go_area(world, plan)), t


def run_survey(world: World, mission: Mission, params: SurveyParams, seed: int = 0,
               progress: Progress | None = None, flight: Callable[[float, float], object] | None = None,
               guidance: str | None = None, runner: Runner | None = None) -> SurveyRun:
    """Plan, fly and measure a survey.

    Parameters
    ----------
    world : World
        Seabed, currents and obstacles.
    mission : Mission
        Launch and recovery points, vehicle, guidance and closed-loop settings.
    params : SurveyParams
        The survey.
    seed : int
        Seed of the transit planner and of the flight's disturbances.
    progress : callable, optional
        Progress of the transit planner.
    flight : callable, optional
        The simulation's progress callback.
    guidance : str, optional
        Override the mission's path follower.
    runner : Runner, optional
        Where the independent transits are planned (:func:`~auvplan.survey.mission.plan_survey`); the flight
        is one closed loop, flown in this process.

    Returns
    -------
    SurveyRun
        Plan, flight and coverage.
    """
    plan = plan_survey(world, mission, params, seed, progress, runner)
    planned = planned_coverage(world, plan, params)
    mower = lawnmower(world.seabed, params.area, params.sensor, plan.lines.heading, params.lines.overlap_min,
                      -max(world.margins.min_depth, 0.0), params.run_in_m, frame=plan.lines.frame)
    empty = np.empty((0, 3))
    if not plan.status.ok:
        return SurveyRun(plan, RunRecord(mission.name, seed, None, plan.route, empty, None), planned, None, mower,
                         math.nan)
    flown_mission = replace(mission, route=tuple(map(tuple, plan.route.tolist())))
    sim = simulate(world, flown_mission, route=plan.route, guidance=guidance, rng=seed, avoidance="none",
                   keys=empty, progress=flight)
    record = RunRecord(mission.name, seed, None, plan.route, empty, sim)
    flown, t = flown_coverage(world, plan, params, record)
    return SurveyRun(plan, record, planned, flown, mower, t)
