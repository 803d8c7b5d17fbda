"""The compiled kernels of the seabed heightfield :class:`~auvplan.world.terrain.Terrain`: the bilinear
elevation of one point (:func:`elevation_kernel`) and the exact least altitude of a segment above the seabed
(:func:`min_altitude_kernel`): every grid line the segment crosses splits it into pieces that each lie in one
cell; along a piece the bilinear surface is a quadratic in the segment parameter, so the altitude is a
quadratic whose minimum is at a piece end or at its vertex (docs/methods.md §4, the exact collision model).
A provable lower bound first clears the segments far above the seabed; :func:`box_floor_kernel` is a second
one, from the highest seabed under the segment's bounding box (:attr:`Terrain.cell_max`).
"""

from __future__ import annotations

import math

from ..._types import FloatArray
from ...runtime.jit import kernel

__all__ = ["elevation_kernel", "min_altitude_kernel", "lipschitz_bound_kernel", "box_floor_kernel",
           "walk_min_kernel"]


@kernel(inline="always")
def _cell(f: float, cells: int) -> int:
    """Index of the cell holding grid coordinate ``f``, clamped to ``[0, cells - 1]``."""
    i = math.floor(f)
    return 0 if i < 0 else (cells - 1 if i > cells - 1 else int(i))


@kernel
def elevation_kernel(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, x: float, y: float) -> float:
    """Compiled :meth:`Terrain.elevation` of one point.

    Parameters
    ----------
    coef : numpy.ndarray
        Bilinear coefficients per cell ``(ny - 1, nx - 1, 4)`` (m).
    x0, y0 : float
        Grid origin (m).
    dx, dy : float
        Cell sizes (m).
    x, y : float
        The point (m).

    Returns
    -------
    float
        Seabed elevation (m); NaN for a NaN coordinate.

    Notes
    -----
    The arguments before ``x`` are the first five of :attr:`Terrain.kernel_data`.
    """
    if not (x == x and y == y):
        return math.nan
    fx = (x - x0) / dx
    fy = (y - y0) / dy
    i = _cell(fx, coef.shape[1])
    j = _cell(fy, coef.shape[0])
    u = min(max(fx - i, 0.0), 1.0)
    v = min(max(fy - j, 0.0), 1.0)
    zb: float = coef[j, i, 0] + coef[j, i, 1] * u + coef[j, i, 2] * v + coef[j, i, 3] * u * v
    return zb


@kernel
def _elevations(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, x: FloatArray, y: FloatArray,
                out: FloatArray) -> None:
    for k in range(x.size):
        out[k] = elevation_kernel(coef, x0, y0, dx, dy, x[k], y[k])


@kernel
def _piece_min(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, px: float, py: float, pz: float,
               ex: float, ey: float, ez: float, ta: float, tb: float) -> float:
    """Minimum altitude over ``p + t e``, ``t in [ta, tb]``, a piece inside one cell: the bilinear
    surface is a quadratic in t there, so the minimum is at an end or at the vertex."""
    nxc, nyc = coef.shape[1], coef.shape[0]
    tm = 0.5 * (ta + tb)
    fx = (px + tm * ex - x0) / dx
    fy = (py + tm * ey - y0) / dy
    i = _cell(fx, nxc)
    j = _cell(fy, nyc)
    # local coordinates u(t) = u0 + du t, v(t) = v0 + dv t; beyond the extent the edge is held
    u0, du = (px - x0) / dx - i, ex / dx
    v0, dv = (py - y0) / dy - j, ey / dy
    if fx < 0.0 or fx > nxc:
        u0, du = (0.0 if fx < 0.0 else 1.0), 0.0
    if fy < 0.0 or fy > nyc:
        v0, dv = (0.0 if fy < 0.0 else 1.0), 0.0
    a, b, c, e = coef[j, i, 0], coef[j, i, 1], coef[j, i, 2], coef[j, i, 3]
    g0 = pz - (a + b * u0 + c * v0 + e * u0 * v0)
    g1 = ez - (b * du + c * dv + e * (u0 * dv + v0 * du))
    g2 = -e * du * dv
    best: float = min(g0 + (g1 + g2 * ta) * ta, g0 + (g1 + g2 * tb) * tb)
    if g2 > 0.0:
        tv = -g1 / (2.0 * g2)
        if ta < tv < tb:
            best = min(best, g0 - g1 * g1 / (4.0 * g2))
    return best


