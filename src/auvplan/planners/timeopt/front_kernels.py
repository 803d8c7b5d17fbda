"""Compiled loops of the reachable-set front (:mod:`.front`) and of Zermelo's heading equation (:mod:`.zermelo`).

The horizontal current table ``cur (nt, nx, ny, 2)`` holds the field on the front's grid (origin
``(ox, oy)``, spacing ``h``) every ``dt`` seconds from ``t0``; lookups are bilinear in space and
linear in time, clamped at the ends.  Headings are mathematical angles here (counter-clockwise from
east): the vehicle's velocity over ground is ``c + V (cos θ, sin θ)``.

Front step (semi-Lagrangian dynamic programming on the reachable set's level-set function, Falcone
and Ferretti 2014, ch. 8): with ``R(t) = {φ(·, t) ≤ 0}``,

    φ(x, t + Δt) = max( min_θ φ(x − Δt (c_m + V ĥ_θ), t),  g(x) )

where ``c_m`` is the current at the step's midpoint (time ``t + Δt/2``, position half a step back)
and ``g`` the obstacle function (positive in land, where φ is held at its cap).  ``K`` headings are
tried, then one more at the vertex of the parabola through the best and its two neighbours; every
value taken is that of a heading the vehicle can fly, so the front never runs ahead of the set it
approximates by more than the interpolation's error.  A foot outside the grid is not reached.
"""

from __future__ import annotations

import math

from ..._types import BoolArray, FloatArray
from ...runtime.jit import kernel
from .kernels import Float32Array

__all__ = ["CAP", "bilinear", "cubic", "current2", "mid_current", "best_heading", "front_step", "shoot"]


@kernel
def bilinear(f: Float32Array, ox: float, oy: float, h: float, x: float, y: float) -> float:
    """Bilinear value of a node field at a point.

    Parameters
    ----------
    f : numpy.ndarray
        Node values ``(nx, ny)``.
    ox, oy : float
        First node of the grid (m).
    h : float
        Node spacing (m).
    x, y : float
        The point (m).

    Returns
    -------
    float
        The value; ``inf`` outside the grid.
    """
    nx, ny = f.shape[0], f.shape[1]
    fx = (x - ox) / h
    fy = (y - oy) / h
    if not (fx >= 0.0 and fy >= 0.0 and fx <= nx - 1 and fy <= ny - 1):
        return math.inf
    i = min(int(fx), nx - 2)
    j = min(int(fy), ny - 2)
    a, b = fx - i, fy - j
    return float((1.0 - a) * ((1.0 - b) * f[i, j] + b * f[i, j + 1])
                 + a * ((1.0 - b) * f[i + 1, j] + b * f[i + 1, j + 1]))


#: φ is kept within ``±CAP`` cells of the front (module notes of :func:`front_step`).
CAP = 4.0


@kernel
def _cr(p0: float, p1: float, p2: float, p3: float, a: float) -> float:
    """Catmull-Rom cubic through four equally spaced values at fraction ``a`` between the middle two."""
    return float(p1 + 0.5 * a * (p2 - p0 + a * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + a * (3.0 * (p1 - p2) + p3 - p0))))


