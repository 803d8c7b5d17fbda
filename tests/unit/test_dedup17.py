"""The pieces written once by the dedup wave: every planner's pathless failure is :meth:`PlanResult.failure`'s record,
and a field made from one base field answers its domain and speed bound from the base (``DerivedCurrent``)."""

from __future__ import annotations

import dataclasses
import math
import types

import numpy as np
import pytest

from auvplan._types import Status
from auvplan.planners import PlannerSpec, PlanningProblem, PlanResult, plan
from auvplan.planners.timeopt.glider import DepthAveragedCurrent
from auvplan.world.currents import GriddedCurrent, PerturbedCurrent, ShiftedCurrent
from auvplan.world.currents.ensemble import DerivedCurrent
from helpers import flat_world


@pytest.mark.parametrize("name", ["iabc", "flow", "grid", "timeopt"])
@pytest.mark.parametrize(("where", "status"), [("start", Status.INVALID_START), ("goal", Status.INVALID_GOAL)])
def test_every_planner_s_refused_end_point_is_the_one_pathless_failure(name, where, status):
    """Oracle: the pathless failure's invariants, field by field (an empty ``(0, 3)`` path, ``inf`` cost, no terms, no
    work, an empty history, no control points), the status of the end point refused and a message naming it; the
    wall time is the only field a planner may set (non-negative).  Four planners built this record by hand."""
    world = flat_world(depth=100.0)
    ends = {"start": [500.0, 500.0, -50.0], "goal": [900.0, 900.0, -50.0]}
    ends[where] = [500.0, 500.0, -99.0]  # 1 m above a seabed the 5 m altitude margin keeps it off
    got = plan(PlanningProblem(world, np.array(ends["start"]), np.array(ends["goal"])), PlannerSpec(name=name), rng=1)
    want = PlanResult.failure(status, got.message, name, got.wall_time_s)
    assert got.status is status and got.message.startswith(f"{where} [500.0, 500.0, -99.0] is not free")
    assert got.wall_time_s >= 0.0 and math.isinf(got.cost) and got.path.shape == (0, 3)
    for f in dataclasses.fields(PlanResult):
        a, b = getattr(got, f.name), getattr(want, f.name)
        if isinstance(a, np.ndarray):
            assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), f.name
        elif isinstance(a, float) and math.isnan(a):
            assert math.isnan(b), f.name
        else:
            assert a == b, f.name


def _grid() -> GriddedCurrent:
    """A 2 km x 1 km grid (non-square) of a current up to 0.5 m/s (0.3 east, 0.4 south at its south-east node)."""
    x, y, z = np.linspace(0.0, 2000.0, 5), np.linspace(0.0, 1000.0, 3), np.array([-100.0, 0.0])
    u = np.zeros((2, 3, 5))
    u[..., -1] = 0.3
    v = np.zeros((2, 3, 5))
    v[:, 0, -1] = -0.4
    return GriddedCurrent(x, y, z, u, v)


@pytest.mark.parametrize("kind", ["perturbed", "shifted", "depth-averaged"])
def test_a_field_made_from_a_base_field_is_defined_where_the_base_is(kind):
    """Oracle: the base grid's own domain, 0 to 2 km east and 0 to 1 km north (a box 1 m beyond any side is not
    covered); and the speed bound: the base's 0.5 m/s, a perturbed field's the base's plus √2 σ √(2M) (its own)."""
    base = _grid()
    field: DerivedCurrent
    if kind == "perturbed":
        field = PerturbedCurrent(base, 0.1, 300.0, seed=4, modes=8)
    elif kind == "shifted":
        field = ShiftedCurrent(base, 3600.0)
    else:
        field = DepthAveragedCurrent(types.SimpleNamespace(currents=base, terrain=None), 10.0, 90.0, 5.0)  # type: ignore[arg-type]
    assert isinstance(field, DerivedCurrent) and field.base is base
    assert field.covers(0.0, 2000.0, 0.0, 1000.0) and field.covers(100.0, 1900.0, 100.0, 900.0)
    for box in ((-1.0, 2000.0, 0.0, 1000.0), (0.0, 2001.0, 0.0, 1000.0), (0.0, 2000.0, -1.0, 1000.0),
                (0.0, 2000.0, 0.0, 1001.0)):
        assert not field.covers(*box), box
    bound = 0.5 + (math.sqrt(2.0) * 0.1 * math.sqrt(2.0 * 8) if kind == "perturbed" else 0.0)
    assert field.max_speed == pytest.approx(bound, rel=1e-12)
