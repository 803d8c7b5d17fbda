"""Move auvplan to one folder per method (issue 33), then to fewer parts (issue 50), and rewrite every reference to
the old module paths.

Two modes::

    python tools/relayout.py                 # git mv every old file to its new place, then rewrite
    python tools/relayout.py --imports-only  # rewrite only (e.g. after merging a branch on the old layout)

Both are idempotent: a file already at its new place is not moved again, and a reference already on the
new layout is left as it is (a second run changes nothing).  A file moved twice (``planners/flow_params.py`` ->
``planners/params.py`` -> ``planners/core/params.py``) is sent straight to its last place.  The rewrite
covers, in src/, tests/, benchmarks/, tools/, docs/, README.md, Makefile and pyproject.toml:

- Python imports (absolute, relative, ``from package import module [as name]``, ``import a.b [as c]``),
  with each imported name sent to the module that now defines it (:data:`SYMBOLS`, then re-exports
  followed); relative imports of a moved file are resolved against its old place when they do not
  resolve at its new one, and written relative to the new one;
- dotted references anywhere in the text (docstrings, mutation targets, import-linter layers, docs):
  ``auvplan.planners.flow_stream`` and ``auvplan.planners.flow.plan_flow`` style; a bare name that is
  both an old module and a new package (``auvplan.planners.flow``) is rewritten only where it stands
  alone as a Python string (a mutation target), since elsewhere it reads as the package;
- file paths ``planners/flow_stream.py`` (with or without ``src/auvplan/``).

Changed Python files get their imports re-sorted (``ruff check --select I --fix``); pyproject.toml's
import-linter layers get ``sim.formation`` inside ``sim``.  A rewritten docstring line may pass 120
characters: ``ruff check`` names it.
"""

from __future__ import annotations

import argparse
import ast
import re
import subprocess
import sys
import textwrap
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

__all__ = ["MOVES", "KEEP", "SYMBOLS", "module_map", "main"]

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"

