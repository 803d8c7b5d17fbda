"""The one way auvplan compiles its inner loops (numba).

Kernels are cached on disk, release the GIL, raise no Python exceptions on division
(``error_model="numpy"``: inf/nan as in numpy) and allow only the floating-point
liberties that cannot change which values are finite: no signed zeros, reciprocal
multiplication and fused multiply-add (no ``nnan``/``ninf``, so ±inf margins keep working).
"""

from __future__ import annotations

from numba import njit

__all__ = ["kernel"]


def kernel(fn=None, **options):
    """Decorator: ``numba.njit`` with auvplan's settings (``options`` are passed on)."""
    settings = dict(cache=True, nogil=True, error_model="numpy", fastmath={"nsz", "arcp", "contract"}, **options)
    return njit(**settings) if fn is None else njit(**settings)(fn)
