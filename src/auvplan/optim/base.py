"""Generic population optimisation: ask/tell optimisers, termination, result.

An objective is vectorised: ``f(X: (P, D)) -> (P,)``.  An :class:`Optimizer`
proposes a batch with :meth:`~Optimizer.ask` and learns the batch's values with
:meth:`~Optimizer.tell`, which returns ``True`` when an iteration of the
algorithm is complete.  :func:`minimize` runs the loop, counts every objective
evaluation and stops at the :class:`Termination` criteria; when the evaluation
budget would be overrun, the last batch is evaluated only up to the budget and
the rest of it is told ``+inf`` (never accepted), so that equal budgets are
exactly equal.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._types import RngLike, as_rng

__all__ = ["Optimizer", "Termination", "OptimizeResult", "minimize"]


class Optimizer:
    """Base class of ask/tell optimisers over the box ``[lower, upper]``."""

    name = "optimizer"

    def __init__(self, lower, upper, population: int, rng: RngLike = None) -> None:
        self.lower = np.asarray(lower, dtype=float).reshape(-1)
        self.upper = np.asarray(upper, dtype=float).reshape(-1)
        if self.lower.shape != self.upper.shape or np.any(self.upper <= self.lower):
            raise ValueError("lower and upper must have the same shape and lower < upper")
        if population < 2:
            raise ValueError(f"population must be >= 2, got {population}")
        self.n = int(population)
        self.dim = self.lower.size
        self.rng = as_rng(rng)
        self.best_x = np.full(self.dim, np.nan)
        self.best_f = np.inf
        self.iteration = 0

    @property
    def span(self) -> np.ndarray:
        """Width of the search box per dimension."""
        return self.upper - self.lower

    def clip(self, X: np.ndarray) -> np.ndarray:
        """Project candidates onto the search box."""
        return np.clip(X, self.lower, self.upper)

    def uniform(self, n: int) -> np.ndarray:
        """``n`` points drawn uniformly in the box (eq. 18 of document 002)."""
        return self.lower + self.rng.random((n, self.dim)) * self.span

    def _note(self, X: np.ndarray, f: np.ndarray) -> None:
        k = int(np.argmin(f))
        if f[k] < self.best_f:
            self.best_f = float(f[k])
            self.best_x = X[k].copy()

    def ask(self) -> np.ndarray:  # pragma: no cover - interface
        """Next batch of candidates ``(B, D)``."""
        raise NotImplementedError

    def tell(self, X: np.ndarray, f: np.ndarray) -> bool:  # pragma: no cover - interface
        """Values of the last batch; True when an iteration has completed."""
        raise NotImplementedError


@dataclass(frozen=True)
class Termination:
    """Stop criteria; any that is reached stops the run (``None`` disables one)."""

    max_iterations: int | None = 100
    max_evaluations: int | None = None
    max_time_s: float | None = None
    stall_iterations: int | None = None
    stall_tolerance: float = 0.0

    def __post_init__(self) -> None:
        if all(v is None for v in (self.max_iterations, self.max_evaluations, self.max_time_s)):
            raise ValueError("at least one of max_iterations, max_evaluations and max_time_s is needed")


@dataclass(frozen=True, eq=False)
class OptimizeResult:
    """Best point, its value, the work done and the convergence history."""

    x: np.ndarray
    f: float
    evaluations: int
    iterations: int
    history: np.ndarray
    wall_time_s: float
    reason: str


def minimize(
    objective: Callable[[np.ndarray], np.ndarray],
    optimizer: Optimizer,
    termination: Termination,
    callback: Callable[[int, float], None] | None = None,
) -> OptimizeResult:
    """Run ``optimizer`` on ``objective`` until ``termination``.

    Parameters
    ----------
    objective : callable
        Vectorised ``(P, D) -> (P,)``.
    optimizer : Optimizer
        Fresh optimiser (its generator fixes the run).
    termination : Termination
        Stop criteria.
    callback : callable, optional
        ``callback(iteration, best_f)`` after each iteration (progress reporting).
    """
    t0 = time.perf_counter()
    evals = 0
    history: list[float] = []
    reason = "max_iterations"
    last_improvement_f = np.inf
    stall = 0
    while True:
        X = optimizer.ask()
        f = np.full(X.shape[0], np.inf)
        take = X.shape[0]
        if termination.max_evaluations is not None:
            take = min(take, termination.max_evaluations - evals)
        if take > 0:
            f[:take] = objective(X[:take])
            evals += take
        finished = optimizer.tell(X, f)
        if finished:
            history.append(optimizer.best_f)
            if callback is not None:
                callback(optimizer.iteration, optimizer.best_f)
            if optimizer.best_f < last_improvement_f - termination.stall_tolerance:
                last_improvement_f = optimizer.best_f
                stall = 0
            else:
                stall += 1
            if termination.max_iterations is not None and optimizer.iteration >= termination.max_iterations:
                reason = "max_iterations"
                break
            if termination.stall_iterations is not None and stall >= termination.stall_iterations:
                reason = "stall"
                break
        if termination.max_evaluations is not None and evals >= termination.max_evaluations:
            if not finished:
                history.append(optimizer.best_f)
            reason = "max_evaluations"
            break
        if termination.max_time_s is not None and time.perf_counter() - t0 >= termination.max_time_s:
            reason = "max_time"
            break
    return OptimizeResult(
        x=optimizer.best_x.copy(),
        f=float(optimizer.best_f),
        evaluations=evals,
        iterations=optimizer.iteration,
        history=np.asarray(history),
        wall_time_s=time.perf_counter() - t0,
        reason=reason,
    )