# old file (under src/auvplan) -> new file; the move commit git-mvs these
MOVES: dict[str, str] = {
    # the flow method (document 000)
    "planners/flow.py": "planners/flow/field.py",
    "planners/flow_body.py": "planners/flow/body.py",
    "planners/flow_design.py": "planners/flow/design.py",
    "planners/flow_elements.py": "planners/flow/elements.py",
    "planners/flow_stream.py": "planners/flow/stream.py",
    "planners/flow_params.py": "planners/params.py",
    # the swarm method (document 002) and its pipelines
    "planners/swarm.py": "planners/swarm/planner.py",
    "planners/swarm_problem.py": "planners/swarm/problem.py",
    "planners/seeding.py": "planners/swarm/seeding.py",
    "planners/progressive.py": "planners/swarm/progressive.py",
    # the lattice reference
    "planners/grid.py": "planners/grid/planner.py",
    "planners/band.py": "planners/grid/band.py",
    "planners/lattice.py": "planners/grid/lattice.py",
    # the time-optimal method
    "planners/timeplan.py": "planners/timeopt/planner.py",
    "planners/timeopt.py": "planners/timeopt/search.py",
    "planners/timeopt_kernels.py": "planners/timeopt/kernels.py",
    # formation flight belongs to the simulation
    "sim_formation.py": "sim/formation.py",
    # io: scenario files
    "io/scenario.py": "io/scenario/loader.py",
    "io/specs.py": "io/scenario/specs.py",
    "io/tables.py": "io/scenario/tables.py",
    "io/schema.py": "io/scenario/schema.py",
    "io/build.py": "io/scenario/build.py",
    # io: input data
    "io/bathymetry.py": "io/data/bathymetry.py",
    "io/elevation.py": "io/data/elevation.py",
    "io/currents.py": "io/data/ocean/currents.py",
    "io/tides.py": "io/data/ocean/tides.py",
    "io/coast.py": "io/data/vector/coast.py",
    "io/grids.py": "io/data/grids.py",
    "io/ncfile.py": "io/data/ncfile.py",
    "io/geo.py": "io/data/geo.py",
    "io/inspect.py": "io/data/inspect.py",
    # io: results folders
    "io/records.py": "io/results/records.py",
    "io/results.py": "io/results/folder.py",
    # io: mission exports
    "io/export.py": "io/missions/export.py",
    "io/formats.py": "io/missions/formats.py",
    "io/formation_export.py": "io/missions/formation.py",
    # wave 3 modules written on the old layout by the parallel branches, placed at the merge
    "io/seabed_model.py": "io/data/seabed_model.py",
    "io/roms.py": "io/data/ocean/roms.py",
    "io/vectors.py": "io/data/ocean/vectors.py",
    "io/inspect_frames.py": "io/data/inspect_frames.py",
    "io/geoinput.py": "io/scenario/inputs/geoinput.py",
    "io/names.py": "io/scenario/names.py",
    "io/energy.py": "io/missions/energy.py",
    "io/mission_speeds.py": "io/missions/speeds.py",
    "io/survey_io.py": "io/results/survey.py",
    # issue 50: the command line in one folder (parsing and printing) over the jobs it shares with serve
    "cli.py": "cli/parser.py",
    "cli_commands.py": "cli/info.py",  # its bench, mission check and the jobs moved out (SYMBOLS)
    "cli_output.py": "cli/output.py",
    "cli_plan.py": "cli/plan.py",
    "cli_run.py": "cli/run.py",
    "cli_sweep.py": "cli/sweep.py",
    "cli_survey.py": "cli/survey.py",
    "cli_serve.py": "cli/serve.py",
    "cli_results.py": "app/results.py",
    "cli_ensemble.py": "app/ensemble.py",
    # issue 50: the package root down to 8 files: paths and their flyability; the vehicle and its power fit
    "path.py": "path/curves.py",
    "pitch_profile.py": "path/pitch.py",
    "flyable.py": "path/flyable.py",
    "vehicles.py": "vehicles/model.py",
    "power_fit.py": "vehicles/power_fit.py",
    # issue 50: guidance by concern
    "guidance/route.py": "guidance/following/route.py",
    "guidance/los.py": "guidance/following/los.py",
    "guidance/hybrid.py": "guidance/following/hybrid.py",
    "guidance/avoid_params.py": "guidance/avoidance/params.py",
    "guidance/local.py": "guidance/avoidance/local.py",
    "guidance/vo.py": "guidance/avoidance/vo.py",
    "guidance/predictive.py": "guidance/avoidance/predictive.py",
    "guidance/turning.py": "guidance/avoidance/turning.py",
    "guidance/sweep.py": "guidance/avoidance/sweep.py",
    "guidance/oracle.py": "guidance/avoidance/oracle.py",
    "guidance/point_model.py": "guidance/avoidance/point_model.py",
    "guidance/formation.py": "guidance/formation/keeping.py",
    "guidance/formation_route.py": "guidance/formation/route.py",
    "guidance/formation_plan.py": "guidance/formation/plan.py",
    "guidance/formation_steer.py": "guidance/formation/steer.py",
    "sim/formation_error.py": "guidance/formation/error.py",
    "guidance/mission.py": "guidance/mission/waypoints.py",
    "guidance/mission_limits.py": "guidance/mission/limits.py",
    "guidance/fit_limits.py": "guidance/mission/fit.py",
    # issue 50: no folder over 12 flat modules
    "world/terrain_kernels.py": "world/kernels/terrain.py",
    "world/ellipsoid_kernels.py": "world/kernels/ellipsoid.py",
    "io/data/currents.py": "io/data/ocean/currents.py",
    "io/data/tides.py": "io/data/ocean/tides.py",
    "io/data/roms.py": "io/data/ocean/roms.py",
    "io/data/vectors.py": "io/data/ocean/vectors.py",
    "world/currents.py": "world/currents/fields.py",
    "world/tides.py": "world/currents/tides.py",
    "world/ensemble_fields.py": "world/currents/ensemble.py",
    "world/crab.py": "world/currents/crab.py",
    "io/data/vector.py": "io/data/vector/reader.py",
    "io/data/coast.py": "io/data/vector/coast.py",
    "io/data/zones.py": "io/data/vector/zones.py",
    "io/data/survey_area.py": "io/data/vector/areas.py",
    "survey/lines.py": "survey/lines/placement.py",
    "survey/swath.py": "survey/lines/swath.py",
    "survey/envelope.py": "survey/lines/envelope.py",
    "survey/navspacing.py": "survey/lines/navspacing.py",
    "survey/frame.py": "survey/lines/frame.py",
    "survey/corridor.py": "survey/lines/corridor.py",
    "io/scenario/geoinput.py": "io/scenario/inputs/geoinput.py",
    "io/scenario/currentspan.py": "io/scenario/inputs/currentspan.py",
    "io/scenario/members.py": "io/scenario/inputs/members.py",
    "io/scenario/uncertainty.py": "io/scenario/inputs/uncertainty.py",
    # issue 50, fewer parts: what every planner shares in one package, the glider beside the method it runs on
    "planners/base.py": "planners/core/base.py",
    "planners/params.py": "planners/core/params.py",
    "planners/registry.py": "planners/core/registry.py",
    "planners/common.py": "planners/core/common.py",
    "planners/zone_check.py": "planners/core/zone_check.py",
    "planners/vehicle_limits.py": "planners/core/vehicle_limits.py",
    "planners/glider.py": "planners/timeopt/glider.py",
    # io's guards of files in and out in one package
    "io/jsonfile.py": "io/files/jsonfile.py",
    "io/limits.py": "io/files/limits.py",
    "io/outdir.py": "io/files/outdir.py",
    "io/safeio.py": "io/files/safeio.py",
    # reading mission files back (``mission check``) apart from writing them: io/missions under 12 modules
    "io/missions/readers.py": "io/missions/readback/readers.py",
    "io/missions/qgc_items.py": "io/missions/readback/qgc_items.py",
    "io/missions/speeds.py": "io/missions/readback/speeds.py",
    "io/missions/terrain_frame.py": "io/missions/readback/terrain_frame.py",
    "io/missions/fixes.py": "io/missions/readback/fixes.py",
    "io/missions/deploy_read.py": "io/missions/readback/deploy_read.py",
    # the bench sweep is the bench job's; a route flown in every current member is a simulation
    "app/bench.py": "app/bench/job.py",
    "bench/__init__.py": "app/bench/__init__.py",
    "bench/sweep.py": "app/bench/sweep.py",
    "bench/rows.py": "app/bench/rows.py",
    "bench/members.py": "app/bench/members.py",
    "ensemble/__init__.py": "sim/ensemble/__init__.py",
    "ensemble/score.py": "sim/ensemble/score.py",
    "ensemble/robust.py": "sim/ensemble/robust.py",
    "ensemble/replan.py": "sim/ensemble/replan.py",
    # what the planning page asks of the library, as data in, data out, is a job: serve keeps its state and actions
    "serve/check.py": "app/page/check.py",
    "serve/budget.py": "app/page/budget.py",
    "serve/lru.py": "app/page/lru.py",
    "serve/plans.py": "app/page/plans.py",
    "serve/paths.py": "app/page/paths.py",
    "serve/tomlout.py": "app/page/tomlout.py",
}

