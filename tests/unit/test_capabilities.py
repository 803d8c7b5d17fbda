"""Planners declare what they do at registration (issue #50.4); the package asks the registry, not the name.

The oracle: the built-in planners are registered through the same :func:`register` as a plug-in (their
entries are indistinguishable in kind), and the one behaviour that depends on a capability today — whether a
plan's cost is re-computed by the project's path cost — follows the declaration for any planner, built-in
or not (a plug-in that declares ``path_cost`` keeps its own cost; the same plug-in without it is re-costed
to exactly :func:`auvplan.planners.core.common.path_cost`).
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from test_registry import SCENARIO, StraightParams, straight

from auvplan.io.scenario import loader as sc
from auvplan.planners import REGISTRY, plan, register
from auvplan.planners.core.common import path_cost
from auvplan.planners.core.registry import CAPABILITIES, PLANNERS, get, has
from auvplan.planners.grid.planner import on_cost_function
from auvplan.sim import planning_problem


def test_every_built_in_planner_declares_its_capabilities() -> None:
    declared = {name: get(name).capabilities for name in PLANNERS}
    assert declared == {
        **{s: frozenset({"path_cost", "currents", "zones"}) for s in ("iabc", "abc", "ga", "pso", "de")},
        "flow": frozenset(), "grid": frozenset({"path_cost", "currents", "zones"}),
        "timeopt": frozenset({"currents", "time_varying", "zones"}),
    }
    assert all(c in CAPABILITIES for caps in declared.values() for c in caps)
    assert has("grid", "path_cost") and not has("flow", "path_cost") and has("timeopt", "time_varying")
    assert not has("no-such-planner", "currents")
    with pytest.raises(ValueError, match="unknown capability 'teleport'"):
        has("grid", "teleport")


def test_an_unknown_capability_is_refused_at_registration() -> None:
    with pytest.raises(ValueError, match=r"capabilities \['teleport'\] unknown"):
        register("teleporter", iterative=False, description="", capabilities=("teleport",))(straight)
    assert "teleporter" not in REGISTRY


@pytest.fixture(params=[(), ("path_cost",)], ids=["undeclared", "path_cost"])
def plugin(request: pytest.FixtureRequest) -> Iterator[tuple[str, ...]]:
    register("straight", iterative=False, description="the straight line", params=StraightParams,
             capabilities=request.param)(straight)
    try:
        yield request.param
    finally:
        REGISTRY.pop("straight")


def test_re_costing_follows_the_declaration_not_the_name(plugin: tuple[str, ...]) -> None:
    world, mission = sc.build(sc.loads(SCENARIO))
    problem = planning_problem(world, mission)
    raw = plan(problem, mission.planner)  # the plug-in's own cost: the length alone
    assert raw.planner == "straight" and raw.cost == pytest.approx(raw.cost_terms["length_m"])
    out = on_cost_function(raw, problem, mission.planner)
    if "path_cost" in plugin:
        assert out is raw
    else:
        terms = path_cost(problem, mission.planner, raw.path)
        assert out.cost == float(terms["total"]) and out.cost > raw.cost
