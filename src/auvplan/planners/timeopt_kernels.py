"""Compiled inner loops of the time-dependent planner: the current table lookup, the travel time
of a straight leg through a current that changes while the vehicle is on it, and the label-setting
(Dijkstra) search on arrival times.

The current table ``cur (nt, nx, ny, nz, 3)`` holds the field at the lattice nodes every ``dt``
seconds from ``t0``; lookups are trilinear in space and linear in time, clamped at the ends.

Travel time of a leg: the vehicle holds the track at through-water speed V (it crabs), so its
ground speed along the unit tangent ŝ is ``g = c·ŝ + √(V² - |c - (c·ŝ) ŝ|²)`` (as in
:mod:`auvplan.cost`); the leg is cut into sub-steps of at most ``ds`` metres and each sub-step is
integrated with the midpoint rule in time (the current at the sub-step's midpoint, at the time the
vehicle reaches it).  Where the cross current beats the vehicle or ``g ≤ 0`` the leg is blocked at
that time (``inf``), never ``nan``.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from .._jit import kernel

__all__ = ["current_at", "ground_speed", "leg_time", "polyline_times", "search"]


@kernel
def _axis(value, origin, step, n):
    """Index and weight of ``value`` on a uniform axis, clamped (a single-node axis gives (0, 0))."""
    if n == 1:
        return 0, 0.0
    f = (value - origin) / step
    if f <= 0.0:
        return 0, 0.0
    if f >= n - 1:
        return n - 2, 1.0
    i = int(f)
    return i, f - i


@kernel
def current_at(cur, org, step, t0, dt, x, y, z, t):
    """Current ``(u, v, w)`` at ``(x, y, z)`` and time ``t`` from the table (module notes)."""
    nt, nx, ny, nz = cur.shape[0], cur.shape[1], cur.shape[2], cur.shape[3]
    it, wt = _axis(t, t0, dt, nt)
    ix, wx = _axis(x, org[0], step[0], nx)
    iy, wy = _axis(y, org[1], step[1], ny)
    iz, wz = _axis(z, org[2], step[2], nz)
    u = v = w = 0.0
    for a in range(2):
        ca = wt if a else 1.0 - wt
        if ca == 0.0:
            continue
        for b in range(2):
            cb = ca * (wx if b else 1.0 - wx)
            if cb == 0.0:
                continue
            for c in range(2):
                cc = cb * (wy if c else 1.0 - wy)
                if cc == 0.0:
                    continue
                for d in range(2):
                    cd = cc * (wz if d else 1.0 - wz)
                    if cd == 0.0:
                        continue
                    u += cd * cur[it + a, ix + b, iy + c, iz + d, 0]
                    v += cd * cur[it + a, ix + b, iy + c, iz + d, 1]
                    w += cd * cur[it + a, ix + b, iy + c, iz + d, 2]
    return u, v, w


@kernel
def ground_speed(u, v, w, ex, ey, ez, speed):
    """Ground speed along the unit tangent ``e`` at through-water ``speed`` in the current
    ``(u, v, w)``; ``-1`` where the current beats the vehicle."""
    c_par = u * ex + v * ey + w * ez
    disc = speed * speed - max(u * u + v * v + w * w - c_par * c_par, 0.0)
    if disc < 0.0:
        return -1.0
    g = c_par + math.sqrt(disc)
    return g if g > 1e-6 else -1.0


@kernel
def leg_time(cur, org, step, t0, dt, ax, ay, az, bx, by, bz, t, speed, ds):
    """Arrival time at ``b`` of a leg ``a -> b`` started at ``t`` (``inf`` when blocked)."""
    ex, ey, ez = bx - ax, by - ay, bz - az
    length = math.sqrt(ex * ex + ey * ey + ez * ez)
    if length == 0.0:
        return t
    ex, ey, ez = ex / length, ey / length, ez / length
    n = max(1, int(math.ceil(length / ds)))
    h = length / n
    for k in range(n):
        s = (k + 0.5) * h
        mx, my, mz = ax + s * ex, ay + s * ey, az + s * ez
        u, v, w = current_at(cur, org, step, t0, dt, mx, my, mz, t + 0.5 * h / speed)
        g = ground_speed(u, v, w, ex, ey, ez, speed)
        if g < 0.0:
            return math.inf
        u, v, w = current_at(cur, org, step, t0, dt, mx, my, mz, t + 0.5 * h / g)
        g = ground_speed(u, v, w, ex, ey, ez, speed)
        if g < 0.0:
            return math.inf
        t += h / g
    return t


@kernel
def polyline_times(cur, org, step, t0, dt, p, t_start, speed, ds, out):
    """Arrival time at every vertex of the polyline ``p (N, 3)`` departing at ``t_start``."""
    out[0] = t_start
    for i in range(1, p.shape[0]):
        out[i] = leg_time(cur, org, step, t0, dt, p[i - 1, 0], p[i - 1, 1], p[i - 1, 2],
                          p[i, 0], p[i, 1], p[i, 2], out[i - 1], speed, ds)


@kernel
def two_legs(cur, org, step, t0, dt, a, cand, c, t_a, speed, ds, out):
    """Arrival at ``c[i]`` through each candidate ``cand[i, j]`` from ``a[i]`` left at ``t_a[i]``."""
    for i in range(cand.shape[0]):
        for j in range(cand.shape[1]):
            tm = leg_time(cur, org, step, t0, dt, a[i, 0], a[i, 1], a[i, 2], cand[i, j, 0], cand[i, j, 1],
                          cand[i, j, 2], t_a[i], speed, ds)
            if math.isinf(tm):
                out[i, j] = math.inf
            else:
                out[i, j] = leg_time(cur, org, step, t0, dt, cand[i, j, 0], cand[i, j, 1], cand[i, j, 2],
                                     c[i, 0], c[i, 1], c[i, 2], tm, speed, ds)


@kernel
def search(cur, org, step, t0, dt, shape, offsets, edge_ok, start_ids, start_arr, goal_link, goal, speed, ds,
           arrival, pred):
    """Label-setting search on arrival times (time-dependent Dijkstra, FIFO legs).

    Nodes are ``(ix * ny + iy) * nz + iz``; ``edge_ok[m, n]`` says the leg from node ``n`` along
    ``offsets[m]`` is free; ``start_ids`` are reached at ``start_arr``; nodes with ``goal_link`` have a
    free leg to ``goal``.  Fills ``arrival`` and ``pred`` (``-1`` for start-linked nodes) and returns
    ``(arrival at the goal, last node)``; stops when no open label can beat the goal's arrival.
    """
    ny, nz = shape[1], shape[2]
    heap = [(0.0, np.int64(0))]
    heap.pop()
    for k in range(start_ids.size):
        n = start_ids[k]
        if start_arr[k] < arrival[n]:
            arrival[n] = start_arr[k]
            pred[n] = -1
            heapq.heappush(heap, (start_arr[k], np.int64(n)))
    best, last = math.inf, np.int64(-1)
    done = np.zeros(arrival.size, dtype=np.bool_)
    while heap:
        t, n = heapq.heappop(heap)
        if done[n] or t > arrival[n]:
            continue
        if t >= best:
            break
        done[n] = True
        iz = n % nz
        iy = (n // nz) % ny
        ix = n // (nz * ny)
        x = org[0] + ix * step[0]
        y = org[1] + iy * step[1]
        z = org[2] + iz * step[2]
        if goal_link[n]:
            tg = leg_time(cur, org, step, t0, dt, x, y, z, goal[0], goal[1], goal[2], t, speed, ds)
            if tg < best:
                best, last = tg, n
        for m in range(offsets.shape[0]):
            if not edge_ok[m, n]:
                continue
            jx, jy, jz = ix + offsets[m, 0], iy + offsets[m, 1], iz + offsets[m, 2]
            q = (jx * ny + jy) * nz + jz
            if done[q]:
                continue
            tq = leg_time(cur, org, step, t0, dt, x, y, z, org[0] + jx * step[0], org[1] + jy * step[1],
                          org[2] + jz * step[2], t, speed, ds)
            if tq < arrival[q]:
                arrival[q] = tq
                pred[q] = n
                heapq.heappush(heap, (tq, np.int64(q)))
    return best, last
