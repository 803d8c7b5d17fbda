"""The command line opens at once: building the parser, ``--version``, ``--help`` and ``scenarios``
import none of the library's numerical layers; each command imports what it needs when it runs
(checked on the modules a fresh interpreter has imported, not on a clock)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

HEAVY = ("numpy", "scipy", "numba", "xarray", "pandas", "matplotlib", "pyproj", "shapely", "dask",
         "auvplan.world", "auvplan.planners", "auvplan.sim", "auvplan.io.scenario.loader", "auvplan.cli.info")


def _imported_by(code: str) -> list[str]:
    """The modules of HEAVY a fresh interpreter has imported after running ``code``."""
    probe = (f"import sys\n{code}\nimport json\n"
             f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY!r} or m in {HEAVY!r} "
             "or any(m.startswith(h + '.') for h in " + repr(HEAVY) + "))))")
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return list(json.loads(run.stdout.strip().splitlines()[-1]))


def test_the_parser_version_and_help_import_nothing_heavy() -> None:
    assert _imported_by("from auvplan import cli\ncli._parser()") == []
    assert _imported_by("from auvplan import cli\ncli.main(['--version'])") == []  # argparse exits: caught
    assert _imported_by("from auvplan import cli\ncli.main(['--help'])") == []


def test_scenarios_reads_the_list_without_the_loader_or_the_planners() -> None:
    got = _imported_by("from auvplan import cli\ncli.main(['scenarios'])")
    # the info commands' module, nothing of the loader, world, planners or data readers
    assert [m for m in got if not m.startswith("numpy")] == ["auvplan.cli.info"], got


def test_a_planner_choice_imports_the_registry_only_when_read() -> None:
    got = _imported_by("from auvplan import cli\ncli.main(['plan', '--help'])")
    assert "auvplan.planners.core.registry" in got  # the --planner choices, read for the help
    methods = tuple(f"auvplan.planners.{m}." for m in ("flow", "swarm", "grid", "timeopt"))
    assert not [m for m in got if m.startswith(methods)], got


FRONT = ("xarray", "pandas", "dask", "pint", "jinja2", "scipy.stats", "matplotlib", "plotly")
"""What a plan never needs (issue 56): the data readers' stack, statistics, plotting."""


def _commands_import(*commands: list[str]) -> list[set[str]]:
    """The modules of FRONT one fresh interpreter has imported after each of ``commands`` (run in turn)."""
    probe = ("import contextlib, io, json, sys\nfrom auvplan.cli import main\nout = []\n"
             f"for argv in {list(commands)!r}:\n"
             "    with contextlib.redirect_stdout(io.StringIO()):\n        code = main(argv)\n"
             "    out.append([code, sorted({m.split('.')[0] if m.split('.')[0] != 'scipy' else m for m in sys.modules} "
             f"& set({FRONT!r}))])\nprint(json.dumps(out))")
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    got = json.loads(run.stdout.strip().splitlines()[-1])
    assert [code for code, _ in got] == [0] * len(commands), run.stderr
    return [set(mods) for _, mods in got]


def test_validate_and_plan_import_what_their_files_need() -> None:
    """flow-spheres (bodies in a uniform flow, no file): neither ``validate`` nor ``plan`` imports xarray (and
    with it pandas, dask, pint, jinja2), scipy.stats or a plotting library; then marcus-wake, whose ETOPO1
    cut-out is read through xarray (which brings pandas; not dask or pint: no indexes are built): no
    statistics or plotting still."""
    after = _commands_import(["validate", "flow-spheres"], ["plan", "flow-spheres", "--json"],
                             ["validate", "marcus-wake"])
    assert after[0] == after[1] == set(), after
    assert "xarray" in after[2] and not after[2] & {"scipy.stats", "matplotlib", "plotly"}, after