# module renames done after the move (whole modules merged into another)
LATER_MODULES: dict[str, str] = {
    "auvplan.planners.timeopt_params": "auvplan.planners.params",
}

# old modules that became packages re-exporting the old module's public names (issue 50): ``from auvplan.path
# import BSplinePath``, ``from auvplan import cli`` and ``import auvplan.vehicles`` keep working and are left alone
KEEP: frozenset[str] = frozenset({"auvplan.cli", "auvplan.path", "auvplan.vehicles", "auvplan.app.bench"})

# (old module, name) -> new module, for names moved out of their file after the move; applied only
# once the new module defines the name
# once the new module defines the name (keys: old module names and the new names of their files)
SYMBOLS: dict[tuple[str, str], str] = {
    **{(m, n): "auvplan.planners.common"
       for m in ("auvplan.planners.swarm_problem", "auvplan.planners.swarm.problem",
                 "auvplan.planners.swarm", "auvplan.planners.swarm.planner")
       for n in ("check_endpoints", "cost_model_for", "search_box", "plan_terms")},
    **{(m, n): "auvplan.planners.flow.planner" for m in ("auvplan.planners.flow", "auvplan.planners.flow.field")
       for n in ("plan_flow", "seabed_plane")},
    **{(m, n): "auvplan.planners.flow.stream" for m in ("auvplan.planners.flow", "auvplan.planners.flow.field")
       for n in ("Streamlines", "integrate_streamlines")},
    **{(m, "densify"): "auvplan.path" for m in ("auvplan.planners.grid", "auvplan.planners.band",
                                                "auvplan.planners.grid.planner", "auvplan.planners.grid.band")},
    **{(m, "free_edges"): "auvplan.planners.grid.lattice" for m in ("auvplan.planners.grid",
                                                                    "auvplan.planners.grid.planner")},
    **{(m, n): "auvplan.io.scenario.builtins" for m in ("auvplan.io.scenario", "auvplan.io.scenario.loader")
       for n in ("builtin_scenarios", "resolve")},
    # issue 50: the jobs out of the command line's modules into auvplan.app, the handlers into their group
    **{(m, n): "auvplan.app.run" for m in ("auvplan.cli_run", "auvplan.cli.run", "auvplan.cli_commands",
                                            "auvplan.cli.info") for n in ("run_scenario", "DEMO_SCENARIO")},
    **{(m, "plan_scenario"): "auvplan.app.plan" for m in ("auvplan.cli_plan", "auvplan.cli.plan")},
    **{(m, n): "auvplan.app.sweep" for m in ("auvplan.cli_sweep", "auvplan.cli.sweep")
       for n in ("parse_duration", "is_offset", "parse_instant")},
    **{(m, n): "auvplan.cli.results" for m in ("auvplan.cli_results", "auvplan.app.results")
       for n in ("cmd_report", "cmd_export")},
    ("auvplan.planners.base", "GridParams"): "auvplan.planners.params",
    ("auvplan", "__version__"): "auvplan._version",
    # issue 50: a polyline's path cost is every planner's (the lattice's band, the swarm's polish, the limits)
    **{(m, "path_cost"): "auvplan.planners.core.common" for m in ("auvplan.planners.grid.band",
                                                                  "auvplan.planners.grid.planner")},
}

