"""The least value of a function of one variable on an interval: Brent's bounded method, step for step as
``scipy.optimize.minimize_scalar(method="bounded")`` takes it.

:func:`auvplan.io.data.regrid.inscribed_extent` refines each side of a grid's footprint with it (20
searches for ``data inspect``'s five seabed models), and the time-optimal planner's shot refinement
(:func:`auvplan.planners.timeopt.zermelo.refine_shot`) its heading.  Importing ``scipy.optimize`` for them
cost ~0.33 s of CPU of a 2 s command, and ~0.2 s of a time-optimal plan's start (issue 56); this is the
same algorithm — golden-section steps and parabolic interpolation (Brent 1973, ch. 5; Forsythe, Malcolm &
Moler 1977, ``fmin``), the acceptance tests, the tolerance ``sqrt(eps) |x| + xatol / 3`` and the
function-count limit of SciPy 1.17's ``_minimize_scalar_bounded`` — in the same floating-point operations,
so that it evaluates the function at the same points and returns the same bits
(``tests/oracles/test_front_door_search.py`` checks this against SciPy itself): the extents, and every
seabed model and plan made from them, are unchanged.
"""

from __future__ import annotations

import math
from collections.abc import Callable

__all__ = ["bounded_min"]

_SQRT_EPS = math.sqrt(2.2e-16)
"""SciPy's ``sqrt_eps`` (from its literal 2.2e-16, not the machine epsilon)."""

_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))
"""The golden-section fraction."""


def _sign(v: float) -> float:
    """``numpy.sign(v) + (v == 0)``: +1 for v ≥ 0 (so a zero step goes right), -1 below, NaN for NaN."""
    if v != v:
        return v
    return 1.0 if v >= 0.0 else -1.0


def bounded_min(func: Callable[[float], float], lo: float, hi: float, xatol: float = 1e-5,
                maxfun: int = 500) -> tuple[float, float, int]:
    """Minimise ``func`` on ``[lo, hi]`` by Brent's bounded method.

    Parameters
    ----------
    func : callable
        ``float -> float``.
    lo, hi : float
        The interval (finite, ``lo <= hi``).
    xatol : float, optional
        Absolute tolerance in x.
    maxfun : int, optional
        Most evaluations of ``func``.

    Returns
    -------
    x, fx : float
        The best point found and its value (SciPy's ``res.x``, ``res.fun``).
    nfev : int
        Evaluations made.

    Raises
    ------
    ValueError
        If the bounds are not finite or ``lo > hi``.
    """
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError("bounds must be finite")
    if lo > hi:
        raise ValueError("the lower bound exceeds the upper bound")
    a, b = float(lo), float(hi)
    fulc = a + _GOLDEN * (b - a)
    nfc = xf = fulc
    rat = e = 0.0
    fx = float(func(xf))
    num = 1
    ffulc = fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(xf - xm) > tol2 - 0.5 * (b - a):
        rat, e = _step(a, b, xf, fx, nfc, fnfc, fulc, ffulc, xm, tol1, tol2, rat, e)
        x = xf + _sign(rat) * max(abs(rat), tol1)
        fu = float(func(x))
        num += 1
        a, b, xf, fx, nfc, fnfc, fulc, ffulc = _keep(a, b, x, fu, xf, fx, nfc, fnfc, fulc, ffulc)
        xm = 0.5 * (a + b)
        tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxfun:
            break
    return xf, fx, num


def _step(a: float, b: float, xf: float, fx: float, nfc: float, fnfc: float, fulc: float, ffulc: float, xm: float,
          tol1: float, tol2: float, rat: float, e: float) -> tuple[float, float]:
    """The next step from the best point ``xf`` and the step before last: a parabola through the three best points
    (``xf``, ``nfc``, ``fulc``) when it is acceptable, else a golden section of the larger part of ``[a, b]``."""
    golden = True
    if abs(e) > tol1:  # try a parabola through the three best points
        golden = False
        r = (xf - nfc) * (fx - ffulc)
        q = (xf - fulc) * (fx - fnfc)
        p = (xf - fulc) * q - (xf - nfc) * r
        q = 2.0 * (q - r)
        if q > 0.0:
            p = -p
        q = abs(q)
        r, e = e, rat
        if abs(p) < abs(0.5 * q * r) and p > q * (a - xf) and p < q * (b - xf):
            rat = (p + 0.0) / q
            x = xf + rat
            if (x - a) < tol2 or (b - x) < tol2:
                rat = tol1 * _sign(xm - xf)
        else:
            golden = True
    if golden:
        e = (a - xf) if xf >= xm else (b - xf)
        rat = _GOLDEN * e
    return rat, e


def _keep(a: float, b: float, x: float, fu: float, xf: float, fx: float, nfc: float, fnfc: float, fulc: float,
          ffulc: float) -> tuple[float, float, float, float, float, float, float, float]:
    """The interval ``[a, b]`` and the three best points (``xf``, ``nfc``, ``fulc``, with their values) once
    ``fu = func(x)`` is known."""
    if fu <= fx:
        if x >= xf:
            a = xf
        else:
            b = xf
        fulc, ffulc = nfc, fnfc
        nfc, fnfc = xf, fx
        xf, fx = x, fu
    else:
        if x < xf:
            a = x
        else:
            b = x
        if fu <= fnfc or nfc == xf:
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = x, fu
        elif fu <= ffulc or fulc == xf or fulc == nfc:
            fulc, ffulc = x, fu
    return a, b, xf, fx, nfc, fnfc, fulc, ffulc
