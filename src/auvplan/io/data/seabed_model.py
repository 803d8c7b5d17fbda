"""The model seabed from gridded soundings: the conservative default, other methods on request, and the
measure of how the model sits against its data.

``[terrain] method``:

* ``"conservative"`` (default) — never deeper than the data: at every sounding and between soundings
  at or above the data's bilinear surface (:func:`auvplan.world.seabed.conservative_nodes`: an upper
  envelope over each cell's footprint when the cell is coarser than the data, the non-overshooting
  linear interpolant lifted by its exact shortfall when finer).  What it costs — how much shallower the
  model is — is measured exactly and reported (:class:`~auvplan.world.seabed.SeabedFit`).
* ``"linear"``, ``"cubic"``, ``"quintic"``, ``"pchip"`` — scipy's ``RegularGridInterpolator`` at the
  model's nodes; they can lie below the data (``cubic`` overshoots into pits, ``linear`` shaves peaks
  between nodes); the same measure reports by how much.

Curvilinear (2-D lat/lon) elevation grids are triangulated linearly whatever the method, and no fit is
measured for them.
"""

from __future__ import annotations

import numpy as np

from ...errors import DataError
from ...world.seabed import SeabedFit, affine_margin, conservative_nodes, fit_report
from .geo import LocalFrame
from .grids import HorizontalGrid
from .regrid import _target_axes, _to_source, covered_source, to_local

__all__ = ["METHODS", "MAX_NODES", "node_indices", "model_seabed"]

#: Most model nodes a resampling may make (~5 GB of work arrays); beyond it the request is refused.
MAX_NODES = 50_000_000

#: Resampling methods of ``[terrain] method``; the first is the default.
METHODS = ("conservative", "linear", "cubic", "quintic", "pchip")

_F64 = np.ndarray


def node_indices(grid: HorizontalGrid, frame: LocalFrame | None, x: _F64, y: _F64) -> tuple[_F64, _F64]:
    """Fractional row and column indices in the data of the local nodes ``meshgrid(x, y)``.

    Parameters
    ----------
    grid : HorizontalGrid
        A rectilinear grid (``lonlat``, ``projected`` or ``local``).
    frame : LocalFrame or None
        The local frame (unused for ``local`` grids).
    x, y : numpy.ndarray
        The model's axes (m).

    Returns
    -------
    fr, fc : numpy.ndarray
        ``(ny, nx)`` fractional indices (piecewise linear along each axis, so the data's bilinear
        surface in its own coordinates is bilinear in these indices too).
    """
    gx, gy = np.meshgrid(x, y)
    if grid.kind == "local" or frame is None:
        r, c = gy, gx
    else:
        r, c = _to_source(grid, frame, gx, gy)
    return _fractional(grid, r, c)


def _fractional(grid: HorizontalGrid, r: _F64, c: _F64) -> tuple[_F64, _F64]:
    """:func:`node_indices` from the nodes' source coordinates ``(r, c)``."""
    rows, cols = np.asarray(grid.rows, dtype=float), np.asarray(grid.cols, dtype=float)
    fr = np.interp(r, rows, np.arange(rows.size, dtype=float))
    fc = np.interp(c, cols, np.arange(cols.size, dtype=float))
    return fr, fc


def _sample(n_cells: int, most: int = 48) -> _F64:
    """Indices of up to ``most`` cells spread over ``n_cells``, the first and last included."""
    return np.unique(np.r_[np.linspace(0, n_cells - 1, min(most, n_cells)).round().astype(int), n_cells - 1])


