"""The exact Euclidean distance transform of a 2D mask: ``scipy.ndimage.distance_transform_edt``'s values,
bit for bit, without importing ``scipy.ndimage`` (~0.2-0.3 s of CPU at a command's start, issue 56).

For every true element, the distance to the nearest false one, in cells.  SciPy finds each element's
nearest false element (an exact feature transform) and returns ``sqrt(dy * dy + dx * dx)`` in float64 from
the integer offsets; the squared distance is an integer far below 2**53, so it is exact, and the square
root is correctly rounded: any exact method that finds the least squared distance returns the same bits.
Here (Felzenszwalb & Huttenlocher 2012, "Distance transforms of sampled functions", Theory of Computing 8):
a pass down each column gives the vertical distance ``g`` to the nearest false element of the column; then
along each row ``D2[j] = min_k g[k]**2 + (j - k)**2`` — in numpy over the column offsets for small masks,
and for large ones by the lower envelope of the parabolas (:func:`_rows_envelope`, compiled; its
breakpoints compared as exact integer fractions, so no rounding picks a wrong parabola).  A mask with no
false element is handed to SciPy (its own convention for that case).

Callers: the time-optimal planner's obstacle distance and the zones' raster (``world.zones.parts``).
``tests/oracles/test_edt.py`` compares every value with SciPy's on random masks of many shapes.
"""

from __future__ import annotations

import numpy as np

from ..._types import BoolArray, FloatArray
from ...runtime.jit import kernel

__all__ = ["dilate_cross", "distance_transform", "window_any"]

SMALL = 1 << 22
"""Above ``rows * cols**2`` elements the row pass takes the compiled envelope, below the numpy offsets."""


def _columns(mask: BoolArray) -> FloatArray:
    """Squared distance down each column to the nearest false element (inf in a column without one)."""
    ny = mask.shape[0]
    at = np.arange(ny, dtype=np.float64)[:, None]
    before = np.maximum.accumulate(np.where(mask, -np.inf, at), axis=0)
    after = np.minimum.accumulate(np.where(mask, np.inf, at)[::-1], axis=0)[::-1]
    g = np.minimum(at - before, after - at)
    return g * g


def _rows_offsets(g2: FloatArray) -> FloatArray:
    """``min_k g2[:, k] + (j - k)**2`` over the offsets ``|j - k|``, stopping once no offset can lower it."""
    d2 = g2.copy()
    nx = g2.shape[1]
    for d in range(1, nx):
        dd = float(d * d)
        if dd >= d2.max():
            break
        np.minimum(d2[:, :-d], g2[:, d:] + dd, out=d2[:, :-d])
        np.minimum(d2[:, d:], g2[:, :-d] + dd, out=d2[:, d:])
    return d2


@kernel
def _rows_envelope(g2: FloatArray, out: FloatArray) -> None:  # pragma: no cover - compiled
    """``out[i, j] = min_k g2[i, k] + (j - k)**2`` by the lower envelope of the parabolas of each row.

    Parameters
    ----------
    g2 : numpy.ndarray
        ``(ny, nx)`` squared column distances: whole numbers, or inf for a column without a false element
        (such a column is no parabola).
    out : numpy.ndarray
        ``(ny, nx)``, filled (float64 whole numbers).
    """
    ny, nx = g2.shape
    v = np.empty(nx, dtype=np.int64)  # the parabolas' columns, left to right
    zn = np.empty(nx + 1, dtype=np.int64)  # breakpoint k is zn[k] / zd[k] (zd > 0); k = 0 is -infinity
    zd = np.empty(nx + 1, dtype=np.int64)
    for i in range(ny):
        k = -1
        for q in range(nx):
            if not np.isfinite(g2[i, q]):
                continue
            fq = np.int64(g2[i, q]) + q * q
            while k >= 0:
                p = v[k]
                num = fq - (np.int64(g2[i, p]) + p * p)  # breakpoint of p and q: num / den
                den = 2 * (q - p)
                if k > 0 and num * zd[k] <= zn[k] * den:  # at or left of p's own: p is never lowest
                    k -= 1
                    continue
                k += 1
                v[k], zn[k], zd[k] = q, num, den
                break
            if k < 0:
                k = 0
                v[0], zn[0], zd[0] = q, -1, 0
        j_k = 0
        for j in range(nx):
            while j_k < k and zn[j_k + 1] < j * zd[j_k + 1]:  # breakpoint strictly left of j
                j_k += 1
            p = v[j_k]
            out[i, j] = float((j - p) * (j - p) + np.int64(g2[i, p]))


