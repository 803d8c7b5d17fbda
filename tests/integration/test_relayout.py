"""tools/relayout.py brings code written against the old layout over: old imports (absolute, relative in a
moved file, ``from package import module``, names moved out of their file) and old dotted names and paths
are rewritten to the new layout, and a second run changes nothing."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def rl():
    spec = importlib.util.spec_from_file_location("relayout", ROOT / "tools" / "relayout.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["relayout"] = module
    spec.loader.exec_module(module)
    module._TREE = module.Tree(module.SRC)
    return module


def _rewrite(rl, text: str, path: str = "tests/test_x.py") -> str:
    info = rl.file_info(ROOT / path)
    out = rl.rewrite_text(rl.rewrite_python(text, info, rl._TREE), True)
    assert rl.rewrite_text(rl.rewrite_python(out, info, rl._TREE), True) == out  # idempotent
    return out


CASES = [
    ("from auvplan.planners.flow_stream import integrate_streamlines\n",
     "from auvplan.planners.flow.stream import integrate_streamlines\n"),
    ("from auvplan.io import scenario as sc\n", "from auvplan.io.scenario import loader as sc\n"),
    ("from auvplan.io import export, records\n",
     "from auvplan.io.missions import export\nfrom auvplan.io.results import records\n"),
    ("from auvplan.planners.swarm_problem import check_endpoints, spline_problem\n",
     "from auvplan.planners.core.common import check_endpoints\n"
     "from auvplan.planners.swarm.problem import spline_problem\n"),
    ("from auvplan.planners.flow import FlowField, plan_flow\n",
     "from auvplan.planners.flow.field import FlowField\nfrom auvplan.planners.flow.planner import plan_flow\n"),
    ("from auvplan.planners.timeopt_params import TimeoptParams\n",
     "from auvplan.planners.core.params import TimeoptParams\n"),  # moved twice: straight to its last place
    ("from auvplan.sim_formation import run_formation\n", "from auvplan.sim.formation import run_formation\n"),
    ("import auvplan.planners.lattice as lat\n", "import auvplan.planners.grid.lattice as lat\n"),
    ('FLOW = "auvplan.planners.flow"\n', 'FLOW = "auvplan.planners.flow.field"\n'),
    ('"""See :func:`auvplan.planners.flow.plan_flow` and planners/swarm_problem.py."""\n',
     '"""See :func:`auvplan.planners.flow.planner.plan_flow` and planners/swarm/problem.py."""\n'),
    ("from auvplan.planners.grid.planner import GridReference\n",  # already on the new layout: untouched
     "from auvplan.planners.grid.planner import GridReference\n"),
    # issue 50: a root file moved into a folder, and its new path left alone on a second run
    ('"""See flyable.py, src/auvplan/cli_run.py and path/flyable.py."""\n',
     '"""See path/flyable.py, src/auvplan/cli/run.py and path/flyable.py."""\n'),
    ("from auvplan.guidance.local import key_waypoints\nfrom auvplan.guidance import mission as gm\n",
     "from auvplan.guidance.avoidance.local import key_waypoints\n"
     "from auvplan.guidance.mission import waypoints as gm\n"),
    ("from auvplan.path import BSplinePath\nfrom auvplan import cli\n",  # packages re-exporting their old module
     "from auvplan.path import BSplinePath\nfrom auvplan import cli\n"),
    ("from auvplan.cli_run import run_scenario\n", "from auvplan.app.run import run_scenario\n"),
    # issue 50, second round: a function its moved package re-exports (not the submodule of the same name), a
    # package that kept its name and a folder moved into another, left alone on a second run, a moved name
    ("from auvplan.bench import SweepSpec, sweep\n", "from auvplan.app.bench.sweep import SweepSpec, sweep\n"),
    ("from auvplan.app.bench import bench\n", "from auvplan.app.bench.job import bench\n"),
    ('"""See :mod:`auvplan.bench`, bench/sweep.py and :func:`auvplan.ensemble.score_route`."""\n',
     '"""See :mod:`auvplan.app.bench`, app/bench/sweep.py and :func:`auvplan.sim.ensemble.score.score_route`."""\n'),
    ("from auvplan.planners.grid.planner import path_cost, refine_plan\n",
     "from auvplan.planners.core.common import path_cost\nfrom auvplan.planners.grid.planner import refine_plan\n"),
]


@pytest.mark.parametrize(("old", "new"), CASES)
def test_old_references_are_rewritten_to_the_new_layout(rl, old, new):
    assert _rewrite(rl, old) == new


def test_relative_imports_of_a_moved_file_are_resolved_at_its_old_place(rl):
    # planners/grid.py, merged from a branch on the old layout, now at planners/grid/planner.py
    old = "from .._types import Status\nfrom .swarm_problem import cost_model_for\nfrom .lattice import search\n"
    got = _rewrite(rl, old, "src/auvplan/planners/grid/planner.py")
    assert got == ("from ..._types import Status\nfrom ..core.common import cost_model_for\n"
                   "from .lattice import search\n")


def test_an_old_module_imported_from_its_old_package_is_not_resolved_at_the_files_old_place(rl):
    # io/scenario/build.py (once io/build.py) imports io/limits.py, now io/files/limits.py, by name
    got = _rewrite(rl, "from .. import limits as _limits\n", "src/auvplan/io/scenario/build.py")
    assert got == "from ..files import limits as _limits\n"


def test_every_old_module_has_a_home(rl):
    tree = rl._TREE
    for old, new in rl.module_map().items():
        assert tree.exists(new), f"{old} -> {new}: no such module"
        assert not tree.exists(old) or old in tree.packages, f"{old} still exists as a module"
