"""Issue 59: the seeded plan's verdict on its own convergence, from the evidence it computed (oracles: the
rules of :mod:`auvplan.planners.swarm.convergence` worked by hand), and its place in the plan's JSON."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.io.results import records
from auvplan.planners.core.base import PlanResult
from auvplan.planners.swarm.convergence import CORRIDOR_MARGIN, assess


def _result(status: Status = Status.EXACT, **work: float) -> PlanResult:
    return PlanResult(status, np.zeros((2, 3)), 1000.0, {}, 10, 1, 0.0, np.empty(0), "iabc", work=work)


@pytest.mark.parametrize(("lattice", "converged", "code"), [
    (1000.0 * (1 - 0.005), False, "corridors-disagree: the seeding lattice's corridor, polished, is 0.50 % below"),
    (1000.0 * (1 - CORRIDOR_MARGIN) + 0.01, True, "the swarm's plan and the seeding lattice's corridor"),
    (1010.0, True, "the swarm's plan and the seeding lattice's corridor"),
    (float("inf"), True, "the swarm's plan is feasible and the seeding lattice's corridor is more than 3 %"),
])
def test_the_corridors_are_compared_after_the_polish(lattice, converged, code):
    work = {"polish_spline_cost": 1000.0, "polish_lattice_cost": lattice}
    got, why = assess(_result(**work), 8000.0, True, False)
    assert got is converged and why.startswith(code)


def test_the_lattice_candidate_not_polished_counts_as_far_off():
    """No ``polish_lattice_cost`` (its taut path more than 3 % above the plan: not polished) is no disagreement."""
    assert assess(_result(polish_spline_cost=1000.0), 8000.0, True, False)[0] is True


def test_no_lattice_path_and_an_infeasible_swarm_are_evidence_first():
    work = {"polish_spline_cost": 1000.0, "polish_lattice_cost": 900.0}
    assert assess(_result(**work), 566544.0, False, False) == (
        False, "no-lattice: no seeding lattice up to 566544 nodes found a path; the swarm ran unseeded and "
        "nothing checks its corridor")
    assert assess(_result(**work), 8000.0, True, True)[1].startswith("infeasible: ")
    assert assess(_result(Status.INFEASIBLE), 8000.0, True, False)[0] is False


def test_without_the_polish_it_is_not_assessed():
    assert assess(_result(), 8000.0, True, False)[0] is None


def test_the_plan_record_carries_the_verdict_only_when_assessed():
    rec = records.plan_record(_result(), "s", 0)
    assert "converged" not in rec and "convergence" not in rec
    r = PlanResult(Status.EXACT, np.zeros((2, 3)), 1.0, {}, 1, 1, 0.0, np.empty(0), "iabc", converged=False,
                   convergence="corridors-disagree: x")
    rec = records.plan_record(r, "s", 0)
    assert rec["converged"] is False and rec["convergence"] == "corridors-disagree: x"
