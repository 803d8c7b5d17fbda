"""Any-angle links of the lattice search (lazy Theta*, reversed): straight segments past the 26 directions.

A 26-neighbour lattice path is metricated: its cost follows the lattice's directions (up to 8 % long
between two of them in the plane), whatever the cell.  The search (:func:`auvplan.planners.grid.lattice.search`)
therefore lets a node ``u`` link straight to the next node ``p`` of its neighbour's path, as Theta*
does, when ``p`` is at most ``link`` cells away on every axis:

* while relaxing, the link's cost is *tentative* (:func:`link_guess`: the straight segment with the
  mean of its two end nodes' currents, the lattice edges' own model) and no test is made;
* when ``u`` is settled its link is checked once (:func:`link_exact`, lazy Theta*): the segment is
  cut in pieces of at most half a cell along its longest axis, each piece must be clear by the
  node fields of its nearest node alone (the seabed's Lipschitz bound on the node's altitude, the
  obstacles' 1-Lipschitz slack, the land's 1-Lipschitz signed distance per column; the depth band
  and the box are convex and hold at both free ends), and its cost is the sum of the pieces' costs,
  each in the current of its nearest node.  A link that fails, or costs more than a lattice edge
  to a settled neighbour, gives way to the cheapest such edge.

The clearance test is conservative (a link it refuses may be free; one it passes is free), so
every link is a free segment and the lattice path stays a real path; near the seabed, where the
bounds are tight, the search falls back to the lattice edges.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..._types import FloatArray
from ...cost import energy_kernel
from ...runtime.jit import kernel

__all__ = ["link_guess", "link_exact"]


@kernel
def _unravel(u: int, ny: int, nz: int) -> tuple[int, int, int]:
    return u // (nz * ny), (u // nz) % ny, u % nz


@kernel
def _piece_cost(ex: float, ey: float, ez: float, cx: float, cy: float, cz: float, use_cost: bool,
                w_length: float, w_energy: float, speed: float, power: float, document: int) -> float:
    ds = math.sqrt(ex * ex + ey * ey + ez * ez)
    if not use_cost:
        return ds
    units, _, _, blocked = energy_kernel(ex, ey, ez, ds, cx, cy, cz, speed, power, document)
    if blocked:
        return np.inf
    return max(w_length * ds + w_energy * units, 1e-12)


@kernel
def link_guess(u: int, p: int, pf: FloatArray, ny: int, nz: int, steps: FloatArray, current: Any, use_cost: bool,
               w_length: float, w_energy: float, speed: float, power: float, document: int) -> float:
    """Tentative cost of the straight link ``u -> p``: one segment in the mean of its ends' currents.

    Parameters
    ----------
    u, p : int
        Flat node ids (``p < 0``: the goal, in the current of ``u``).
    pf : ndarray, shape (3,)
        The far end in cells (fractional for the goal).
    ny, nz : int
        Lattice shape along y and z.
    steps : ndarray, shape (3,)
        Cell sizes (m).
    current : ndarray, shape (N, 3) or (0, 3)
        Node currents.
    use_cost : bool
        False: the cost is the length alone.
    w_length, w_energy, speed, power : float
        The edge cost's weights, the vehicle's speed (m/s) and electrical power at that speed (W).
    document : int
        :func:`~auvplan.cost.energy_mode`: 0 joules, 1 or 2 document 002's energy (eqs. 16–17) in either reading.

    Returns
    -------
    float
        The cost (``inf`` where the current beats the vehicle).
    """
    ui, uj, uk = _unravel(u, ny, nz)
    ex, ey, ez = (pf[0] - ui) * steps[0], (pf[1] - uj) * steps[1], (pf[2] - uk) * steps[2]
    if not use_cost:
        return math.sqrt(ex * ex + ey * ey + ez * ez)
    q = p if p >= 0 else u
    cx = 0.5 * (np.float64(current[u, 0]) + np.float64(current[q, 0]))
    cy = 0.5 * (np.float64(current[u, 1]) + np.float64(current[q, 1]))
    cz = 0.5 * (np.float64(current[u, 2]) + np.float64(current[q, 2]))
    return _piece_cost(ex, ey, ez, cx, cy, cz, True, w_length, w_energy, speed, power, document)


@kernel
def link_exact(u: int, pf: FloatArray, ny: int, nz: int, steps: FloatArray, alt: Any, obs: Any, land: Any,
               has_terrain: bool, has_land: bool, lipschitz: float, min_alt: float, current: Any, use_cost: bool,
               w_length: float, w_energy: float, speed: float, power: float, document: int) -> float:
    """Cost of the straight link ``u -> p`` piece by piece, or ``inf`` when the node fields cannot
    clear it (module notes).

    Parameters
    ----------
    u : int
        Flat node id (free).
    pf : ndarray, shape (3,)
        The far end in cells (a free node, or the goal).
    ny, nz : int
        Lattice shape along y and z.
    steps : ndarray, shape (3,)
        Cell sizes (m).
    alt, obs : ndarray of float32, shape (nx, ny, nz)
        Node altitudes above the seabed and obstacle slack, never above the true values.
    land : ndarray of float32, shape (nx, ny)
        Land signed distance of each column, never above the true value (unused without land).
    has_terrain, has_land : bool
        Whether the seabed and the land constrain.
    lipschitz : float
        The seabed's largest slope.
    min_alt : float
        Least altitude (m).
    current : ndarray, shape (N, 3) or (0, 3)
        Node currents.
    use_cost : bool
        False: the cost is the length alone.
    w_length, w_energy, speed, power : float
        The edge cost's weights, the vehicle's speed (m/s) and electrical power at that speed (W).
    document : int
        :func:`~auvplan.cost.energy_mode`: 0 joules, 1 or 2 document 002's energy (eqs. 16–17) in either reading.

    Returns
    -------
    float
        The link's cost, ``inf`` when a piece is not cleared or the current beats the vehicle.
    """
    ui, uj, uk = _unravel(u, ny, nz)
    di, dj, dk = pf[0] - ui, pf[1] - uj, pf[2] - uk
    m = max(1, int(math.ceil(2.0 * max(abs(di), abs(dj), abs(dk)) - 1e-9)))
    hx, hy, hz = di * steps[0] / m, dj * steps[1] / m, dk * steps[2] / m  # one piece (m)
    half = 0.5 * math.sqrt(hx * hx + hy * hy + hz * hz)
    half_xy, half_z = 0.5 * math.hypot(hx, hy), 0.5 * abs(hz)
    total = 0.0
    for q in range(m):
        f = (q + 0.5) / m  # the piece's midpoint, in cells from u
        ci, cj, ck = ui + f * di, uj + f * dj, uk + f * dk
        ni, nj, nk = int(math.floor(ci + 0.5)), int(math.floor(cj + 0.5)), int(math.floor(ck + 0.5))
        ox, oy, oz = (ci - ni) * steps[0], (cj - nj) * steps[1], (ck - nk) * steps[2]
        rxy = math.hypot(ox, oy) + half_xy
        if obs[ni, nj, nk] < math.sqrt(ox * ox + oy * oy + oz * oz) + half:
            return np.inf
        if has_terrain and alt[ni, nj, nk] + oz - half_z - lipschitz * rxy < min_alt:
            return np.inf
        if has_land and land[ni, nj] < rxy:
            return np.inf
        n = (ni * ny + nj) * nz + nk
        c0 = np.float64(current[n, 0]) if use_cost else 0.0
        c1 = np.float64(current[n, 1]) if use_cost else 0.0
        c2 = np.float64(current[n, 2]) if use_cost else 0.0
        total += _piece_cost(hx, hy, hz, c0, c1, c2, use_cost, w_length, w_energy, speed, power, document)
    return total
