"""Plan and fly every built-in scenario and dump every array and number of the records to one ``.npz``.

Used to show that a refactoring (issue 33's move to one folder per method) leaves every result
bit-identical: run it before and after, then compare the two files::

    python tools/identity_dump.py --out before.npz
    ... refactor ...
    python tools/identity_dump.py --out after.npz
    python tools/identity_dump.py --compare before.npz after.npz

Budgets are cut so the whole sweep runs in minutes (the swarm budget to ``--budget`` evaluations,
the flight to ``--max-time`` simulated seconds); the same cuts are applied on both sides, so the
comparison is exact.  Besides each built-in with its own planner, every registered planner is run on
a small problem of its kind, so each method package is exercised.  Clock fields are left out by name
(:data:`SKIP`: wall and CPU times such as ``wall_time_s``, ``seeding_cpu_s``, ``polish_cpu_s``,
``search_cpu_s``, timeopt's ``build_s``): they differ from run to run, so two dumps of the same commit
compare equal and any difference left is a result's.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["SKIP", "collect", "compare", "is_clock", "main"]

SKIP = ("wall_time", "decision_time", "cpu", "build_s")
"""Parts of a field's name (its last key) that mark a wall-clock or CPU time: left out of the dump."""


def is_clock(key: str) -> bool:
    """Whether ``key``'s last part names a wall or CPU time (:data:`SKIP`), which differs run to run."""
    return any(s in key.rsplit("/", 1)[-1].lower() for s in SKIP)

# extra (scenario, planner) pairs, so every method package runs at least once
EXTRA = (
    ("marcus-wake", "abc"), ("marcus-wake", "ga"), ("marcus-wake", "pso"), ("marcus-wake", "de"),
    ("marcus-wake", "grid"), ("dynamic-terrain", "iabc"), ("flow-ellipsoid", "flow"),
    ("juan-de-fuca-tides", "timeopt"),
)


def _flatten(value: Any, key: str, out: dict[str, np.ndarray]) -> None:
    if is_clock(key):
        return
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            _flatten(getattr(value, f.name), f"{key}/{f.name}", out)
    elif isinstance(value, dict):
        for k in sorted(value):
            _flatten(value[k], f"{key}/{k}", out)
    elif isinstance(value, list | tuple):
        if all(isinstance(v, str) for v in value):
            out[key] = np.asarray(["|".join(value)])
        else:
            for i, v in enumerate(value):
                _flatten(v, f"{key}/{i}", out)
    elif isinstance(value, np.ndarray):
        out[key] = value
    elif isinstance(value, bool | int | float | np.number):
        out[key] = np.asarray(value)
    elif value is None:
        out[key] = np.asarray("None")
    elif isinstance(value, str) or not hasattr(value, "__dict__"):  # Status and other enums, strings
        out[key] = np.asarray(str(value))
    else:  # a plain object (FormationRoute): its attributes
        for k in sorted(vars(value)):
            if not callable(getattr(value, k)):
                _flatten(getattr(value, k), f"{key}/{k}", out)


def _shorten(mission: Any, budget: int, max_time: float) -> Any:
    planner = mission.planner
    if planner.name in ("iabc", "abc", "ga", "pso", "de"):
        cap = budget if planner.budget == 0 else min(planner.budget, budget)
        planner = dataclasses.replace(planner, budget=cap, population=min(planner.population, 20))
    sim = mission.sim
    sim = dataclasses.replace(sim, max_time=max_time if sim.max_time == 0 else min(sim.max_time, max_time))
    return dataclasses.replace(mission, planner=planner, sim=sim)


def _run_one(name: str, planner: str | None, budget: int, max_time: float) -> dict[str, np.ndarray]:
    import auvplan
    from auvplan.planners import plan

    world, mission = auvplan.load_scenario(name)
    out: dict[str, np.ndarray] = {}
    if planner is not None:  # the planner alone on the scenario's problem
        spec = dataclasses.replace(mission.planner, name=planner)
        mission = _shorten(dataclasses.replace(mission, planner=spec, route=()), budget, max_time)
        result = plan(auvplan.planning_problem(world, mission), mission.planner, rng=mission.seed)
        _flatten(result, f"{name}+{planner}/plan", out)
        return out
    mission = _shorten(mission, budget, max_time)
    if mission.formation is not None:
        try:
            from auvplan.sim.formation import run_formation  # type: ignore[import-not-found, unused-ignore]
        except ImportError:
            from auvplan.sim_formation import run_formation  # type: ignore[import-not-found, no-redef, unused-ignore]
        _flatten(run_formation(world, mission), f"{name}/formation", out)
    else:
        _flatten(auvplan.run_mission(world, mission), f"{name}/run", out)
    return out


