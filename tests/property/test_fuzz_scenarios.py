"""Property test (issue #20): a hostile scenario document gives either a valid World or a
ScenarioError/DataError naming the file and a key — never another exception, never unbounded
memory or time.  500 generated documents (mutated built-ins) run here within the suite's budget;
``make fuzz`` runs 20 000 (and plans and flies 600 generated documents where the suite does 30).

And ``validate`` never passes what ``plan``/``run`` then reject: on the built-ins and on generated
documents that validate, planning (small budget) and flying (short time limit) raise nothing.
"""

from __future__ import annotations

import functools
import os
import time
import tracemalloc
from dataclasses import replace
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings

from auvplan.errors import DataError, ScenarioError
from auvplan.io.scenario import build as build_io
from auvplan.io.scenario import loader as scenario_io
from auvplan.io.scenario.validate import _TOP_KEYS
from auvplan.planners import plan
from auvplan.sim import pipeline, planning_problem, run_mission
from auvplan.world import World
from scenario_mutations import BUILTINS, documents

SOURCE = "generated.toml"
BASE = Path(str(resources.files("auvplan") / "data" / "scenarios"))
EXAMPLES = int(os.environ.get("AUVPLAN_FUZZ_EXAMPLES", "500"))
MAX_SECONDS_PER_DOCUMENT = 60.0  # a bound, not a speed target: a resource bomb runs for minutes
MAX_RSS_GIB = 2.0  # the default [limits] memory_mb


@pytest.fixture(scope="module", autouse=True)
def cached_terrain():
    """The built-ins' terrains are read and resampled once (same arguments → same Terrain)."""
    original = build_io.load_terrain
    cached = functools.lru_cache(maxsize=64)(
        lambda spec, frame_key, base_dir, extent: original(spec, frame_key and _frame(frame_key),
                                                             base_dir=base_dir, extent_m=extent))

    def load_terrain(spec, frame, *, base_dir=None, extent_m=None):
        key = (frame.lat0, frame.lon0) if frame is not None else None
        return cached(spec, key, base_dir, tuple(extent_m) if extent_m is not None else None)

    build_io.load_terrain = load_terrain
    yield
    build_io.load_terrain = original


def _frame(key):
    from auvplan.io.data.geo import LocalFrame

    return LocalFrame(*key)


def _names(path) -> set[str]:
    return {str(k) for k in path if isinstance(k, str)}


def check_document(doc, touched) -> World | None:
    """Build ``doc``; the World, or None after an error that names the file and a key."""
    try:
        world, _ = scenario_io.build(scenario_io.from_dict(doc, SOURCE, BASE))
    except (ScenarioError, DataError) as exc:
        msg = str(exc)
        assert msg.startswith(SOURCE), msg
        keys = set().union(*(_names(p) for p in touched)) | set(_TOP_KEYS) | {"bounds", "terrain"}
        assert any(k in msg for k in keys), msg
        assert "\n" not in msg, msg
        return None
    assert isinstance(world, World)
    return world


@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(documents())
def test_mutated_documents_give_a_world_or_a_named_error(case):
    _, doc, touched = case
    t0 = time.perf_counter()
    tracemalloc.start()  # this document's own allocations (numpy's included), not the process's past
    try:
        event("valid World" if check_document(doc, touched) is not None else "named error")
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    assert time.perf_counter() - t0 < MAX_SECONDS_PER_DOCUMENT
    assert peak < MAX_RSS_GIB * 2**30


def _plan_and_fly(doc) -> None:
    """What ``plan`` and ``run`` do after ``validate``'s checks, on a small budget and a short flight.  A mission
    that plans is planned once: ``run_mission`` makes the very call ``plan`` makes (same problem, spec and seed),
    whose result is checked as it comes out; a fixed route is flown unplanned, so ``plan`` is called for it."""
    sc = scenario_io.from_dict(doc, SOURCE, BASE)
    world, mission = scenario_io.build(sc)
    spec = replace(mission.planner, budget=min(mission.planner.budget or 10**9, 300), iterations=3)
    mission = replace(mission, planner=spec, sim=replace(mission.sim, max_time=20.0))
    if mission.route:
        result = plan(planning_problem(world, mission), spec, mission.seed)
        assert np.isfinite(result.path).all()
        run_mission(world, mission, mission.seed)
        return
    plans, original = [], pipeline.global_plan

    def planned(problem, pspec, seed, progress=None):  # the pipeline's plan(planning_problem(...), spec, seed)
        result = original(problem, pspec, seed, progress)
        plans.append((problem, pspec, seed, result))
        return result

    pipeline.global_plan = planned
    try:
        run_mission(world, mission, mission.seed)
    finally:
        pipeline.global_plan = original
    problem, pspec, seed, result = plans[0]  # the first: the global plan, before any contract round
    assert pspec == spec and seed == mission.seed and np.array_equal(problem.start, mission.start)
    assert np.isfinite(result.path).all()


@pytest.mark.parametrize("name", sorted(BUILTINS))
def test_validate_passes_only_what_plan_and_run_accept_builtins(name):
    _plan_and_fly(BUILTINS[name])


@settings(max_examples=int(os.environ.get("AUVPLAN_FUZZ_PLAN_EXAMPLES", "30")), deadline=None, derandomize=True,
          database=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                                HealthCheck.filter_too_much])
@given(documents(max_mutations=2, numeric=True))
def test_validate_passes_only_what_plan_and_run_accept_generated(case):
    _, doc, touched = case
    if check_document(doc, touched) is None:
        event("validate rejects it")
        return  # validate rejects it (exit 2): nothing more to hold
    event("validate accepts it: planned and flown")
    _plan_and_fly(doc)  # validate accepted it: plan and run must not raise
