"""Real-coded genetic algorithm: tournament selection, SBX crossover, polynomial mutation, elitism.

Defaults follow Deb & Agrawal (1995, SBX η_c = 15) and Deb & Goyal (1996,
polynomial mutation η_m = 20, probability 1/D), as in pymoo's GA.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._types import RngLike
from .base import Optimizer

__all__ = ["GAParams", "GA", "tournament", "sbx", "polynomial_mutation"]


@dataclass(frozen=True)
class GAParams:
    """GA settings: tournament size, crossover probability and η, mutation η and probability (0 → 1/D), elites."""

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


def tournament(f: np.ndarray, n: int, size: int, rng: np.random.Generator) -> np.ndarray:
    """Indices of ``n`` winners of tournaments of ``size`` (lowest f wins)."""
    entrants = rng.integers(0, f.size, size=(n, size))
    return entrants[np.arange(n), np.argmin(f[entrants], axis=1)]


def sbx(p1: np.ndarray, p2: np.ndarray, eta: float, prob: float, lower, upper, rng: np.random.Generator):
    """Simulated binary crossover of parent pairs ``(M, D)`` → two children ``(M, D)`` each."""
    u = rng.random(p1.shape)
    beta = np.where(u <= 0.5, (2.0 * u) ** (1.0 / (eta + 1.0)), (1.0 / (2.0 * (1.0 - u))) ** (1.0 / (eta + 1.0)))
    pair = np.asarray(rng.random(p1.shape[0]) < prob)
    cross = pair[:, None] & (rng.random(p1.shape) < 0.5)
    c1 = np.where(cross, 0.5 * ((1 + beta) * p1 + (1 - beta) * p2), p1)
    c2 = np.where(cross, 0.5 * ((1 - beta) * p1 + (1 + beta) * p2), p2)
    return np.clip(c1, lower, upper), np.clip(c2, lower, upper)


def polynomial_mutation(X: np.ndarray, eta: float, prob: float, lower, upper, rng: np.random.Generator) -> np.ndarray:
    """Deb's polynomial mutation of each coordinate with probability ``prob``."""
    span = np.asarray(upper) - np.asarray(lower)
    d1 = (X - lower) / span
    d2 = (upper - X) / span
    u = rng.random(X.shape)
    mpow = 1.0 / (eta + 1.0)
    lo = (2 * u + (1 - 2 * u) * (1 - d1) ** (eta + 1)) ** mpow - 1.0
    hi = 1.0 - (2 * (1 - u) + 2 * (u - 0.5) * (1 - d2) ** (eta + 1)) ** mpow
    delta = np.where(u < 0.5, lo, hi)
    mutate = rng.random(X.shape) < prob
    return np.clip(np.where(mutate, X + delta * span, X), lower, upper)


class GA(Optimizer):
    """Generational GA with elitism; one iteration evaluates ``population - elites`` children."""

    name = "ga"

    def __init__(self, lower, upper, population: int = 50, params: GAParams | None = None, rng: RngLike = None):
        super().__init__(lower, upper, population, rng)
        self.params = params if params is not None else GAParams()
        if self.params.elites >= self.n:
            raise ValueError("elites must be smaller than the population")
        self.X = np.empty((self.n, self.dim))
        self.f = np.full(self.n, np.inf)
        self._init = True

    def ask(self) -> np.ndarray:
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

    def tell(self, X: np.ndarray, f: np.ndarray) -> bool:
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
