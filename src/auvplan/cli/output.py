"""What the commands of the command line share: progress on stderr and their output (a human line, or one JSON
object with ``--json``).  The check of ``--out`` before any work is each job's (:func:`auvplan.io.safeio.prepare_out`
in :mod:`auvplan.app`)."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import argparse

    from ..planners import PlannerSpec

__all__: list[str] = []  # handlers: CLI internals, not library API


class Progress:
    """Progress of the long stages on stderr: a tqdm bar for the swarm planners' iterations and one
    for the flight (simulated time against the route's expected duration), a line for the other
    stages; all silent with ``quiet`` (``-q`` or ``--json``)."""

    def __init__(self, spec: PlannerSpec, scenario: str, quiet: bool) -> None:
        from tqdm import tqdm

        from ..planners import get as get_planner

        self._tqdm, self.quiet, self.scenario = tqdm, quiet, scenario
        self.flight_bar: Any = None
        # only the iterating planners (the swarm optimisers) report progress; the others get a line, not a
        # bar stuck at 0
        iterative = get_planner(spec.name).iterative
        self.bar = tqdm(total=spec.iterations, desc=f"{spec.name} on {scenario}", file=sys.stderr,
                        disable=quiet or not iterative, leave=False, mininterval=0.5)
        if not iterative:
            self.stage(f"planning with {spec.name}")

    def __call__(self, iteration: int, best: float) -> None:
        self.bar.update(iteration - self.bar.n)
        self.bar.set_postfix_str(f"best {best:.6g}", refresh=False)

    def flight(self, t: float, expected: float) -> None:
        """The simulation's callback: simulated seconds flown of about ``expected``."""
        if self.flight_bar is None:
            self.bar.close()
            self.flight_bar = self._tqdm(total=max(1, round(expected)), desc=f"flight on {self.scenario}", unit="s",
                                         file=sys.stderr, disable=self.quiet, leave=False, mininterval=0.5)
        self.flight_bar.update(min(round(t), self.flight_bar.total) - self.flight_bar.n)

    def stage(self, text: str) -> None:
        """One line on stderr for a stage without a bar (the report, a lattice plan)."""
        if not self.quiet:
            self._tqdm.write(f"auvplan: {text} …", file=sys.stderr)

    def close(self) -> None:
        self.bar.close()
        if self.flight_bar is not None:
            self.flight_bar.close()


def reporter(quiet: bool) -> Callable[[PlannerSpec, str], Progress]:
    """The progress reporter a job builds from its planner and scenario (:class:`auvplan.app.Reporter`)."""
    return lambda spec, scenario: Progress(spec, scenario, quiet)


JSON_WARNINGS: list[str] = []
"""Warnings (logging and Python) raised while a ``--json`` command ran: :func:`emit` puts them in the JSON
object's ``warnings`` instead of on stderr (issue 51: ``--json`` leaves stderr empty on success)."""


def emit(record: dict[str, Any], as_json: bool, human: str) -> None:
    """A command's record: one JSON object on stdout with ``as_json`` (with the ``warnings`` collected while it
    ran, :data:`JSON_WARNINGS`), else the human text."""
    from ..io.results import records

    if as_json and JSON_WARNINGS:
        record = {**record, "warnings": list(JSON_WARNINGS)}
    if as_json:
        sys.stdout.write(json.dumps(records.jsonable(record)) + "\n")
    else:
        print(human)


def runner_of(args: argparse.Namespace) -> Any:
    """The :class:`auvplan.parallel.Runner` of ``--workers``, ``--scheduler`` and ``--retries``.

    Parameters
    ----------
    args : argparse.Namespace
        The command's arguments (those three absent: this process, one retry).

    Returns
    -------
    Runner
        Where the job's independent tasks run.
    """
    from ..parallel import Runner

    return Runner(workers=getattr(args, "workers", None) or 0, scheduler=getattr(args, "scheduler", None),
                  retries=getattr(args, "retries", 1))
