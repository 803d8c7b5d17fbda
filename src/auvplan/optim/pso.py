"""Particle swarm optimisation with inertia, cognitive and social terms and a velocity clamp.

Defaults are Clerc & Kennedy's (2002) constriction-equivalent constants
w = 0.7298, c1 = c2 = 1.49618; the velocity is clamped to ``vmax`` of the
range per dimension (0.2, Eberhart & Shi 2000).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._types import ArrayLike, FloatArray, RngLike
from .base import Optimizer

__all__ = ["PSOParams", "PSO", "pso_step"]


@dataclass(frozen=True)
class PSOParams:
    """Inertia ``w``, cognitive ``c1``, social ``c2`` and velocity clamp ``vmax`` (fraction of the range).

    Parameters
    ----------
    w : float, default 0.7298
        Inertia weight.
    c1 : float, default 1.49618
        Cognitive (personal best) coefficient.
    c2 : float, default 1.49618
        Social (global best) coefficient.
    vmax : float, default 0.2
        Velocity clamp as a fraction of the box width per dimension.

    Raises
    ------
    ValueError
        If a coefficient is negative or ``vmax`` is not positive.
    """

    w: float = 0.7298
    c1: float = 1.49618
    c2: float = 1.49618
    vmax: float = 0.2

    def __post_init__(self) -> None:
        if self.w < 0 or self.c1 < 0 or self.c2 < 0 or not self.vmax > 0:
            raise ValueError("w, c1, c2 must be >= 0 and vmax > 0")


def pso_step(X: FloatArray, V: FloatArray, pbest: FloatArray, gbest: FloatArray, w: float, c1: float, c2: float,
             r1: FloatArray, r2: FloatArray, vmax: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Pure PSO update with the random draws given.

    Parameters
    ----------
    X, V : numpy.ndarray
        Positions and velocities ``(P, D)``.
    pbest : numpy.ndarray
        Personal bests ``(P, D)``.
    gbest : numpy.ndarray
        Global best ``(D,)``.
    w, c1, c2 : float
        Inertia, cognitive and social coefficients.
    r1, r2 : numpy.ndarray
        Uniform draws in [0, 1) ``(P, D)``.
    vmax : numpy.ndarray
        Velocity clamp per dimension ``(D,)``.

    Returns
    -------
    X_new, V_new : numpy.ndarray
        New positions (not clipped to the box) and velocities (clamped to ±vmax).
    """
    V = w * V + c1 * r1 * (pbest - X) + c2 * r2 * (gbest - X)
    V = np.clip(V, -vmax, vmax)
    return X + V, V


class PSO(Optimizer):
    """Global-best PSO; one iteration evaluates the whole swarm once.

    Parameters
    ----------
    lower, upper : array_like
        Search box ``(D,)``.
    population : int, default 50
        Swarm size.
    params : PSOParams, optional
        Settings (defaults when omitted).
    rng : numpy.random.Generator or int or None
        The run's generator or its seed.
    """

    name = "pso"

    def __init__(self, lower: ArrayLike, upper: ArrayLike, population: int = 50, params: PSOParams | None = None,
                 rng: RngLike = None) -> None:
        super().__init__(lower, upper, population, rng)
        self.params = params if params is not None else PSOParams()
        self.X = self.uniform(self.n)
        vmax = self.params.vmax * self.span
        self.V = self.rng.uniform(-vmax, vmax, size=self.X.shape)
        self.pbest = self.X.copy()
        self.pbest_f = np.full(self.n, np.inf)
        self._init = True

    def ask(self) -> FloatArray:
        """Next batch of candidates.

        Returns
        -------
        numpy.ndarray
            Candidates ``(B, D)``.
        """
        if self._init:
            self.X = self.seeded(self.X)
            return self.X.copy()
        p = self.params
        r1 = self.rng.random(self.X.shape)
        r2 = self.rng.random(self.X.shape)
        X, V = pso_step(self.X, self.V, self.pbest, self.best_x, p.w, p.c1, p.c2, r1, r2, p.vmax * self.span)
        clipped = self.clip(X)
        self.V = np.where(clipped != X, 0.0, V)  # particles stop at the wall
        self.X = clipped
        return self.X.copy()

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
        better = f < self.pbest_f
        self.pbest[better] = X[better]
        self.pbest_f[better] = f[better]
        if self._init:
            self._init = False
            return False
        self.iteration += 1
        return True
