"""The previous release's CODE as a peer of ``benchmarks/hard.py``: its default plan, same problems and seeds.

``iabc/release`` in ``hard.py`` is today's code with the release's settings; this peer is the release
itself (``--release-code``, default f5c6a15), checked out into a temporary ``git worktree`` and run by
the same interpreter in one long-lived child process that imports ``auvplan`` from ``<tree>/src``
(``PYTHONPATH``), as ``benchmarks/regress.py`` does.  ``hard.py`` asks it for one plan at a time,
interleaved seed by seed with today's methods, so both see the same machine load, and a speed-up of a
kernel both share counts for today's code only.

The problem is today's scenario file, handed to the release as a file: a built-in terrain the release
does not ship (``etopo1-mariana``) is named by its file in today's tree instead (``file = ...``).
Each scenario's first plan in the child is a warm-up (numba compiles into the worktree's cache), not
timed, and so is the first reference; each reply's CPU is ``time.process_time()`` around the release's
``plan`` alone.  The same worker, on another commit (``hard.py --reference-peer``), times that commit's
``--reference`` on the same problem.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path
from types import TracebackType

from auvplan.io.data.bathymetry import builtin_terrain_path
from auvplan.io.scenario.builtins import resolve

__all__ = ["RELEASE_COMMIT", "ReleasePeer", "portable_scenario"]

ROOT = Path(__file__).resolve().parents[1]
RELEASE_COMMIT = "f5c6a15"
"""The previous release (wave 3's end): no polish, a 20 000-node seeding lattice."""

WORKER = r'''
import json, sys, time
from dataclasses import replace
from auvplan.io.scenario import loader as sc
from auvplan.planners import plan, reference
from auvplan.sim import planning_problem

problems = {}
for line in sys.stdin:
    ask = json.loads(line)
    key = (ask["scenario"], ask["budget"])
    if key not in problems:
        world, mission = sc.build(sc.load(ask["scenario"]))
        prob = planning_problem(world, mission)
        spec = replace(mission.planner, budget=ask["budget"])
        plan(prob, spec, rng=0)  # warm-up: compile / load the numba cache
        problems[key] = (prob, spec)
    prob, spec = problems[key]
    if ask["seed"] < 0 and not problems.get("reference warm"):
        reference(prob, spec)  # warm-up: the lattice's and the band's kernels
        problems["reference warm"] = True
    c0 = time.process_time()
    r = reference(prob, spec) if ask["seed"] < 0 else plan(prob, spec, rng=ask["seed"])
    cpu = time.process_time() - c0
    print(json.dumps({"status": r.status.value, "cost": float(r.cost), "evaluations": int(r.evaluations),
                      "cpu_s": cpu}), flush=True)
'''


def portable_scenario(name: str, folder: Path) -> Path:
    """Today's scenario file with its built-in terrain named by file, written into ``folder``.

    Parameters
    ----------
    name : str
        A built-in scenario of today's tree.
    folder : pathlib.Path
        Where to write the copy.

    Returns
    -------
    pathlib.Path
        The copy (``<folder>/<name>.toml``).
    """
    text = resolve(name).read_text()

    def by_file(m: re.Match[str]) -> str:
        return f'file = "{builtin_terrain_path(m.group(1))}"'

    out = folder / f"{name}.toml"
    out.write_text(re.sub(r'^builtin\s*=\s*"([^"]+)"', by_file, text, flags=re.M))
    return out


class ReleasePeer:
    """A child process planning with the release's code (a context manager: the worktree is removed on exit).

    Parameters
    ----------
    commit : str
        The release's commit.
    """

    def __init__(self, commit: str = RELEASE_COMMIT) -> None:
        self.commit = commit
        self._tmp = tempfile.TemporaryDirectory(prefix="auvplan-release-")
        self.tree = Path(self._tmp.name) / "release"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(self.tree), commit],
                       check=True)
        env = {**os.environ, "PYTHONPATH": str(self.tree / "src")}
        self._child = subprocess.Popen([sys.executable, "-c", WORKER], env=env, cwd=self._tmp.name, text=True,
                                       stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        self._files: dict[str, Path] = {}

    def plan(self, scenario: str, seed: int, budget: int) -> dict[str, object]:
        """One plan of the release: status, cost, evaluations and CPU (s) of its ``plan`` call
        (``seed < 0``: its ``reference`` instead)."""
        if scenario not in self._files:
            self._files[scenario] = portable_scenario(scenario, Path(self._tmp.name))
        assert self._child.stdin is not None and self._child.stdout is not None
        self._child.stdin.write(json.dumps({"scenario": str(self._files[scenario]), "seed": seed,
                                            "budget": budget}) + "\n")
        self._child.stdin.flush()
        line = self._child.stdout.readline()
        if not line:
            raise RuntimeError(f"the release's worker ({self.commit}) ended without an answer")
        row: dict[str, object] = json.loads(line)
        return row

    def close(self) -> None:
        """Stop the child and remove the worktree."""
        if self._child.stdin is not None:
            self._child.stdin.close()
        self._child.wait(timeout=60)
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(self.tree)], check=False)
        self._tmp.cleanup()

    def __enter__(self) -> ReleasePeer:
        return self

    def __exit__(self, kind: type[BaseException] | None, value: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()
