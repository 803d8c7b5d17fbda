"""Small shared types: the result status vocabulary and the random-generator coercion."""

from __future__ import annotations

import enum

import numpy as np

__all__ = ["Status", "RngLike", "as_rng"]

RngLike = np.random.Generator | int | None


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

    @property
    def ok(self) -> bool:
        """True for the two success states."""
        return self in (Status.EXACT, Status.APPROXIMATE)


def as_rng(rng: RngLike) -> np.random.Generator:
    """Return a ``numpy.random.Generator`` for a seed, a generator or ``None``."""
    if isinstance(rng, np.random.Generator):
        return rng
    return np.random.default_rng(rng)
