"""Document 002's eq. 17 under its two readings of V_oc, beside the physical energy (issue #36.3)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from auvplan.cost import ENERGY_READINGS, CostModel, energy_mode, evaluate_paths
from auvplan.planners.core.base import PlannerSpec
from auvplan.world import Bounds, UniformCurrent, World


def _leg(current: tuple[float, float, float]) -> tuple[World, np.ndarray]:
    world = World(Bounds(-100.0, 2100.0, -1000.0, 1000.0, -500.0, 0.0), currents=UniformCurrent(current))
    x = np.linspace(0.0, 2000.0, 41)
    return world, np.c_[x, np.zeros_like(x), np.full_like(x, -100.0)]


@pytest.mark.parametrize("current", [(0.3, 0.4, 0.0), (-0.5, 0.0, 0.0), (0.0, 0.0, 0.0)])
def test_document_vehicle_energy_of_a_straight_leg_in_uniform_current(current):
    """Straight 2 km leg along x, V = 1.5 m/s, current (u, v): the ground speed is
    |V_h| = u + sqrt(V² - v²) and eq. 17 with V_oc = V gives ρ |V_h|³ L / V, ρ = scale = 1 / V²."""
    world, path = _leg(current)
    v, (u, w, _) = 1.5, current
    model = CostModel(speed=v, energy="document-vehicle")
    terms = evaluate_paths(world, path, model, exact=True)
    ground = u + math.sqrt(v * v - w * w)
    assert terms.energy[0] == pytest.approx(ground**3 * 2000.0 / v / v**2, rel=1e-12)
    assert terms.duration_s[0] == pytest.approx(2000.0 / ground, rel=1e-12)
    # the document's literal reading divides by the current's speed instead (floored at 1 mm/s)
    literal = evaluate_paths(world, path, CostModel(speed=v, energy="document"), exact=True)
    speed_c = max(math.hypot(u, w), 1e-3)
    assert literal.energy[0] == pytest.approx(ground**3 * 2000.0 / speed_c / v**2, rel=1e-12)


def test_still_water_is_finite_under_the_vehicle_reading_only():
    world, path = _leg((0.0, 0.0, 0.0))
    vehicle = evaluate_paths(world, path, CostModel(speed=2.0, energy="document-vehicle"))
    literal = evaluate_paths(world, path, CostModel(speed=2.0, energy="document"))
    assert vehicle.energy[0] == pytest.approx(2000.0, rel=1e-12)  # ρ V³ L / V = L with ρ = 1/V²
    assert literal.energy[0] == pytest.approx(2000.0 * 2.0 / 1e-3, rel=1e-12)  # the floor's blow-up


def test_readings_are_validated_by_name():
    assert ENERGY_READINGS == ("physical", "document", "document-vehicle")
    assert [energy_mode(CostModel(energy=e)) for e in ENERGY_READINGS] == [0, 1, 2]
    assert PlannerSpec(energy="document-vehicle").energy == "document-vehicle"
    with pytest.raises(ValueError, match="document-vehicle"):
        PlannerSpec(energy="vehicle")
    with pytest.raises(ValueError, match="document-vehicle"):
        CostModel(energy="document_vehicle")


@pytest.mark.parametrize("energy", ENERGY_READINGS)
def test_lattice_reference_costs_its_edges_under_the_scenarios_reading(energy):
    """Still water, cost objective: every lattice direction costs the same per metre, so the cost-to-go
    of the nodes straight above the goal is the cost of that vertical segment, which the swarm's cost
    function (:func:`evaluate_paths`, its own code) gives under each reading: the lattice must use the
    scenario's reading (it used the physical energy for ``document-vehicle``, whose still water is
    ρ V² per metre, not P / V)."""
    from auvplan.planners import GridParams, GridReference, PlanningProblem
    from auvplan.planners.core.common import cost_model_for, search_box

    world = World(Bounds(0.0, 200.0, 0.0, 200.0, -200.0, 0.0))
    prob = PlanningProblem(world, [10.0, 10.0, -190.0], [100.0, 100.0, -100.0], 1.5)
    spec = PlannerSpec(name="grid", energy=energy, grid=GridParams(objective="cost", cell=20.0, cell_z=20.0,
                                                                   any_angle=0))
    lo, hi = search_box(prob)
    model = cost_model_for(prob, spec)
    ref = GridReference(world, prob.goal, model, lo, hi, spec.grid)
    i, j, k = (int(np.argmin(np.abs(ax - g))) for ax, g in zip(ref.axes, prob.goal))
    assert (ref.axes[0][i], ref.axes[1][j], ref.axes[2][k]) == (100.0, 100.0, -100.0)
    for kk in range(ref.shape[2]):
        node = np.array([ref.axes[0][i], ref.axes[1][j], ref.axes[2][kk]])
        want = evaluate_paths(world, np.stack([node, prob.goal]), model, exact=True).total[0]
        assert ref.cost_to_go[i, j, kk] == pytest.approx(want, rel=1e-9, abs=1e-9), kk