@kernel
def cubic(f: Float32Array, ox: float, oy: float, h: float, x: float, y: float) -> float:
    """Bicubic (Catmull-Rom) value of a node field, clipped to the range of the cell's four corners
    (quasi-monotone, Bermejo and Staniforth 1992: no undershoot lets the front leak along a coast);
    bilinear in the outer cells.

    Parameters
    ----------
    f : numpy.ndarray
        Node values ``(nx, ny)``.
    ox, oy : float
        First node of the grid (m).
    h : float
        Node spacing (m).
    x, y : float
        The point (m).

    Returns
    -------
    float
        The value; ``inf`` outside the grid.
    """
    nx, ny = f.shape[0], f.shape[1]
    fx = (x - ox) / h
    fy = (y - oy) / h
    if not (fx >= 0.0 and fy >= 0.0 and fx <= nx - 1 and fy <= ny - 1):
        return math.inf
    i = min(int(fx), nx - 2)
    j = min(int(fy), ny - 2)
    if i < 1 or j < 1 or i > nx - 3 or j > ny - 3:
        return bilinear(f, ox, oy, h, x, y)
    a, b = fx - i, fy - j
    r0 = _cr(f[i - 1, j - 1], f[i, j - 1], f[i + 1, j - 1], f[i + 2, j - 1], a)
    r1 = _cr(f[i - 1, j], f[i, j], f[i + 1, j], f[i + 2, j], a)
    r2 = _cr(f[i - 1, j + 1], f[i, j + 1], f[i + 1, j + 1], f[i + 2, j + 1], a)
    r3 = _cr(f[i - 1, j + 2], f[i, j + 2], f[i + 1, j + 2], f[i + 2, j + 2], a)
    lo = min(f[i, j], f[i + 1, j], f[i, j + 1], f[i + 1, j + 1])
    hi = max(f[i, j], f[i + 1, j], f[i, j + 1], f[i + 1, j + 1])
    return float(min(max(_cr(r0, r1, r2, r3, b), lo), hi))  # quasi-monotone: within the cell's corner values


@kernel
def current2(cur: Float32Array, ox: float, oy: float, h: float, t0: float, dt: float, x: float, y: float,
             t: float) -> tuple[float, float]:
    """Horizontal current at a point and time from the table (clamped at its edges).

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, 2)`` (m/s, float32).
    ox, oy : float
        First node of the grid (m).
    h : float
        Node spacing (m).
    t0, dt : float
        First time and time step of the table (s).
    x, y : float
        The point (m).
    t : float
        Time (s).

    Returns
    -------
    tuple of float
        ``(u, v)`` (m/s); ``nan`` for a point or time that is not finite.
    """
    nt, nx, ny = cur.shape[0], cur.shape[1], cur.shape[2]
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(t)):
        return math.nan, math.nan
    ft = min(max((t - t0) / dt, 0.0), nt - 1.0)
    fx = min(max((x - ox) / h, 0.0), nx - 1.0)
    fy = min(max((y - oy) / h, 0.0), ny - 1.0)
    k = min(int(ft), max(nt - 2, 0))
    i = min(int(fx), nx - 2)
    j = min(int(fy), ny - 2)
    c, a, b = ft - k, fx - i, fy - j
    u = v = 0.0
    for dk in range(2):
        wk = c if dk else 1.0 - c
        if wk == 0.0 or k + dk >= nt:
            continue
        for di in range(2):
            wi = wk * (a if di else 1.0 - a)
            for dj in range(2):
                w = wi * (b if dj else 1.0 - b)
                u += w * cur[k + dk, i + di, j + dj, 0]
                v += w * cur[k + dk, i + di, j + dj, 1]
    return u, v


@kernel
def _foot_value(phi: Float32Array, ox: float, oy: float, h: float, x: float, y: float, cu: float, cv: float,
                step: float, speed: float, th: float) -> float:
    """φ at the foot of the characteristic that ends at ``(x, y)`` flying heading ``th`` for ``step`` s
    in the current ``(cu, cv)``."""
    return cubic(phi, ox, oy, h, x - step * (cu + speed * math.cos(th)), y - step * (cv + speed * math.sin(th)))


