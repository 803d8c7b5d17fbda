"""The planner registry is the plug-in point: a planner registered from outside the package, with its own
settings type, is accepted by PlannerSpec, read from a scenario's [planner.<name>] table, run by
auvplan.planners.plan and by the command line."""

from __future__ import annotations

import json
import math
from collections.abc import Iterator
from dataclasses import dataclass, replace

import numpy as np
import pytest

from auvplan import cli
from auvplan._types import RngLike, Status
from auvplan.errors import ScenarioError
from auvplan.io.scenario import loader as sc
from auvplan.planners import PLANNERS, REGISTRY, PlannerSpec, PlanningProblem, PlanResult, plan, register
from auvplan.planners.core.base import Progress
from auvplan.planners.core.registry import get, names
from auvplan.sim import planning_problem


@dataclass(frozen=True)
class StraightParams:
    """Settings of the test's straight-line planner.

    Attributes
    ----------
    spacing : float
        Distance between the path's points (m).
    """

    spacing: float = 100.0

    def __post_init__(self) -> None:
        if not self.spacing > 0:
            raise ValueError(f"spacing = {self.spacing}: must be > 0")


def straight(problem: PlanningProblem, spec: PlannerSpec, rng: RngLike = None,
             progress: Progress | None = None) -> PlanResult:
    """The straight line from the start to the goal, a point every ``spacing`` metres at most."""
    return straight_line(problem, spec.params_for())


def straight_line(problem: PlanningProblem, params: StraightParams) -> PlanResult:
    """:func:`straight` of the settings alone (a deterministic plan function)."""
    length = float(np.linalg.norm(problem.goal - problem.start))
    path = np.linspace(problem.start, problem.goal, math.ceil(length / params.spacing) + 1)
    status = Status.EXACT if problem.world.path_free(path) else Status.INFEASIBLE
    return PlanResult(status, path, length, {"length_m": length}, 0, 0, 0.0, np.empty(0), "straight")


@pytest.fixture
def registered() -> Iterator[None]:
    register("straight", iterative=False, description="the straight line (a test plug-in)",
             params=StraightParams)(straight)
    try:
        yield
    finally:
        REGISTRY.pop("straight")


SCENARIO = """
name = "plug-in"
seed = 3

[bounds]
x = [0.0, 1000.0]
y = [0.0, 1000.0]
z = [-120.0, 0.0]

[terrain.synthetic]
kind = "hills"
depth = 100.0
cell_m = 20.0
hills = [[500.0, 500.0, 60.0, 80.0]]

[mission]
start = [50.0, 50.0, -20.0]
goal = [950.0, 950.0, -20.0]
min_altitude_m = 5.0

[planner]
name = "straight"
"""

LENGTH = math.hypot(900.0, 900.0)


def test_a_registered_planner_is_read_from_a_scenario_and_planned(registered: None) -> None:
    world, mission = sc.build(sc.loads(SCENARIO + "\n[planner.straight]\nspacing = 30.0\n"))
    assert mission.planner.params_for() == StraightParams(30.0)
    assert mission.planner.params_for("flow") is mission.planner.flow  # the built-ins' tables as before
    result = plan(planning_problem(world, mission), mission.planner)
    assert result.status is Status.EXACT and result.planner == "straight"
    assert len(result.path) == math.ceil(LENGTH / 30.0) + 1  # 44 points: its settings reached it
    np.testing.assert_allclose(result.path[[0, -1]], [mission.start, mission.goal])
    # without a [planner.straight] table: its settings type's defaults
    _, mission = sc.build(sc.loads(SCENARIO))
    assert mission.planner.params_for() == StraightParams()


