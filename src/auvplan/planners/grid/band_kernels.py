"""The elastic band's array work, compiled: one pass's candidate moves and its choice among them.

:func:`auvplan.planners.grid.band._relax` spent half its time in some forty small numpy operations per
pass (normals, the five moves, the segment arrays, the choice and the step updates), each a few
microseconds on a path of 10–500 points: on the short built-ins the polish (14 relaxations of 2–4 sweeps)
cost 0.025–0.05 s per plan, most of it in that overhead (issue 59's CPU A/B).  These kernels do the same
arithmetic in three calls per pass, with numpy's IEEE operations (``fastmath=False``) in numpy's order, so
the band moves the points to the same bits (``tests/unit/test_band_kernels.py`` checks them against the
numpy formulation).  The world's queries (the segments' cost in the current, the exact segment test)
stay where they were.
"""

from __future__ import annotations

import numpy as np

from ..._types import BoolArray, FloatArray, IntArray
from ...runtime.jit import kernel

__all__ = ["band_choose", "band_gains", "band_moves", "band_segments", "chord_lengths"]


@kernel(fastmath=False)
def band_moves(p: FloatArray, i: IntArray, alpha: FloatArray, delta: FloatArray, ends: FloatArray,
               tips: FloatArray) -> None:  # pragma: no cover - compiled
    """Fill the segments of each point ``i`` and of its five moves.

    For point ``b = p[i]`` between ``a = p[i-1]`` and ``c = p[i+1]``: the pull towards the neighbours'
    midpoint by ``alpha[i]`` and moves of ``±delta[i]`` along two unit normals of the chord ``c - a``
    (``t × z``, or ``t × x`` for a steep chord, and ``t`` × that).  ``ends[:6]`` / ``tips[:6]`` are the
    segments ``a -> move`` (move 0 is ``b`` itself), ``ends[6:]`` / ``tips[6:]`` the segments
    ``move -> c``.

    Parameters
    ----------
    p : numpy.ndarray
        The path ``(n, 3)``.
    i : numpy.ndarray
        The interior points to move ``(m,)``.
    alpha, delta : numpy.ndarray
        Per point of the path ``(n,)``: pull fraction and normal step.
    ends, tips : numpy.ndarray
        Outputs ``(12, m, 3)``.
    """
    for j in range(i.shape[0]):
        k = i[j]
        t0 = p[k + 1, 0] - p[k - 1, 0]
        t1 = p[k + 1, 1] - p[k - 1, 1]
        t2 = p[k + 1, 2] - p[k - 1, 2]
        norm = np.sqrt((t0 * t0 + t2 * t2) + t1 * t1)  # numpy's einsum order for three terms
        if norm <= 1e-12:
            t0, t1, t2 = 1.0, 0.0, 0.0
        else:
            t0, t1, t2 = t0 / norm, t1 / norm, t2 / norm
        if abs(t2) >= 0.9:
            u0, u1, u2 = 0.0, t2, -t1
        else:
            u0, u1, u2 = t1, -t0, 0.0
        un = np.sqrt((u0 * u0 + u2 * u2) + u1 * u1)
        u0, u1, u2 = u0 / un, u1 / un, u2 / un
        v0 = t1 * u2 - t2 * u1
        v1 = t2 * u0 - t0 * u2
        v2 = t0 * u1 - t1 * u0
        d, al = delta[k], alpha[k]
        for x in range(3):
            a, b, c = p[k - 1, x], p[k, x], p[k + 1, x]
            u = (u0, u1, u2)[x]
            v = (v0, v1, v2)[x]
            du, dv = d * u, d * v
            moves = (b, b + al * (0.5 * (a + c) - b), b + du, b - du, b + dv, b - dv)
            for s in range(6):
                ends[s, j, x] = a
                tips[s, j, x] = moves[s]
                ends[6 + s, j, x] = moves[s]
                tips[6 + s, j, x] = c


