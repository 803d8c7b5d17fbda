"""Where a Monte Carlo benchmark's independent runs go (issue 56): ``--workers N`` / ``--scheduler ADDR`` /
``--retries N`` onto :class:`auvplan.runtime.parallel.Runner`, the mapper of ``auvplan bench`` and of the sweeps
(docs/parallel.md).

``benchmarks/avoidance.py``, ``montecarlo.py``, ``gap.py`` and ``formation.py`` map their runs with it:
``--workers 0`` runs them one by one in this process (no dask), ``--workers N`` on a ``LocalCluster`` of N
single-threaded processes, ``--scheduler tcp://host:8786`` on a running cluster (a SLURM one: docs/parallel.md).
Each run is a pure function of its seed, so the rows are the same on 1 and N workers but for the fields that
measure time (:data:`TIMING`); the rows come back in task order.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from typing import Any

from auvplan.runtime.parallel import Runner

__all__ = ["TIMING", "add_arguments", "runner", "where", "run_all", "measured_apart"]

TIMING = frozenset({"wall_s", "cpu_s", "decision_time_s", "replan_s"})
"""Row fields that measure the machine, not the run: they differ between any two runs."""


def add_arguments(ap: argparse.ArgumentParser, workers: int) -> None:
    """Add ``--workers`` (default ``workers``), ``--scheduler`` and ``--retries`` to a benchmark's parser.

    Parameters
    ----------
    ap : argparse.ArgumentParser
        The benchmark's parser.
    workers : int
        Default number of local worker processes (0: this process).
    """
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, default=workers,
                   help=f"local dask worker processes, 0 for this process (default {workers})")
    g.add_argument("--scheduler", default=None, help="address of a running dask scheduler (docs/parallel.md)")
    ap.add_argument("--retries", type=int, default=1, help="runs again of a run that raised (default 1)")


def runner(args: argparse.Namespace) -> Runner:
    """The :class:`Runner` of the parsed ``--workers``, ``--scheduler`` and ``--retries``.

    Parameters
    ----------
    args : argparse.Namespace
        The benchmark's arguments.

    Returns
    -------
    Runner
        Where the runs go.
    """
    return Runner(workers=args.workers, scheduler=args.scheduler, retries=args.retries)


def where(args: argparse.Namespace) -> str:
    """Where the runs went, for a summary: ``"2 workers"``, ``"this process"`` or ``"scheduler ADDR"``.

    Parameters
    ----------
    args : argparse.Namespace
        The benchmark's arguments.

    Returns
    -------
    str
        The phrase.
    """
    if args.scheduler:
        return f"scheduler {args.scheduler}"
    return f"{args.workers} worker{'s' if args.workers > 1 else ''}" if args.workers else "this process"


def run_all(args: argparse.Namespace, fn: Callable[[Any], dict], tasks: Sequence[Any],
            on_row: Callable[[dict], None] | None = None) -> list[dict]:
    """Run ``fn`` on every task where ``args`` says; ``on_row`` sees each row as it arrives (any order).

    Parameters
    ----------
    args : argparse.Namespace
        The benchmark's arguments (:func:`add_arguments`).
    fn : callable
        A module-level function of one task returning its row.
    tasks : sequence
        The tasks (picklable).
    on_row : callable, optional
        Called in this process with each row as it arrives (a benchmark's ``rows.jsonl``).

    Returns
    -------
    list of dict
        The rows in task order.
    """
    return runner(args).map(fn, tasks, on_result=None if on_row is None else (lambda _, row: on_row(row))).results


def measured_apart(rows: Sequence[dict]) -> list[dict]:
    """The rows without their :data:`TIMING` fields (what 1 and N workers must agree on bit for bit).

    Parameters
    ----------
    rows : sequence of dict
        A benchmark's rows.

    Returns
    -------
    list of dict
        The same rows, timing fields dropped.
    """
    return [{k: v for k, v in row.items() if k not in TIMING} for row in rows]