@kernel
def _crossings(pa: float, pb: float, origin: float, step: float,
               lines: int) -> tuple[float, float, float, float, float]:
    """First grid line crossed from ``pa`` to ``pb``, the last one and the direction (+1/-1), and
    the ends in grid units; lines ``0 .. lines`` exist.  ``first`` past ``last`` means none."""
    ka = (pa - origin) / step
    kb = (pb - origin) / step
    if kb > ka:
        return max(math.floor(ka) + 1.0, 0.0), min(math.ceil(kb) - 1.0, float(lines)), 1.0, ka, kb
    if kb < ka:
        return min(math.ceil(ka) - 1.0, float(lines)), max(math.floor(kb) + 1.0, 0.0), -1.0, ka, kb
    return 1.0, 0.0, 1.0, ka, kb


@kernel
def _walk_min(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, px: float, py: float, pz: float,
              qx: float, qy: float, qz: float) -> float:
    """Exact minimum altitude along the segment ``p -> q``: split at every grid line it crosses,
    in order of the segment parameter, and take the least piece minimum."""
    ex, ey, ez = qx - px, qy - py, qz - pz
    kx, kx_end, sx, kxa, kxb = _crossings(px, qx, x0, dx, coef.shape[1])
    ky, ky_end, sy, kya, kyb = _crossings(py, qy, y0, dy, coef.shape[0])
    best = math.inf
    ta = 0.0
    while True:
        tx = (kx - kxa) / (kxb - kxa) if (kx_end - kx) * sx >= 0.0 else 2.0
        ty = (ky - kya) / (kyb - kya) if (ky_end - ky) * sy >= 0.0 else 2.0
        tb = min(tx, ty, 1.0)
        best = min(best, _piece_min(coef, x0, y0, dx, dy, px, py, pz, ex, ey, ez, ta, tb))
        if tb >= 1.0:
            return best
        if tx <= tb:
            kx += sx
        if ty <= tb:
            ky += sy
        ta = tb


@kernel
def min_altitude_kernel(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, lipschitz: float,
                        px: float, py: float, pz: float, qx: float, qy: float, qz: float,
                        g_a: float, g_b: float, threshold: float) -> float:
    """Compiled :meth:`Terrain.segment_min_altitude` of one segment ``p -> q``.

    The lower bound where it already clears ``threshold``, the exact walk elsewhere.

    Parameters
    ----------
    coef : numpy.ndarray
        Bilinear coefficients per cell ``(ny - 1, nx - 1, 4)`` (m).
    x0, y0 : float
        Grid origin (m).
    dx, dy : float
        Cell sizes (m).
    lipschitz : float
        Steepest slope of the surface (m/m).
    px, py, pz : float
        Segment start (m).
    qx, qy, qz : float
        Segment end (m).
    g_a, g_b : float
        Altitudes of the start and the end above the seabed (m).
    threshold : float
        Altitude below which the result is exact (m).

    Returns
    -------
    float
        Minimum altitude along the segment (m), or a lower bound of it that is ``>= threshold``.

    Notes
    -----
    The arguments before ``px`` are :attr:`Terrain.kernel_data`.
    """
    bound = lipschitz_bound_kernel(lipschitz, px, py, pz, qx, qy, qz, g_a, g_b)
    return bound if bound >= threshold else _walk_min(coef, x0, y0, dx, dy, px, py, pz, qx, qy, qz)


@kernel(inline="always")
def lipschitz_bound_kernel(lipschitz: float, px: float, py: float, pz: float, qx: float, qy: float, qz: float,
                           g_a: float, g_b: float) -> float:
    """Lower bound of the least altitude along a segment: :func:`min_altitude_kernel`'s first test.

    Parameters
    ----------
    lipschitz : float
        Steepest slope of the surface (m/m).
    px, py, pz, qx, qy, qz : float
        The segment's ends (m).
    g_a, g_b : float
        Altitudes of its ends above the seabed (m).

    Returns
    -------
    float
        ``min(g_a, g_b, (g_a + g_b - |Δz| - lipschitz · L_h) / 2)`` (m), L_h the horizontal length.
    """
    bound: float = min(g_a, g_b,
                       0.5 * (g_a + g_b - abs(qz - pz) - lipschitz * math.sqrt((qx - px) ** 2 + (qy - py) ** 2)))
    return bound


