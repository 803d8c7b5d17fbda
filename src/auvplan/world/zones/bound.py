"""The zones' fine lower-bound field (:func:`.parts.distance_field`), compiled: its look-up, its march along a
trace, and its making.

The field holds, for each fine cell, a lower bound of the horizontal distance from any point of the cell to
the footprints, in one plane for every depth *slab* and one for all zones.  The slabs split the depths
between the lowest and the highest finite band end of the zones (the broad phase's bands: a seabed band
up to the highest seabed under its box) into :data:`SLABS` equal layers, the first and the last open
downwards and upwards; slab ``s``'s plane bounds the distance to the footprints of the zones whose band
meets it (:func:`_slab` of its bottom ``<= s <=`` :func:`_slab` of its top).  A segment whose z-range
runs from slab ``ka`` to slab ``kb`` can only enter a zone whose band meets one of those slabs (the
zone's band and the segment share a depth ``z``, and :func:`_slab` is monotone, so ``z``'s slab is
between the ends' slabs of both), so the least of planes ``ka..kb`` bounds its distance to every zone it
can enter.  On a seamount's flank the wrecks (seabed bands) lie far below the path and the charted areas'
bands end far above it: their footprints do not stop the swarm's legs there.
"""

from __future__ import annotations

import math

from ..._types import BoolArray, FloatArray, IntArray
from ...runtime.jit import kernel
from .exact import _ring_distance

__all__ = ["FIELD_UNITS", "SLABS"]  # the kernels are the internals of auvplan.world.zones

#: The fine distance field's values are whole units of a fine cell / FIELD_UNITS (uint16).
FIELD_UNITS = 64

#: Depth slabs of the fine field (its planes: one per slab and one for every zone).  On the ``cpu`` problem of
#: ``benchmarks/zones.py`` (1 000 zones over marcus-wake) slabs leave 3.5 % of the swarm's legs to the cells
#: against 7.2 % with one plane; with 4 the swarm's pass takes 0.063-0.069 s a plan against 0.072-0.077 s with 1
#: (in the plan, paired), 6 and 8 the same as 4, 2 no gain; 4 planes more hold 3 MB and build in ~0.01 s.
SLABS = 4

# Only the field's look-up, march and slabs (:func:`_far`, :func:`_clear`, :func:`_slab`), run for every leg, are
# inlined by numba (``inline="always"``): the swarm's pass is as fast as with every helper inlined (0.0512 vs
# 0.0510 s a plan replayed; 5.6 % slower with none) and the two any-hit passes compile in half the time.


@kernel(inline="always")
def _slab(z: float, z0: float, zinv: float, top: int) -> int:
    """The slab of depth ``z`` (z up, m): ``(z - z0) * zinv`` rounded down, within ``0..top``; monotone in
    ``z`` (0 for NaN)."""
    u = (z - z0) * zinv
    if u >= top:
        return top
    if u > 0.0:
        return int(u)
    return 0


@kernel
def slabs_kernel(z: FloatArray, z0: float, zinv: float, top: int, out: IntArray) -> None:
    """:func:`_slab` of every ``z`` (the zones' band ends: the same compiled arithmetic as the passes')."""
    for i in range(z.shape[0]):
        out[i] = _slab(z[i], z0, zinv, top)


@kernel(inline="always")
def _far(px: float, py: float, ka: int, kb: int, fx0: float, fy0: float, f: float, fnx: int, fny: int,
         bound: IntArray) -> float:
    """A lower bound of the horizontal distance from ``p`` to the footprints of planes ``ka..kb`` (m): the
    least of their values in ``p``'s cell, or the distance to the field's rectangle (which holds every
    footprint) outside it."""
    u, v = (px - fx0) / f, (py - fy0) / f
    if u >= 0.0 and v >= 0.0 and u < fnx and v < fny:
        i, j = int(u), int(v)
        least = bound[ka, j, i]
        for k in range(ka + 1, kb + 1):
            least = min(least, bound[k, j, i])
        return float(least) * (f / FIELD_UNITS)
    return math.hypot(max(-u, u - fnx, 0.0), max(-v, v - fny, 0.0)) * f


