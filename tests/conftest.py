"""Shared fixtures: the real built-in worlds (built once per session) and small synthetic scenes."""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path

# OpenBLAS's worker threads spin while they wait: on a loaded 2-core machine each small LAPACK call (scipy's
# Delaunay barycentric transforms under LinearNDInterpolator, small solves) then costs up to seconds of CPU
# instead of microseconds (a 551-node curvilinear current regridded: 1.7 s CPU with the default threads,
# 0.002 s with one).  Set before numpy is imported; subprocesses inherit it.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

# The readers' on-disk cache (auvplan.io.data.cache) is off in the tests, so that a test that changes a reader
# or a file sees its own computation; tests/unit/test_data_cache.py turns it on in a folder of its own.
os.environ.setdefault("AUVPLAN_CACHE", "0")

# The kernels compiled ahead of time (auvplan.runtime.aot: `auvplan kernels build`) are not used in the tests, so
# that a module built in this checkout does not decide which machine code a test runs (it gives the JIT's bits;
# tests/integration/test_aot.py builds its own and checks that); subprocesses inherit it.
os.environ.setdefault("AUVPLAN_AOT", "0")

# The user's cache folder ($XDG_CACHE_HOME, ~/.cache) is the session's own: a job run without --out keeps its
# checkpoints in $XDG_CACHE_HOME/auvplan/tasks (a departure sweep), keyed on its inputs and auvplan's version but not
# on the code, so that checkpoints left there by a killed run of other code (another checkout on the machine)
# would be read back as this run's rows, and two runs of one job at once would share one folder.  Subprocesses
# inherit it; removed when the session ends.
_CACHE_HOME = tempfile.mkdtemp(prefix="auvplan-tests-cache-")
os.environ["XDG_CACHE_HOME"] = _CACHE_HOME

import pytest  # noqa: E402

from auvplan.io.scenario import loader as sc  # noqa: E402


@pytest.fixture(scope="session")
def marcus():
    """(Scenario, World, Mission) of the real marcus-wake scenario."""
    s = sc.load("marcus-wake")
    w, m = sc.build(s)
    return s, w, m


@pytest.fixture(scope="session")
def salish():
    """(Scenario, World, Mission) of the real salish-shelf scenario."""
    s = sc.load("salish-shelf")
    w, m = sc.build(s)
    return s, w, m


@pytest.fixture(scope="session")
def lofoten_plan(tmp_path_factory):
    """``auvplan plan lofoten-two-models --out DIR --json`` (the robust plan over two real current models), run
    once for the tests that read it: (exit code, DIR, the JSON record or None)."""
    import contextlib
    import io
    import json

    from auvplan.cli import main

    out = tmp_path_factory.mktemp("lofoten") / "lofoten"
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["plan", "lofoten-two-models", "--out", str(out), "--json"])
    return code, out, json.loads(printed.getvalue()) if code == 0 else None


@pytest.fixture(scope="session")
def mariana_nav_plan():
    """(World, Mission, route, NavPlan) of the built-in mariana-nav: its route (seed 1) with its fixes planned
    (``auvplan.sim.navigation.navigation_plan``, ~5 s), once for the tests that read it."""
    from auvplan.sim.navigation import navigation_plan
    from auvplan.sim.pipeline import planned_route

    world, mission = sc.build(sc.load("mariana-nav"))
    _, route = planned_route(world, mission, 1)
    return world, mission, route, navigation_plan(world, mission, route)


def pytest_collection_finish(session):
    """mypy's run over src/ (~40 s of CPU on a fresh checkout) starts as soon as the tests are collected when
    its test is among them, and goes on beside the suite (tests/static/lint_runs.py).  So does the kernels'
    warm-up (tests/warm_kernels.py: the charted zones' kernels, ~40 s of compiling on a fresh checkout, into
    numba's cache before the zones' tests need them) when numba compiles and the session is a long one that
    holds those tests."""
    import lint_runs

    if any(item.nodeid.endswith("test_lint.py::test_mypy_clean") for item in session.items):
        lint_runs.start("mypy")
    from auvplan.runtime.jit import jit_enabled

    if jit_enabled() and len(session.items) > 500 and any("/test_zones" in item.nodeid for item in session.items):
        lint_runs.start(sys.executable, str(Path(__file__).with_name("warm_kernels.py")), nice=False)


def pytest_sessionfinish(session):
    import lint_runs

    lint_runs.stop_all()
    shutil.rmtree(_CACHE_HOME, ignore_errors=True)
