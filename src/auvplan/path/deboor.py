"""The basis matrix of a B-spline by de Boor's recursion, in numpy: ``scipy.interpolate.BSpline``'s values,
bit for bit, without importing ``scipy.interpolate`` (~0.2 s of every ``plan``'s start; issue 56).

``BSpline(t, eye(K), k).derivative(m)(u)`` is what :func:`auvplan.path.curves.basis_matrix` needs.  SciPy
makes the derivative's coefficients with FITPACK's differencing (``splder``: ``(c[i+1] - c[i]) * k /
(t[i+k+1] - t[i+1])``, knots trimmed, degree lowered, once per order), then evaluates at each ``u``: the
knot interval ``l`` with ``t[l] <= u < t[l+1]`` (clipped to the base interval), the ``k + 1`` non-zero
basis values by de Boor's recursion (``_deBoor_D``), and ``sum_a c[l + a - k] * h[a]`` from 0.0 in the
order ``a = 0 … k``.  :func:`basis` performs the same IEEE operations in the same order, vectorised over
``u``: the same doubles (``tests/unit/test_deboor.py`` compares against SciPy over the shapes the planners use).
"""

from __future__ import annotations

import numpy as np

from .._types import FloatArray

__all__ = ["basis"]


def _derivative_coefficients(t: FloatArray, c: FloatArray, k: int, order: int) -> tuple[FloatArray, FloatArray, int]:
    """``splder``: the knots, coefficients (padded to the knots' length) and degree of the ``order``-th
    derivative."""
    pad = t.shape[0] - c.shape[0]
    if pad > 0:
        c = np.concatenate([c, np.zeros((pad,) + c.shape[1:])])
    with np.errstate(invalid="raise", divide="raise"):
        for _ in range(order):
            dt = (t[k + 1:-1] - t[1:-k - 1])[:, None]
            c = (c[1:-1 - k] - c[:-2 - k]) * k / dt
            c = np.concatenate([c, np.zeros((k,) + c.shape[1:])])
            t = t[1:-1]
            k -= 1
    return t, c, k


def _intervals(t: FloatArray, k: int, u: FloatArray) -> np.ndarray:
    """``l`` with ``t[l] <= u < t[l+1]``, within ``[k, n - 1]`` (SciPy's ``find_interval``, extrapolating)."""
    n = t.shape[0] - k - 1
    return np.clip(np.searchsorted(t, u, side="right") - 1, k, n - 1)


def _deboor(t: FloatArray, k: int, ell: np.ndarray, u: FloatArray) -> FloatArray:
    """The ``k + 1`` non-zero basis values at each ``u`` (``(S, k + 1)``): de Boor's recursion."""
    h = np.zeros((u.shape[0], k + 1))
    h[:, 0] = 1.0
    for j in range(1, k + 1):
        hh = h[:, :j].copy()
        h[:, 0] = 0.0
        for n in range(1, j + 1):
            xb, xa = t[ell + n], t[ell + n - j]
            same = xb == xa  # SciPy's guard; never true inside a non-empty span t[l] < t[l+1]
            with np.errstate(divide="ignore", invalid="ignore"):
                w = hh[:, n - 1] / (xb - xa)
            h[:, n - 1] = np.where(same, h[:, n - 1], h[:, n - 1] + w * (xb - u))
            h[:, n] = np.where(same, 0.0, w * (u - xa))
    return h


def basis(knots: FloatArray, n_control: int, u: FloatArray, order: int, degree: int = 3) -> FloatArray:
    """``BSpline(knots, eye(n_control), degree).derivative(order)(u)`` (``order`` 0: the spline itself).

    Parameters
    ----------
    knots : numpy.ndarray
        Knot vector ``(n_control + degree + 1,)``, non-decreasing.
    n_control : int
        Number of coefficients ``K``.
    u : numpy.ndarray
        Parameters ``(S,)`` (outside the base interval: extrapolated from the end intervals).
    order : int
        Derivative order, ``0 <= order <= degree``.
    degree : int, default 3
        Spline degree.

    Returns
    -------
    numpy.ndarray
        ``(S, K)``: row ``s`` holds every basis function's (derivative's) value at ``u[s]``.

    Raises
    ------
    ValueError
        If ``order`` exceeds ``degree``, or the knots repeat inside so that the derivative does not exist.
    """
    if not 0 <= order <= degree:
        raise ValueError(f"derivative order {order} must be within [0, {degree}]")
    t = np.asarray(knots, dtype=float)
    u = np.asarray(u, dtype=float)
    try:
        t, c, k = _derivative_coefficients(t, np.eye(n_control), degree, order)
    except FloatingPointError as exc:
        raise ValueError(f"the spline has internal repeated knots and is not differentiable {order} times") from exc
    ell = _intervals(t, k, u)
    h = _deboor(t, k, ell, u)
    out = np.zeros((u.shape[0], n_control))
    for a in range(k + 1):
        out += c[ell + a - k, :n_control] * h[:, a:a + 1]
    return out
