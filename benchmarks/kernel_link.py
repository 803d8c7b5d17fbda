"""What binding every kernel's calls inside its own machine code costs (``auvplan.runtime.linking``): CPU of a
first run (numba compiles every kernel it needs) and of a later run (it loads them from its disk cache),
against a previous commit, A/B interleaved.

    nice -n 5 .venv/bin/python benchmarks/kernel_link.py --prev 45c929ae --rounds 3
    make bench-kernel-link                 # the same

The previous commit (``--prev``) is checked out into a temporary ``git worktree`` (removed afterwards); both
trees run under this interpreter and its packages (``PYTHONPATH=<tree>/src``, ``python -m auvplan``) and are
byte-compiled first (``front_door.byte_compile``).  For each scenario (``--scenarios``, default salish-shelf,
whose seabed model runs ``cell_extremes`` and its callee ``_segment``, and marcus-wake) and each round, each
tree gets a new empty ``NUMBA_CACHE_DIR``: ``plan NAME --json`` once there (*first run*: every kernel the plan
needs is compiled and written), then once more (*later run*: loaded).  The readers' cache is off
(``AUVPLAN_CACHE=0``), so that both runs read the same files.  Each figure is the CPU (user + system,
``os.wait4``) of one process; the table gives each tree's median over the rounds and the ratio.  Targets:
current ≤ 1.10 × previous for both (the change adds a pass over a module's function list at each compile and
nothing at load; the margin is the noise of a loaded two-core machine).  Exit status 1 when one is missed.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from front_door import byte_compile, cpu_of  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
TARGET = 1.10
"""Current over previous, median CPU, at most."""


def first_and_later(tree: Path, name: str) -> tuple[float, float]:
    """CPU of ``plan NAME --json`` in a new empty numba cache, then again in the same cache."""
    with tempfile.TemporaryDirectory(prefix="kernel-link-") as cache:
        saved = {k: os.environ.get(k) for k in ("NUMBA_CACHE_DIR", "AUVPLAN_CACHE")}
        os.environ.update(NUMBA_CACHE_DIR=cache, AUVPLAN_CACHE="0")
        try:
            first, rc1 = cpu_of(tree, ["plan", name, "--json"])
            later, rc2 = cpu_of(tree, ["plan", name, "--json"])
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
    if rc1 or rc2:
        raise SystemExit(f"plan {name} failed in {tree} (exit {rc1}, {rc2})")
    return first, later


def measure(prev: Path, cur: Path, names: list[str], rounds: int) -> dict[tuple[str, str, str], list[float]]:
    """``{(scenario, tree, 'first'|'later'): [CPU per round]}``, previous / current in one round and current /
    previous in the next."""
    out: dict[tuple[str, str, str], list[float]] = {}
    for r in range(rounds):
        for name in names:
            for label, tree in (("previous", prev), ("current", cur))[::1 if r % 2 == 0 else -1]:
                first, later = first_and_later(tree, name)
                out.setdefault((name, label, "first"), []).append(first)
                out.setdefault((name, label, "later"), []).append(later)
                print(f"round {r + 1} {name:16s} {label:8s} first {first:6.2f} s  later {later:5.2f} s", flush=True)
    return out


def table(got: dict[tuple[str, str, str], list[float]], names: list[str], prev_rev: str, rounds: int) -> bool:
    """Print the medians and ratios; True when every target is met."""
    ok = True
    print(f"\nmedian CPU (s) of {rounds} rounds, previous = {prev_rev}")
    print("| scenario | run | previous | current | ratio | target |\n|---|---|---|---|---|---|")
    for name in names:
        for run in ("first", "later"):
            p, c = (statistics.median(got[(name, t, run)]) for t in ("previous", "current"))
            met = c <= TARGET * p
            ok &= met
            print(f"| {name} | {run} | {p:.2f} | {c:.2f} | {c / p:.2f} | {'met' if met else 'MISSED'} |")
    return ok


def main(argv: list[str] | None = None) -> int:
    """Command line: ``--prev REV --rounds N --scenarios NAME ...``."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--prev", required=True, help="the commit to compare with")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--scenarios", nargs="+", default=["salish-shelf", "marcus-wake"])
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="kernel-link-prev-") as tmp:
        wt = Path(tmp) / "prev"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(wt), args.prev], check=True)
        try:
            byte_compile(wt)
            byte_compile(ROOT)
            print(f"load average at start {os.getloadavg()[0]:.1f}", flush=True)
            got = measure(wt, ROOT, args.scenarios, args.rounds)
            print(f"load average at end {os.getloadavg()[0]:.1f}")
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(wt)], check=False)
    return 0 if table(got, args.scenarios, args.prev, args.rounds) else 1


if __name__ == "__main__":
    raise SystemExit(main())
