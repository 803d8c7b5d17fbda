"""The lattice's directions and its node fields, one slab of x at a time (:mod:`auvplan.planners.grid.lattice`).

What the edge test needs is kept in single precision rounded towards the safe side (altitude and obstacle
clearance rounded down), the current in single precision.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from ...._types import FloatArray
from ....world import World

__all__ = ["HALF", "OFFSETS", "down32", "node_fields"]


HALF = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)
                 if (i, j, k) > (0, 0, 0)], dtype=np.int64)
"""The 13 lattice offsets with a positive first non-zero component (the other 13 are their reverses)."""


OFFSETS = np.concatenate([HALF, -HALF]).astype(np.int64)
"""The 26 lattice directions; bit ``s`` of a node's edge mask is the edge along ``OFFSETS[s]``."""


_SLAB = 100_000
"""Points per slab of the node-field evaluation (bounds the temporaries to a few tens of MB)."""


def down32(a: FloatArray) -> Any:
    """``a`` in single precision, rounded down (never above the double value: a safe clearance).

    Parameters
    ----------
    a : ndarray
        Double-precision values.

    Returns
    -------
    ndarray of float32
        The largest single-precision values not above ``a``.
    """
    b = a.astype(np.float32)
    return np.where(b > a, np.nextafter(b, np.float32(-np.inf)), b)


def node_fields(world: World, axes: tuple[FloatArray, ...], currents: bool) -> tuple[Any, Any, Any, Any]:
    """Free nodes, altitudes, obstacle clearances and currents of the lattice ``axes``.

    Parameters
    ----------
    world : World
        Static constraints only are applied.
    axes : tuple of ndarray
        Node coordinates along x, y and z.
    currents : bool
        Evaluate the current at the nodes (else an empty ``(0, 3)`` array).

    Returns
    -------
    free : ndarray of bool, shape (nx, ny, nz)
        Where every static constraint of :meth:`World.clearances` holds.
    altitude : ndarray of float32, shape (nx, ny, nz)
        Height above the seabed (``inf`` without terrain), rounded down.
    obstacle : ndarray of float32, shape (nx, ny, nz)
        Static-obstacle slack (distance minus margin), rounded down.
    current : ndarray of float32, shape (N, 3) or (0, 3)
        Current at the nodes in flat C order (m/s).
    """
    ax, ay, az = (np.asarray(a, dtype=float) for a in axes)
    shape = (ax.size, ay.size, az.size)
    columns = np.stack(np.meshgrid(ax, ay, indexing="ij"), axis=-1)
    seabed = world.terrain.elevation(columns[..., 0], columns[..., 1]) if world.terrain is not None else None
    land = world.land.signed_distance(columns) if world.land is not None else None
    body = replace(world, terrain=None, land=None)  # the 3D constraints; seabed and land per column
    free = np.empty(shape, dtype=bool)
    alt = np.full(shape, np.inf, dtype=np.float32)
    obs = np.empty(shape, dtype=np.float32)
    cur = np.empty((int(np.prod(shape)) if currents else 0, 3), dtype=np.float32)
    step = max(1, _SLAB // (shape[1] * shape[2]))
    for i0 in range(0, shape[0], step):
        i1 = min(shape[0], i0 + step)
        pts = np.empty((i1 - i0, shape[1], shape[2], 3))
        pts[..., 0] = ax[i0:i1, None, None]
        pts[..., 1] = ay[None, :, None]
        pts[..., 2] = az[None, None, :]
        slack = body.clearances(pts, moving=False)
        least = np.minimum.reduce(list(slack.values()))
        if seabed is not None:
            height = pts[..., 2] - seabed[i0:i1, :, None]
            least = np.minimum(least, height - world.margins.min_altitude)
            alt[i0:i1] = down32(height)
        if land is not None:
            least = np.minimum(least, land[i0:i1, :, None])
        free[i0:i1] = least >= 0.0
        obs[i0:i1] = down32(np.minimum(slack["obstacles"], slack["zones"]))  # both lower-bound a distance
        if currents:
            n = shape[1] * shape[2]
            cur[i0 * n:i1 * n] = world.currents.velocity(pts).reshape(-1, 3)
    return free, alt, obs, cur
