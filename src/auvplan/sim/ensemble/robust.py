"""One route for every member of a current ensemble (``[planner] robust``).

The robust planner plans candidate routes with the scenario's own planner
(:func:`auvplan.sim.planned_route`, the route a mission flies), each on one view of the
forecast: the nominal field, every member, and the members' mean
(:class:`~auvplan.world.currents.ensemble.MeanCurrent`).  Each candidate is flown in every member
(:func:`~auvplan.sim.ensemble.score.score_route`) and the best by the objective is kept:

* ``"p90"``: least 90th-percentile arrival time, then the highest success probability, then the
  least median;
* ``"success"``: highest success probability, then the least P90, then the least median.

The nominal plan is always a candidate, so the robust plan's objective is never worse than the
nominal plan's in the same members (a scenario approach over the planner's own optima).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ..._types import RngLike
from ...planners.core.base import PlanResult
from ...runtime.parallel import Runner
from ...world import CurrentField, World
from ...world.currents.ensemble import MeanCurrent
from .. import Mission, planned_route
from .score import EnsembleScore, score_route

__all__ = ["Candidate", "RobustPlan", "rank_key", "plan_robust", "OBJECTIVES"]

OBJECTIVES = ("none", "p90", "success")
"""The values of ``[planner] robust``."""


@dataclass(frozen=True, eq=False)
class Candidate:
    """One candidate route, the field it was planned on, and its score in every member.

    Attributes
    ----------
    label : str
        ``nominal``, a member's name, or ``mean``.
    plan : PlanResult or None
        The planner's result (None for a fixed route).
    route : numpy.ndarray or None
        ``(N, 3)`` mission waypoints (None when planning failed).
    score : EnsembleScore or None
        Its score in the members (None without a route).
    """

    label: str
    plan: PlanResult | None
    route: NDArray[np.float64] | None
    score: EnsembleScore | None


@dataclass(frozen=True, eq=False)
class RobustPlan:
    """The outcome of robust planning.

    Attributes
    ----------
    objective : str
        ``none``, ``p90`` or ``success``.
    chosen : Candidate
        The route kept.
    nominal : Candidate
        The plan on the nominal field.
    candidates : tuple of Candidate
        Every candidate, the nominal first.
    """

    objective: str
    chosen: Candidate
    nominal: Candidate
    candidates: tuple[Candidate, ...]


def rank_key(score: EnsembleScore | None, objective: str) -> tuple[float, float, float]:
    """Sort key of a candidate under an objective (smaller is better; no score is worst).

    Parameters
    ----------
    score : EnsembleScore or None
        The candidate's score.
    objective : str
        ``p90`` (or ``none``) or ``success``.

    Returns
    -------
    tuple of float
        ``(P90, −success, P50)`` for ``p90``; ``(−success, P90, P50)`` for ``success``.
    """
    if score is None:
        return (math.inf, math.inf, math.inf)
    p90, p50, fail = score.arrival_p90_s, score.arrival_p50_s, -score.success_probability
    return (fail, p90, p50) if objective == "success" else (p90, fail, p50)


@dataclass(frozen=True, eq=False)
class _Shared:
    """What every candidate's task shares: the world, the mission, the members and the planner's seed."""

    world: World
    mission: Mission
    members: tuple[tuple[str, CurrentField], ...]
    seed: RngLike


def _candidate_task(shared: _Shared, task: tuple[str, CurrentField | None]) -> Candidate:
    """One candidate as a task of :meth:`auvplan.runtime.parallel.Runner.map`."""
    return _candidate(shared.world, shared.mission, task[0], task[1], shared.members, shared.seed)


def _candidate(world: World, mission: Mission, label: str, field: CurrentField | None,
               members: Sequence[tuple[str, CurrentField]], seed: RngLike) -> Candidate:
    w = world if field is None else replace(world, currents=field)
    plan, route = planned_route(w, mission, seed)
    score = None if route is None else score_route(world, members, route, mission.vehicle)
    return Candidate(label, plan, route, score)


def plan_robust(world: World, mission: Mission, members: Sequence[tuple[str, CurrentField]],
                objective: str = "p90", seed: RngLike = None, runner: Runner | None = None) -> RobustPlan:
    """Plan one route for every member (module notes).

    Parameters
    ----------
    world : World
        The world with its nominal current field.
    mission : Mission
        End points, vehicle and planner.
    members : sequence of (str, CurrentField)
        The ensemble.
    objective : str, default ``"p90"``
        ``none`` (the nominal plan, scored), ``p90`` or ``success``.
    seed : Generator, int or None
        Seed of every candidate's planner (the mission's by default).
    runner : Runner, optional
        Where the candidates are planned and scored (:class:`auvplan.runtime.parallel.Runner`; this process by
        default): each is one task, seeded by ``seed``, so the choice does not depend on the workers.

    Returns
    -------
    RobustPlan
        The chosen route, the nominal one and every candidate with its score.
    """
    if objective not in OBJECTIVES:
        raise ValueError(f"robust = {objective!r}: choose one of {', '.join(OBJECTIVES)}")
    if not members:
        raise ValueError("robust planning needs at least one member")
    seed = mission.seed if seed is None else seed
    if isinstance(seed, np.random.Generator):  # one seed for every candidate, whichever worker plans it
        seed = int(seed.integers(2**62))
    tasks: list[tuple[str, CurrentField | None]] = [("nominal", None)]
    if objective != "none" and not mission.route:
        tasks += list(members)
        if len(members) > 1:
            tasks.append(("mean", MeanCurrent([f for _, f in members])))
    shared = _Shared(world, mission, tuple(members), seed)
    cands = (runner or Runner()).map(_candidate_task, tasks, shared=shared).results
    nominal = cands[0]
    chosen = min(cands, key=lambda c: rank_key(c.score, objective))  # the first of equals: the nominal
    return RobustPlan(objective, chosen, nominal, tuple(cands))
