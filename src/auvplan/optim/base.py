"""Generic population optimisation: ask/tell optimisers, termination, result.

An objective is vectorised: ``f(X: (P, D)) -> (P,)``.  A :class:`Problem` (after pymoo's) holds
the objective with its box, the candidates that seed the first population and the evaluation
counter, budget and convergence trace (best value against evaluations).  An :class:`Optimizer`
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
from dataclasses import dataclass, field

import numpy as np

from .._types import RngLike, as_rng

__all__ = ["Optimizer", "Problem", "Termination", "OptimizeResult", "minimize"]


class Problem:
    """A box-bounded, vectorised minimisation problem that counts its evaluations.

    Parameters
    ----------
    objective : callable
        ``(P, D) -> (P,)``.
    lower, upper : array_like, shape (D,)
        Search box.
    x0 : array_like, shape (M, D), optional
        Candidates that seed the first population (clipped to the box).
    budget : int, optional
        Evaluations allowed; :meth:`evaluate` evaluates a batch only up to it and gives the rest
        ``+inf`` (never accepted by the optimisers).

    Attributes
    ----------
    evaluations : int
        Objective evaluations so far.
    best_x, best_f
        Best point seen and its value.
    trace : list of (int, float)
        ``(evaluations, best value)`` after every batch.
    """

    def __init__(self, objective: Callable[[np.ndarray], np.ndarray], lower, upper, x0=None,
                 budget: int | None = None) -> None:
        self.objective = objective
        self.lower = np.asarray(lower, dtype=float).reshape(-1)
        self.upper = np.asarray(upper, dtype=float).reshape(-1)
        if self.lower.shape != self.upper.shape or np.any(self.upper <= self.lower):
            raise ValueError("lower and upper must have the same shape and lower < upper")
        x0 = np.empty((0, self.lower.size)) if x0 is None else np.asarray(x0, dtype=float).reshape(-1, self.lower.size)
        self.x0 = np.clip(x0, self.lower, self.upper)
        if budget is not None and budget < 1:
            raise ValueError(f"budget must be >= 1, got {budget}")
        self.budget = budget
        self.evaluations = 0
        self.best_x = np.full(self.lower.size, np.nan)
        self.best_f = np.inf
        self.trace: list[tuple[int, float]] = []

    @property
    def dim(self) -> int:
        """Number of variables."""
        return self.lower.size

    @property
    def remaining(self) -> int | None:
        """Evaluations left (None without a budget)."""
        return None if self.budget is None else self.budget - self.evaluations

    @property
    def left(self) -> int:
        """Evaluations left, for the optimisers that need a budget (ValueError without one)."""
        if self.budget is None:
            raise ValueError("this optimiser needs an evaluation budget (Problem.budget)")
        return self.budget - self.evaluations

    def evaluate(self, X: np.ndarray) -> np.ndarray:
        """Values of the batch ``X (B, D)``; rows beyond the budget are not evaluated (``+inf``)."""
        X = np.asarray(X, dtype=float)
        f = np.full(X.shape[0], np.inf)
        take = X.shape[0] if self.budget is None else max(min(X.shape[0], self.budget - self.evaluations), 0)
        if take > 0:
            f[:take] = self.objective(X[:take])
            self.evaluations += take
            k = int(np.argmin(f[:take]))
            if f[k] < self.best_f:
                self.best_f, self.best_x = float(f[k]), X[k].copy()
            self.trace.append((self.evaluations, self.best_f))
        return f


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

    def seeded(self, X: np.ndarray) -> np.ndarray:
        """The initial population ``X`` with its first rows replaced by the seeds given to
        :meth:`seed` (at most half of the population)."""
        x0 = getattr(self, "_x0", None)
        if x0 is None or x0.shape[0] == 0:
            return X
        m = min(x0.shape[0], max(X.shape[0] // 2, 1))
        X = X.copy()
        X[:m] = self.clip(x0[:m])
        return X

    def seed(self, x0: np.ndarray) -> None:
        """Candidates ``(M, D)`` to place in the initial population."""
        self._x0 = np.asarray(x0, dtype=float).reshape(-1, self.dim)

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
    trace: np.ndarray = field(default_factory=lambda: np.empty((0, 2)))
    """``(evaluations, best value)`` after every batch, shape ``(M, 2)``."""


def minimize(
    problem: Problem | Callable[[np.ndarray], np.ndarray],
    optimizer: Optimizer,
    termination: Termination,
    callback: Callable[[int, float], None] | None = None,
) -> OptimizeResult:
    """Run ``optimizer`` on ``problem`` until ``termination``.

    Parameters
    ----------
    problem : Problem or callable
        The problem (its seeds go into the initial population and its evaluation counter is
        shared with later stages), or a vectorised objective ``(P, D) -> (P,)`` over the
        optimiser's box.
    optimizer : Optimizer
        Fresh optimiser (its generator fixes the run).
    termination : Termination
        Stop criteria.
    callback : callable, optional
        ``callback(iteration, best_f)`` after each iteration (progress reporting).
    """
    t0 = time.perf_counter()
    if not isinstance(problem, Problem):
        problem = Problem(problem, optimizer.lower, optimizer.upper)
    if problem.x0.shape[0]:
        optimizer.seed(problem.x0)
    first, evals = problem.evaluations, 0
    trace0 = len(problem.trace)
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
            f[:take] = problem.evaluate(X[:take])
            evals = problem.evaluations - first
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
        if problem.remaining is not None and problem.remaining <= 0:
            if not finished:
                history.append(optimizer.best_f)
            reason = "max_evaluations"
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
        trace=np.asarray(problem.trace[trace0:], dtype=float).reshape(-1, 2),
    )