@kernel
def mid_current(cur: Float32Array, ox: float, oy: float, h: float, t0: float, dt: float, x: float, y: float,
                t_mid: float, step: float) -> tuple[float, float]:
    """The current of a step that ends at a point: at mid-step, half the drift back (the same for every
    heading: exact in a current uniform in space, first order in its gradient).

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, 2)`` (m/s, float32).
    ox, oy : float
        First node of the grid (m).
    h : float
        Node spacing (m).
    t0, dt : float
        First time and time step of the table (s).
    x, y : float
        End of the step (m).
    t_mid : float
        Middle of the step (s).
    step : float
        Its length (s).

    Returns
    -------
    tuple of float
        ``(u, v)`` (m/s).
    """
    u, v = current2(cur, ox, oy, h, t0, dt, x, y, t_mid)
    return current2(cur, ox, oy, h, t0, dt, x - 0.5 * step * u, y - 0.5 * step * v, t_mid)


@kernel
def best_heading(phi: Float32Array, ox: float, oy: float, h: float, x: float, y: float, cu: float, cv: float,
                 step: float, speed: float, cosk: FloatArray, sink: FloatArray) -> tuple[float, float]:
    """The least value of φ at a characteristic's foot over the headings and the parabola's vertex.

    Parameters
    ----------
    phi : numpy.ndarray
        φ at the step's start ``(nx, ny)``.
    ox, oy : float
        First node of the grid (m).
    h : float
        Node spacing (m).
    x, y : float
        End of the step (m).
    cu, cv : float
        Current of the step (:func:`mid_current`, m/s).
    step : float
        Its length (s).
    speed : float
        Through-water speed V (m/s).
    cosk, sink : numpy.ndarray
        Cosines and sines of the ``k`` headings ``2π m / k``.

    Returns
    -------
    tuple of float
        ``(value, heading)`` (m; mathematical angle, rad); ``(inf, 0)`` when every foot is off the grid.
    """
    k = cosk.shape[0]
    best, kb = math.inf, -1
    d = 2.0 * math.pi / k
    for m in range(k):
        val = cubic(phi, ox, oy, h, x - step * (cu + speed * cosk[m]), y - step * (cv + speed * sink[m]))
        if val < best:
            best, kb = val, m
    if kb < 0:
        return math.inf, 0.0
    th = kb * d
    lo = _foot_value(phi, ox, oy, h, x, y, cu, cv, step, speed, th - d)
    hi = _foot_value(phi, ox, oy, h, x, y, cu, cv, step, speed, th + d)
    curv = lo - 2.0 * best + hi
    if math.isfinite(lo) and math.isfinite(hi) and curv > 0.0:
        tv = th + 0.5 * d * (lo - hi) / curv
        val = _foot_value(phi, ox, oy, h, x, y, cu, cv, step, speed, tv)
        if val < best:
            return val, tv
    return best, th


@kernel
def front_step(phi: Float32Array, out: Float32Array, g: Float32Array, active: BoolArray, cur: Float32Array, ox: float,
               oy: float, h: float, t0: float, dt: float, t_mid: float, step: float, speed: float, cosk: FloatArray,
               sink: FloatArray) -> None:
    """One step of the front (module notes): ``out`` receives φ at ``t + step`` from ``phi`` at ``t``
    (clamped to ``±CAP h``: only the values near the front matter, and a bounded field keeps the
    cubic interpolation's overshoot small; a foot outside the grid and a blocked node take ``+CAP h``
    — no less than unreached water, or the seabed would feed the front —; nodes not ``active`` keep
    their value).

    Parameters
    ----------
    phi : numpy.ndarray
        φ at ``t`` ``(nx, ny)``.
    out : numpy.ndarray
        Receives φ at ``t + step``.
    g : numpy.ndarray
        Obstacle function ``(nx, ny)`` (m; > 0 blocked).
    active : numpy.ndarray of bool
        Nodes to update (the others are farther from the front than a step can reach).
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, 2)`` (m/s, float32).
    ox, oy : float
        First node of the grid (m).
    h : float
        Node spacing (m).
    t0, dt : float
        First time and time step of the table (s).
    t_mid : float
        Middle of the step (s).
    step : float
        Its length (s).
    speed : float
        Through-water speed V (m/s).
    cosk, sink : numpy.ndarray
        Cosines and sines of the headings tried.
    """
    nx, ny = phi.shape[0], phi.shape[1]
    cap = CAP * h
    for i in range(nx):
        for j in range(ny):
            if g[i, j] > 0.0 or not active[i, j]:
                out[i, j] = cap if g[i, j] > 0.0 else phi[i, j]
                continue
            x, y = ox + i * h, oy + j * h
            cu, cv = mid_current(cur, ox, oy, h, t0, dt, x, y, t_mid, step)
            val = best_heading(phi, ox, oy, h, x, y, cu, cv, step, speed, cosk, sink)[0]
            out[i, j] = min(max(val, g[i, j], -cap), cap)


