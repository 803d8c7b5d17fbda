"""Local refinement of one point: a bounded pattern search that spends an exact budget.

A generalised pattern search (Torczon 1997; the poll directions of mesh adaptive direct
search, Audet & Dennis 2006): from the incumbent ``x`` with step ``h`` (per dimension, a
fraction of the box), poll ``x ± h ⊙ q_j`` for the ``D`` columns ``q_j`` of a random rotation
(one batch of ``2D`` evaluations), move to the best poll point if it improves and grow ``h`` by
``expand``, else shrink ``h`` by ``contract``.  When ``h`` falls below ``tolerance`` the search
restarts from the incumbent at a quarter of the initial step, so that the budget is always spent
exactly.  Needs no gradient: the planners' costs jump where a segment starts to touch the seabed.
The incumbent never gets worse, and only points the objective scores finite can replace it
(objectives return ``inf`` for what must never be accepted, e.g. a path failing the exact test).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._types import ArrayLike, FloatArray, RngLike, as_rng
from .base import OptimizeResult, Problem

__all__ = ["PatternParams", "pattern_search", "random_rotation"]


@dataclass(frozen=True)
class PatternParams:
    """Initial step (fraction of the box per dimension), step growth and shrink, restart tolerance.

    Attributes
    ----------
    step : float
        Initial poll step as a fraction of the box width per dimension, in (0, 1].
    expand : float
        Step growth after an improving poll (≥ 1; the step is capped at 0.25).
    contract : float
        Step shrink after a failed poll, in (0, 1).
    tolerance : float
        Step below which the search restarts from the incumbent at a quarter of the initial step.

    Raises
    ------
    ValueError
        If a setting is outside its range.
    """

    step: float = 0.02
    expand: float = 1.5
    contract: float = 0.5
    tolerance: float = 1e-5

    def __post_init__(self) -> None:
        if not (0 < self.step <= 1 and self.expand >= 1 and 0 < self.contract < 1 and self.tolerance > 0):
            raise ValueError("need 0 < step <= 1, expand >= 1, 0 < contract < 1 and tolerance > 0")


def random_rotation(dim: int, rng: np.random.Generator) -> FloatArray:
    """A random orthogonal matrix (QR of a Gaussian matrix, signs fixed).

    Parameters
    ----------
    dim : int
        Dimension D.
    rng : numpy.random.Generator
        Source of the Gaussian matrix.

    Returns
    -------
    numpy.ndarray
        Orthogonal ``(D, D)``.
    """
    q, r = np.linalg.qr(rng.standard_normal((dim, dim)))
    rotation: FloatArray = q * np.sign(np.diag(r))
    return rotation


def pattern_search(problem: Problem, x0: ArrayLike, f0: float, params: PatternParams | None = None,
                   rng: RngLike = None) -> OptimizeResult:
    """Refine ``x0`` (value ``f0``) until ``problem``'s budget is spent.

    Parameters
    ----------
    problem : Problem
        Objective, box and budget (required).
    x0 : array_like
        Starting point ``(D,)`` (clipped to the box).
    f0 : float
        Its known value (not re-evaluated).
    params : PatternParams, optional
        Step settings.
    rng : numpy.random.Generator or int or None
        Source of the poll rotations.

    Returns
    -------
    OptimizeResult
        The best point (``x0`` itself when nothing better was found), its value and the
        evaluations spent; ``history`` holds the incumbent's value after each poll.

    Raises
    ------
    ValueError
        If the problem has no evaluation budget.
    """
    if problem.budget is None:
        raise ValueError("pattern_search needs a problem with an evaluation budget")
    p = params if params is not None else PatternParams()
    gen = as_rng(rng)
    t0 = time.perf_counter()
    span = problem.upper - problem.lower
    x, f = np.clip(np.asarray(x0, dtype=float), problem.lower, problem.upper), float(f0)
    h0 = p.step
    h = h0
    first, trace0 = problem.evaluations, len(problem.trace)
    history: list[float] = []
    while problem.left > 0:
        q = random_rotation(problem.dim, gen) * (h * span)[:, None]
        polls = np.clip(np.vstack([x + q.T, x - q.T]), problem.lower, problem.upper)
        fp = problem.evaluate(polls)
        k = int(np.argmin(fp))
        if np.isfinite(fp[k]) and fp[k] < f:
            x, f = polls[k].copy(), float(fp[k])
            h = min(h * p.expand, 0.25)
        else:
            h *= p.contract
            if h < p.tolerance:
                h0 *= 0.25
                h = max(h0, 4 * p.tolerance)
        history.append(f)
    return OptimizeResult(
        x=x, f=f, evaluations=problem.evaluations - first, iterations=len(history), history=np.asarray(history),
        wall_time_s=time.perf_counter() - t0, reason="max_evaluations",
        trace=np.asarray(problem.trace[trace0:], dtype=float).reshape(-1, 2),
    )