BOX_CELLS = 36
"""Largest bounding box (in cells) that :func:`box_floor_kernel` scans; a longer segment is left to the walk."""


@kernel
def box_floor_kernel(cell_max: FloatArray, x0: float, y0: float, dx: float, dy: float, px: float, py: float,
                     pz: float, qx: float, qy: float, qz: float) -> float:
    """Lower bound of the least altitude along the segment ``p -> q``: its lowest end less the highest seabed
    of the cells its horizontal bounding box meets (beyond the grid the edge cells, as the surface holds them).

    Parameters
    ----------
    cell_max : numpy.ndarray
        Highest elevation per cell ``(ny - 1, nx - 1)`` (:attr:`Terrain.cell_max`, m).
    x0, y0, dx, dy : float
        Grid origin and cell sizes (m), as in :attr:`Terrain.kernel_data`.
    px, py, pz, qx, qy, qz : float
        The segment's ends (m).

    Returns
    -------
    float
        The bound (m), lowered by 1 µm per km of seabed height against rounding; ``-inf`` when the box
        spans more than :data:`BOX_CELLS` cells or a coordinate is not finite (then nothing is bounded).
    """
    if not (abs(px) < 1e15 and abs(py) < 1e15 and abs(qx) < 1e15 and abs(qy) < 1e15):
        return -math.inf  # NaN or huge: no index
    nxc, nyc = cell_max.shape[1], cell_max.shape[0]
    i0 = _cell(math.floor((min(px, qx) - x0) / dx), nxc)
    i1 = _cell(math.floor((max(px, qx) - x0) / dx), nxc)
    j0 = _cell(math.floor((min(py, qy) - y0) / dy), nyc)
    j1 = _cell(math.floor((max(py, qy) - y0) / dy), nyc)
    if (i1 - i0 + 1) * (j1 - j0 + 1) > BOX_CELLS:
        return -math.inf
    top = -math.inf
    for j in range(j0, j1 + 1):
        for i in range(i0, i1 + 1):
            top = max(top, cell_max[j, i])
    floor: float = min(pz, qz) - top - 1e-9 * (1.0 + abs(top))
    return floor


@kernel
def walk_min_kernel(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, px: float, py: float, pz: float,
                    qx: float, qy: float, qz: float) -> float:
    """Exact least altitude along a segment: the walk of :func:`min_altitude_kernel` without its bound.

    Parameters
    ----------
    coef : numpy.ndarray
        Bilinear coefficients per cell ``(ny - 1, nx - 1, 4)`` (m).
    x0, y0, dx, dy : float
        Grid origin and cell sizes (m): with ``coef`` the first five of :attr:`Terrain.kernel_data`.
    px, py, pz, qx, qy, qz : float
        The segment's ends (m).

    Returns
    -------
    float
        The least altitude above the seabed along the segment (m).
    """
    return _walk_min(coef, x0, y0, dx, dy, px, py, pz, qx, qy, qz)


@kernel
def _min_altitudes(coef: FloatArray, x0: float, y0: float, dx: float, dy: float, lipschitz: float, a: FloatArray,
                   b: FloatArray, ga: FloatArray, gb: FloatArray, known: bool, threshold: float,
                   out: FloatArray) -> None:
    for k in range(a.shape[0]):
        px, py, pz, qx, qy, qz = a[k, 0], a[k, 1], a[k, 2], b[k, 0], b[k, 1], b[k, 2]
        if known:
            g_a, g_b = ga[k], gb[k]
        else:
            g_a = pz - elevation_kernel(coef, x0, y0, dx, dy, px, py)
            g_b = qz - elevation_kernel(coef, x0, y0, dx, dy, qx, qy)
        out[k] = min_altitude_kernel(coef, x0, y0, dx, dy, lipschitz, px, py, pz, qx, qy, qz, g_a, g_b, threshold)
