"""Optimisers: pure kernels with fixed draws, convergence on test functions, determinism, budgets."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.optim import ABC, GA, IABC, PSO, Termination, minimize
from auvplan.optim.bee import abc_fitness, gaussian_mutation, logistic_map_population, neighbour_move
from auvplan.optim.ga import polynomial_mutation, sbx, tournament
from auvplan.optim.pso import pso_step

OPTIMISERS = [ABC, IABC, GA, PSO]


def sphere(X):
    return (X**2).sum(axis=1)


def rosenbrock(X):
    return (100.0 * (X[:, 1:] - X[:, :-1] ** 2) ** 2 + (1.0 - X[:, :-1]) ** 2).sum(axis=1)


@pytest.mark.parametrize("cls", OPTIMISERS)
def test_sphere_10d(cls):
    """Budget 50 000 evaluations, population 50: f < 1e-6 (the optimum is 0)."""
    r = minimize(sphere, cls(np.full(10, -5.0), np.full(10, 5.0), 50, rng=1),
                 Termination(max_iterations=None, max_evaluations=50_000))
    assert r.f < 1e-6 and np.abs(r.x).max() < 1e-3
    assert r.evaluations == 50_000


@pytest.mark.parametrize("cls", OPTIMISERS)
def test_rosenbrock_10d(cls):
    """Budget 100 000 evaluations: f < 10 from a start around 1e4 (the valley floor is reached)."""
    r = minimize(rosenbrock, cls(np.full(10, -2.0), np.full(10, 2.0), 50, rng=2),
                 Termination(max_iterations=None, max_evaluations=100_000))
    assert r.f < 10.0
    assert np.all(np.diff(r.history) <= 1e-12)  # best-so-far never gets worse


@pytest.mark.parametrize("cls", OPTIMISERS)
def test_same_seed_same_result(cls):
    runs = [minimize(rosenbrock, cls(np.full(6, -2.0), np.full(6, 2.0), 20, rng=7), Termination(max_iterations=30))
            for _ in range(2)]
    assert np.array_equal(runs[0].x, runs[1].x) and np.array_equal(runs[0].history, runs[1].history)
    other = minimize(rosenbrock, cls(np.full(6, -2.0), np.full(6, 2.0), 20, rng=8), Termination(max_iterations=30))
    assert not np.array_equal(other.x, runs[0].x)


@pytest.mark.parametrize("cls", OPTIMISERS)
def test_budget_is_exact_and_bounds_respected(cls):
    seen = []

    def f(X):
        seen.append(X.copy())
        return sphere(X - 3.0)

    r = minimize(f, cls(np.full(4, -1.0), np.full(4, 1.0), 10, rng=0), Termination(max_evaluations=777))
    X = np.vstack(seen)
    assert r.evaluations == 777 == X.shape[0]
    assert X.min() >= -1.0 and X.max() <= 1.0
    assert np.allclose(r.x, 1.0, atol=0.2)  # the optimum sits on the bound


def test_abc_fitness_eq20():
    assert np.allclose(abc_fitness(np.array([0.0, 1.0, 3.0, -2.0, np.inf])), [1.0, 0.5, 0.25, 3.0, 0.0])


def test_neighbour_move_eq19_changes_one_dimension():
    X = np.arange(12.0).reshape(4, 3)
    V = neighbour_move(X, np.array([0, 2]), np.array([1, 3]), np.array([2, 0]), np.array([0.5, -1.0]))
    assert np.allclose(V[0], [0, 1, 2 + 0.5 * (2 - 5)]) and np.allclose(V[1], [6 - 1.0 * (6 - 9), 7, 8])


def test_logistic_map_is_the_recurrence_and_chaotic():
    rng = np.random.default_rng(0)
    P = logistic_map_population(200, 5, 4.0, rng)
    assert np.allclose(P[1:], 4.0 * P[:-1] * (1.0 - P[:-1]))
    assert P.min() >= 0 and P.max() <= 1
    # the invariant density of the μ = 4 map is the arcsine law: mean 1/2, variance 1/8
    big = logistic_map_population(20000, 1, 4.0, np.random.default_rng(1))
    assert big.mean() == pytest.approx(0.5, abs=0.02) and big.var() == pytest.approx(0.125, abs=0.01)


def test_gaussian_mutation_statistics():
    X = np.zeros((20000, 2))
    Y = gaussian_mutation(X, np.array([1.0, 0.1]), np.random.default_rng(3))
    assert Y.std(axis=0) == pytest.approx([1.0, 0.1], rel=0.03)


# "IABC's mutation only accepts improvements" is held by
# test_oracles.py::test_one_iabc_iteration_mutates_the_worst_and_keeps_only_improvements (one ask/tell by hand
# with the generator's draws copied); the shape-only test that stood here could not fail.


def test_pso_step_pure():
    X = np.zeros((1, 2))
    V = np.ones((1, 2))
    Xn, Vn = pso_step(X, V, np.ones((1, 2)), np.full(2, 2.0), 0.5, 1.0, 1.0, np.ones((1, 2)), np.ones((1, 2)), 10.0)
    assert np.allclose(Vn, 0.5 + 1 + 2) and np.allclose(Xn, 3.5)
    _, Vc = pso_step(X, V, np.ones((1, 2)), np.full(2, 2.0), 0.5, 1.0, 1.0, np.ones((1, 2)), np.ones((1, 2)), 1.0)
    assert np.allclose(Vc, 1.0)


def test_ga_operators():
    rng = np.random.default_rng(0)
    f = np.array([5.0, 1.0, 3.0])
    winners = tournament(f, 1000, 3, rng)
    assert np.mean(winners == 1) > 0.6
    p1, p2 = np.zeros((500, 4)), np.ones((500, 4))
    c1, c2 = sbx(p1, p2, 15.0, 1.0, 0.0, 1.0, rng)
    assert np.allclose(c1 + c2, 1.0)  # SBX preserves the parents' mean
    M = polynomial_mutation(np.full((2000, 3), 0.5), 20.0, 1.0, 0.0, 1.0, rng)
    assert M.min() >= 0 and M.max() <= 1 and abs(M.mean() - 0.5) < 0.01
