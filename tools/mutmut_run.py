"""Mutation testing (mutmut 2) of the safety-relevant functions, module by module.

Usage: ``.venv/bin/python tools/mutmut_run.py [MODULE ...]`` (default: every module below), then
``.venv/bin/mutmut results`` / ``mutmut show ID``.  ``make mutants`` runs it.

mutmut mutates every line of a file by default: thousands of mutants, each running numba's
compiler again (a mutated kernel module changes the kernels' cache stamp).  Here each module is
restricted to the functions that decide safety (a patch file that marks only their lines as
changed, mutmut's ``--use-patch-file``) and each mutant runs only the tests that exercise that
module (``-x``: the first failure kills it).  docs/mutants.md records the last run.
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "auvplan"

# module: (file, functions to mutate ("Class.method" or "function"), the pytest selection that guards
# them: the module's fast oracle and unit tests, not the whole suite, so the kill rate is a lower bound)
MODULES: dict[str, tuple[str, tuple[str, ...], str]] = {
    "terrain": ("world/terrain.py", ("Terrain.altitude_lower_bound", "min_altitude_kernel"),
                "tests/test_oracles.py tests/test_terrain.py -k 'ridge or slope or lower_bound or outside'"),
    "grid": ("planners/grid.py", ("GridReference._lattice_edges",),
             "tests/test_oracles.py tests/test_grid.py -k 'edge or cost_to_go or empty'"),
    "world": ("world/world.py", ("World.segments_free",),
              "tests/test_world.py tests/test_oracles.py::test_every_edge_of_the_cost_to_go_tree_is_free"),
    "cost": ("cost.py", ("energy_kernel",), "tests/test_oracles.py tests/test_cost.py -k 'energy or compiled'"),
    "local": ("guidance/local.py", ("apf_force",), "tests/test_oracles.py tests/test_local.py -k 'apf_force'"),
    "flow": ("planners/flow.py", ("FlowField._sphere_parts",),
             "tests/test_oracles.py tests/test_flow.py -k 'sphere_field or exact_field'"),
    "route": ("guidance/route.py", ("RouteTracker.update",),
              "tests/test_oracles.py tests/test_tracking.py -k 'switch_radius or closed_form or converges'"),
    "sim": ("sim.py", ("simulate",),
            "tests/test_oracles.py tests/test_tracking.py -k 'seabed or collision or deadlock'"),
}


def _line_ranges(path: Path, names: tuple[str, ...]) -> list[tuple[int, int]]:
    """First and last line of the body of each named function (decorators and docstring excluded)."""
    tree = ast.parse(path.read_text())
    found: dict[str, tuple[int, int]] = {}

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef):
                body = child.body[1:] if ast.get_docstring(child) else child.body
                if body:
                    found[prefix + child.name] = (body[0].lineno, child.end_lineno or body[-1].lineno)
            elif isinstance(child, ast.ClassDef):
                visit(child, prefix + child.name + ".")

    visit(tree, "")
    missing = [n for n in names if n not in found]
    if missing:
        raise SystemExit(f"{path}: no function {missing}")
    return [found[n] for n in names]


def _patch(rel: str, ranges: list[tuple[int, int]]) -> str:
    """A unified diff that marks exactly ``ranges`` of ``rel`` as added lines."""
    lines = (SRC / rel).read_text().splitlines()
    out = [f"--- a/src/auvplan/{rel}", f"+++ b/src/auvplan/{rel}"]
    for a, b in ranges:
        out.append(f"@@ -{a - 1},0 +{a},{b - a + 1} @@")
        out += ["+" + ln for ln in lines[a - 1:b]]
    return "\n".join(out) + "\n"


def run(module: str) -> int:
    rel, names, tests = MODULES[module]
    patch = _patch(rel, _line_ranges(SRC / rel, names))
    with tempfile.NamedTemporaryFile("w", suffix=".patch", delete=False) as fh:
        fh.write(patch)
    runner = f"{sys.executable} -m pytest -x -q -p no:cacheprovider {tests}"
    cmd = [str(Path(sys.executable).with_name("mutmut")), "run", "--paths-to-mutate", f"src/auvplan/{rel}",
           "--use-patch-file", fh.name, "--runner", runner, "--no-progress"]
    print(f"== {module}: {', '.join(names)}", flush=True)
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run(cmd, cwd=ROOT, env=env).returncode


def main() -> int:
    modules = sys.argv[1:] or list(MODULES)
    codes = [run(m) for m in modules]
    return 0 if all(c in (0, 2) for c in codes) else 1


if __name__ == "__main__":
    sys.exit(main())
