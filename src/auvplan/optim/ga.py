"""Real-coded genetic algorithm: tournament selection, SBX crossover, polynomial mutation, elitism.

Defaults follow Deb & Agrawal (1995, SBX η_c = 15) and Deb & Goyal (1996,
polynomial mutation η_m = 20, probability 1/D), as in pymoo's GA.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._types import ArrayLike, FloatArray, IntArray, RngLike
from .base import Optimizer

__all__ = ["GAParams", "GA", "tournament", "sbx", "polynomial_mutation"]


@dataclass(frozen=True)
class GAParams:
    """GA settings: tournament size, crossover probability and η, mutation η and probability (0 → 1/D), elites.

    Parameters
    ----------
    tournament : int, default 2
        Entrants per tournament.
    crossover_prob : float, default 0.9
        Probability that a parent pair is crossed.
    eta_c : float, default 15.0
        SBX distribution index.
    eta_m : float, default 20.0
        Polynomial-mutation distribution index.
    mutation_prob : float, default 0.0
        Probability of mutating a coordinate; 0 means 1/D.
    elites : int, default 2
        Best individuals carried over unchanged.

    Raises
    ------
    ValueError
        If a setting is outside its range.
    """

    tournament: int = 2
    crossover_prob: float = 0.9
    eta_c: float = 15.0
    eta_m: float = 20.0
    mutation_prob: float = 0.0
    elites: int = 2

    def __post_init__(self) -> None:
        if self.tournament < 1 or self.elites < 0:
            raise ValueError("tournament must be >= 1 and elites >= 0")
        if not 0 <= self.crossover_prob <= 1 or not 0 <= self.mutation_prob <= 1:
            raise ValueError("crossover_prob and mutation_prob must lie in [0, 1]")
        if self.eta_c <= 0 or self.eta_m <= 0:
            raise ValueError("eta_c and eta_m must be positive")


def tournament(f: FloatArray, n: int, size: int, rng: np.random.Generator) -> IntArray:
    """Winners of tournaments (lowest value wins).

    Parameters
    ----------
    f : numpy.ndarray
        Values of the population ``(P,)``.
    n : int
        Number of tournaments.
    size : int
        Entrants per tournament (drawn with replacement).
    rng : numpy.random.Generator
        Source of the draws.

    Returns
    -------
    numpy.ndarray
        Indices of the ``n`` winners.
    """
    entrants = rng.integers(0, f.size, size=(n, size))
    winners: IntArray = entrants[np.arange(n), np.argmin(f[entrants], axis=1)]
    return winners


def sbx(p1: FloatArray, p2: FloatArray, eta: float, prob: float, lower: ArrayLike, upper: ArrayLike,
        rng: np.random.Generator) -> tuple[FloatArray, FloatArray]:
    """Simulated binary crossover of parent pairs.

    Parameters
    ----------
    p1, p2 : numpy.ndarray
        Parents ``(M, D)``.
    eta : float
        Distribution index η_c.
    prob : float
        Probability that a pair is crossed (each coordinate of a crossed pair with probability 1/2).
    lower, upper : array_like
        Search box ``(D,)``.
    rng : numpy.random.Generator
        Source of the draws.

    Returns
    -------
    c1, c2 : numpy.ndarray
        Two children ``(M, D)``, clipped to the box.
    """
    u = rng.random(p1.shape)
    beta = np.where(u <= 0.5, (2.0 * u) ** (1.0 / (eta + 1.0)), (1.0 / (2.0 * (1.0 - u))) ** (1.0 / (eta + 1.0)))
    pair = np.asarray(rng.random(p1.shape[0]) < prob)
    cross = pair[:, None] & (rng.random(p1.shape) < 0.5)
    c1 = np.where(cross, 0.5 * ((1 + beta) * p1 + (1 - beta) * p2), p1)
    c2 = np.where(cross, 0.5 * ((1 - beta) * p1 + (1 + beta) * p2), p2)
    return np.clip(c1, lower, upper), np.clip(c2, lower, upper)


def polynomial_mutation(X: FloatArray, eta: float, prob: float, lower: ArrayLike, upper: ArrayLike,
                        rng: np.random.Generator) -> FloatArray:
    """Deb's polynomial mutation of each coordinate with probability ``prob``.

    Parameters
    ----------
    X : numpy.ndarray
        Individuals ``(M, D)``.
    eta : float
        Distribution index η_m.
    prob : float
        Probability of mutating each coordinate.
    lower, upper : array_like
        Search box ``(D,)``.
    rng : numpy.random.Generator
        Source of the draws.

    Returns
    -------
    numpy.ndarray
        Mutated individuals ``(M, D)``, clipped to the box.
    """
    lower, upper = np.asarray(lower), np.asarray(upper)
    span = upper - lower
    d1 = (X - lower) / span
    d2 = (upper - X) / span
    u = rng.random(X.shape)
    mpow = 1.0 / (eta + 1.0)
    lo = (2 * u + (1 - 2 * u) * (1 - d1) ** (eta + 1)) ** mpow - 1.0
    hi = 1.0 - (2 * (1 - u) + 2 * (u - 0.5) * (1 - d2) ** (eta + 1)) ** mpow
    delta = np.where(u < 0.5, lo, hi)
    mutate = rng.random(X.shape) < prob
    mutated: FloatArray = np.clip(np.where(mutate, X + delta * span, X), lower, upper)
    return mutated


class GA(Optimizer):
    """Generational GA with elitism; one iteration evaluates ``population - elites`` children.

    Parameters
    ----------
    lower, upper : array_like
        Search box ``(D,)``.
    population : int, default 50
        Individuals per generation.
    params : GAParams, optional
        Settings (defaults when omitted).
    rng : numpy.random.Generator or int or None
        The run's generator or its seed.

    Raises
    ------
    ValueError
        If there are not fewer elites than individuals.
    """

    name = "ga"

    def __init__(self, lower: ArrayLike, upper: ArrayLike, population: int = 50, params: GAParams | None = None,
                 rng: RngLike = None) -> None:
        super().__init__(lower, upper, population, rng)
        self.params = params if params is not None else GAParams()
        if self.params.elites >= self.n:
            raise ValueError("elites must be smaller than the population")
        self.X = np.empty((self.n, self.dim))
        self.f = np.full(self.n, np.inf)
        self._init = True

    def ask(self) -> FloatArray:
        """Next batch of candidates.

        Returns
        -------
        numpy.ndarray
            Candidates ``(B, D)``.
        """
        if self._init:
            return self.seeded(self.uniform(self.n))
        p = self.params
        m = self.n - p.elites
        pairs = (m + 1) // 2
        a = tournament(self.f, pairs, p.tournament, self.rng)
        b = tournament(self.f, pairs, p.tournament, self.rng)
        c1, c2 = sbx(self.X[a], self.X[b], p.eta_c, p.crossover_prob, self.lower, self.upper, self.rng)
        children = np.vstack([c1, c2])[:m]
        prob = p.mutation_prob or 1.0 / self.dim
        return polynomial_mutation(children, p.eta_m, prob, self.lower, self.upper, self.rng)

    def tell(self, X: FloatArray, f: FloatArray) -> bool:
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
        f = np.asarray(f, dtype=float)
        self._note(X, f)
        if self._init:
            self.X[:], self.f[:] = X, f
            self._init = False
            return False
        elite = np.argsort(self.f, kind="stable")[: self.params.elites]
        self.X = np.vstack([self.X[elite], X])
        self.f = np.concatenate([self.f[elite], f])
        self.iteration += 1
        return True
