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
from typing import TypeAlias

import numpy as np

from .._types import ArrayLike, FloatArray, RngLike, as_rng

__all__ = ["Optimizer", "Problem", "Termination", "OptimizeResult", "minimize", "Objective"]

#: A vectorised objective: candidates ``(P, D)`` to values ``(P,)``.
Objective: TypeAlias = Callable[[FloatArray], FloatArray]


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
    repair : callable, optional
        ``(B, D) -> (B, D)``: the canonical form of candidates in the problem's representation
        (e.g. control points put in order along the track), which optimisers that opt in (the
        improved IABC) apply to their candidates before evaluation, keeping the repaired ones
        (pymoo's ``Repair``).  It must map the box into the box.

    Attributes
    ----------
    evaluations : int
        Objective evaluations so far.
    best_x, best_f
        Best point seen and its value.
    trace : list of (int, float)
        ``(evaluations, best value)`` after every batch.

    Raises
    ------
    ValueError
        If the box is empty or mis-shaped, or ``budget < 1``.
    """

    def __init__(self, objective: Objective, lower: ArrayLike, upper: ArrayLike, x0: ArrayLike | None = None,
                 budget: int | None = None, repair: Callable[[FloatArray], FloatArray] | None = None) -> None:
        self.objective = objective
        self.repair = repair
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
        self.best_x: FloatArray = np.full(self.lower.size, np.nan)
        self.best_f = np.inf
        self.trace: list[tuple[int, float]] = []

    @property
    def dim(self) -> int:
        """Number of variables.

        Returns
        -------
        int
            D.
        """
        return self.lower.size

    @property
    def remaining(self) -> int | None:
        """Evaluations left.

        Returns
        -------
        int or None
            ``budget - evaluations``; None without a budget.
        """
        return None if self.budget is None else self.budget - self.evaluations

    @property
    def left(self) -> int:
        """Evaluations left, for the optimisers that need a budget.

        Returns
        -------
        int
            ``budget - evaluations``.

        Raises
        ------
        ValueError
            Without a budget.
        """
        if self.budget is None:
            raise ValueError("this optimiser needs an evaluation budget (Problem.budget)")
        return self.budget - self.evaluations

    def evaluate(self, X: ArrayLike) -> FloatArray:
        """Values of a batch, counted; rows beyond the budget are not evaluated.

        Parameters
        ----------
        X : array_like
            Candidates ``(B, D)``.

        Returns
        -------
        numpy.ndarray
            Values ``(B,)``; ``+inf`` for the rows beyond the budget.
        """
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
    """Base class of ask/tell optimisers over the box ``[lower, upper]``.

    Parameters
    ----------
    lower, upper : array_like
        Search box ``(D,)``.
    population : int
        Population size (at least 2).
    rng : numpy.random.Generator or int or None
        The run's generator or its seed.

    Attributes
    ----------
    repair : callable or None
        The problem's repair (:class:`Problem`), set by :func:`minimize`; optimisers that opt in
        apply it to their candidates.

    Raises
    ------
    ValueError
        If the box is empty or mis-shaped, or the population is below 2.
    """

    name = "optimizer"

    def __init__(self, lower: ArrayLike, upper: ArrayLike, population: int, rng: RngLike = None) -> None:
        self.lower = np.asarray(lower, dtype=float).reshape(-1)
        self.upper = np.asarray(upper, dtype=float).reshape(-1)
        if self.lower.shape != self.upper.shape or np.any(self.upper <= self.lower):
            raise ValueError("lower and upper must have the same shape and lower < upper")
        if population < 2:
            raise ValueError(f"population must be >= 2, got {population}")
        self.n = int(population)
        self.dim = self.lower.size
        self.rng = as_rng(rng)
        self.best_x: FloatArray = np.full(self.dim, np.nan)
        self.best_f = np.inf
        self.iteration = 0
        self.repair: Callable[[FloatArray], FloatArray] | None = None
        self._x0: FloatArray = np.empty((0, self.dim))  # seeds (:meth:`seed`)

    @property
    def span(self) -> FloatArray:
        """Width of the search box per dimension.

        Returns
        -------
        numpy.ndarray
            ``upper - lower`` ``(D,)``.
        """
        span: FloatArray = self.upper - self.lower
        return span

    def clip(self, X: FloatArray) -> FloatArray:
        """Project candidates onto the search box.

        Parameters
        ----------
        X : numpy.ndarray
            Candidates ``(B, D)``.

        Returns
        -------
        numpy.ndarray
            The candidates clipped to ``[lower, upper]``.
        """
        clipped: FloatArray = np.clip(X, self.lower, self.upper)
        return clipped

    def uniform(self, n: int) -> FloatArray:
        """Points drawn uniformly in the box (eq. 18 of document 002).

        Parameters
        ----------
        n : int
            Number of points.

        Returns
        -------
        numpy.ndarray
            ``(n, D)``.
        """
        drawn: FloatArray = self.lower + self.rng.random((n, self.dim)) * self.span
        return drawn

    def seeded(self, X: FloatArray) -> FloatArray:
        """The initial population with its first rows replaced by the seeds of :meth:`seed`.

        Parameters
        ----------
        X : numpy.ndarray
            Initial population ``(P, D)``.

        Returns
        -------
        numpy.ndarray
            ``X`` with at most half of its rows replaced by the (clipped) seeds; ``X`` itself
            without seeds.
        """
        x0 = self._x0
        if x0.shape[0] == 0:
            return X
        m = min(x0.shape[0], max(X.shape[0] // 2, 1))
        X = X.copy()
        X[:m] = self.clip(x0[:m])
        return X

    def seed(self, x0: ArrayLike) -> None:
        """Candidates to place in the initial population.

        Parameters
        ----------
        x0 : array_like
            Candidates ``(M, D)``.
        """
        self._x0 = np.asarray(x0, dtype=float).reshape(-1, self.dim)

    def _note(self, X: FloatArray, f: FloatArray) -> None:
        k = int(np.argmin(f))
        if f[k] < self.best_f:
            self.best_f = float(f[k])
            self.best_x = X[k].copy()

    def ask(self) -> FloatArray:  # pragma: no cover - interface
        """Next batch of candidates.

        Returns
        -------
        numpy.ndarray
            Candidates ``(B, D)``.
        """
        raise NotImplementedError

    def tell(self, X: FloatArray, f: FloatArray) -> bool:  # pragma: no cover - interface
        """Learn the values of the last batch.

        Parameters
        ----------
        X : numpy.ndarray
            The batch ``(B, D)`` returned by :meth:`ask`.
        f : numpy.ndarray
            Its values ``(B,)`` (``+inf`` for rows not evaluated).

        Returns
        -------
        bool
            True when an iteration of the algorithm has completed.
        """
        raise NotImplementedError


@dataclass(frozen=True)
class Termination:
    """Stop criteria; any that is reached stops the run (``None`` disables one).

    Parameters
    ----------
    max_iterations : int or None, default 100
        Completed iterations of the algorithm.
    max_evaluations : int or None
        Objective evaluations of this run.
    max_time_s : float or None
        Wall-clock time (s).
    stall_iterations : int or None
        Iterations without an improvement of more than ``stall_tolerance``.
    stall_tolerance : float, default 0.0
        Least improvement of the best value that resets the stall count.
    on_stall : callable, optional
        ``on_stall(best_f) -> bool``, asked when the stall count reaches ``stall_iterations``: True stops
        the run (reason ``stall``), False resets the count and the run goes on.  None: the stall stops it.

    Raises
    ------
    ValueError
        If none of the iteration, evaluation and time limits is set.
    """

    max_iterations: int | None = 100
    max_evaluations: int | None = None
    max_time_s: float | None = None
    stall_iterations: int | None = None
    stall_tolerance: float = 0.0
    on_stall: Callable[[float], bool] | None = None

    def __post_init__(self) -> None:
        if all(v is None for v in (self.max_iterations, self.max_evaluations, self.max_time_s)):
            raise ValueError("at least one of max_iterations, max_evaluations and max_time_s is needed")


@dataclass(frozen=True, eq=False)
class OptimizeResult:
    """Best point, its value, the work done and the convergence history.

    Parameters
    ----------
    x : numpy.ndarray
        Best point ``(D,)``.
    f : float
        Its value.
    evaluations : int
        Objective evaluations of the run.
    iterations : int
        Completed iterations.
    history : numpy.ndarray
        Best value after each iteration.
    wall_time_s : float
        Run time (s).
    reason : str
        Why the run stopped: ``max_iterations``, ``max_evaluations``, ``stall`` or ``max_time``.
    trace : numpy.ndarray
        ``(evaluations, best value)`` after every batch, shape ``(M, 2)``.
    """

    x: FloatArray
    f: float
    evaluations: int
    iterations: int
    history: FloatArray
    wall_time_s: float
    reason: str
    trace: FloatArray = field(default_factory=lambda: np.empty((0, 2)))
    """``(evaluations, best value)`` after every batch, shape ``(M, 2)``."""


def minimize(
    problem: Problem | Objective,
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

    Returns
    -------
    OptimizeResult
        The optimiser's best point and the run's record.
    """
    t0 = time.perf_counter()
    problem = _prepared(problem, optimizer)
    first, evals = problem.evaluations, 0
    trace0 = len(problem.trace)
    history: list[float] = []
    last_improvement_f = np.inf
    stall = 0
    while True:
        X = optimizer.ask()
        f, evals = _evaluate(problem, X, termination, first, evals)
        finished = optimizer.tell(X, f)
        reason = ""
        if finished:
            history.append(optimizer.best_f)
            if callback is not None:
                callback(optimizer.iteration, optimizer.best_f)
            improved = optimizer.best_f < last_improvement_f - termination.stall_tolerance
            last_improvement_f, stall = (optimizer.best_f, 0) if improved else (last_improvement_f, stall + 1)
            reason = _iterations_reached(termination, optimizer.iteration, stall)
            if reason == "stall" and termination.on_stall is not None and not termination.on_stall(optimizer.best_f):
                reason, stall = "", 0  # asked, the run goes on
        if not reason and _evaluations_spent(problem, termination, evals):
            if not finished:
                history.append(optimizer.best_f)
            reason = "max_evaluations"
        if not reason and termination.max_time_s is not None and time.perf_counter() - t0 >= termination.max_time_s:
            reason = "max_time"
        if reason:
            break
    return OptimizeResult(x=optimizer.best_x.copy(), f=float(optimizer.best_f), evaluations=evals,
                          iterations=optimizer.iteration, history=np.asarray(history),
                          wall_time_s=time.perf_counter() - t0, reason=reason,
                          trace=np.asarray(problem.trace[trace0:], dtype=float).reshape(-1, 2))


def _prepared(problem: Problem | Objective, optimizer: Optimizer) -> Problem:
    """``problem`` as a :class:`Problem` over the optimiser's box; its seeds and repair given to the optimiser."""
    if not isinstance(problem, Problem):
        problem = Problem(problem, optimizer.lower, optimizer.upper)
    if problem.x0.shape[0]:
        optimizer.seed(problem.x0)
    if problem.repair is not None:
        optimizer.repair = problem.repair
    return problem


def _evaluate(problem: Problem, X: FloatArray, termination: Termination, first: int,
              evals: int) -> tuple[FloatArray, int]:
    """The values of the batch ``X`` (``+inf`` beyond the run's evaluations) and the run's evaluations after it."""
    f = np.full(X.shape[0], np.inf)
    take = X.shape[0]
    if termination.max_evaluations is not None:
        take = min(take, termination.max_evaluations - evals)
    if take > 0:
        f[:take] = problem.evaluate(X[:take])
        evals = problem.evaluations - first
    return f, evals


def _iterations_reached(termination: Termination, iteration: int, stall: int) -> str:
    """``"max_iterations"`` or ``"stall"`` when that limit is reached after an iteration, else ``""``."""
    if termination.max_iterations is not None and iteration >= termination.max_iterations:
        return "max_iterations"
    if termination.stall_iterations is not None and stall >= termination.stall_iterations:
        return "stall"
    return ""


def _evaluations_spent(problem: Problem, termination: Termination, evals: int) -> bool:
    """Whether the problem's budget or the run's evaluations are spent."""
    if problem.remaining is not None and problem.remaining <= 0:
        return True
    return termination.max_evaluations is not None and evals >= termination.max_evaluations
