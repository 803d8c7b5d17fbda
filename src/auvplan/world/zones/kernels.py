"""The zones' compiled any-hit passes (:mod:`auvplan.world.zones`): which segments, or which legs of polylines
(the swarm's populations), enter any zone, exactly.

A segment the fine field proves clear of the footprints of every zone whose band its z-range can meet
(:mod:`.bound`: the planes of its depth slabs) is passed at once; the others walk the broad phase's cells
(:func:`.broad._scan`), testing the flat bands exactly as they go (:mod:`.exact`) and listing the
seabed-band candidates for the caller's exact test (GEOS and the terrain).
"""

from __future__ import annotations

import math

from ..._types import BoolArray, FloatArray, IntArray
from ...runtime.jit import kernel
from .bound import _clear, _far, _slab
from .broad import _scan
from .exact import _flat_hit

__all__ = ["RUN", "STEPS"]  # the kernels are the internals of auvplan.world.zones

#: Legs of a polyline passed at once by one disc of the fine field (:func:`path_hits_kernel`).
RUN = 4

#: Most discs of the fine field's march along one segment (:func:`.bound._clear`) before the cells decide.
STEPS = 256


@kernel
def any_hits_kernel(seg: FloatArray, x0: float, y0: float, cell: float, nx: int, ny: int, start: IntArray,
                    ids: IntArray, box: FloatArray, zlo: FloatArray, zhi: FloatArray, seabed: BoolArray,
                    xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray, fx0: float, fy0: float,
                    f: float, fnx: int, fny: int, bound: IntArray, z0: float, zinv: float, top: int, mark: IntArray,
                    hit: BoolArray, pairs: IntArray, capacity: int) -> int:
    """Broad phase and exact flat-band test in one pass: ``hit[n]`` is True where segment ``n`` enters a
    flat-band zone (the search stops at the first); the seabed-band candidates of every other segment
    are written to ``pairs (2, capacity)`` while they fit (the caller tests them exactly).

    A segment the fine field ``bound`` (:func:`.parts.distance_field`; slabs ``z0``, ``zinv``, ``top`` as in
    :func:`.bound._slab`) proves clear of the footprints of its slabs' zones (:func:`.bound._clear`) is passed
    at once.  Otherwise the grid, scratch and bands of :func:`.broad.candidates_kernel`; ``seabed`` flags the
    seabed bands.  Returns the number of seabed pairs (more than ``capacity``: call again with room for them).
    """
    m = 0
    for n in range(seg.shape[0]):
        ax, ay, az = seg[n, 0, 0], seg[n, 0, 1], seg[n, 0, 2]
        bx, by, bz = seg[n, 1, 0], seg[n, 1, 1], seg[n, 1, 2]
        ka, kb = _slab(min(az, bz), z0, zinv, top), _slab(max(az, bz), z0, zinv, top)
        fa = _far(ax, ay, ka, kb, fx0, fy0, f, fnx, fny, bound)
        fb = _far(bx, by, ka, kb, fx0, fy0, f, fnx, fny, bound)
        if _clear(ax, ay, bx, by, fa, fb, ka, kb, fx0, fy0, f, fnx, fny, bound, STEPS):
            hit[n] = False
            continue
        hit[n], m, _ = _scan(n, ax, ay, az, bx, by, bz, x0, y0, cell, nx, ny, start, ids, box, zlo, zhi, seabed,
                             xy, ring, rings, disc, mark, pairs, m, capacity, False)
    return m


