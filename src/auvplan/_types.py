"""Small shared types: the result status vocabulary and the random-generator coercion."""

from __future__ import annotations

import enum
from typing import TypeAlias

import numpy as np
import numpy.typing as npt

__all__ = ["Status", "RngLike", "as_rng", "FloatArray", "IntArray", "BoolArray", "ArrayLike"]

#: Anything :func:`as_rng` turns into a generator: a generator, an integer seed or ``None`` (fresh entropy).
RngLike: TypeAlias = np.random.Generator | int | None
#: A float64 array of any shape (positions in m, velocities in m/s, angles in rad …).
FloatArray: TypeAlias = npt.NDArray[np.float64]
#: An integer array of any shape (indices, counts).
IntArray: TypeAlias = npt.NDArray[np.intp]
#: A boolean array of any shape (masks).
BoolArray: TypeAlias = npt.NDArray[np.bool_]
#: Anything ``numpy.asarray`` accepts (scalars, sequences, arrays).
ArrayLike: TypeAlias = npt.ArrayLike


class Status(enum.StrEnum):
    """Closed vocabulary of outcomes (after OMPL's ``PlannerStatus``).

    ``EXACT`` and ``APPROXIMATE`` are successes; everything else is a failure
    that is reported, never raised.
    """

    EXACT = "EXACT"
    APPROXIMATE = "APPROXIMATE"
    INVALID_START = "INVALID_START"
    INVALID_GOAL = "INVALID_GOAL"
    TIMEOUT = "TIMEOUT"
    INFEASIBLE = "INFEASIBLE"
    UNAVOIDABLE = "UNAVOIDABLE"
    COLLISION = "COLLISION"
    DEADLOCK = "DEADLOCK"
    RESERVE_BROKEN = "RESERVE_BROKEN"

    @property
    def ok(self) -> bool:
        """Whether the status is one of the two success states.

        Returns
        -------
        bool
            True for ``EXACT`` and ``APPROXIMATE``.
        """
        return self in (Status.EXACT, Status.APPROXIMATE)


def as_rng(rng: RngLike) -> np.random.Generator:
    """Return a ``numpy.random.Generator`` for a seed, a generator or ``None``.

    Parameters
    ----------
    rng : numpy.random.Generator or int or None
        A generator (returned as is), an integer seed, or ``None`` for fresh OS entropy.

    Returns
    -------
    numpy.random.Generator
        The generator to draw from (never the global numpy state).
    """
    if isinstance(rng, np.random.Generator):
        return rng
    return np.random.default_rng(rng)