def _projection_margin(grid: HorizontalGrid, frame: LocalFrame, data: _F64, x: _F64, y: _F64, fr: _F64,
                       fc: _F64) -> _F64:
    """:func:`affine_margin` from a spread sample of the model's cells (corners and edges of the extent included)."""
    ii, jj = np.meshgrid(_sample(x.size - 1), _sample(y.size - 1))
    ii, jj = ii.ravel(), jj.ravel()
    dx, dy = x[1] - x[0], y[1] - y[0]
    half = np.array([0.0, 0.5, 1.0])
    px = x[ii][:, None, None] + half[None, None, :] * dx + 0.0 * half[None, :, None]
    py = y[jj][:, None, None] + half[None, :, None] * dy + 0.0 * half[None, None, :]
    r, c = (np.asarray(a, dtype=float) for a in _to_source(grid, frame, px, py))
    rows, cols = np.asarray(grid.rows, dtype=float), np.asarray(grid.cols, dtype=float)
    true_r = np.interp(r, rows, np.arange(rows.size, dtype=float))
    true_c = np.interp(c, cols, np.arange(cols.size, dtype=float))
    cr = np.stack([np.stack([fr[jj, ii], fr[jj, ii + 1]], -1), np.stack([fr[jj + 1, ii], fr[jj + 1, ii + 1]], -1)], 1)
    cc = np.stack([np.stack([fc[jj, ii], fc[jj, ii + 1]], -1), np.stack([fc[jj + 1, ii], fc[jj + 1, ii + 1]], -1)], 1)
    return affine_margin(data, fr, fc, cr, cc, true_r, true_c)


def model_seabed(grid: HorizontalGrid, z: _F64, frame: LocalFrame, *,
                 extent_m: tuple[float, float, float, float] | None, cell_m: float | None, method: str,
                 what: str) -> tuple[_F64, _F64, _F64, SeabedFit | None]:
    """The model's axes and node values, and how they sit against the data.

    Parameters
    ----------
    grid : HorizontalGrid
        The data's nodes.
    z : numpy.ndarray
        ``(nrow, ncol)`` elevation (positive up, finite).
    frame : LocalFrame
        The local frame.
    extent_m : tuple of 4 float or None
        ``(xmin, xmax, ymin, ymax)`` to cover; None: the largest rectangle inside the data.
    cell_m : float or None
        The model's cell (m); None: the data's own spacing.
    method : str
        One of :data:`METHODS`.
    what : str
        Name for messages.

    Returns
    -------
    x, y, zn : numpy.ndarray
        Axes (m) and ``(ny, nx)`` node elevations (m).
    fit : SeabedFit or None
        The model against the data (None for curvilinear grids).
    """
    base = "linear" if method == "conservative" else method
    x, y = _target_axes(grid, frame, extent_m, cell_m, what)
    if x.size * y.size > MAX_NODES:  # the data's own extent at a tiny cell: refuse before allocating
        raise DataError(f"{what}: a {x[1] - x[0]:.3g} m cell over {x[-1] - x[0]:.0f} x {y[-1] - y[0]:.0f} m gives "
                        f"{x.size} x {y.size} nodes (more than {MAX_NODES:.0e}); set a larger resample_m, or "
                        "limit the area ([bounds] or [terrain] box)")
    extent, cell = (x[0], x[-1], y[0], y[-1]), float(x[1] - x[0]) if cell_m is None else cell_m
    if method == "conservative" and grid.kind != "curvilinear":
        # the nodes' values come from conservative_nodes: to_local's interpolation would be thrown away, so
        # only its axes and coverage check are made, and the nodes are projected once (issue 56)
        x, y = _target_axes(grid, frame, extent, cell, what)
        gx, gy = np.meshgrid(x, y)
        fr, fc = _fractional(grid, *covered_source(grid, frame, gx, gy, what))
    else:
        x, y, zn = to_local(grid, z, frame, extent_m=extent, cell_m=cell, method=base, what=what)
        if grid.kind == "curvilinear":
            return x, y, zn, None
        fr, fc = node_indices(grid, frame, x, y)
    data = np.asarray(z, dtype=float)
    if method == "conservative":
        margin: _F64 | float = 0.0
        if grid.kind != "local":  # a projection: bound what the affine map of a cell leaves out
            margin = _projection_margin(grid, frame, data, x, y, fr, fc)
        zn = conservative_nodes(data, fr, fc, margin)
    return x, y, zn, fit_report(data, fr, fc, zn, method)
