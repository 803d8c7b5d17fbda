"""A formation's shapes along its route: the slot offsets of each shape (:func:`shape_offsets`), the shape
changes blended over a transition (:class:`Schedule`) and the route with its slots (:class:`FormationRoute`).

Shapes (``spacing_m`` between neighbours): ``line`` (abreast: port, starboard, port … of the leader),
``column`` (single file behind the leader, every vehicle on the route at the route's depth), ``wedge`` (each
rank ``spacing`` back and ``spacing`` out).  A shape change at a route position blends the offsets over
``transition_m`` metres (smoothstep).  The formation's parameters are in :mod:`auvplan.guidance.formation`.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence

import numpy as np

from ..._types import ArrayLike, FloatArray

__all__ = ["SHAPES", "shape_offsets", "Schedule", "FormationRoute"]


SHAPES = ("line", "column", "wedge")
"""The formation shapes, by name."""


def shape_offsets(shape: str, n: int, spacing: float, depth_offsets: ArrayLike | None = None) -> FloatArray:
    """Slot offsets of a shape; slot 0 is the leader's.

    ``line``: abreast, port then starboard in rising ranks; ``column``: ``k·spacing`` behind;
    ``wedge``: rank ``r`` is ``r·spacing`` behind and ``r·spacing`` out.

    Parameters
    ----------
    shape : str
        ``line``, ``column`` or ``wedge``.
    n : int
        Number of slots.
    spacing : float
        Distance between neighbouring slots (m).
    depth_offsets : array_like (n,), optional
        Depths below the reference (m, positive deeper), for the abreast shapes (a column flies on
        the route).

    Returns
    -------
    ndarray (n, 3)
        (along ahead, to starboard, up) in metres.
    """
    if shape not in SHAPES:
        raise ValueError(f"shape = {shape!r}: choose {', '.join(SHAPES)}")
    k = np.arange(n)
    rank = (k + 1) // 2
    side = np.where(k % 2 == 1, -1.0, 1.0)
    out = np.zeros((n, 3))
    if shape == "column":
        out[:, 0] = -k * spacing
        return out
    out[:, 1] = side * rank * spacing
    if shape == "wedge":
        out[:, 0] = -rank * spacing
    if depth_offsets is not None:
        out[:, 2] = -np.asarray(depth_offsets, dtype=float)
    return out


def _smoothstep(x: ArrayLike) -> FloatArray:
    c = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    out: FloatArray = c * c * (3.0 - 2.0 * c)
    return out


class Schedule:
    """Shapes along the route, each blended in over ``transition`` metres from the shape before it.

    Parameters
    ----------
    breaks : sequence of (float, str)
        ``(route position, shape)`` breakpoints; the first at 0 m.
    n : int
        Number of vehicles.
    spacing : float
        Slot spacing (m).
    transition : float
        Blend length (m).
    depth_offsets : array_like (n,), optional
        The vehicles' depth offsets (m, positive deeper).
    """

    def __init__(self, breaks: Sequence[tuple[float, str]], n: int, spacing: float, transition: float,
                 depth_offsets: ArrayLike | None = None) -> None:
        self.breaks = sorted((float(s), str(sh)) for s, sh in breaks)
        if not self.breaks or self.breaks[0][0] > 0:
            raise ValueError("a schedule starts with the shape at 0 m")
        self.n, self.spacing, self.transition = n, float(spacing), float(transition)
        self.depth = np.zeros(n) if depth_offsets is None else np.asarray(depth_offsets, dtype=float)
        self._offsets = [shape_offsets(sh, n, spacing, self.depth) for _, sh in self.breaks]

    def shape_at(self, s: float) -> str:
        """The shape in force (or being formed) at a route position.

        Parameters
        ----------
        s : float
            Route position (m).

        Returns
        -------
        str
            The shape.
        """
        name = self.breaks[0][1]
        for b, sh in self.breaks:
            if s >= b:
                name = sh
        return name

    def offsets(self, s: ArrayLike) -> FloatArray:
        """Slot offsets at route positions.

        Parameters
        ----------
        s : array_like (...)
            Route positions (m).

        Returns
        -------
        ndarray (..., n, 3)
            (along ahead, to starboard, up) of every slot.
        """
        s = np.asarray(s, dtype=float)
        out = np.broadcast_to(self._offsets[0], s.shape + (self.n, 3)).copy()
        for (b, _), prev, new in zip(self.breaks[1:], self._offsets[:-1], self._offsets[1:]):
            w = _smoothstep((s - b) / self.transition)[..., None, None]
            out = out + w * (new - prev)
        return out


class FormationRoute:
    """The global route as the formation's virtual structure: slots at a reference position ``s``.

    Parameters
    ----------
    route : array_like (N, 3)
        The route the leader flies (the checked mission).
    schedule : Schedule
        Shapes along it.
    course_window : float
        Half-window (m) of the chord that gives the slots' orientation (smooths corners).
    """

    def __init__(self, route: ArrayLike, schedule: Schedule, course_window: float) -> None:
        w = np.asarray(route, dtype=float).reshape(-1, 3)
        d = np.hypot(*np.diff(w[:, :2], axis=0).T)
        keep = np.r_[True, d > 1e-9]
        self.w = w[keep]
        self.cum = np.r_[0.0, np.cumsum(np.hypot(*np.diff(self.w[:, :2], axis=0).T))]
        self.length = float(self.cum[-1])
        self.schedule = schedule
        self.window = float(course_window)
        first, last = self.w[1] - self.w[0], self.w[-1] - self.w[-2]
        self._t0 = first[:2] / np.hypot(*first[:2])
        self._t1 = last[:2] / np.hypot(*last[:2])
        # plain-float copies for the closed loop's scalar queries (one vehicle step = a few of them)
        self._cum = self.cum.tolist()
        self._w = self.w.tolist()
        self._breaks = [(b, shape_offsets(sh, schedule.n, schedule.spacing, schedule.depth).tolist())
                        for b, sh in schedule.breaks]

    def point(self, s: ArrayLike) -> FloatArray:
        """Route points at arc lengths (straight extensions beyond the ends).

        Parameters
        ----------
        s : array_like (...)
            Arc lengths (m).

        Returns
        -------
        ndarray (..., 3)
            The points.
        """
        s = np.asarray(s, dtype=float)
        sc = np.clip(s, 0.0, self.length)
        out = np.stack([np.interp(sc, self.cum, self.w[:, j]) for j in range(3)], axis=-1)
        before, after = np.minimum(s, 0.0), np.maximum(s - self.length, 0.0)
        out[..., 0] += before * self._t0[0] + after * self._t1[0]
        out[..., 1] += before * self._t0[1] + after * self._t1[1]
        return out

    def course(self, s: ArrayLike) -> FloatArray:
        """Smoothed compass course: the chord from ``s − window`` to ``s + window``.

        Parameters
        ----------
        s : array_like (...)
            Arc lengths (m).

        Returns
        -------
        ndarray (...)
            Courses (rad, compass).
        """
        s = np.asarray(s, dtype=float)
        d = self.point(s + self.window) - self.point(s - self.window)
        course: FloatArray = np.arctan2(d[..., 0], d[..., 1])
        return course

    def slots(self, s: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Every slot with the formation's reference at ``s``.

        Parameters
        ----------
        s : array_like (...)
            Reference positions (m along the route).

        Returns
        -------
        positions : ndarray (..., n, 3)
            Slot positions.
        courses : ndarray (..., n)
            The slots' courses (rad, compass).
        """
        s = np.asarray(s, dtype=float)
        off = self.schedule.offsets(s)
        sa = s[..., None] + off[..., 0]
        base = self.point(sa)
        psi = self.course(sa)
        nx, ny = np.cos(psi), -np.sin(psi)
        base[..., 0] += off[..., 1] * nx
        base[..., 1] += off[..., 1] * ny
        base[..., 2] += off[..., 2]
        return base, psi

    def tracks(self, step: float) -> tuple[np.ndarray, np.ndarray]:
        """Every slot's swept track over the whole route.

        Parameters
        ----------
        step : float
            Largest spacing of the reference positions (m); route vertices and shape-change ends are
            included.

        Returns
        -------
        s : ndarray (M,)
            Reference positions.
        tracks : ndarray (n, M, 3)
            The slots at each of them.
        """
        extra = [b for b, _ in self.schedule.breaks] + [b + self.schedule.transition for b, _ in self.schedule.breaks]
        s = np.unique(np.r_[np.linspace(0.0, self.length, max(2, int(math.ceil(self.length / step)) + 1)),
                            self.cum, [e for e in extra if 0 <= e <= self.length]])
        pos, _ = self.slots(s)
        return s, np.swapaxes(pos, 0, 1)

    def point_at(self, s: float) -> tuple[float, float, float]:
        """:meth:`point` for one arc length, in plain floats (the closed loop's fast path).

        Parameters
        ----------
        s : float
            Arc length (m).

        Returns
        -------
        tuple of 3 float
            The point.
        """
        L = self.length
        if s <= 0.0 or s >= L:
            p, e, t = (self._w[0], s, self._t0) if s <= 0.0 else (self._w[-1], s - L, self._t1)
            return p[0] + e * t[0], p[1] + e * t[1], p[2]
        k = bisect.bisect_right(self._cum, s) - 1
        a, b = self._w[k], self._w[k + 1]
        f = (s - self._cum[k]) / (self._cum[k + 1] - self._cum[k])
        return a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])

    def slots_at(self, s: float) -> tuple[list[tuple[float, float, float]], list[float]]:
        """:meth:`slots` for one reference position, in plain floats (the closed loop's fast path).

        Parameters
        ----------
        s : float
            Reference position (m).

        Returns
        -------
        positions : list of (float, float, float)
            Slot positions.
        courses : list of float
            The slots' courses (rad).
        """
        off = [list(o) for o in self._breaks[0][1]]
        tr = self.schedule.transition
        for (b, new), (_, prev) in zip(self._breaks[1:], self._breaks[:-1]):
            x = min(max((s - b) / tr, 0.0), 1.0)
            w = x * x * (3.0 - 2.0 * x)
            if w:
                for o, p, q in zip(off, prev, new):
                    o[0] += w * (q[0] - p[0])
                    o[1] += w * (q[1] - p[1])
                    o[2] += w * (q[2] - p[2])
        pts, psis = [], []
        h = self.window
        for a, c, up in off:
            sa = s + a
            x, y, z = self.point_at(sa)
            x0, y0, _ = self.point_at(sa - h)
            x1, y1, _ = self.point_at(sa + h)
            psi = math.atan2(x1 - x0, y1 - y0)
            pts.append((x + c * math.cos(psi), y - c * math.sin(psi), z + up))
            psis.append(psi)
        return pts, psis

    def project(self, x: float, y: float, s_prev: float, behind: float = 30.0, ahead: float = 120.0) -> float:
        """Arc length of the nearest route point within a window about the previous one.

        Continuous: no jumps at leg switches, no short-cuts to a distant part of the route.  Behind the
        route's start the first leg extends straight back (negative arc lengths, as in :meth:`point`):
        a leader launched behind the start carries the slots with it instead of pinning them to the
        start while the followers, which cannot stop, run past them.

        Parameters
        ----------
        x, y : float
            Horizontal position (m).
        s_prev : float
            The previous arc length (m).
        behind, ahead : float
            The window ``[s_prev − behind, s_prev + ahead]`` (m).

        Returns
        -------
        float
            Arc length (m).
        """
        lo, hi = s_prev - behind, min(s_prev + ahead, self.length)
        cum, w = self._cum, self._w
        k = max(bisect.bisect_right(cum, lo) - 1, 0)
        best, s_best = math.inf, min(max(s_prev, lo), hi)
        while k < len(cum) - 1 and cum[k] <= hi:
            ax, ay = w[k][0], w[k][1]
            dx, dy = w[k + 1][0] - ax, w[k + 1][1] - ay
            dd = dx * dx + dy * dy
            f = ((x - ax) * dx + (y - ay) * dy) / dd if dd > 0 else 0.0
            f = min(max(f, 0.0) if k else f, 1.0)  # the first leg extends back past the start
            d = math.hypot(ax + f * dx - x, ay + f * dy - y)
            if d < best:
                best, s_best = d, cum[k] + f * (cum[k + 1] - cum[k])
            k += 1
        return min(max(s_best, lo), hi)
