"""The compiled nearest surface point of an ellipsoid (:meth:`auvplan.world.obstacles.Ellipsoid._foot_point`).

The foot point of a body-frame point ``p`` (first octant by symmetry) is ``a² p / (a² + t)`` where
``t`` is the root of ``Σ (a p / (a² + t))² = 1`` (outside: ``t`` in ``[0, a_max |p|]``; inside:
``t`` in ``[-a_min², 0]``); 64 bisections shrink the bracket below float64 resolution.  The kernel
runs exactly the operations of the numpy version it replaced, point by point and in the same order,
without fast-math liberties (``fastmath=False``), so its results are bit-identical to it
(``tests/test_ellipsoid_kernels.py`` holds them against that numpy reference).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .._types import FloatArray

__all__ = ["foot_point_kernel"]


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
