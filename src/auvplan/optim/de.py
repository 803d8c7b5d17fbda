"""Differential evolution through :func:`scipy.optimize.differential_evolution` on a :class:`Problem`.

scipy runs the algorithm (Storn & Price 1997; ``best1bin`` with dithered F ∈ [0.5, 1) and
CR = 0.7 by default) with ``vectorized=True`` and ``updating="deferred"``, so that each
generation is one call of the population objective.  auvplan only adapts the interface: the
initial population (uniform draws from the run's generator, the problem's seeds first) is
passed as ``init``, the problem counts the evaluations and stops scipy when the budget is spent
(the last generation truncated, as for the other optimisers), and scipy's own polishing is
off (the planners refine on their own, with the exact feasibility test).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._types import FloatArray, RngLike, as_rng
from .base import OptimizeResult, Problem

__all__ = ["DEParams", "differential_evolution"]


@dataclass(frozen=True)
class DEParams:
    """Settings of scipy's DE: ``strategy``, ``mutation`` (F, or a dithering range) and ``recombination`` (CR).

    Parameters
    ----------
    strategy : str, default "best1bin"
        scipy's DE strategy name.
    mutation : tuple of float, default (0.5, 1.0)
        Differential weight F, or a dithering range ``(min, max)`` within [0, 2].
    recombination : float, default 0.7
        Crossover probability CR in [0, 1].

    Raises
    ------
    ValueError
        If ``mutation`` or ``recombination`` is out of range.
    """

    strategy: str = "best1bin"
    mutation: tuple[float, float] = (0.5, 1.0)
    recombination: float = 0.7

    def __post_init__(self) -> None:
        m = tuple(self.mutation) if isinstance(self.mutation, list | tuple) else (self.mutation,)
        if not 1 <= len(m) <= 2 or not all(0 <= v <= 2 for v in m):
            raise ValueError(f"mutation = {self.mutation}: one value or a range within [0, 2]")
        if not 0 <= self.recombination <= 1:
            raise ValueError(f"recombination = {self.recombination}: must lie in [0, 1]")


class _Spent(Exception):
    """Raised inside scipy's loop when the evaluation budget is spent."""


def differential_evolution(problem: Problem, population: int, params: DEParams | None = None, rng: RngLike = None,
                           callback: Callable[[int, float], None] | None = None) -> OptimizeResult:
    """Minimise ``problem`` with scipy's DE until its budget is spent.

    Parameters
    ----------
    problem : Problem
        Objective, box, seeds and budget (required).
    population : int
        Individuals per generation (>= 5, scipy's minimum).
    params : DEParams, optional
        Strategy settings.
    rng : Generator, int or None
        Seed of the run.
    callback : callable, optional
        ``callback(generation, best_f)`` after each generation.

    Returns
    -------
    OptimizeResult
        The problem's best point and the run's record (``reason = "max_evaluations"``).

    Raises
    ------
    ValueError
        If the problem has no evaluation budget.
    """
    if problem.budget is None:
        raise ValueError("differential_evolution needs a problem with an evaluation budget")
    p = params if params is not None else DEParams()
    gen = as_rng(rng)
    t0 = time.perf_counter()
    n = max(int(population), 5)
    init = _initial(problem, n, gen)
    first, trace0 = problem.evaluations, len(problem.trace)
    history: list[float] = []

    def each_generation(intermediate_result: object) -> None:  # scipy's OptimizeResult, unused
        history.append(problem.best_f)
        if callback is not None:
            callback(len(history), problem.best_f)

    from scipy.optimize import differential_evolution as _scipy_de  # imported when used (#56)

    func, mutation = _counted(problem), _scipy_mutation(p)
    while problem.left > 0:  # a restart (best kept) only if the population collapsed early
        try:
            _scipy_de(func, list(zip(problem.lower, problem.upper)), strategy=p.strategy, maxiter=10**9,
                      popsize=1, init=init, tol=0.0, atol=0.0, mutation=mutation, recombination=p.recombination,
                      rng=gen, polish=False, vectorized=True, updating="deferred", callback=each_generation)
        except _Spent:
            break
        init = problem.lower + gen.random((n, problem.dim)) * (problem.upper - problem.lower)
        init[0] = problem.best_x
    if not history or history[-1] != problem.best_f:
        history.append(problem.best_f)
    return OptimizeResult(x=problem.best_x.copy(), f=float(problem.best_f), evaluations=problem.evaluations - first,
                          iterations=len(history), history=np.asarray(history),
                          wall_time_s=time.perf_counter() - t0, reason="max_evaluations",
                          trace=np.asarray(problem.trace[trace0:], dtype=float).reshape(-1, 2))


def _initial(problem: Problem, n: int, gen: np.random.Generator) -> FloatArray:
    """``n`` uniform draws in the problem's box, its seeds first (at most half the population)."""
    init: FloatArray = problem.lower + gen.random((n, problem.dim)) * (problem.upper - problem.lower)
    m = min(problem.x0.shape[0], n // 2)
    init[:m] = problem.x0[:m]
    return init


def _counted(problem: Problem) -> Callable[[FloatArray], FloatArray]:
    """scipy's vectorised objective ``(D, S) -> (S,)`` over ``problem``, which stops scipy (:class:`_Spent`) once
    the budget is spent."""
    def func(xt: FloatArray) -> FloatArray:  # scipy passes (D, S)
        if problem.left <= 0:
            raise _Spent
        f = problem.evaluate(np.atleast_2d(xt.T))
        if problem.left <= 0:
            raise _Spent
        return f

    return func


def _scipy_mutation(p: DEParams) -> float | tuple[float, ...]:
    """``p.mutation`` as scipy takes it: one F, or a dithering range."""
    mutation: float | tuple[float, ...] = tuple(p.mutation) if isinstance(p.mutation, list | tuple) else p.mutation
    if isinstance(mutation, tuple) and len(mutation) == 1:
        mutation = mutation[0]
    return mutation