def test_kernels_wait_for_their_first_use_and_inspect_imports_no_optimiser_or_duck_arrays(tmp_path) -> None:
    """Issue 56, in one fresh interpreter.  Defining the kernels imports no numba, and ``validate`` of a mission
    whose start and goal are well clear of the seabed decides them in numpy and loads none, nor for its survey
    (the area under water and the size checks decided by the numpy seabed's bound); then ``data
    inspect`` of a seabed file: its edge searches are Brent's bounded method without scipy.optimize, its
    window maxima without scipy.ndimage, its conservative models do not interpolate (scipy.interpolate), and
    xarray opens the file without building the indexes that import dask and pint; its first kernel put every
    kernel's dispatcher in place of its stand-in, in the module that defines it and in those that import it
    (the cost pass's copy of the terrain's kernel); a stand-in pickles by name.  numba's registries loaded
    without scipy.linalg (:class:`auvplan.runtime.jit._BlasProbe`), numba's ``ensure_blas`` back in both its
    modules, the hook gone, and numba's BLAS flag what importing SciPy's BLAS says."""
    import netCDF4
    import numpy as np

    from helpers import RIDGE

    survey = ('[survey]\npolygon_xy = [[300.0, 50.0], [800.0, 50.0], [800.0, 350.0], [300.0, 350.0]]\n'
              'sensor = "multibeam"\nopening_deg = 120.0\nmounting = "surface"\noverlap = [0.10, 0.20]\n')
    (tmp_path / "ridge.toml").write_text(RIDGE + survey)
    seabed = str(tmp_path / "seabed.nc")  # 40 x 56 nodes at 0.02 deg: five small models
    with netCDF4.Dataset(seabed, "w") as nc:
        for name, values, units in (("lat", np.linspace(10.0, 10.78, 40), "degrees_north"),
                                    ("lon", np.linspace(150.0, 151.1, 56), "degrees_east")):
            nc.createDimension(name, values.size)
            nc.createVariable(name, "f8", (name,))[:] = values
            nc[name].units = units
        e = nc.createVariable("elevation", "f8", ("lat", "lon"))
        e[:] = -3000.0 + 900.0 * np.sin(np.arange(40)[:, None] * 0.7) * np.cos(np.arange(56)[None, :] * 0.4)
        e.units, e.positive = "m", "up"
    probe = ("import contextlib, io, json, pickle, sys\nfrom auvplan.cli import main\n"
             "import auvplan.cost.paths as cost, auvplan.world.kernels.terrain as kt\n"
             "before = [type(kt.elevation_kernel).__name__, type(cost.elevation_kernel).__name__]\n"
             "same = pickle.loads(pickle.dumps(kt.elevation_kernel)) is kt.elevation_kernel\n"
             "with contextlib.redirect_stdout(io.StringIO()) as out:\n"
             f"    code = main(['validate', {str(tmp_path / 'ridge.toml')!r}])\n"
             "clear = 'numba' not in sys.modules\n"
             "with contextlib.redirect_stdout(io.StringIO()):\n"
             f"    code += main(['data', 'inspect', {seabed!r}])\n"
             "mods = sorted(m for m in sys.modules if m in ('scipy.optimize', 'scipy.ndimage', 'scipy.interpolate', "
             "'dask', 'pint', 'xarray'))\n"
             "after = [type(kt.elevation_kernel).__name__, cost.elevation_kernel is kt.elevation_kernel]\n"
             "import numba.np.arraymath as am, numba.np.linalg as la, auvplan.runtime.jit as jit\n"
             "blas = ['scipy.linalg' in sys.modules, am.ensure_blas is la.ensure_blas, la.ensure_blas.__module__, "
             "any(type(f) is jit._BlasProbe for f in sys.meta_path)]\n"
             "import scipy.linalg.cython_blas\n"  # numba's own question, asked after: BLAS is there
             "blas.append(am._HAVE_BLAS)\n"
             "print(json.dumps([code, 'OK' in out.getvalue(), clear, before, same, mods, after, blas]))")
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    got = json.loads(run.stdout.strip().splitlines()[-1])
    assert got == [0, True, True, ["_Deferred", "_Deferred"], True, ["xarray"], ["CPUDispatcher", True],
                   [False, True, "numba.np.linalg", False, True]], run.stderr


def test_a_plan_without_files_imports_no_pyproj_and_flies_nothing() -> None:
    """Issue 56: ``plan flow-spheres`` (no file) projects nothing, so pyproj is not imported (a ``LocalFrame``
    makes its transformers at their first use), and a plan flies no mission: ``auvplan.sim`` loads its loop
    and pipeline, and with them guidance, only when they are read."""
    probe = ("import contextlib, io, json, sys\nfrom auvplan.cli import main\n"
             "with contextlib.redirect_stdout(io.StringIO()):\n    code = main(['plan', 'flow-spheres', '--json'])\n"
             "print(json.dumps([code, sorted(sys.modules)]))")
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    code, modules = json.loads(run.stdout.strip().splitlines()[-1])
    assert code == 0 and "auvplan.sim.problem" in modules, run.stderr
    late = ("pyproj", "auvplan.sim.loop", "auvplan.sim.pipeline", "auvplan.guidance.mission.waypoints")
    assert not [m for m in modules if m in late or m.startswith("pyproj.")], modules
    import auvplan.sim as sim

    assert sim.run_mission.__module__ == "auvplan.sim.pipeline" and "simulate" in dir(sim)
    assert sim.planning_problem is sys.modules["auvplan.sim.pipeline"].planning_problem


SCIPY_LATE = ("scipy.ndimage", "scipy.optimize", "scipy.interpolate", "scipy.spatial", "scipy.sparse", "scipy.linalg")
"""SciPy's subpackages a time-optimal plan and a zoned scenario's raster no longer import (~0.2-0.45 s)."""


def test_time_optimal_plans_and_zone_rasters_import_no_scipy_subpackage() -> None:
    """Issue 56: ``plan rotary-tide`` (the time-optimal planner: its front's active band, its shot's bounded
    Brent refinement) and ``validate chagos-reefs`` (the zones' raster and its distance transform) run
    ``auvplan.world.kernels.edt`` and ``auvplan.optim.bounded_min`` (SciPy's values, bit for bit:
    tests/oracles/test_edt.py, test_front_door_search.py), not scipy.ndimage or scipy.optimize.  The readers'
    cache is off, so the files are read as on a first run (the test does not depend on the cache's state)."""
    probe = ("import contextlib, io, json, sys\nfrom auvplan.cli import main\nout = []\n"
             "for argv in (['plan', 'rotary-tide', '--json'], ['validate', 'chagos-reefs']):\n"
             "    with contextlib.redirect_stdout(io.StringIO()):\n        code = main(argv)\n"
             "    out.append([code, sorted(m for m in sys.modules if m.startswith('scipy.'))])\n"
             "print(json.dumps(out))")
    env = {**os.environ, "AUVPLAN_CACHE": "0"}
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, env=env)
    got = json.loads(run.stdout.strip().splitlines()[-1])
    assert [code for code, _ in got] == [0, 0], run.stderr
    for _, modules in got:
        assert not [m for m in modules if m.startswith(SCIPY_LATE)], modules
