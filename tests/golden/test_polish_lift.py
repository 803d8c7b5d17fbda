"""Issue #35.1 (wave 7): the plan lifted to the depth ceiling as a third polish candidate.

On new-england-seamounts 4 seeds in 10 ended +0.38 … +0.54 % above the best known: their splines pass
100–300 m deeper round a rise that the best known path crosses just under the 4 200 m ceiling, and no band
move crosses between.  The same path with its interior points put 1 m below the ceiling, polished, finds the
crossing."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan.io.scenario import loader as sc
from auvplan.planners import plan
from auvplan.planners.core.common import path_cost
from auvplan.planners.swarm import polish
from auvplan.sim import planning_problem

SEAMOUNTS_BEST = 424_003.0
"""new-england-seamounts' best known cost (docs/figures/bench-hard-default.md, wave 6)."""


@pytest.fixture(scope="module")
def seamounts():
    world, mission = sc.build(sc.load("new-england-seamounts"))
    return planning_problem(world, mission), replace(mission.planner, budget=10_000)


def test_lifted_candidate_crosses_the_rise_the_worst_seed_goes_round(seamounts, monkeypatch):
    """Seed 8 (wave 6's worst, +0.54 %): with the lifted candidate the plan is within +0.1 % of the best
    known, free, from the lifted path, the budget spent exactly; without it the same seed stays above
    +0.3 % (the candidate is what closes the gap)."""
    prob, spec = seamounts
    r = plan(prob, spec, rng=8)
    assert r.status.ok and r.evaluations == spec.budget and prob.world.path_free(r.path)
    assert "lifted to the depth ceiling" in r.message
    assert r.cost <= SEAMOUNTS_BEST * 1.001
    monkeypatch.setattr(polish, "_lifted_plan", lambda *a: None)
    alone = plan(prob, spec, rng=8)
    assert alone.cost > SEAMOUNTS_BEST * 1.003 and r.cost < alone.cost


def test_lifted_candidate_is_the_path_at_the_ceiling_within_the_margin(seamounts):
    """``_lifted_plan``: the ends kept, every interior point at ``-min_depth - LIFT_BELOW``, the x, y
    unchanged; kept iff its cost (computed here independently) is within ``1 + LIFT_WITHIN`` of the
    plan's (both sides of the threshold); None without a ceiling."""
    prob, spec = seamounts
    base = plan(prob, replace(spec, polish=0), rng=0)
    lifted = base.path.copy()
    lifted[1:-1, 2] = -prob.world.margins.min_depth - polish.LIFT_BELOW
    cost = path_cost(prob, spec, lifted)["total"]
    above = replace(base, cost=cost / (1.0 + polish.LIFT_WITHIN) * 0.999)
    within = replace(base, cost=cost / (1.0 + polish.LIFT_WITHIN) * 1.001)
    assert polish._lifted_plan(prob, spec, above) is None
    kept = polish._lifted_plan(prob, spec, within)
    assert kept is not None and kept.cost == float("inf") and np.array_equal(kept.path, lifted)
    assert np.array_equal(kept.path[[0, -1]], base.path[[0, -1]])
    open_sea = replace(prob, world=replace(prob.world, margins=replace(prob.world.margins, min_depth=-float("inf"))))
    assert polish._lifted_plan(open_sea, spec, within) is None


def test_spline_polish_is_not_run_when_the_lifted_path_wins(seamounts, monkeypatch):
    """Seed 8: the lifted candidate is polished first and wins, so the refinement runs once (the spline's
    own polish skipped, the far lattice corridor not polished): the polish costs what it did before."""
    prob, spec = seamounts
    calls: list[float] = []
    real = polish.refine_plan

    def spy(*args, **kwargs):
        calls.append(float(args[2].path[1:-1, 2].max()))
        return real(*args, **kwargs)

    monkeypatch.setattr(polish, "refine_plan", spy)
    r = plan(prob, spec, rng=8)
    assert "lifted to the depth ceiling" in r.message
    assert calls == [-prob.world.margins.min_depth - polish.LIFT_BELOW]
