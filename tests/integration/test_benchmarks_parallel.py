"""Issue 56: the Monte Carlo benchmarks map their runs through auvplan's Runner (benchmarks/parallel_runs.py),
whose rows come back in task order and equal on 1 and N workers but for the timing fields: ``gap.py``'s plans
(real marcus-wake, a 200-evaluation budget) in this process, on one worker and on two (threads of a
``LocalCluster``; real processes: ``make bench-workers``), the cluster's start told and no dask warning about
a busy port, and no benchmark left on a process pool."""

from __future__ import annotations

import argparse
import contextlib
import re
import socket
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "benchmarks"))
import gap  # noqa: E402
from parallel_runs import add_arguments, measured_apart, run_all  # noqa: E402

from auvplan.runtime.parallel import Runner  # noqa: E402

TASKS = [("marcus-wake", "pso", 1, 200), ("marcus-wake", "de", 0, 200)]


def _args(*argv: str) -> argparse.Namespace:
    ap = argparse.ArgumentParser()
    add_arguments(ap, workers=2)
    return ap.parse_args(argv)


def test_gap_plans_are_the_same_in_process_and_on_one_and_two_workers():
    from dask.distributed import LocalCluster

    seen: list[dict] = []
    here = run_all(_args("--workers", "0"), gap._run, TASKS, seen.append)
    oracle = gap.run(*TASKS[1])  # independent of the Runner: the benchmark's own function, called here
    assert [(r["planner"], r["seed"]) for r in here] == [("pso", 1), ("de", 0)]  # task order
    assert measured_apart(here[1:]) == measured_apart([oracle]) and len(seen) == len(TASKS)
    said: list[str] = []  # the LocalCluster's start is told (a stage line on the command line)
    with socket.socket() as busy, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with contextlib.suppress(OSError):  # dask's default HTTP port taken (by this test or another cluster)
            busy.bind(("127.0.0.1", 8787))
            busy.listen()
        one = Runner(workers=1, processes=False, announce=said.append).map(gap._run, TASKS).results
    assert not [w for w in caught if "already in use" in str(w.message)]  # no dask warning on stderr
    assert measured_apart(one) == measured_apart(here)
    assert said[0] == "starting 1 dask worker (threads: a LocalCluster) …"
    assert said[1].startswith("1 dask worker ready in ") and said[1].endswith(" s; 2 tasks to run")
    assert said[2:] == ["stopping the dask workers …"]
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None,
                      scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as two:
        there = run_all(_args("--scheduler", two.scheduler_address), gap._run, TASKS)
    assert measured_apart(there) == measured_apart(here)
    assert {r["status"] for r in here} == {"EXACT"} and here[1]["cost"] != here[0]["cost"]


def test_no_benchmark_or_module_maps_on_a_process_pool():
    """Every embarrassingly parallel job goes through the Runner (dask): no ProcessPoolExecutor or Pool left."""
    pool = re.compile(r"ProcessPoolExecutor|multiprocessing\.Pool|mp\.Pool")
    hits = [str(p.relative_to(ROOT)) for d in ("benchmarks", "src", "tools") for p in (ROOT / d).rglob("*.py")
            if pool.search(p.read_text(encoding="utf-8"))]
    assert hits == []
