"""The jobs the command line and the planning page both run: plan, run, survey, sweep, ensemble, bench (its
sweeps: :mod:`.bench`), mission check, the planning page's own (:mod:`.page`), and the one writer of a results
folder (:mod:`.results`).

A job takes plain values (a scenario name or file, an output folder, overrides), reports its progress to a
:class:`Reporter` the caller builds, and returns data; it prints nothing (the command line prints, the page
answers in JSON).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from ..planners import PlannerSpec

__all__ = ["Reporter", "Silent", "ReporterFor", "silent"]


class Reporter(Protocol):
    """What a job reports its progress to: the planner's iterations, the flight's simulated time, stages."""

    def __call__(self, iteration: int, best: float) -> None:
        """The planner's callback.

        Parameters
        ----------
        iteration : int
            Iterations done.
        best : float
            Best cost so far.
        """

    def flight(self, t: float, expected: float) -> None:
        """The simulation's callback.

        Parameters
        ----------
        t : float
            Simulated seconds flown.
        expected : float
            About how many the flight takes (s).
        """

    def stage(self, text: str) -> None:
        """A stage without a bar.

        Parameters
        ----------
        text : str
            What the job is doing.
        """

    def close(self) -> None:
        """The job is over."""


class Silent:
    """A reporter that reports nothing (the planning page, scripts)."""

    def __call__(self, iteration: int, best: float) -> None:
        """Nothing.

        Parameters
        ----------
        iteration : int
            Iterations done.
        best : float
            Best cost so far.
        """

    def flight(self, t: float, expected: float) -> None:
        """Nothing.

        Parameters
        ----------
        t : float
            Simulated seconds flown.
        expected : float
            About how many the flight takes (s).
        """

    def stage(self, text: str) -> None:
        """Nothing.

        Parameters
        ----------
        text : str
            What the job is doing.
        """

    def close(self) -> None:
        """Nothing."""


ReporterFor = Callable[["PlannerSpec", str], Reporter]
"""Builds the reporter of a job from the planner's settings and the scenario's name."""


def silent(spec: PlannerSpec, name: str) -> Reporter:
    """The reporter of a job whose caller shows no progress.

    Parameters
    ----------
    spec : PlannerSpec
        The planner's settings.
    name : str
        The scenario's name.

    Returns
    -------
    Reporter
        A :class:`Silent` one.
    """
    return Silent()
