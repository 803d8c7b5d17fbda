"""The lattice of the time-dependent search (step 1 of :mod:`.search`'s notes): nodes every ``cell`` metres over
the search box on ``levels`` depth levels, the free ones by the World's clearances, and each node's 50 legs (16
horizontal directions of the 5 × 5 stencil on three levels, and up and down) kept where the grid lattice's exact
edge test passes (:func:`auvplan.planners.grid.lattice.free_edges`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._types import ArrayLike, BoolArray, FloatArray, IntArray
from ...world import World
from ..grid.lattice import free_edges

__all__ = ["Lattice", "build_lattice"]


def _stencil() -> IntArray:
    """The 50 leg offsets: 16 horizontal directions (5 × 5 stencil) on three levels, and up/down."""
    hor = [(i, j) for i in range(-2, 3) for j in range(-2, 3) if (i, j) != (0, 0) and math.gcd(abs(i), abs(j)) == 1]
    off = [(i, j, k) for (i, j) in hor for k in (-1, 0, 1)] + [(0, 0, -1), (0, 0, 1)]
    return np.array(off, dtype=np.int64)


_OFFSETS = _stencil()
_OPPOSITE = np.array([next(j for j, o in enumerate(_OFFSETS) if (o == -off).all()) for off in _OFFSETS],
                     dtype=np.int64)


@dataclass(frozen=True, eq=False)
class Lattice:
    """Free nodes and free legs of the search lattice.

    Attributes
    ----------
    origin, step : ndarray, shape (3,)
        First node and node spacing (m); a single level has ``step[2] = 1``.
    shape : tuple of int
        Nodes along x, y, z.
    free : ndarray of bool, shape (N,)
        Free nodes (flattened ``(ix * ny + iy) * nz + iz``).
    edge_ok : ndarray of bool, shape (50, N)
        Free legs from each node along each offset.
    """

    origin: FloatArray
    step: FloatArray
    shape: tuple[int, int, int]
    free: BoolArray
    edge_ok: BoolArray

    @property
    def xyz(self) -> FloatArray:
        """Node coordinates.

        Returns
        -------
        numpy.ndarray
            ``(N, 3)`` (m), in the flattened node order.
        """
        axes = [self.origin[d] + self.step[d] * np.arange(self.shape[d]) for d in range(3)]
        return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)

    @property
    def legs(self) -> int:
        """Number of free directed legs.

        Returns
        -------
        int
            Count of True entries of ``edge_ok``.
        """
        return int(self.edge_ok.sum())


def build_lattice(world: World, lower: ArrayLike, upper: ArrayLike, cell: float, levels: int,
                  z_single: float) -> Lattice:
    """The lattice over a box, its free nodes and free legs.

    Parameters
    ----------
    world : World
        The world whose exact tests decide the free nodes and legs (moving obstacles ignored).
    lower, upper : array_like
        Corners of the search box ``(3,)`` (m).
    cell : float
        Horizontal node spacing (m).
    levels : int
        Depth levels over the box's height; 1 for a single level.
    z_single : float
        Elevation of the single level when ``levels == 1`` (m).

    Returns
    -------
    Lattice
        Nodes centred in the box, with their free flags and free legs.
    """
    lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    n_xy = np.floor((upper[:2] - lower[:2]) / cell + 1e-9).astype(int) + 1
    origin = np.r_[lower[:2] + 0.5 * ((upper[:2] - lower[:2]) - (n_xy - 1) * cell), z_single]
    step = np.array([cell, cell, 1.0])
    nz = 1
    if levels > 1:
        eps = 1e-6 * max(1.0, upper[2] - lower[2])
        top, bottom = upper[2] - eps, lower[2] + eps
        nz = levels
        step[2] = (top - bottom) / (levels - 1)
        origin[2] = bottom
    shape = (int(n_xy[0]), int(n_xy[1]), nz)
    lat = Lattice(origin, step, shape, np.zeros(0, bool), np.zeros((0, 0), bool))
    xyz = lat.xyz
    slack = world.clearances(xyz, moving=False)
    free = np.minimum.reduce(list(slack.values())) >= 0.0
    alt = (slack["altitude"] + world.margins.min_altitude).reshape(shape)
    obs = np.minimum(slack["obstacles"], slack["zones"]).reshape(shape)  # both lower-bound a distance
    return Lattice(origin, step, shape, free, _legs(world, xyz, free.reshape(shape), alt, obs, step))


def _legs(world: World, xyz: FloatArray, free3: BoolArray, alt: FloatArray, obs: FloatArray,
          step: FloatArray) -> BoolArray:
    """``edge_ok (50, N)``: each offset's legs tested as array slices (bounds, then a provable
    clearance from the node values, then the exact segment test for the rest)."""
    shape = free3.shape
    ok = np.zeros((len(_OFFSETS), free3.size), dtype=bool)
    for slot, off in enumerate(_OFFSETS):
        if shape[2] == 1 and off[2] != 0:
            continue
        src, _ = free_edges(world, free3, alt, obs, step, off, xyz.__getitem__)
        ok[slot, src] = True
    return ok
