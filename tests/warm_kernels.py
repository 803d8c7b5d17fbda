"""Compile, beside the suite, the kernels its later tests need (numba's on-disk cache, warmed in a process of its own).

On a fresh checkout (CI) every kernel is compiled on its first call: ~130 s of the suite's CPU, all in the one
pytest process.  ``tests/conftest.py`` starts this script as soon as the tests are collected, on the core the
suite leaves idle (like mypy's run, ``static/lint_runs.py``): it makes the calls of real workloads whose
kernels the suite first needs a minute or more after its start, in the order the suite needs them (the default
plan of avoidance-gauntlet: tests/golden/test_avoid_scenes.py's fast movers; the robust plan of
lofoten-two-models: the conftest's ``lofoten_plan``; the charted zones' broad phase and exact tests: ~40 s of
compiling, first called by tests/integration/test_zones_*.py), so that numba's cache holds them by then and the
suite loads them instead of compiling them.  It checks nothing and changes no test: a kernel it has not
compiled yet when the suite needs it is compiled by the suite as before (numba writes its cache files
atomically), and a kernel whose source changed is compiled again (``auvplan.runtime.jit``'s stamp).  With a
warm cache it only loads them and plans (a few seconds).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np


def gauntlet() -> None:
    """avoidance-gauntlet's default plan (the call of tests/golden/test_avoid_scenes.py's ``gauntlet`` fixture)."""
    from auvplan.io.scenario import loader as sc
    from auvplan.planners import plan
    from auvplan.sim import planning_problem

    world, mission = sc.build(sc.load("avoidance-gauntlet"))
    plan(planning_problem(world, mission), mission.planner, rng=mission.seed)


def lofoten() -> None:
    """``auvplan plan lofoten-two-models`` (the robust plan over two current models: tests/conftest.py's
    ``lofoten_plan``), into a temporary folder."""
    import contextlib
    import io
    import tempfile

    from auvplan.cli import main

    with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()):
        main(["-q", "plan", "lofoten-two-models", "--out", f"{tmp}/lofoten", "--json"])


def zones() -> None:
    """chagos-reefs (Natural Earth reef zones on ETOPO1): a small plan, then the zones' queries on its route."""
    from auvplan.io.scenario import loader as sc
    from auvplan.planners import plan
    from auvplan.sim import planning_problem

    world, mission = sc.build(sc.load("chagos-reefs"))
    spec = replace(mission.planner, population=8, iterations=3)
    path = np.asarray(plan(planning_problem(world, mission), spec, rng=0).path, dtype=float)
    seg = np.ascontiguousarray(np.stack([path[:-1], path[1:]], axis=1))
    world.segments_free(seg)
    world.path_free(path)
    z = world.zones
    z.polyline_slack(path[None])
    z.polyline_inside_lengths(path[None])
    z.segments_enter(seg)
    z.inside_lengths(seg)
    z.signed_distance(path)
    z.distances(path)
    z.nearest(path[0], 5000.0)
    z.clearance(path)


def main() -> None:
    """The workloads, each on its own: one that fails (a renamed scenario, a changed call) leaves the others."""
    for work in (gauntlet, lofoten, zones):
        try:
            work()
        except Exception as exc:  # noqa: BLE001 - a warm-up only: the suite's own tests report real failures
            print(f"warm_kernels: {work.__name__}: {type(exc).__name__}: {exc}")


if __name__ == "__main__":
    main()
