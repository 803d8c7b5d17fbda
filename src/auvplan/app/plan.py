"""``plan`` and ``simulate`` as jobs: the global plan of a scenario (with its current members, or against the
lattice reference and the seeded optimisers), and the flight of the same pipeline as ``run``."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..io.files.safeio import RESULT_NAMES, prepare_out
from . import ReporterFor, silent

if TYPE_CHECKING:
    from ..io.scenario.specs import Scenario
    from ..planners import PlannerSpec, PlanResult
    from ..runtime.parallel import Runner
    from ..sim import RunRecord
    from ..world import World

__all__ = ["plan_scenario", "simulate_scenario"]


def plan_scenario(scenario: str, out: str | None = None, force: bool = False, planner: str | None = None,
                  budget: int | None = None, pipeline: str | None = None, seed: int | None = None,
                  reference: bool = False, reporter: ReporterFor = silent, runner: Runner | None = None
                  ) -> tuple[Scenario, PlanResult, int, World, dict[str, Any]]:
    """Load, build and plan a scenario (with its members, or against the reference).

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file.
    out : str, optional
        The results folder, checked before any work.
    force : bool
        Replace the folder's result files.
    planner, budget, pipeline, seed : optional
        Override the scenario's.
    reference : bool
        Also plan the grid reference and report the gap.
    reporter : callable
        Builds the progress reporter.
    runner : Runner, optional
        Where the robust plan's candidates are planned (:class:`auvplan.runtime.parallel.Runner`; this process
        by default).

    Returns
    -------
    tuple
        The scenario, the plan, the seed, the World and the ensemble fields (empty without members).
    """
    from ..io.scenario import loader as scenario_io
    from ..io.scenario.inputs.members import scenario_members
    from ..planners import plan
    from ..sim import planning_problem
    from .ensemble import ensemble_plan

    if out is not None:
        prepare_out(out, RESULT_NAMES, force=force, job="plan", inputs=(scenario,))
    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    spec = _planner_spec(mission.planner, planner, budget, pipeline)
    seed = sc.seed if seed is None else seed
    members = scenario_members(sc, world)  # issue 39: [currents] members, read (and checked) before planning
    bar = reporter(spec, sc.name)
    problem = planning_problem(world, mission)
    ensemble: dict[str, Any] = {}
    try:
        if members:  # the plan flown in every member, or the robust plan
            result, ensemble = ensemble_plan(members, world, replace(mission, planner=spec), seed, runner)
        else:
            result = plan(problem, spec, seed, bar)
    finally:
        bar.close()
    if reference:  # the grid planner's modules only here (issue 56)
        from ..planners import reference as plan_reference
        from ..planners import with_reference

        bar.stage("reference: the converged lattice plan and the seeded iabc, pso, de at twice the budget")
        result = with_reference(result, problem, spec, plan_reference(problem, spec))
    return sc, result, seed, world, ensemble



def _planner_spec(spec: PlannerSpec, planner: str | None, budget: int | None, pipeline: str | None) -> PlannerSpec:
    """The scenario's ``[planner]`` with the command line's planner, budget and pipeline."""
    from ..io.files.limits import check_plan_work

    if planner:
        spec = replace(spec, name=planner)
    if budget is not None:  # bounded as the [planner] keys are (was: 1e12 ran for hours)
        spec = replace(spec, budget=budget)
        check_plan_work("--budget:", spec.population, spec.iterations, budget, spec.samples)
    if pipeline:
        spec = replace(spec, pipeline=pipeline)
    return spec

def simulate_scenario(scenario: str, out: str | None = None, force: bool = False, guidance: str | None = None,
                      avoidance: str | None = None, seed: int | None = None, full: bool = False,
                      reporter: ReporterFor = silent) -> tuple[Scenario, RunRecord, int]:
    """The pipeline of ``run`` (the same plan, mission and seed fly the same track); with ``out`` the flight's
    files (``sim_metrics.json``, ``track.csv``).

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file.
    out : str, optional
        The folder of the flight's files, checked before any work.
    force : bool
        Replace the folder's result files.
    guidance, avoidance, seed : optional
        Override the scenario's.
    full : bool
        Full-rate time series.
    reporter : callable
        Builds the progress reporter.

    Returns
    -------
    tuple
        The scenario, the run (its ``sim`` is None when the plan failed) and the seed.
    """
    from ..io.results import records
    from ..io.scenario import loader as scenario_io
    from ..sim import run_mission

    if out is not None:
        prepare_out(out, RESULT_NAMES, force=force, job="simulate", inputs=(scenario,))
    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    seed = sc.seed if seed is None else seed
    bar = reporter(mission.planner, sc.name)
    try:
        run = run_mission(world, mission, seed, bar, guidance=guidance, avoidance=avoidance, flight=bar.flight)
    finally:
        bar.close()
    from ..io.scenario.inputs.currentspan import run_note

    run_note(sc.source, sc.currents.beyond, world, run)  # issue 51: currents past the file refused (the note: run)
    if out and run.sim is not None:
        result = run.sim
        records.write_sim(Path(out), result, sc.name, seed, result.avoidance, full, world.origin)
    return sc, run, seed