@kernel
def path_hits_kernel(p: FloatArray, x0: float, y0: float, cell: float, nx: int, ny: int, start: IntArray,
                     ids: IntArray, box: FloatArray, zlo: FloatArray, zhi: FloatArray, seabed: BoolArray,
                     xy: FloatArray, ring: IntArray, rings: IntArray, disc: FloatArray, fx0: float, fy0: float,
                     f: float, fnx: int, fny: int, bound: IntArray, z0: float, zinv: float, top: int, mark: IntArray,
                     hit: BoolArray, pairs: IntArray, capacity: int) -> int:
    """:func:`any_hits_kernel` over the legs of polylines ``p (P, S, 3)``: ``hit (P * (S - 1),)`` and the
    pairs' segment ``n = i (S - 1) + s``.

    The legs go in runs of :data:`RUN`, each with the field's planes of the slabs of its z-range: a run whose
    vertices all lie within the bound at the centre of their box (a disc off those footprints, holding the
    run's legs: it is convex) is passed with one look-up; otherwise leg by leg, each vertex's bound looked up
    once.  A leg that is not proven clear is first tried against the flat-band zone the path's last entering
    leg entered (most often it enters that one too), then walks the cells."""
    m = 0
    legs = p.shape[1] - 1
    for i in range(p.shape[0]):
        last = -1  # the flat-band zone the last entering leg entered
        for s0 in range(0, legs, RUN):
            s1 = min(s0 + RUN, legs)
            lx, hx, ly, hy, lz, hz = p[i, s0, 0], p[i, s0, 0], p[i, s0, 1], p[i, s0, 1], p[i, s0, 2], p[i, s0, 2]
            for s in range(s0 + 1, s1 + 1):
                lx, hx = min(lx, p[i, s, 0]), max(hx, p[i, s, 0])
                ly, hy = min(ly, p[i, s, 1]), max(hy, p[i, s, 1])
                lz, hz = min(lz, p[i, s, 2]), max(hz, p[i, s, 2])
            ka, kb = _slab(lz, z0, zinv, top), _slab(hz, z0, zinv, top)
            cx, cy = 0.5 * (lx + hx), 0.5 * (ly + hy)
            rr = 0.0
            for s in range(s0, s1 + 1):
                rr = max(rr, (p[i, s, 0] - cx) ** 2 + (p[i, s, 1] - cy) ** 2)
            r = _far(cx, cy, ka, kb, fx0, fy0, f, fnx, fny, bound)
            if r * r > rr:
                for s in range(s0, s1):
                    hit[i * legs + s] = False
                continue
            ax, ay, az = p[i, s0, 0], p[i, s0, 1], p[i, s0, 2]
            fa = _far(ax, ay, ka, kb, fx0, fy0, f, fnx, fny, bound)
            for s in range(s0, s1):
                n = i * legs + s
                bx, by, bz = p[i, s + 1, 0], p[i, s + 1, 1], p[i, s + 1, 2]
                fb = _far(bx, by, ka, kb, fx0, fy0, f, fnx, fny, bound)
                if _clear(ax, ay, bx, by, fa, fb, ka, kb, fx0, fy0, f, fnx, fny, bound, STEPS):
                    hit[n] = False
                elif last >= 0 and _flat_hit(ax, ay, az, bx, by, bz, zlo[last], zhi[last], last, xy, ring, rings,
                                             disc):
                    hit[n] = True
                else:
                    hit[n], m, last = _scan(n, ax, ay, az, bx, by, bz, x0, y0, cell, nx, ny, start, ids, box, zlo,
                                            zhi, seabed, xy, ring, rings, disc, mark, pairs, m, capacity, False)
                ax, ay, az, fa = bx, by, bz, fb
    return m


@kernel
def slack_kernel(p: FloatArray, hit: BoolArray, out: FloatArray) -> None:
    """The swarm cost's zone slack of the legs of polylines ``p (P, S, 3)``: ``out (P, S - 1)`` is minus the
    length of each leg ``hit`` flags (``hit (P * (S - 1),)``; at least 1 m), ``+inf`` elsewhere."""
    legs = p.shape[1] - 1
    for i in range(p.shape[0]):
        for s in range(legs):
            if hit[i * legs + s]:
                dx, dy, dz = p[i, s + 1, 0] - p[i, s, 0], p[i, s + 1, 1] - p[i, s, 1], p[i, s + 1, 2] - p[i, s, 2]
                out[i, s] = -max(math.sqrt(dx * dx + dy * dy + dz * dz), 1.0)
            else:
                out[i, s] = math.inf