@kernel(inline="always")
def _clear(ax: float, ay: float, bx: float, by: float, fa: float, fb: float, ka: int, kb: int, fx0: float,
           fy0: float, f: float, fnx: int, fny: int, bound: IntArray, steps: int) -> bool:
    """Whether planes ``ka..kb`` of the field prove the segment's trace clear of their footprints (False: not
    proven).

    ``fa``/``fb`` are the ends' bounds (:func:`_far`).  Every point within ``r = _far(p)`` of a point
    ``p`` (open disc) is off those footprints, so the trace is marched from ``a`` by those discs until
    they reach ``b``'s; a point with ``r = 0`` (near a footprint) or more than ``steps`` discs stop the march.
    """
    dx, dy = bx - ax, by - ay
    length = math.hypot(dx, dy)
    if length < fa + fb:
        return True
    if fa == 0.0 or fb == 0.0:
        return False
    t, tb = fa / length, 1.0 - fb / length
    for _ in range(steps):
        r = _far(ax + t * dx, ay + t * dy, ka, kb, fx0, fy0, f, fnx, fny, bound)
        if r == 0.0:
            return False
        t += r / length
        if t > tb:
            return True
    return False


@kernel
def clear_kernel(t: FloatArray, fx0: float, fy0: float, f: float, fnx: int, fny: int, bound: IntArray,
                 out: BoolArray) -> None:
    """Which horizontal traces ``t (T, 2, 2)`` the field's last plane (every zone) proves clear of every
    footprint: :func:`_clear`'s march, given up after 24 discs (a long trace skirting a footprint: the cells'
    test is cheaper)."""
    every = bound.shape[0] - 1
    for n in range(t.shape[0]):
        ax, ay, bx, by = t[n, 0, 0], t[n, 0, 1], t[n, 1, 0], t[n, 1, 1]
        fa = _far(ax, ay, every, every, fx0, fy0, f, fnx, fny, bound)
        fb = _far(bx, by, every, every, fx0, fy0, f, fnx, fny, bound)
        out[n] = _clear(ax, ay, bx, by, fa, fb, every, every, fx0, fy0, f, fnx, fny, bound, 24)


@kernel
def field_kernel(xy: FloatArray, ring: IntArray, rings: IntArray, box: FloatArray, lo: IntArray, hi: IntArray,
                 fx0: float, fy0: float, f: float, reach: float, out: FloatArray) -> None:
    """The horizontal distance from each fine cell's centre to the nearest footprint of each plane, where it is
    below ``reach`` (m): ``out (P, fny, fnx)``, filled with ``reach`` by the caller, lowered to the distance to
    every polygon ``k`` (rings as in :func:`.exact._meets_polygon`; 0 inside) over the cells of its box
    ``box[k]`` grown by ``reach``, in planes ``lo[k]..hi[k]`` (its slabs) and in the last (every zone)."""
    every, fny, fnx = out.shape[0] - 1, out.shape[1], out.shape[2]
    for k in range(box.shape[0]):
        i0 = max(int(math.floor((box[k, 0] - reach - fx0) / f - 0.5)), 0)
        i1 = min(int(math.ceil((box[k, 2] + reach - fx0) / f - 0.5)), fnx - 1)
        j0 = max(int(math.floor((box[k, 1] - reach - fy0) / f - 0.5)), 0)
        j1 = min(int(math.ceil((box[k, 3] + reach - fy0) / f - 0.5)), fny - 1)
        for j in range(j0, j1 + 1):
            py = fy0 + (j + 0.5) * f
            for i in range(i0, i1 + 1):
                done = out[every, j, i] == 0.0
                for s in range(lo[k], hi[k] + 1):
                    done = done and out[s, j, i] == 0.0
                if done:
                    continue
                px = fx0 + (i + 0.5) * f
                edge, inside = _ring_distance(px, py, k, xy, ring, rings)
                d = 0.0 if inside else edge
                out[every, j, i] = min(out[every, j, i], d)
                for s in range(lo[k], hi[k] + 1):
                    out[s, j, i] = min(out[s, j, i], d)
