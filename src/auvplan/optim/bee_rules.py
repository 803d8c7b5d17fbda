"""The update rules of the artificial bee colonies (document 002, eqs. 18–25), as pure functions on arrays.

Used by :class:`~auvplan.optim.bee.ABC` and :class:`~auvplan.optim.bee.IABC` (see :mod:`.bee` for the
equations and the two IABC variants): eq. 20's fitness (:func:`abc_fitness`), eq. 19's neighbour move
(:func:`neighbour_move`) and its multi-dimension, best-guided form (:func:`guided_move`), eqs. 23–24's
chaotic start (:func:`logistic_map_population`) and its uniform image (:func:`chaotic_uniform_population`),
eq. 25's Gaussian mutation (:func:`gaussian_mutation`) and the onlookers' linear ranking
(:func:`rank_probabilities`).
"""

from __future__ import annotations

import numpy as np

from .._types import ArrayLike, BoolArray, FloatArray, IntArray

__all__ = [
    "abc_fitness",
    "neighbour_move",
    "logistic_map_population",
    "chaotic_uniform_population",
    "gaussian_mutation",
    "guided_move",
    "rank_probabilities",
]


def abc_fitness(f: ArrayLike) -> FloatArray:
    """Document 002 eq. 20: ``1/(1+f)`` for ``f ≥ 0``, ``1 + |f|`` otherwise (inf → 0).

    Parameters
    ----------
    f : array_like
        Objective values.

    Returns
    -------
    numpy.ndarray
        Fitness, same shape (0 where ``f`` is not finite).
    """
    f = np.asarray(f, dtype=float)
    with np.errstate(divide="ignore", over="ignore"):
        fit = np.where(f >= 0, 1.0 / (1.0 + np.abs(f)), 1.0 + np.abs(f))
    fitness: FloatArray = np.where(np.isfinite(f), fit, 0.0)
    return fitness


def neighbour_move(X: FloatArray, idx: IntArray, partner: IntArray, dim: IntArray, phi: FloatArray) -> FloatArray:
    """Eq. 19 on one dimension: candidates ``X[idx]`` with ``x_j += φ (x_j - x_{partner, j})``.

    Parameters
    ----------
    X : numpy.ndarray
        Food sources ``(N, D)``.
    idx : numpy.ndarray
        Sources to move ``(B,)``.
    partner : numpy.ndarray
        A partner source k ≠ i for each ``(B,)``.
    dim : numpy.ndarray
        The dimension j changed in each ``(B,)``.
    phi : numpy.ndarray
        φ ∈ [-1, 1] for each ``(B,)``.

    Returns
    -------
    numpy.ndarray
        Candidates ``(B, D)`` (not clipped).
    """
    V = X[idx].copy()
    rows = np.arange(idx.size)
    V[rows, dim] = X[idx, dim] + phi * (X[idx, dim] - X[partner, dim])
    return V


def _partners(idx: IntArray, n: int, rng: np.random.Generator) -> IntArray:
    """A random partner k ≠ i for each i in ``idx``."""
    k = rng.integers(0, n - 1, size=idx.size)
    partners: IntArray = k + (k >= idx)
    return partners


def logistic_map_population(n: int, dim: int, mu: float, rng: np.random.Generator) -> FloatArray:
    """Eqs. 23–24: ``n`` chaotic points in ``[0, 1]^dim`` from the logistic map.

    Each dimension runs its own sequence from a random seed ``x_0`` that avoids
    the map's fixed and pre-fixed points (0, 0.25, 0.5, 0.75, 1).

    Parameters
    ----------
    n : int
        Number of points.
    dim : int
        Dimension D.
    mu : float
        Logistic-map parameter μ.
    rng : numpy.random.Generator
        Source of the seeds ``x_0``.

    Returns
    -------
    numpy.ndarray
        ``(n, dim)`` in [0, 1].
    """
    x = rng.uniform(0.01, 0.99, size=dim)
    bad = np.isclose(x[:, None], np.array([0.25, 0.5, 0.75]), atol=1e-3).any(axis=1)
    x = np.where(bad, x + 0.0123, x)
    out = np.empty((n, dim))
    for k in range(n):  # a recurrence: each term needs the previous one
        x = mu * x * (1.0 - x)
        out[k] = x
    return out