def test_a_registered_planner_runs_from_the_command_line(registered: None, tmp_path, capsys) -> None:
    path = tmp_path / "plug.toml"
    path.write_text(SCENARIO + "\n[planner.straight]\nspacing = 30.0\n")
    assert cli.main(["plan", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["planner"] == "straight" and out["status"] == "EXACT"
    assert out["length_m"] == pytest.approx(LENGTH, rel=1e-12)
    # and as an override of another scenario's planner
    other = tmp_path / "other.toml"
    other.write_text(SCENARIO.replace('name = "straight"', 'name = "grid"'))
    assert cli.main(["plan", str(other), "--planner", "straight", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["planner"] == "straight"


def test_the_names_and_settings_types_come_from_the_registry(registered: None) -> None:
    assert names() == (*PLANNERS, "straight")
    assert get("straight").settings_type is StraightParams and get("straight").table is None
    assert get("flow").settings_type is type(PlannerSpec().flow)
    assert get("iabc").settings_type is type(PlannerSpec().iabc) and get("iabc").iterative
    assert PlannerSpec(name="straight").name == "straight"


def test_an_unregistered_or_misconfigured_planner_is_a_named_error(registered: None, tmp_path, capsys) -> None:
    with pytest.raises(ScenarioError, match=r"\[planner.straight\] spacing = -1.0: must be > 0"):
        sc.loads(SCENARIO + "\n[planner.straight]\nspacing = -1.0\n", "plug.toml")
    with pytest.raises(ScenarioError, match=r"\[planner.straight\] unknown key 'step'"):
        sc.loads(SCENARIO + "\n[planner.straight]\nstep = 1.0\n", "plug.toml")
    with pytest.raises(ValueError, match="already registered"):
        register("straight", iterative=False, description="again")(straight)
    REGISTRY.pop("straight")
    try:
        with pytest.raises(ScenarioError, match=r"plug.toml: \[planner\] name = 'straight': choose one of iabc"):
            sc.loads(SCENARIO, "plug.toml")
        path = tmp_path / "plug.toml"
        path.write_text(SCENARIO)
        assert cli.main(["validate", str(path)]) == 2
        assert "name = 'straight'" in capsys.readouterr().err
    finally:
        register("straight", iterative=False, description="again", params=StraightParams)(straight)



def test_a_deterministic_plan_function_is_registered_with_a_flag(registered: None) -> None:
    """``plan(problem, spec)`` and ``plan(problem, settings)`` registered with ``deterministic``: the registry
    calls them under its signature with the spec or the planner's own settings, and neither the generator
    nor the progress callback reaches them; they plan what the full-signature planner plans."""
    text = SCENARIO + "\n[planner.straight]\nspacing = 30.0\n"
    world, mission = sc.build(sc.loads(text))
    problem = planning_problem(world, mission)
    want = plan(problem, mission.planner)
    seen: list[object] = []

    def by_spec(problem: PlanningProblem, spec: PlannerSpec) -> PlanResult:
        seen.append(spec)
        return straight(problem, spec)

    def by_settings(problem: PlanningProblem, settings: StraightParams) -> PlanResult:
        seen.append(settings)
        return straight_line(problem, settings)

    register("by_spec", iterative=False, description="spec form", deterministic="spec")(by_spec)
    register("by_settings", iterative=False, description="settings form", params=StraightParams,
             deterministic="settings")(by_settings)
    try:
        spec = sc.build(sc.loads(text.replace('name = "straight"', 'name = "by_settings"')
                                 + "\n[planner.by_settings]\nspacing = 45.0\n"))[1].planner
        got = [get("by_spec").run(problem, mission.planner, 7, lambda *a: seen.append("progress")),
               plan(problem, spec, 7, lambda *a: seen.append("progress"))]
        with pytest.raises(ValueError, match="does not iterate"):
            register("looping", iterative=True, description="", deterministic="spec")(by_spec)
        with pytest.raises(ValueError, match="choose 'spec' or 'settings'"):
            register("odd", iterative=False, description="", deterministic="rng")(by_spec)  # type: ignore[arg-type]
    finally:
        REGISTRY.pop("by_spec")
        REGISTRY.pop("by_settings")
    assert seen == [mission.planner, StraightParams(45.0)]  # the spec, then its own settings only; no progress
    np.testing.assert_array_equal(got[0].path, want.path)
    assert got[0].cost == want.cost and got[0].status is want.status
    assert len(got[1].path) == math.ceil(LENGTH / 45.0) + 1  # [planner.by_settings] reached it, not straight's


def test_the_built_in_deterministic_planners_are_their_plan_functions() -> None:
    """The lattice and the streamline planner run through the registry plan exactly what their plan functions
    plan (the adapters they used to carry are the registry's one wrapper now)."""
    from auvplan.planners.flow.planner import plan_flow
    from auvplan.planners.grid.planner import plan_grid

    world, mission = sc.build(sc.loads(SCENARIO.replace('name = "straight"', 'name = "grid"')
                                       + "\n[planner.grid]\ncell = 50.0\n"))
    problem = planning_problem(world, mission)
    for name, direct in (("grid", lambda: plan_grid(problem, mission.planner)),
                         ("flow", lambda: plan_flow(problem, mission.planner.flow))):
        assert get(name).deterministic is not None and not get(name).iterative
        via = plan(problem, replace(mission.planner, name=name), 11)
        ref = direct()
        np.testing.assert_array_equal(via.path, ref.path)
        assert (via.status, via.cost, via.planner) == (ref.status, ref.cost, ref.planner)
