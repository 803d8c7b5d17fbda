"""The command line opens at once: building the parser, ``--version``, ``--help`` and ``scenarios``
import none of the library's numerical layers; each command imports what it needs when it runs
(checked on the modules a fresh interpreter has imported, not on a clock)."""

from __future__ import annotations

import json
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
    assert "auvplan.planners.registry" in got  # the --planner choices, read for the help
    methods = tuple(f"auvplan.planners.{m}." for m in ("flow", "swarm", "grid", "timeopt"))
    assert not [m for m in got if m.startswith(methods)], got