PACKAGE_DOCS: dict[str, str] = {
    "planners/flow": "The streamline planner of document 000: potential-flow field, bodies, streamlines.",
    "planners/swarm": "The population planners of document 002 (IABC, ABC, GA, PSO, DE) and their pipelines.",
    "planners/grid": "The lattice reference planner: Dijkstra / A* on a 26-connected lattice, band refinement.",
    "planners/timeopt": "The time-optimal planner: earliest-arrival search in a time-varying current.",
    "io/scenario": "Scenario files: the TOML tables, their checks and schema, and the World and Mission they build.",
    "io/data": "Input data: bathymetry, elevation grids, currents, tides, coastlines, and the local frame.",
    "io/results": "Results folders: run records and the files beside them.",
    "io/missions": "Mission exports: GPX, CSV, QGroundControl, MOOS and ROS files, and formation missions.",
    "guidance/following": "Route following: the route and its active leg, LOS and ILOS, document 001's hybrid field.",
    "guidance/avoidance": "Local avoidance of moving obstacles: key waypoints and APF (document 004), predictive "
                          "avoidance and velocity obstacles, the movers' prediction, the avoidability oracle.",
    "guidance/formation": "Formations: slots and shapes along the route, their swept tracks, each vehicle's "
                          "steering to its slot, and the formation error figures.",
    "guidance/mission": "The executable waypoint mission: built from a plan, its convex limits, and the mission "
                        "fitted to the vehicle.",
    "world/kernels": "The compiled kernels of the seabed's heightfield and of the ellipsoids' distances.",
    "world/currents": "Ocean currents: the fields (uniform, Lamb-Oseen vortices, gridded; :mod:`.fields`), tidal "
                      "currents (:mod:`.tides`), fields built from fields for ensembles (:mod:`.ensemble`) and the "
                      "ground speed of a vehicle holding a line in them (:mod:`.crab`).",
    "io/data/ocean": "Ocean data: current files (regular grids, ROMS, vector rotation) and tide tables.",
    "io/scenario/inputs": "What a scenario's inputs become in its World beyond the tables: geographic positions "
                          "(:mod:`.geoinput`), currents needed past a file's time span (:mod:`.currentspan`), the "
                          "members of a forecast ensemble (:mod:`.members`) and the seabed at a confidence "
                          "(:mod:`.uncertainty`).",
    "survey/lines": "Where a survey's lines go: the line frame (:mod:`.frame`), the sensor's swath (:mod:`.swath`), "
                    "depth-adaptive placement with guaranteed overlap (:mod:`.placement`, its envelopes "
                    ":mod:`.envelope`, its spacing under navigation error :mod:`.navspacing`) and corridor lines "
                    "along a centre line (:mod:`.corridor`).",
    "io/data/vector": "Vector feature files: the one reader (:mod:`.reader`), coastlines (:mod:`.coast`), charted "
                      "zones (:mod:`.zones`) and survey areas and centre lines (:mod:`.areas`).",
    "planners/core": "What every planner shares: the interface (:mod:`.base`), the settings of the methods "
                     "(:mod:`.params`), the registry, the plug-in point (:mod:`.registry`), the cost function and "
                     "end-point check (:mod:`.common`), and the zones' and the vehicle's last word on a plan "
                     "(:mod:`.zone_check`, :mod:`.vehicle_limits`).",
    "io/files": "Files in and out, guarded: bounded JSON reading (:mod:`.jsonfile`), a scenario's resource budget "
                "checked before allocation (:mod:`.limits`), the locked ``--out`` folders (:mod:`.outdir`) and "
                "atomic writes that never overwrite a user's file (:mod:`.safeio`).",
    "io/missions/readback": "Mission files read back (``auvplan mission check``): the parsers of every format "
                            "(:mod:`.readers`, a ``.plan``'s items :mod:`.qgc_items`), each leg's speed "
                            "(:mod:`.speeds`), the terrain-following legs (:mod:`.terrain_frame`), the position "
                            "fixes (:mod:`.fixes`) and what makes the file deployable (:mod:`.deploy_read`).",
    "app/page": "The jobs of the planning page (``auvplan serve``), data in, data out: the mission check and the "
                "energy budget of a mission held in memory, re-flying only the legs an edit changed (:mod:`.check`, "
                ":mod:`.budget`, their per-leg cache :mod:`.lru`), the surveys, plans and flights it asks for "
                "(:mod:`.plans`), file access confined to the folders it was started with (:mod:`.paths`) and a "
                "scenario written back as TOML (:mod:`.tomlout`).",
    "app": "The jobs the command line and the planning page both run: plan, run, survey, sweep, ensemble, and the "
           "one writer of a results folder.",
}

