"""The B-spline basis by de Boor's recursion (:mod:`auvplan.path.deboor`) is SciPy's, bit for bit: the
planners' basis matrices no longer import ``scipy.interpolate`` (issue 56) and their results must not move."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import BSpline

from auvplan.path.curves import clamped_knots
from auvplan.path.deboor import basis


def _scipy(knots: np.ndarray, k: int, u: np.ndarray, order: int) -> np.ndarray:
    spline = BSpline(knots, np.eye(k), 3)
    return np.ascontiguousarray((spline.derivative(order) if order else spline)(u))


@pytest.mark.parametrize("order", [0, 1, 2, 3])
def test_the_clamped_basis_is_scipys_bit_for_bit(order: int) -> None:
    """Oracle: ``scipy.interpolate.BSpline``; compared as int64 bit patterns (so even a zero's sign counts), over
    control counts from the fewest (4) to a grid path's hundreds and sample counts odd, even and 2."""
    for k in (4, 5, 6, 7, 12, 33, 64, 257):
        for s in (2, 3, 50, 200, 513):
            u = np.linspace(0.0, 1.0, s)
            want, got = _scipy(clamped_knots(k), k, u, order), basis(clamped_knots(k), k, u, order)
            assert got.shape == want.shape == (s, k)
            assert np.array_equal(got.view(np.int64), want.view(np.int64)), (k, s, order)


def test_uneven_knots_and_parameters_outside_the_base_interval() -> None:
    """Oracle: SciPy again, on non-uniform interior knots and parameters beyond [0, 1] (extrapolated from the
    end spans) and exactly on knots."""
    knots = np.r_[np.zeros(4), 0.1, 0.15, 0.5, 0.9, np.ones(4)]
    u = np.r_[-0.2, 0.0, 0.1, 0.12, 0.15, 0.5, 0.77, 0.9, 1.0, 1.3]
    for order in range(4):
        want, got = _scipy(knots, 8, u, order), basis(knots, 8, u, order)
        assert np.array_equal(got.view(np.int64), want.view(np.int64)), order
    triple = np.r_[np.zeros(4), 0.3, 0.5, 0.5, 0.5, 0.8, np.ones(4)]  # a triple inner knot: empty spans inside
    for order in range(2):
        want, got = _scipy(triple, 9, u, order), basis(triple, 9, u, order)
        assert np.array_equal(got.view(np.int64), want.view(np.int64)), order


def test_positions_sum_to_one_and_bad_orders_are_refused() -> None:
    """Partition of unity (the basis of a clamped spline sums to 1 at every parameter), by hand."""
    m = basis(clamped_knots(9), 9, np.linspace(0.0, 1.0, 41), 0)
    assert np.allclose(m.sum(axis=1), 1.0, rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="derivative order 4"):
        basis(clamped_knots(9), 9, np.linspace(0.0, 1.0, 5), 4)
    with pytest.raises(ValueError, match="not differentiable"):
        basis(np.r_[np.zeros(4), 0.5, 0.5, 0.5, 0.5, np.ones(4)], 8, np.linspace(0.0, 1.0, 5), 1)
