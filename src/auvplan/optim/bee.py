"""Artificial bee colony (Karaboga 2005) and the improved colony of document 002.

Document 002 (IABC for 3D global path planning of a manned submersible),
equations 18–25, as restated in docs/methods.md §2:

* eq. 18 — initial food sources ``g_i = L + r (U - L)`` (ABC);
* eq. 19 — neighbour move ``g_new = g_i + φ (g_i - g_k)``, ``φ ∈ [-1, 1]``,
  ``k ≠ i``, on one random dimension (employed and onlooker bees);
* eq. 20 — fitness ``1 / (1 + f)`` for ``f ≥ 0``, ``1 + |f|`` otherwise;
* eq. 21 — onlookers pick sources with probability ``fit_i / Σ fit``;
* eq. 22 — a source not improved for ``limit`` trials is replaced by a scout;
* eqs. 23–24 — IABC: initial sources from the logistic map
  ``x_k = μ x_{k-1} (1 - x_{k-1})``, μ = 4;
* eq. 25 — IABC: after every iteration, Gaussian mutation
  ``g_new = g + N(μ_g, σ²)`` of the worst fraction of sources, kept if better.

The document does not state μ_g, σ or the fraction.  Two variants (``IABCParams.variant``):

* ``"document"`` — the literal reading: logistic-map coordinates used as they are (their
  marginal is the arcsine law, which piles 29 % of them within 5 % of the box edges), one-dimension
  neighbour moves, and mutation ``g + N(0, σ²)`` of the worst 20 % with σ = 0.1 of the range
  decayed linearly to 0.01 of it over ``max_iterations``;
* ``"improved"`` (default) — the same two ideas done well: the chaotic sequence is mapped
  through the map's invariant distribution, ``y = (2/π) asin(√x)`` (:func:`chaotic_uniform_population`:
  uniform marginals, still ergodic and non-repeating); the mutation's mean is the shift to the best
  source, ``μ_g = g_best − g``, and its σ is ``sigma_spread`` times the population's current
  standard deviation per dimension, so the step shrinks with the colony instead of with an
  iteration count that an evaluation budget does not fix; neighbour moves change each dimension
  with probability ``modification_rate`` (at least one; Akay & Karaboga 2012), since the
  coordinates of neighbouring B-spline control points are strongly correlated, and are pulled
  towards the best source by ``ψ (g_best − g)``, ψ ∈ U(0, ``guided``) (Zhu & Kwong 2010);
  onlookers choose sources by linear ranking (:func:`rank_probabilities`; Bao & Zeng 2009),
  since eq. 20's ``1/(1 + f)`` makes eq. 21 uniform on costs of ~10^5; and, when the colony has
  no seeds, the random sources (chaotic initial ones, scouts) go through the problem's repair
  (``Problem.repair``: for paths, control points in order along the track).

The update rules are pure functions on arrays, in :mod:`.bee_rules` (:func:`neighbour_move`,
:func:`guided_move`, :func:`abc_fitness`, :func:`logistic_map_population`,
:func:`chaotic_uniform_population`, :func:`gaussian_mutation`, :func:`rank_probabilities`); this module
holds the settings and the two colonies as ask/tell optimisers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._types import ArrayLike, FloatArray, IntArray, RngLike
from .base import Optimizer
from .bee_rules import (
    _partners,
    abc_fitness,
    chaotic_uniform_population,
    gaussian_mutation,
    guided_move,
    logistic_map_population,
    neighbour_move,
    rank_probabilities,
)

__all__ = [
    "ABCParams",
    "IABCParams",
    "ABC",
    "IABC",
    "abc_fitness",
    "neighbour_move",
    "logistic_map_population",
    "chaotic_uniform_population",
    "gaussian_mutation",
    "guided_move",
    "rank_probabilities",
]


@dataclass(frozen=True)
class ABCParams:
    """ABC settings.

    Attributes
    ----------
    limit : int
        Trials without improvement before a source is abandoned (eq. 22).  Karaboga's rule
        ``SN × D`` exceeds a 100-iteration run for path problems, so that no scout would ever fly;
        40 trials is used instead (a source stuck for ~40 % of the document's run is abandoned).
    scouts_per_iteration : int
        At most this many sources are abandoned per iteration (1 in Karaboga 2005).

    Raises
    ------
    ValueError
        If either is below 1.
    """

    limit: int = 40
    scouts_per_iteration: int = 1

    def __post_init__(self) -> None:
        if self.limit < 1 or self.scouts_per_iteration < 1:
            raise ValueError("limit and scouts_per_iteration must be >= 1")


@dataclass(frozen=True)
class IABCParams:
    """IABC settings on top of ABC (see the module notes for the two variants).

    Attributes
    ----------
    limit, scouts_per_iteration : int
        As in :class:`ABCParams`.
    variant : str
        ``"improved"`` or ``"document"``.
    mu : float
        Logistic-map parameter (4: fully chaotic).
    mutation_fraction : float
        Share of the worst sources mutated each iteration.
    sigma : float
        Document variant: mutation σ as a fraction of the search range, decayed linearly ...
    sigma_final : float
        ... to this fraction over ``max_iterations``.
    max_iterations : int
        Iterations of the document variant's σ decay.
    sigma_spread : float
        Improved variant: mutation σ in units of the population's standard deviation per dimension.
    modification_rate : float
        Improved variant: probability that a neighbour move changes a dimension.
    guided : float
        Improved variant: largest pull ψ towards the best source.
    elite : float
        Improved variant: 0 aims the mutation and the pull at the best source; > 0 at a source
        drawn among the best ``elite`` share of the colony, which keeps the colony from collapsing
        onto one infeasible source in a maze (``elite = 0.2`` with ``mutation_fraction = 0.1`` is
        the robust setting for the algorithm alone, docs/bench_hard.md).
    rank_pressure : float
        Improved variant: onlookers pick sources by linear ranking with this selection pressure
        ``s ∈ [1, 2]`` (the best source drawn with probability ``s/N``, the worst ``(2 - s)/N``;
        Bao & Zeng 2009) instead of eq. 21; 0 keeps eq. 21.  Eq. 20's fitness ``1/(1 + f)`` is not
        scale-free: on path costs of ~5·10^5 every source gets ``p_i = 1/N`` within 1 %, so that
        eq. 21's onlookers choose at random.
    repair : bool
        Improved variant: put the random sources (the chaotic initial ones and the scouts, not
        the seeds nor the moves) through the problem's repair (``Problem.repair``; for paths,
        control points sorted along the track), so that the colony starts from loop-free
        arrangements but stays free to reach an optimum the repair would not keep.  Only when the
        colony has no seeds: seeds (the lattice's arrangements) are the better prior, and with
        them the ordered random sources cost 0.4 % on chagos-banks (docs/bench_hard.md).

    Raises
    ------
    ValueError
        If a setting is outside its range.
    """

    limit: int = 40
    scouts_per_iteration: int = 1
    variant: str = "improved"
    mu: float = 4.0
    mutation_fraction: float = 0.2
    sigma: float = 0.1
    sigma_final: float = 0.01
    max_iterations: int = 100
    sigma_spread: float = 0.5
    modification_rate: float = 0.2
    guided: float = 1.5
    elite: float = 0.0
    rank_pressure: float = 2.0
    repair: bool = True

    def __post_init__(self) -> None:
        if self.limit < 1 or self.scouts_per_iteration < 1 or self.max_iterations < 1:
            raise ValueError("limit, scouts_per_iteration and max_iterations must be >= 1")
        if self.variant not in ("improved", "document"):
            raise ValueError(f"variant = {self.variant!r}: choose 'improved' or 'document'")
        if not 3.57 <= self.mu <= 4.0:
            raise ValueError(f"mu = {self.mu}: the logistic map is chaotic only for 3.57 <= mu <= 4")
        if not 0.0 < self.mutation_fraction <= 1.0:
            raise ValueError(f"mutation_fraction = {self.mutation_fraction}: must lie in (0, 1]")
        if not (self.sigma > 0 and self.sigma_final >= 0 and self.sigma_spread > 0):
            raise ValueError("sigma and sigma_spread must be > 0 and sigma_final >= 0")
        if not 0.0 < self.modification_rate <= 1.0:
            raise ValueError(f"modification_rate = {self.modification_rate}: must lie in (0, 1]")
        if self.guided < 0:
            raise ValueError(f"guided = {self.guided}: must be >= 0")
        if not 0.0 <= self.elite <= 1.0:
            raise ValueError(f"elite = {self.elite}: must lie in [0, 1]")
        if not (self.rank_pressure == 0.0 or 1.0 <= self.rank_pressure <= 2.0):
            raise ValueError(f"rank_pressure = {self.rank_pressure}: must be 0 (eq. 21) or lie in [1, 2]")


# ---------------------------------------------------------------------- optimisers
class ABC(Optimizer):
    """Karaboga's artificial bee colony as an ask/tell optimiser.

    One iteration = employed phase (N candidates) + onlooker phase
    (N candidates) + scouts (at most ``scouts_per_iteration`` random sources).

    Parameters
    ----------
    lower, upper : array_like
        Search box ``(D,)``.
    population : int, default 50
        Number of food sources SN.
    params : ABCParams or IABCParams, optional
        Settings (defaults when omitted).
    rng : numpy.random.Generator or int or None
        The run's generator or its seed.
    """

    name = "abc"

    def __init__(self, lower: ArrayLike, upper: ArrayLike, population: int = 50,
                 params: ABCParams | IABCParams | None = None, rng: RngLike = None) -> None:
        super().__init__(lower, upper, population, rng)
        self.params = params if params is not None else ABCParams()
        self.X = np.empty((self.n, self.dim))
        self.f = np.full(self.n, np.inf)
        self.trials = np.zeros(self.n, dtype=np.intp)
        self._phase = "init"
        self._idx = np.arange(self.n)

    def _initial(self) -> FloatArray:
        return self.uniform(self.n)

    def _greedy(self, idx: IntArray, V: FloatArray, fv: FloatArray) -> None:
        """Greedy selection of candidates ``V`` for sources ``idx`` (duplicates allowed)."""
        order = np.lexsort((fv, idx))  # per source, best candidate first
        idx_s, fv_s, V_s = idx[order], fv[order], V[order]
        first = np.r_[True, idx_s[1:] != idx_s[:-1]]
        counts = np.diff(np.r_[np.flatnonzero(first), idx_s.size])
        src, best_f, best_V = idx_s[first], fv_s[first], V_s[first]
        better = best_f < self.f[src]
        self.X[src[better]] = best_V[better]
        self.f[src[better]] = best_f[better]
        self.trials[src[better]] = 0
        self.trials[src[~better]] += counts[~better]

    def ask(self) -> FloatArray:
        """Next batch of candidates (the phase's sources, scouts or mutants).

        Returns
        -------
        numpy.ndarray
            Candidates ``(B, D)``.
        """
        rng = self.rng
        if self._phase == "init":
            return self.seeded(self._initial())
        if self._phase == "employed":
            self._idx = np.arange(self.n)
        elif self._phase == "onlooker":
            self._idx = rng.choice(self.n, size=self.n, p=self._onlooker_probabilities())
        elif self._phase == "scout":
            return self._fresh(self._idx.size)
        elif self._phase == "mutation":
            return self._mutants()
        return self.clip(self._move(self._idx))

    def _fresh(self, m: int) -> FloatArray:
        """``m`` scouts' sources: uniform in the box (eq. 22)."""
        return self.uniform(m)

    def _onlooker_probabilities(self) -> FloatArray:
        """Eq. 21: ``p_i = fit_i / Σ fit`` (uniform when no source has a finite value)."""
        fit = abc_fitness(self.f)
        total = fit.sum()
        p: FloatArray = fit / total if total > 0 else np.full(self.n, 1.0 / self.n)
        return p

    def _move(self, idx: IntArray) -> FloatArray:
        """Eq. 19 candidates for the sources ``idx``."""
        rng = self.rng
        partner = _partners(idx, self.n, rng)
        dim = rng.integers(0, self.dim, size=idx.size)
        phi = rng.uniform(-1.0, 1.0, size=idx.size)
        return neighbour_move(self.X, idx, partner, dim, phi)

    def _mutants(self) -> FloatArray:  # pragma: no cover - IABC only
        raise NotImplementedError

    def _after_onlooker(self) -> str:
        over = np.flatnonzero(self.trials > self.params.limit)
        if over.size:
            worst_first = over[np.argsort(-self.trials[over], kind="stable")]
            self._idx = worst_first[: self.params.scouts_per_iteration]
            return "scout"
        return self._end_of_iteration()

    def _end_of_iteration(self) -> str:
        self.iteration += 1
        return "employed"

    def tell(self, X: FloatArray, f: FloatArray) -> bool:
        """Learn the values of the last batch (greedy selection, scouts, mutants).

        Parameters
        ----------
        X : numpy.ndarray
            The batch ``(B, D)`` returned by :meth:`ask`.
        f : numpy.ndarray
            Its values ``(B,)`` (``+inf`` for rows not evaluated).

        Returns
        -------
        bool
            True when an iteration of the colony has completed.
        """
        f = np.asarray(f, dtype=float)
        self._note(X, f)
        before = self.iteration
        if self._phase == "init":
            self.X[:] = X
            self.f[:] = f
            self.trials[:] = 0
            self._phase = "employed"
            return False
        if self._phase in ("employed", "onlooker"):
            self._greedy(self._idx, X, f)
            self._phase = "onlooker" if self._phase == "employed" else self._after_onlooker()
        elif self._phase == "scout":
            self.X[self._idx] = X
            self.f[self._idx] = f
            self.trials[self._idx] = 0
            self._phase = self._end_of_iteration()
        elif self._phase == "mutation":
            better = f < self.f[self._idx]
            self.X[self._idx[better]] = X[better]
            self.f[self._idx[better]] = f[better]
            self.trials[self._idx[better]] = 0
            self.iteration += 1
            self._phase = "employed"
        return self.iteration > before


class IABC(ABC):
    """Document 002's improved colony: chaotic initialisation + Gaussian mutation of the worst
    (``params.variant``: ``"improved"`` or the literal ``"document"``; see the module notes).

    Parameters
    ----------
    lower, upper : array_like
        Search box ``(D,)``.
    population : int, default 50
        Number of food sources SN.
    params : IABCParams, optional
        Settings (defaults when omitted).
    rng : numpy.random.Generator or int or None
        The run's generator or its seed.
    """

    name = "iabc"

    def __init__(self, lower: ArrayLike, upper: ArrayLike, population: int = 50, params: IABCParams | None = None,
                 rng: RngLike = None) -> None:
        super().__init__(lower, upper, population, params if params is not None else IABCParams(), rng)

    params: IABCParams

    @property
    def literal(self) -> bool:
        """Whether this is the document's literal variant.

        Returns
        -------
        bool
            ``params.variant == "document"``.
        """
        return self.params.variant == "document"

    def _onlooker_probabilities(self) -> FloatArray:
        s = self.params.rank_pressure
        if self.literal or s == 0.0:
            return super()._onlooker_probabilities()
        return rank_probabilities(self.f, s)

    def _ordered(self, X: FloatArray) -> FloatArray:
        """Random sources put through the problem's repair (improved variant with ``repair``, no seeds)."""
        if self.literal or self.repair is None or not self.params.repair or self._x0.size:
            return X
        return self.clip(self.repair(X))

    def _initial(self) -> FloatArray:
        chaos = logistic_map_population if self.literal else chaotic_uniform_population
        return self._ordered(self.lower + chaos(self.n, self.dim, self.params.mu, self.rng) * self.span)

    def _fresh(self, m: int) -> FloatArray:
        return self._ordered(super()._fresh(m))

    def _move(self, idx: IntArray) -> FloatArray:
        if self.literal:
            return super()._move(idx)
        rng, p = self.rng, self.params
        partner = _partners(idx, self.n, rng)
        mask = rng.random((idx.size, self.dim)) < p.modification_rate
        mask[np.arange(idx.size), rng.integers(0, self.dim, size=idx.size)] = True
        phi = rng.uniform(-1.0, 1.0, size=mask.shape)
        psi = rng.uniform(0.0, p.guided, size=mask.shape)
        return guided_move(self.X, idx, partner, mask, phi, psi, self._centres(idx.size))

    def _end_of_iteration(self) -> str:
        return "mutation"

    def _mutants(self) -> FloatArray:
        p = self.params
        m = max(1, int(round(p.mutation_fraction * self.n)))
        self._idx = np.argsort(self.f, kind="stable")[-m:]
        if self.literal:
            frac = min(self.iteration / max(p.max_iterations - 1, 1), 1.0)
            sigma = (p.sigma + (p.sigma_final - p.sigma) * frac) * self.span
            return self.clip(gaussian_mutation(self.X[self._idx], sigma, self.rng))
        sigma = p.sigma_spread * self.X.std(axis=0)
        return self.clip(gaussian_mutation(self._centres(m), sigma, self.rng))

    def _centres(self, m: int) -> FloatArray:
        """``m`` attraction centres: the best source (``elite = 0``), or sources drawn at random
        among the best ``elite`` share of the colony."""
        e = max(1, int(round(self.params.elite * self.n)))
        if e == 1:
            best: FloatArray = np.broadcast_to(self.X[int(np.argmin(self.f))], (m, self.dim))
            return best
        top = np.argsort(self.f, kind="stable")[:e]
        drawn: FloatArray = self.X[top[self.rng.integers(0, e, size=m)]]
        return drawn