TEXT_GLOBS = ("src/**/*.py", "tests/**/*.py", "benchmarks/**/*.py", "tools/**/*.py", "docs/**/*.md",
              "README.md", "Makefile", "pyproject.toml")
SKIP_FILES = {"tools/relayout.py", "tools/identity_dump.py",  # the latter runs on both layouts
              "docs/architecture.md", "tests/integration/test_relayout.py"}  # these name the old paths on purpose


def _mod(rel: str) -> str:
    """``planners/flow.py`` -> ``auvplan.planners.flow``; ``io/__init__.py`` -> ``auvplan.io``."""
    parts = ["auvplan", *rel[:-3].split("/")]
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def module_map() -> dict[str, str]:
    """Old dotted module -> new dotted module."""
    out = {_mod(old): _mod(new) for old, new in MOVES.items()}
    out.update(LATER_MODULES)
    for old, new in out.items():  # a module moved twice (``planners/flow_params.py`` -> ``planners/params.py``
        seen = {old}  # -> ``planners/core/params.py``): straight to its last place
        while new in out and new not in seen and out[new] != new and new not in KEEP:  # a package kept its name
            seen.add(new)
            new = out[new]
        out[old] = new
    return out


MODULES = module_map()


# ---------------------------------------------------------------------------------------- the new tree
class Tree:
    """What exists on disk now: modules, packages, and the top-level names each module binds."""

    def __init__(self, src: Path) -> None:
        self.files: dict[str, Path] = {}
        self.packages: set[str] = set()
        for p in (src / "auvplan").rglob("*.py"):
            rel = p.relative_to(src).with_suffix("")
            parts = list(rel.parts)
            if parts[-1] == "__init__":
                parts.pop()
                self.packages.add(".".join(parts))
            self.files[".".join(parts)] = p
        self._names: dict[str, dict[str, str | None]] = {}

    def exists(self, module: str) -> bool:
        return module in self.files

    def names(self, module: str) -> dict[str, str | None]:
        """Top-level names of a module: None where it defines them, the source module where it imports them."""
        if module not in self._names:
            found: dict[str, str | None] = {}
            self._names[module] = found  # filled below; a module importing itself sees it as it stands
            path = self.files.get(module)
            if path is not None:
                try:
                    tree = ast.parse(path.read_text())
                except SyntaxError:
                    tree = ast.Module(body=[], type_ignores=[])
                info = file_info(path)
                for node in _top_level(tree.body):
                    if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                        found[node.name] = None
                    elif isinstance(node, ast.Assign | ast.AnnAssign):
                        for t in node.targets if isinstance(node, ast.Assign) else [node.target]:
                            for n in ast.walk(t):
                                if isinstance(n, ast.Name):
                                    found[n.id] = None
                    elif isinstance(node, ast.ImportFrom):
                        src = resolve_from(self, info, node)
                        src = new_module(src) or src
                        for a in node.names:
                            found.setdefault(a.asname or a.name, f"{src}:{a.name}")
            self._names[module] = found
        return self._names[module]

    def defines(self, module: str, name: str) -> bool:
        return name in self.names(module) or f"{module}.{name}" in self.files

    def origin(self, module: str, name: str, depth: int = 4) -> str:
        """The module that defines ``name``, following re-exports from ``module``."""
        where = self.names(module).get(name)
        if where is None or depth == 0:
            return module
        src, real = where.split(":")
        if real != name or not self.exists(src) or src in MODULES and MODULES[src] != src:
            return module
        if f"{src}.{name}" in self.files:  # a submodule, not a name
            return module
        return self.origin(src, name, depth - 1) if name in self.names(src) else module


def _top_level(body: list[ast.stmt]) -> Iterable[ast.stmt]:
    for node in body:
        if isinstance(node, ast.If | ast.Try):  # TYPE_CHECKING blocks, optional imports
            yield from _top_level(node.body)
            yield from _top_level(getattr(node, "orelse", []))
            for h in getattr(node, "handlers", []):
                yield from _top_level(h.body)
        else:
            yield node