@kernel
def _zermelo_rhs(cur: Float32Array, ox: float, oy: float, h: float, t0: float, dt: float, x: float, y: float,
                 th: float, t: float, speed: float) -> tuple[float, float, float]:
    """``(ẋ, ẏ, θ̇)`` of Zermelo's navigation problem (gradients by central differences over a cell)."""
    u, v = current2(cur, ox, oy, h, t0, dt, x, y, t)
    e = 0.5 * h
    ue, ve = current2(cur, ox, oy, h, t0, dt, x + e, y, t)
    uw, vw = current2(cur, ox, oy, h, t0, dt, x - e, y, t)
    un, vn = current2(cur, ox, oy, h, t0, dt, x, y + e, t)
    us, vs = current2(cur, ox, oy, h, t0, dt, x, y - e, t)
    ux, vx = (ue - uw) / (2 * e), (ve - vw) / (2 * e)
    uy, vy = (un - us) / (2 * e), (vn - vs) / (2 * e)
    s, c = math.sin(th), math.cos(th)
    dth = s * s * vx + s * c * (ux - vy) - c * c * uy
    return u + speed * c, v + speed * s, dth


@kernel
def shoot(cur: Float32Array, ox: float, oy: float, h: float, t0: float, dt: float, x0: float, y0: float,
          th0: float, t_start: float, step: float, speed: float, out: FloatArray) -> None:
    """Integrate Zermelo's navigation equations (:mod:`.zermelo`) by RK4.

    Parameters
    ----------
    cur : numpy.ndarray
        Current table ``(nt, nx, ny, 2)`` (m/s, float32).
    ox, oy : float
        First node of the grid (m).
    h : float
        Node spacing (m).
    t0, dt : float
        First time and time step of the table (s).
    x0, y0 : float
        Start (m).
    th0 : float
        First heading (mathematical angle, rad).
    t_start : float
        Departure (s).
    step : float
        RK4 step (s).
    speed : float
        Through-water speed V (m/s).
    out : numpy.ndarray
        Receives ``(x, y, θ)`` every step ``(n, 3)``, the first row the start.
    """
    x, y, th, t = x0, y0, th0, t_start
    out[0, 0], out[0, 1], out[0, 2] = x, y, th
    for n in range(1, out.shape[0]):
        k1 = _zermelo_rhs(cur, ox, oy, h, t0, dt, x, y, th, t, speed)
        k2 = _zermelo_rhs(cur, ox, oy, h, t0, dt, x + 0.5 * step * k1[0], y + 0.5 * step * k1[1],
                          th + 0.5 * step * k1[2], t + 0.5 * step, speed)
        k3 = _zermelo_rhs(cur, ox, oy, h, t0, dt, x + 0.5 * step * k2[0], y + 0.5 * step * k2[1],
                          th + 0.5 * step * k2[2], t + 0.5 * step, speed)
        k4 = _zermelo_rhs(cur, ox, oy, h, t0, dt, x + step * k3[0], y + step * k3[1], th + step * k3[2], t + step,
                          speed)
        x += step * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]) / 6.0
        y += step * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]) / 6.0
        th += step * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]) / 6.0
        t += step
        out[n, 0], out[n, 1], out[n, 2] = x, y, th
