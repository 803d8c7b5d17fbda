"""The compiled nearest surface point of an ellipsoid (:meth:`auvplan.world.obstacles.Ellipsoid._foot_point`).

The foot point of a body-frame point ``p`` (first octant by symmetry) is ``a² p / (a² + t)`` where
``t`` is the root of ``Σ (a p / (a² + t))² = 1`` (outside: ``t`` in ``[0, a_max |p|]``; inside:
``t`` in ``[-a_min², 0]``); 64 bisections shrink the bracket below float64 resolution.  The kernel
runs exactly the operations of the numpy version it replaced, point by point and in the same order,
without fast-math liberties (``fastmath=False``), so its results are bit-identical to it
(``tests/oracles/test_ellipsoid_kernels.py`` holds them against that numpy reference).

That numpy version is kept as :func:`foot_point_numpy`: with compiling switched off
(``NUMBA_DISABLE_JIT=1``) the kernel would run its bisection as plain Python point by point, so
:func:`foot_point` then runs the numpy version on all points at once (same results, bit for bit).
"""

from __future__ import annotations

import math

import numpy as np

from ..._types import FloatArray
from ...runtime.jit import jit_enabled, kernel

__all__ = ["foot_point", "foot_point_kernel", "foot_point_numpy"]


@kernel(fastmath=False)
def foot_point_kernel(a: FloatArray, pb: FloatArray) -> FloatArray:
    """Nearest surface points (body frame) of body-frame points.

    Parameters
    ----------
    a : numpy.ndarray
        Semi-axes ``(3,)`` (m).
    pb : numpy.ndarray
        Points ``(N, 3)`` in the ellipsoid's body frame (m).

    Returns
    -------
    numpy.ndarray
        Foot points ``(N, 3)`` (m, body frame).
    """
    n = pb.shape[0]
    out = np.empty((n, 3))
    a2 = np.empty(3)
    ap = np.empty(3)
    p = np.empty(3)
    amin = a[0]
    amax = a[0]
    for k in range(3):
        a2[k] = a[k] * a[k]
        amin = a[k] if a[k] < amin else amin
        amax = a[k] if a[k] > amax else amax
    for i in range(n):
        s2 = 0.0
        nn = 0.0
        for k in range(3):
            v = abs(pb[i, k])
            floor = 1e-10 * a[k]
            # a zero coordinate on the minor axis is a degenerate (non-smooth) case: nudge it (NaN stays NaN)
            p[k] = floor if v < floor else v
            r = p[k] / a[k]
            s2 = s2 + r * r if k else r * r
            nn = nn + p[k] * p[k] if k else p[k] * p[k]
            ap[k] = a[k] * p[k]
        if s2 >= 1.0:
            lo = 0.0
            hi = amax * math.sqrt(nn)
        else:
            lo = -(amin * amin)
            hi = 0.0
        for _ in range(64):  # the bracket shrinks 2^-64: below float64 resolution of t
            mid = 0.5 * (lo + hi)
            f = 0.0
            for k in range(3):
                r = ap[k] / (a2[k] + mid)
                f = f + r * r if k else r * r
            if f - 1.0 > 0:
                lo = mid
            else:
                hi = mid
        t = 0.5 * (lo + hi)
        for k in range(3):
            q = a2[k] * p[k] / (a2[k] + t)
            out[i, k] = -q if pb[i, k] < 0 else q
    return out


def foot_point_numpy(a: FloatArray, pb: FloatArray) -> FloatArray:
    """:func:`foot_point_kernel` vectorised over the points in numpy (the same operations, bit-identical).

    Parameters
    ----------
    a : numpy.ndarray
        Semi-axes ``(3,)`` (m).
    pb : numpy.ndarray
        Points ``(N, 3)`` in the ellipsoid's body frame (m).

    Returns
    -------
    numpy.ndarray
        Foot points ``(N, 3)`` (m, body frame).
    """
    with np.errstate(all="ignore"):  # inf/nan as in the kernel, silently (error_model="numpy")
        sign = np.where(pb < 0, -1.0, 1.0)
        p = np.maximum(np.abs(pb), 1e-10 * a)
        outside = ((p / a) ** 2).sum(axis=-1) >= 1.0
        lo = np.where(outside, 0.0, -(a.min() ** 2))
        hi = np.where(outside, a.max() * np.linalg.norm(p, axis=-1), 0.0)
        a2 = a * a
        ap = a * p
        for _ in range(64):
            mid = 0.5 * (lo + hi)
            pos = ((ap / (a2 + mid[:, None])) ** 2).sum(axis=-1) - 1.0 > 0
            lo = np.where(pos, mid, lo)
            hi = np.where(pos, hi, mid)
        t = 0.5 * (lo + hi)
        out: FloatArray = sign * (a2 * p / (a2 + t[:, None]))
    return out


def foot_point(a: FloatArray, pb: FloatArray) -> FloatArray:
    """Nearest surface points (body frame): the compiled kernel, or its numpy version when compiling is off.

    Parameters
    ----------
    a : numpy.ndarray
        Semi-axes ``(3,)`` (m).
    pb : numpy.ndarray
        Points ``(N, 3)`` in the ellipsoid's body frame (m).

    Returns
    -------
    numpy.ndarray
        Foot points ``(N, 3)`` (m, body frame).
    """
    if jit_enabled():
        return foot_point_kernel(a, pb)
    return foot_point_numpy(np.asarray(a, dtype=float), np.asarray(pb, dtype=float))