def collect(budget: int = 2000, max_time: float = 600.0, only: str | None = None) -> dict[str, np.ndarray]:
    """Plan and fly every built-in scenario (and the extra planner runs); every array and number, flat.

    Parameters
    ----------
    budget : int
        Cap of the swarm planners' evaluations.
    max_time : float
        Cap of each flight's simulated time (s).
    only : str, optional
        Run only the scenarios whose name contains this text.

    Returns
    -------
    dict
        ``"scenario/run/plan/path"``-style keys to arrays.
    """
    names = sorted(_builtin_names())
    jobs: list[tuple[str, str | None]] = [(n, None) for n in names] + list(EXTRA)
    out: dict[str, np.ndarray] = {}
    for name, planner in jobs:
        if only and only not in name:
            continue
        t0 = time.perf_counter()
        got = _run_one(name, planner, budget, max_time)
        out.update(got)
        print(f"{name:24s} {planner or '':8s} {len(got):4d} arrays {time.perf_counter() - t0:6.1f} s", flush=True)
    return out


def _builtin_names() -> list[str]:
    import subprocess

    exe = Path(sys.executable).with_name("auvplan")
    text = subprocess.run([str(exe), "scenarios"], capture_output=True, text=True, check=True).stdout
    return [line.split()[0] for line in text.splitlines() if line.strip()]


def compare(a: Path, b: Path) -> int:
    """Compare two dumps exactly (NaN equal to NaN); print the differences.

    Parameters
    ----------
    a, b : Path
        The two ``.npz`` files.

    Returns
    -------
    int
        0 when every array is identical, 1 otherwise.
    """
    da, db = np.load(a, allow_pickle=False), np.load(b, allow_pickle=False)
    keys_a, keys_b = set(da.files), set(db.files)
    bad = 0
    for k in sorted(keys_a ^ keys_b):
        print(f"only in {'first' if k in keys_a else 'second'}: {k}")
        bad += 1
    values = 0
    for k in sorted(keys_a & keys_b):
        x, y = da[k], db[k]
        same = x.shape == y.shape and x.dtype == y.dtype and (
            np.array_equal(x, y, equal_nan=x.dtype.kind in "fc") if x.dtype.kind in "fcbiu" else np.array_equal(x, y))
        if not same:
            print(f"differs: {k} {x.dtype}{x.shape} vs {y.dtype}{y.shape}")
            bad += 1
        values += x.size
    scenarios = {k.split("/", 1)[0] for k in keys_a & keys_b}
    print(f"{len(keys_a & keys_b)} arrays ({values} values) from {len(scenarios)} runs compared; {bad} differ")
    return 1 if bad else 0


def main(argv: list[str] | None = None) -> int:
    """Command line: ``--out FILE`` to dump, ``--compare A B`` to compare."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path)
    ap.add_argument("--compare", nargs=2, type=Path)
    ap.add_argument("--budget", type=int, default=2000)
    ap.add_argument("--max-time", type=float, default=600.0)
    ap.add_argument("--only")
    args = ap.parse_args(argv)
    if args.compare:
        return compare(*args.compare)
    if args.out is None:
        ap.error("--out or --compare is required")
    if args.out.exists():
        ap.error(f"{args.out} exists; not overwritten")
    data = collect(args.budget, args.max_time, args.only)
    np.savez_compressed(args.out, **data)  # type: ignore[arg-type]
    print(f"{len(data)} arrays written to {args.out}")
    from auvplan.runtime import aot  # which machine code ran: the kernels compiled ahead of time, or numba's JIT

    print(f"numba imported: {'numba' in sys.modules}; kernels compiled ahead of time: "
          f"{'off' if not aot.enabled() else 'first miss ' + aot.MISSES[0] if aot.MISSES else 'every call bound'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