@kernel(fastmath=False)
def band_gains(cost: FloatArray, new: FloatArray, better: BoolArray) -> None:  # pragma: no cover - compiled
    """The two segments' cost of each move and whether it lowers the point's cost.

    Parameters
    ----------
    cost : numpy.ndarray
        ``(12, m)``: the costs of :func:`band_moves`'s segments.
    new : numpy.ndarray
        ``(5, m)``, filled: the cost of moves 1–5 (``a -> move -> c``).
    better : numpy.ndarray
        ``(5, m)`` of bool, filled: where a move's cost is below the point's own by more than 1e-9 of it.
    """
    for j in range(cost.shape[1]):
        old = cost[0, j] + cost[6, j]
        bar = old - 1e-9 * abs(old)
        for s in range(5):
            v = cost[s + 1, j] + cost[s + 7, j]
            new[s, j] = v
            better[s, j] = v < bar


@kernel(fastmath=False)
def band_choose(p: FloatArray, i: IntArray, tips: FloatArray, new: FloatArray, better: BoolArray,
                alpha: FloatArray, delta: FloatArray, step: float) -> None:  # pragma: no cover - compiled
    """Move each point ``i`` to its cheapest move that is ``better``, and update its steps, in place.

    The first cheapest wins (numpy's ``argmin`` over the costs with ``inf`` where a move is not better);
    a pull that wins grows ``alpha`` by half (at most 1), a normal move grows ``delta`` by half (at most
    ``step``); every other point halves the step that did not win.

    Parameters
    ----------
    p : numpy.ndarray
        The path ``(n, 3)``, updated.
    i : numpy.ndarray
        The points moved ``(m,)``.
    tips : numpy.ndarray
        :func:`band_moves`'s output: ``tips[s]`` holds move ``s``.
    new : numpy.ndarray
        ``(5, m)`` costs of moves 1–5 (:func:`band_gains`).
    better : numpy.ndarray
        ``(5, m)`` of bool: the moves that lower the cost and are free.
    alpha, delta : numpy.ndarray
        ``(n,)``, updated.
    step : float
        The level's spacing (the largest ``delta``).
    """
    for j in range(i.shape[0]):
        k, best = 0, np.inf
        for s in range(5):
            v = new[s, j] if better[s, j] else np.inf
            if v < best:
                k, best = s, v
        q = i[j]
        pulled = pushed = False
        if np.isfinite(best):
            for x in range(3):
                p[q, x] = tips[k + 1, j, x]
            pulled, pushed = k == 0, k > 0
        alpha[q] = min(alpha[q] * 1.5, 1.0) if pulled else alpha[q] * 0.5
        delta[q] = min(delta[q] * 1.5, step) if pushed else delta[q] * 0.5


@kernel(fastmath=False)
def band_segments(ends: FloatArray, tips: FloatArray, kk: IntArray, jj: IntArray,
                  out: FloatArray) -> None:  # pragma: no cover - compiled
    """The two segments of each move ``(kk + 1, jj)`` for the exact test: ``out[r] = (a -> move, move -> c)``.

    Parameters
    ----------
    ends, tips : numpy.ndarray
        :func:`band_moves`'s output ``(12, m, 3)``.
    kk, jj : numpy.ndarray
        Move (0–4 for moves 1–5) and point of each row ``(r,)``.
    out : numpy.ndarray
        ``(r, 2, 2, 3)``, filled.
    """
    for r in range(kk.shape[0]):
        s, j = kk[r] + 1, jj[r]
        for x in range(3):
            out[r, 0, 0, x] = ends[s, j, x]
            out[r, 0, 1, x] = tips[s, j, x]
            out[r, 1, 0, x] = ends[s + 6, j, x]
            out[r, 1, 1, x] = tips[s + 6, j, x]


@kernel(fastmath=False)
def chord_lengths(a: FloatArray, b: FloatArray, out: FloatArray) -> None:  # pragma: no cover - compiled
    """``|b - a|`` of each row, as ``numpy.linalg.norm(b - a, axis=-1)`` computes it (``(x² + y²) + z²``).

    Parameters
    ----------
    a, b : numpy.ndarray
        ``(N, 3)``.
    out : numpy.ndarray
        ``(N,)``, filled.
    """
    for k in range(a.shape[0]):
        dx, dy, dz = b[k, 0] - a[k, 0], b[k, 1] - a[k, 1], b[k, 2] - a[k, 2]
        out[k] = np.sqrt((dx * dx + dy * dy) + dz * dz)
