"""Local seabed slopes per lattice column: a tighter Lipschitz bound for the lattice's edge test.

The edge test of :func:`auvplan.planners.grid.lattice.edge_states` clears an edge from its end
altitudes alone when the seabed cannot rise fast enough between them to come within the minimum
altitude.  With the terrain's steepest slope anywhere (:attr:`Terrain.max_slope`) that bound is
loose away from the steepest flank, and every edge it cannot clear goes through the exact segment
test.  A lattice edge ``u -> u + off`` (``|off_x|, |off_y| <= 1``) lies horizontally inside the
rectangle of one cell either side of ``u``'s column, so the steepest slope of the bilinear cells
meeting that rectangle bounds the seabed's rise along it: the same bound, local.  Only which edges
need the exact test changes, not which edges are free.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..._types import FloatArray
from ...runtime.jit import kernel
from ...world import Terrain

__all__ = ["column_slopes"]


@kernel
def _range_max(cells: FloatArray, lo: Any, hi: Any, out: FloatArray) -> None:
    """``out[:, c] = max(cells[:, lo[c]:hi[c] + 1], axis=1)``."""
    for r in range(cells.shape[0]):
        for c in range(lo.size):
            m = 0.0
            for q in range(lo[c], hi[c] + 1):
                m = max(m, cells[r, q])
            out[r, c] = m


def _ranges(axis: FloatArray, reach: float, origin: float, step: float, cells: int) -> tuple[Any, Any]:
    """First and last terrain cell meeting ``[a - reach, a + reach]`` for each node coordinate ``a``
    (clamped to the grid: outside it the seabed is the edge cell's, no steeper)."""
    lo = np.floor((axis - reach - origin) / step - 1e-9).astype(np.int64)
    hi = np.floor((axis + reach - origin) / step + 1e-9).astype(np.int64)
    return np.clip(lo, 0, cells - 1), np.clip(hi, 0, cells - 1)


def column_slopes(terrain: Terrain, ax: FloatArray, ay: FloatArray, rx: float, ry: float) -> Any:
    """The steepest seabed slope within ``rx`` along x and ``ry`` along y of each lattice column.

    Parameters
    ----------
    terrain : Terrain
        The bilinear seabed.
    ax, ay : ndarray
        The lattice's node coordinates along x and y (m).
    rx, ry : float
        Half-widths of the rectangle round each column (m): the lattice's cells.

    Returns
    -------
    ndarray of float64, shape (ax.size, ay.size)
        A Lipschitz constant of the seabed over each column's rectangle, never above
        :attr:`Terrain.max_slope`.
    """
    coef, x0, y0, dx, dy, _ = terrain.kernel_data
    # per cell, the bilinear gradient's components are extreme on the cell's edges (as Terrain.max_slope)
    gx = np.maximum(np.abs(coef[..., 1]), np.abs(coef[..., 1] + coef[..., 3])) / dx
    gy = np.maximum(np.abs(coef[..., 2]), np.abs(coef[..., 2] + coef[..., 3])) / dy
    cells = np.sqrt(gx**2 + gy**2)  # (ny - 1, nx - 1)
    xlo, xhi = _ranges(np.asarray(ax, dtype=float), rx, x0, dx, cells.shape[1])
    ylo, yhi = _ranges(np.asarray(ay, dtype=float), ry, y0, dy, cells.shape[0])
    by_x = np.empty((cells.shape[0], xlo.size))
    _range_max(np.ascontiguousarray(cells), xlo, xhi, by_x)
    out = np.empty((xlo.size, ylo.size))
    _range_max(np.ascontiguousarray(by_x.T), ylo, yhi, out)  # the rows of by_x.T are the lattice's x columns
    return out