def _absolute(package: str, level: int, module: str | None) -> str:
    if level == 0:
        return module or ""
    parts = package.split(".")
    base = parts[: len(parts) - (level - 1)] if level > 1 else parts
    return ".".join(base + ([module] if module else []))


def _relative(package: str, target: str) -> tuple[int, str]:
    p, t = package.split("."), target.split(".")
    common = 0
    while common < min(len(p), len(t)) and p[common] == t[common]:
        common += 1
    return len(p) - common + 1, ".".join(t[common:])


# ------------------------------------------------------------------------------------- resolving names
def new_module(old: str) -> str | None:
    """The new name of an old module (None when ``old`` is not an old module, or kept its name)."""
    new = MODULES.get(old)
    return None if new is None or new == old else new


def where_now(tree: Tree, module: str, name: str) -> tuple[str, str]:
    """Where ``from module import name`` must import from now: (module, name)."""
    sub = f"{module}.{name}"
    if sub in KEEP or module in KEEP and tree.defines(module, name):
        return module, name  # a package that re-exports its old module's names
    moved_sub = new_module(sub)
    moved_pkg = new_module(module)
    if moved_sub is not None and moved_pkg is not None and name in tree.names(moved_pkg) \
            and tree.names(moved_pkg)[name] != f"{moved_pkg}:{name}":  # ``from auvplan.bench import sweep``: the
        return tree.origin(moved_pkg, name), name  # function its package re-exports, not its module ``sweep``
    if tree.exists(sub) and moved_sub is None:
        return module, name  # a module of the new tree
    if moved_sub is not None:  # ``from auvplan.io import scenario``: an old module imported by name
        parent, leaf = moved_sub.rsplit(".", 1)
        return parent, leaf
    target = SYMBOLS.get((module, name))
    target = MODULES.get(target, target) if target is not None else None  # a target that moved since
    if target is not None and tree.defines(target, name):
        return target, name
    moved = new_module(module)
    if moved is None:
        return module, name
    return tree.origin(moved, name), name


def _valid(tree: Tree, module: str, names: list[str]) -> bool:
    """Whether ``from module import names`` works on the new tree as written."""
    if new_module(module) is not None and not tree.exists(module):
        return True  # an old module: rewritten below
    if not tree.exists(module):
        return False
    # an old module or a moved name imported from where it was (``from .. import limits`` in io/scenario/build.py):
    # on the new layout as written, rewritten below
    return all(n == "*" or tree.defines(module, n) or new_module(f"{module}.{n}") is not None
               or (module, n) in SYMBOLS for n in names)


# ------------------------------------------------------------------------------------- rewriting Python
@dataclass
class FileInfo:
    rel: str  # path relative to the repository
    module: str | None  # dotted module of the file now (src only)
    old_module: str | None  # its module before the move (a moved file only)
    package: str | None  # the package its relative imports start from


def file_info(path: Path) -> FileInfo:
    rel = path.relative_to(ROOT).as_posix()
    if not rel.startswith("src/auvplan/"):
        return FileInfo(rel, None, None, None)
    inner = rel[len("src/auvplan/"):]
    module = _mod(inner)
    old = next((_mod(o) for o, n in MOVES.items() if n == inner), None)
    package = module if inner.endswith("__init__.py") else module.rsplit(".", 1)[0]
    return FileInfo(rel, module, old, package)


def _render_from(indent: str, level_module: str, names: list[tuple[str, str | None]], width: int = 120,
                 split: bool = False) -> str:
    items = [n if a is None or a == n else f"{n} as {a}" for n, a in names]
    line = f"{indent}from {level_module} import {', '.join(items)}"
    if len(line) <= width and not (split and len(items) > 1):
        return line
    inner = ",\n".join(f"{indent}    {i}" for i in items)
    return f"{indent}from {level_module} import (\n{inner},\n{indent})"


def rewrite_python(text: str, info: FileInfo, tree: Tree) -> str:
    try:
        mod = ast.parse(text)
    except SyntaxError:
        return text
    lines = text.splitlines(keepends=True)
    edits: list[tuple[int, int, str]] = []  # (first line, last line, new text), 0-based inclusive
    for node in ast.walk(mod):
        if isinstance(node, ast.ImportFrom):
            new = _rewrite_from(node, info, tree)
        elif isinstance(node, ast.Import):
            new = _rewrite_import(node)
        else:
            continue
        if new is None:
            continue
        first, last = node.lineno - 1, (node.end_lineno or node.lineno) - 1
        head = lines[first][: node.col_offset]
        tail = lines[last][node.end_col_offset or 0:]
        if head.strip():  # ``x; from a import b`` - leave such lines alone
            continue
        edits.append((first, last, head + new.lstrip() + tail))
    for first, last, new in sorted(edits, reverse=True):
        lines[first: last + 1] = [new if new.endswith("\n") else new + "\n"]
    return "".join(lines)