def chaotic_uniform_population(n: int, dim: int, mu: float, rng: np.random.Generator) -> FloatArray:
    """Logistic-map points (eqs. 23–24) mapped through the μ = 4 map's invariant distribution.

    ``y = (2/π) asin(√x)``: the arcsine law becomes uniform on ``[0, 1]`` (the sequence
    ``y_k`` is the tent map's orbit, still chaotic and non-repeating).

    Parameters
    ----------
    n : int
        Number of points.
    dim : int
        Dimension D.
    mu : float
        Logistic-map parameter μ.
    rng : numpy.random.Generator
        Source of the seeds ``x_0``.

    Returns
    -------
    numpy.ndarray
        ``(n, dim)`` in [0, 1].
    """
    x = logistic_map_population(n, dim, mu, rng)
    y: FloatArray = (2.0 / np.pi) * np.arcsin(np.sqrt(np.clip(x, 0.0, 1.0)))
    return y


def guided_move(X: FloatArray, idx: IntArray, partner: IntArray, mask: BoolArray, phi: FloatArray,
                psi: FloatArray, best: FloatArray) -> FloatArray:
    """Eq. 19 on the dimensions in ``mask`` plus a pull to the best source.

    ``x_j += φ_j (x_j - x_{partner, j}) + ψ_j (best_j - x_j)`` where ``mask`` holds.

    Parameters
    ----------
    X : numpy.ndarray
        Food sources ``(N, D)``.
    idx : numpy.ndarray
        Sources to move ``(B,)``.
    partner : numpy.ndarray
        A partner source k ≠ i for each ``(B,)``.
    mask : numpy.ndarray of bool
        Dimensions changed ``(B, D)``.
    phi : numpy.ndarray
        φ ∈ [-1, 1] ``(B, D)``.
    psi : numpy.ndarray
        ψ ≥ 0 ``(B, D)``.
    best : numpy.ndarray
        The best source ``(D,)``, or one attraction centre per candidate ``(B, D)``.

    Returns
    -------
    numpy.ndarray
        Candidates ``(B, D)`` (not clipped).
    """
    V = X[idx].copy()
    step = phi * (X[idx] - X[partner]) + psi * (np.atleast_2d(best) - X[idx])
    V[mask] += step[mask]
    return V


def rank_probabilities(f: ArrayLike, pressure: float = 2.0) -> FloatArray:
    """Linear-ranking selection probabilities (Baker 1985; in ABC, Bao & Zeng 2009).

    The source of rank ``r`` (0 the best, ties in index order) is drawn with probability
    ``(s - (2 s - 2) r / (N - 1)) / N``: ``s/N`` for the best, ``(2 - s)/N`` for the worst,
    whatever the scale of the values.

    Parameters
    ----------
    f : array_like
        Objective values ``(N,)``, N ≥ 2.
    pressure : float, default 2.0
        Selection pressure ``s`` in [1, 2] (1: uniform).

    Returns
    -------
    numpy.ndarray
        Probabilities ``(N,)`` summing to 1.
    """
    f = np.asarray(f, dtype=float)
    n = f.size
    rank = np.empty(n)
    rank[np.argsort(f, kind="stable")] = np.arange(n)
    p: FloatArray = (pressure - (2.0 * pressure - 2.0) * rank / (n - 1)) / n
    return p


def gaussian_mutation(X: FloatArray, sigma: FloatArray | float, rng: np.random.Generator,
                      mean: float = 0.0) -> FloatArray:
    """Eq. 25: ``X + N(mean, sigma²)`` per coordinate (``sigma`` broadcast per dimension).

    Parameters
    ----------
    X : numpy.ndarray
        Sources ``(M, D)``.
    sigma : float or numpy.ndarray
        Standard deviation, a scalar or per dimension ``(D,)``.
    rng : numpy.random.Generator
        Source of the draws.
    mean : float, default 0.0
        Mean of the unit normal draws before scaling by ``sigma``.

    Returns
    -------
    numpy.ndarray
        Mutants ``(M, D)`` (not clipped).
    """
    mutants: FloatArray = X + rng.normal(mean, 1.0, size=X.shape) * sigma
    return mutants
