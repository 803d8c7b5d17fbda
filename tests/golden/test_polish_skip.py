"""Issue #35 (wave 6): the seeding lattice's taut polygon is polished only when its cost is within
``LATTICE_WITHIN`` of the spline's; far-off lattice corridors no longer cost a 4-sweep polish."""

from __future__ import annotations

from dataclasses import replace

import pytest

from auvplan.guidance.avoidance.local import key_waypoints
from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.planners.core.common import path_cost
from auvplan.planners.swarm import polish
from auvplan.sim import planning_problem


@pytest.fixture(scope="module")
def seamounts():
    world, mission = sc.build(sc.load("new-england-seamounts"))
    return planning_problem(world, mission), replace(mission.planner, budget=10_000)


def test_far_lattice_corridor_is_not_polished_and_nothing_is_lost(seamounts, monkeypatch):
    """new-england-seamounts: the 8 000-node lattice takes another corridor (its taut polygon ~+6 % above
    the spline), so only the spline is polished (one call of the refinement), and the plan is the same, to
    the bit, as with the lattice candidate always polished (it lost there).  The lifted candidate (wave 7,
    tests/golden/test_polish_lift.py) is left out here: this test is about the lattice's rule."""
    prob, spec = seamounts
    monkeypatch.setattr(polish, "_lifted_plan", lambda *a: None)
    calls: list[float] = []
    real = polish.refine_plan

    def spy(*args, **kwargs):
        calls.append(args[2].cost)
        return real(*args, **kwargs)

    monkeypatch.setattr(polish, "refine_plan", spy)
    r = plan(prob, spec, rng=0)
    assert r.status.ok and len(calls) == 1 and calls[0] < float("inf")
    monkeypatch.setattr(polish, "LATTICE_WITHIN", float("inf"))
    calls.clear()
    always = plan(prob, spec, rng=0)
    assert len(calls) == 2 and always.cost == r.cost
    assert always.path.shape == r.path.shape and (always.path == r.path).all()


def test_lattice_candidate_kept_exactly_within_the_margin(seamounts):
    """``LatticeCorridor.candidate`` keeps the taut polygon iff its cost (computed here independently) is at
    most ``1 + LATTICE_WITHIN`` times the plan's: checked on both sides of the threshold."""
    prob, spec = seamounts
    base = plan(prob, replace(spec, polish=0), rng=0)
    lattice = base.path  # any free start-goal polyline stands in for the lattice's path
    taut = path_cost(prob, spec, key_waypoints(lattice, prob.world))["total"]
    above = replace(base, cost=taut / (1.0 + polish.LATTICE_WITHIN) * 0.999)
    within = replace(base, cost=taut / (1.0 + polish.LATTICE_WITHIN) * 1.001)
    corridor = polish.LatticeCorridor(prob, spec, lattice)
    assert corridor.candidate(above) is None
    kept = corridor.candidate(within)
    assert kept is not None and kept.cost == float("inf")
