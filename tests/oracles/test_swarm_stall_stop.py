"""The seeded pipeline stops a swarm stalled behind the seeding lattice's corridor (issue 53's CPU figure).

Oracles: the plan with the stop against the same plan with it off (an explicit budget of the same size is
spent exactly: the stop never applies), path bytes; the stall in the plan's own history; the corridor's
polish kept for the final polish against :func:`refine_plan` run on the same candidate.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from benchmarks.zones import scattered_zones

import auvplan.planners.swarm.planner as swarm_planner
from auvplan.io.scenario.build import build
from auvplan.io.scenario.loader import load
from auvplan.planners import plan
from auvplan.planners.grid.planner import refine_plan
from auvplan.planners.swarm.convergence import STALL_ITERATIONS
from auvplan.planners.swarm.polish import LatticeCorridor
from auvplan.planners.swarm.seeding import coarse_reference
from auvplan.sim.pipeline import planning_problem


@pytest.fixture(scope="module")
def zoned():  # type: ignore[no-untyped-def]
    world, mission = build(load("marcus-wake"))
    base = planning_problem(replace(world, zones=None), mission)
    zones = scattered_zones(base.world, base.start, base.goal, 1000, 7)  # the benchmark's `cpu` problem
    problem = replace(base, world=replace(base.world, zones=zones))
    return problem, mission.planner


def test_a_swarm_stalled_behind_the_corridor_stops_and_plans_the_same_path(zoned) -> None:  # type: ignore[no-untyped-def]
    problem, spec = zoned
    assert spec.budget == 0  # the default budget: the stop applies
    stopped = plan(problem, spec, rng=2)
    full = plan(problem, replace(spec, budget=spec.evaluations), rng=2)  # spent exactly: no stop
    assert "swarm_stopped_at_evaluations" in stopped.work and "swarm_stopped_at_evaluations" not in full.work
    assert full.evaluations == spec.evaluations
    at = stopped.work["swarm_stopped_at_evaluations"]
    assert stopped.evaluations == at < 0.7 * spec.evaluations  # neither the rest of the swarm nor the refinement
    assert "stopped after" in stopped.message
    # the stop is a stall: the last STALL_ITERATIONS iterations did not improve on the one before them
    tail = stopped.history[-(STALL_ITERATIONS + 1):]
    assert len(stopped.history) > STALL_ITERATIONS and np.all(tail == tail[0])
    # the corridor won either way, so the plan is the same, to the bit
    assert stopped.status.ok and full.status.ok
    assert np.array_equal(stopped.path, full.path) and stopped.cost == full.cost


def test_a_stall_with_the_swarm_ahead_of_the_corridor_goes_on(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """salish-shelf's swarm stalls 27 iterations but is ahead of the lattice: asked, it is not stopped."""
    world, mission = build(load("salish-shelf"))
    problem, spec = planning_problem(world, mission), mission.planner
    asked: list[bool] = []
    real = swarm_planner.stalled_behind

    def spy(corridor, best):  # type: ignore[no-untyped-def]
        asked.append(real(corridor, best))
        return asked[-1]

    monkeypatch.setattr(swarm_planner, "stalled_behind", spy)
    went_on = plan(problem, spec, rng=mission.seed)
    full = plan(problem, replace(spec, budget=spec.evaluations), rng=mission.seed)
    assert asked and not any(asked)
    assert "swarm_stopped_at_evaluations" not in went_on.work and went_on.evaluations == spec.evaluations
    assert np.array_equal(went_on.path, full.path) and went_on.cost == full.cost


def test_the_corridor_polished_once_is_what_refine_plan_returns(zoned) -> None:  # type: ignore[no-untyped-def]
    problem, spec = zoned
    _, lattice = coarse_reference(problem, spec)
    result = plan(problem, replace(spec, polish=0, budget=400), rng=0)  # a plan whose fields the candidate takes
    corridor = LatticeCorridor(problem, spec, lattice)
    candidate = corridor.candidate(result)
    assert candidate is not None and corridor.polished_plan(candidate) is None  # not polished yet
    cost = corridor.polished_cost()
    band = replace(spec, grid=replace(spec.grid, relax_iterations=2 * spec.polish, converge_tol=0.5))
    direct = refine_plan(problem, band, candidate, finest=512.0)
    kept = corridor.polished_plan(candidate)
    assert kept is not None and np.isfinite(cost) and cost == direct.cost == kept.cost
    assert np.array_equal(kept.path, direct.path)
    assert kept.cost_terms == direct.cost_terms and kept.message == direct.message
    assert kept.evaluations == result.evaluations and kept.planner == result.planner