def resolve_from(tree: Tree, info: FileInfo, node: ast.ImportFrom) -> str:
    """The absolute module a ``from ... import`` names, a relative one resolved at the file's new place
    when it works there, else at its old place."""
    if not node.level:
        return node.module or ""
    if info.package is None:
        return ""
    module = _absolute(info.package, node.level, node.module)
    if not _valid(tree, module, [a.name for a in node.names]) and info.old_module is not None:
        old_pkg = info.old_module if info.rel.endswith("__init__.py") else info.old_module.rsplit(".", 1)[0]
        alt = _absolute(old_pkg, node.level, node.module)
        if tree.exists(alt) or alt in MODULES:  # else the import is on the new layout, a name moved out
            module = alt
    return module


def _rewrite_from(node: ast.ImportFrom, info: FileInfo, tree: Tree) -> str | None:
    if node.level and info.package is None:
        return None
    module = resolve_from(tree, info, node)
    if not (module == "auvplan" or module.startswith("auvplan.")):
        return None
    groups: dict[str, list[tuple[str, str | None]]] = {}
    changed = False
    for a in node.names:
        if a.name == "*":
            target, name = new_module(module) or module, "*"
        else:
            target, name = where_now(tree, module, a.name)
        asname = a.asname if a.asname is not None else (a.name if name != a.name else None)
        groups.setdefault(target, []).append((name, asname))
        changed |= target != module or name != a.name
    if node.level:
        level_now = _absolute(info.package or "", node.level, node.module)
        changed |= level_now != module  # resolved against the old place
    if not changed:
        return None
    indent = " " * node.col_offset
    out = []
    for target, items in groups.items():
        if node.level and info.package is not None:
            level, rest = _relative(info.package, target)
            spec = "." * level + rest
        else:
            spec = target
        out.append(_render_from(indent, spec, items, split=(node.end_lineno or 0) > node.lineno))
    return "\n".join(out)


def _rewrite_import(node: ast.Import) -> str | None:
    out, changed = [], False
    for a in node.names:
        new = _dotted(a.name, standalone=True)
        changed |= new != a.name
        out.append(new if a.asname is None else f"{new} as {a.asname}")
    if not changed:
        return None
    return " " * node.col_offset + "import " + ", ".join(out)


# ---------------------------------------------------------------------------------- rewriting any text
_TREE: Tree | None = None
DOTTED = re.compile(r"(?<![\w.])auvplan(?:\.[A-Za-z_]\w*)+")


def _dotted(ref: str, standalone: bool = False) -> str:
    """New name of a dotted reference (``auvplan.x.y[.attr...]``)."""
    tree = _TREE
    assert tree is not None
    parts = ref.split(".")
    for cut in range(len(parts), 1, -1):  # the longest old-module prefix
        head = ".".join(parts[:cut])
        if head not in MODULES and (head, parts[cut] if cut < len(parts) else "") not in SYMBOLS:
            continue
        rest = parts[cut:]
        if head in KEEP and (not rest or tree.defines(head, rest[0])):
            return ref
        if not rest:
            moved = new_module(head)
            if moved is None or (tree.exists(head) and not standalone):
                return ref  # a package of the new tree, or a name that kept its place
            return moved
        if tree.exists(f"{head}.{rest[0]}") and new_module(f"{head}.{rest[0]}") is None:
            return ref  # already on the new layout
        target, name = where_now(tree, head, rest[0])
        return ".".join([target, name, *rest[1:]])
    return ref


# old file names that name no file of the new tree: rewritten even without their folder (``flow_stream.py``)
BASENAMES = ("flow_body.py", "flow_design.py", "flow_elements.py", "flow_params.py", "flow_stream.py",
             "swarm_problem.py", "timeopt_kernels.py", "timeplan.py", "formation_export.py", "sim_formation.py")


def _paths(text: str) -> str:
    for old, new in MOVES.items():
        if old.rsplit("/", 1)[-1] in BASENAMES:
            text = re.sub(r"(?<![\w./])" + re.escape(old.rsplit("/", 1)[-1]) + r"(?!\w)", new, text)
        # a file of the package root (``flyable.py``) is not one of a folder (``path/flyable.py``, its new place)
        # and a folder moved into another (``bench/sweep.py`` -> ``app/bench/sweep.py``) is not its new place
        before = r"(?<![\w./])" if "/" not in old or new.endswith("/" + old) else r"(?<![\w.])"
        pat = re.compile(before + r"((?:src/)?auvplan/)?" + re.escape(old) + r"(?!\w)")
        text = pat.sub(lambda m, new=new: (m.group(1) or "") + new, text)
    return text