def distance_transform(mask: BoolArray) -> FloatArray:
    """``scipy.ndimage.distance_transform_edt(mask)`` of a 2D mask, the same float64 bits.

    Parameters
    ----------
    mask : numpy.ndarray
        ``(ny, nx)``, bool (or anything whose truth is taken elementwise).

    Returns
    -------
    numpy.ndarray
        ``(ny, nx)`` float64: 0 where ``mask`` is false, else the distance (cells) to the nearest false element.
    """
    mask = np.asarray(mask, dtype=bool)
    if mask.ndim != 2 or mask.size == 0 or mask.all():
        from scipy.ndimage import distance_transform_edt  # SciPy's own answer for what is not covered here

        return np.asarray(distance_transform_edt(mask), dtype=np.float64)
    g2 = _columns(mask)
    ny, nx = mask.shape
    if ny * nx * nx <= SMALL:
        d2 = _rows_offsets(g2)
    else:
        d2 = np.empty_like(g2)
        _rows_envelope(np.ascontiguousarray(g2), d2)
    return np.sqrt(d2)


def dilate_cross(mask: BoolArray, iterations: int) -> BoolArray:
    """``scipy.ndimage.binary_dilation(mask, iterations=iterations)`` of a 2D mask (the cross, 4-neighbours).

    Each iteration adds the 4-neighbours of the true elements inside the array (SciPy's border is false):
    the elements within ``iterations`` steps of a true one.

    Parameters
    ----------
    mask : numpy.ndarray
        ``(ny, nx)`` bool.
    iterations : int
        Steps, at least 1.

    Returns
    -------
    numpy.ndarray
        ``(ny, nx)`` bool.
    """
    out = np.array(mask, dtype=bool)
    if out.ndim != 2 or iterations < 1:
        from scipy.ndimage import binary_dilation  # SciPy's own conventions (iterate until stable, n-D)

        return np.asarray(binary_dilation(mask, iterations=iterations), dtype=bool)
    for _ in range(iterations):
        grown = out.copy()
        grown[1:] |= out[:-1]
        grown[:-1] |= out[1:]
        grown[:, 1:] |= out[:, :-1]
        grown[:, :-1] |= out[:, 1:]
        out = grown
    return out


def window_any(mask: BoolArray, size: tuple[int, ...]) -> BoolArray:
    """``scipy.ndimage.maximum_filter(mask, size=size, mode="nearest")`` of a bool array, odd sizes.

    The maximum of booleans over a box is their OR, taken one axis at a time; ``mode="nearest"`` repeats
    the edge, which adds nothing to an OR over the box clipped to the array.

    Parameters
    ----------
    mask : numpy.ndarray
        bool, any number of dimensions.
    size : tuple of int
        The box's odd length along each axis (centred).

    Returns
    -------
    numpy.ndarray
        bool, the shape of ``mask``.
    """
    out = np.array(mask, dtype=bool)
    if len(size) != out.ndim or any(s < 1 or s % 2 == 0 for s in size):
        from scipy.ndimage import maximum_filter  # even boxes: SciPy's own origin convention

        return np.asarray(maximum_filter(mask, size=size, mode="nearest"), dtype=bool)
    for axis, s in enumerate(size):
        src = np.moveaxis(out, axis, 0)
        grown = src.copy()
        for o in range(1, s // 2 + 1):
            grown[o:] |= src[:-o]
            grown[:-o] |= src[o:]
        out = np.moveaxis(grown, 0, axis)
    return out