def rewrite_text(text: str, python: bool) -> str:
    def whole_string(m: re.Match[str]) -> str:
        return m.group(1) + _dotted(m.group(2), standalone=True) + m.group(1)

    if python:  # "auvplan.planners.flow" alone in a string: a module reference (mutation targets)
        text = re.sub(r"(['\"])(auvplan(?:\.\w+)+)\1", whole_string, text)
    text = DOTTED.sub(lambda m: _dotted(m.group(0)), text)
    return _paths(text)


# ------------------------------------------------------------------------------------------ the moves
def git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=ROOT, check=True, capture_output=True, text=True).stdout


def move_files() -> list[str]:
    moved = []
    for old, new in MOVES.items():
        src, dst = SRC / "auvplan" / old, SRC / "auvplan" / new
        if not src.exists() or dst.exists():
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        git("mv", str(src), str(dst))
        moved.append(f"{old} -> {new}")
    ignore = ROOT / ".gitignore"
    rule = "!/src/auvplan/io/results/"  # the package, not an output folder (``results/`` is ignored)
    if ignore.exists() and rule not in ignore.read_text().split():
        ignore.write_text(ignore.read_text().replace("results/\n", f"results/\n{rule}\n", 1))
        git("add", str(ignore))
    for folder, doc in PACKAGE_DOCS.items():
        init = SRC / "auvplan" / folder / "__init__.py"
        if init.parent.is_dir() and not init.exists():
            text = textwrap.fill(f'"""{doc}"""', 117, break_long_words=False, break_on_hyphens=False)
            init.write_text(f"{text}\n\n__all__: list[str] = []\n")
            git("add", str(init))
    return moved


def files() -> list[Path]:
    out: set[Path] = set()
    for g in TEXT_GLOBS:
        out.update(p for p in ROOT.glob(g) if p.is_file())
    return sorted(p for p in out if p.relative_to(ROOT).as_posix() not in SKIP_FILES
                  and ".egg-info" not in p.as_posix())


def rewrite_all() -> list[Path]:
    global _TREE, MODULES
    tree = _TREE = Tree(SRC)
    # a later merge applies once its old module is gone
    MODULES = {o: n for o, n in module_map().items() if not (o in LATER_MODULES and tree.exists(o))}
    changed = []
    for path in files():
        text = path.read_text()
        python = path.suffix == ".py"
        new = rewrite_python(text, file_info(path), tree) if python else text
        new = rewrite_text(new, python)
        if new != text:
            path.write_text(new)
            changed.append(path)
    py = [str(p) for p in changed if p.suffix == ".py"]
    if py:
        ruff = Path(sys.executable).with_name("ruff")
        subprocess.run([str(ruff) if ruff.exists() else "ruff", "check", "--quiet", "--select", "I", "--fix", *py],
                       cwd=ROOT, check=False)
    return changed


def fix_contracts() -> bool:
    """pyproject.toml's import-linter layers after the move: ``sim_formation`` is inside ``sim`` now (a layer
    of its own in the sim contract, not one of the package's); idempotent."""
    path = ROOT / "pyproject.toml"
    if not path.exists():
        return False
    text = path.read_text()
    lines = []
    for line in text.splitlines(keepends=True):
        m = re.match(r'(\s*)"([^"]*\bauvplan\.sim\.formation\b[^"]*)",(.*)$', line, re.S)
        if m:  # a layer (or a group "a | b", "a : b") naming it: drop it from the group
            sep = " | " if "|" in m.group(2) else " : "
            items = [i.strip() for i in re.split(r"[|:]", m.group(2)) if i.strip() != "auvplan.sim.formation"]
            if not items:
                continue
            line = f'{m.group(1)}"{sep.join(items)}",{m.group(3)}'
        lines.append(line)
    new = "".join(lines)
    sim = re.search(r'containers = \["auvplan\.sim"\]\nlayers = \[\n', new)
    if sim and not re.search(r'"[^"]*\bformation\b', new[sim.end(): new.find("]", sim.end())]):
        new = (new[: sim.end()] + '    "formation",  # several vehicles: the pipeline\'s route, one loop per vehicle\n'
               + new[sim.end():])
    if new != text:
        path.write_text(new)
        return True
    return False


def main(argv: list[str] | None = None) -> int:
    """Command line (see the module docstring)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--imports-only", action="store_true", help="rewrite references only; move no file")
    args = ap.parse_args(argv)
    if not args.imports_only:
        for line in move_files():
            print("moved", line)
    for path in rewrite_all():
        print("rewrote", path.relative_to(ROOT))
    if fix_contracts():
        print("rewrote pyproject.toml's import-linter layers (sim.formation inside sim)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
