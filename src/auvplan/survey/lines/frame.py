"""The line frame of a survey: coordinates ``(s, n)`` along and across the nominal line direction.

A polygon survey's lines run along a compass heading ``ψ``: ``s`` along ``d = (sin ψ, cos ψ)``, ``n`` along
the right normal ``(cos ψ, -sin ψ)`` (:class:`StraightFrame`).  A corridor's lines run along its centre line:
``s`` is the arc length along the (rounded) centre line ``P(s)`` and ``n`` the offset along its right
normal ``N(s)``, so a line of constant ``n`` is the centre line's parallel (offset) curve and
``x = P(s) + n N(s)`` (:class:`CurveFrame`).  The map is one to one while ``|n|`` stays under the centre
line's least radius of curvature: the corridor's centre line is rounded (:func:`round_corners`, shapely's
``offset_curve`` out and back, a morphological closing of the line on both sides) to a radius larger than
the widest offset, so no parallel crosses itself at a bend and each turns with at least
``radius - |n|``.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
import shapely.affinity
from numpy.typing import NDArray

__all__ = ["Frame", "StraightFrame", "CurveFrame", "round_corners"]

Arr = NDArray[np.float64]


class Frame:
    """Coordinates along and across the lines (the base of the two frames).

    Attributes
    ----------
    heading : float
        Compass heading of the nominal direction at its start (rad).
    n_limit : float
        Largest ``|n|`` where the frame is one to one (m; ``inf`` for a straight frame).
    """

    heading: float = 0.0
    n_limit: float = math.inf

    def from_sn(self, s: Arr, n: Arr) -> tuple[Arr, Arr]:
        """World coordinates of line coordinates.

        Parameters
        ----------
        s, n : numpy.ndarray
            Along and across (to the right) (m).

        Returns
        -------
        tuple of numpy.ndarray
            ``x`` and ``y`` (m).
        """
        raise NotImplementedError

    def to_sn(self, x: Arr, y: Arr) -> tuple[Arr, Arr]:
        """Line coordinates of world coordinates (the inverse of :meth:`from_sn`).

        Parameters
        ----------
        x, y : numpy.ndarray
            World coordinates (m).

        Returns
        -------
        tuple of numpy.ndarray
            ``s`` along and ``n`` across (m).
        """
        raise NotImplementedError

    def right(self, s: Arr) -> Arr:
        """Unit vectors across, to the right of the nominal direction.

        Parameters
        ----------
        s : numpy.ndarray
            ``(K,)`` along (m).

        Returns
        -------
        numpy.ndarray
            ``(K, 2)`` unit vectors.
        """
        raise NotImplementedError

    def area_sn(self, area: shapely.Polygon) -> shapely.Geometry:
        """The area mapped into line coordinates.

        Parameters
        ----------
        area : shapely.Polygon
            The area in the world frame (m).

        Returns
        -------
        shapely geometry
            The area in ``(s, n)`` (m).
        """
        raise NotImplementedError


class StraightFrame(Frame):
    """Straight lines along a compass heading.

    Parameters
    ----------
    heading : float
        Compass heading (rad).
    """

    def __init__(self, heading: float) -> None:
        self.heading = float(heading)
        self._sh, self._ch = math.sin(self.heading), math.cos(self.heading)

    def from_sn(self, s: Arr, n: Arr) -> tuple[Arr, Arr]:
        return s * self._sh + n * self._ch, s * self._ch - n * self._sh

    def to_sn(self, x: Arr, y: Arr) -> tuple[Arr, Arr]:
        return x * self._sh + y * self._ch, x * self._ch - y * self._sh

    def right(self, s: Arr) -> Arr:
        return np.broadcast_to(np.array([self._ch, -self._sh]), (np.size(s), 2)).copy()

    def area_sn(self, area: shapely.Polygon) -> shapely.Geometry:
        sh, ch = self._sh, self._ch
        return shapely.affinity.affine_transform(area, [sh, ch, ch, -sh, 0.0, 0.0])


class CurveFrame(Frame):
    """Lines parallel to a smooth centre line (the corridor's).

    The centre line between its vertices is the cubic Hermite curve through them with their tangents,
    so its direction turns continuously with the normal: a polyline's kinks would be magnified by
    ``1 / (1 - n κ)`` on a parallel far inside a bend.

    Parameters
    ----------
    points : numpy.ndarray
        ``(M, 2)`` the centre line, finely sampled along a curve of bounded curvature (m).
    n_limit : float
        Largest offset the frame is used for (m): under the centre line's least radius.
    """

    def __init__(self, points: Arr, n_limit: float) -> None:
        p = np.asarray(points, dtype=float)
        keep = np.r_[True, np.hypot(*np.diff(p, axis=0).T) > 1e-6]
        self.p = p[keep]
        seg = np.diff(self.p, axis=0)
        length = np.hypot(seg[:, 0], seg[:, 1])
        self.s = np.concatenate([[0.0], np.cumsum(length)])
        t_seg = seg / length[:, None]
        t = np.vstack([t_seg[:1], t_seg[:-1] + t_seg[1:], t_seg[-1:]])
        self.t = t / np.linalg.norm(t, axis=1)[:, None]  # unit tangents at the vertices
        self.line = shapely.LineString(self.p)
        self.n_limit = float(n_limit)
        self.heading = math.atan2(self.t[0, 0], self.t[0, 1])

    @property
    def length(self) -> float:
        """Length of the centre line (m)."""
        return float(self.s[-1])

    def _at(self, s: Arr) -> tuple[Arr, Arr]:
        """Position and right normal at ``s`` on the Hermite curve."""
        s = np.clip(np.asarray(s, dtype=float), 0.0, self.s[-1])
        i = np.clip(np.searchsorted(self.s, s, side="right") - 1, 0, self.s.size - 2)
        h = (self.s[i + 1] - self.s[i])[..., None]
        u = ((s - self.s[i]) / h[..., 0])[..., None]
        p0, p1, t0, t1 = self.p[i], self.p[i + 1], self.t[i] * h, self.t[i + 1] * h
        pos = ((2 * u**3 - 3 * u**2 + 1) * p0 + (u**3 - 2 * u**2 + u) * t0 + (-2 * u**3 + 3 * u**2) * p1
               + (u**3 - u**2) * t1)
        d = (6 * u**2 - 6 * u) * p0 + (3 * u**2 - 4 * u + 1) * t0 + (-6 * u**2 + 6 * u) * p1 + (3 * u**2 - 2 * u) * t1
        d = d / np.linalg.norm(d, axis=-1, keepdims=True)
        return pos, np.stack([d[..., 1], -d[..., 0]], axis=-1)

    def from_sn(self, s: Arr, n: Arr) -> tuple[Arr, Arr]:
        p, r = self._at(s)
        n = np.asarray(n, dtype=float)
        return p[..., 0] + n * r[..., 0], p[..., 1] + n * r[..., 1]

    def _along(self, s: Arr, x: Arr, y: Arr) -> Arr:
        """``(q - P(s)) · T(s)``: zero where ``q`` is on the normal at ``s``."""
        p, r = self._at(s)
        return np.asarray((x - p[..., 0]) * -r[..., 1] + (y - p[..., 1]) * r[..., 0])

    def to_sn(self, x: Arr, y: Arr) -> tuple[Arr, Arr]:
        # the nearest point of the polyline, then Newton's method on the curve's normals, so that to_sn
        # inverts from_sn (the polyline's nearest point differs by the sampled arcs' angle)
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        s = np.asarray(shapely.line_locate_point(self.line, shapely.points(x, y)), dtype=float)
        for _ in range(4):
            f = self._along(s, x, y)
            df = self._along(s + 0.5, x, y) - self._along(s - 0.5, x, y)
            ok = np.abs(df) > 1e-6
            step = np.where(ok, -f / np.where(ok, df, 1.0), 0.0)
            s = np.clip(s + np.clip(step, -50.0, 50.0), 0.0, self.length)
        p, r = self._at(s)
        return s, (x - p[..., 0]) * r[..., 0] + (y - p[..., 1]) * r[..., 1]

    def right(self, s: Arr) -> Arr:
        return self._at(np.asarray(s, dtype=float).reshape(-1))[1]

    def area_sn(self, area: shapely.Polygon) -> shapely.Geometry:
        ring = np.asarray(shapely.segmentize(area, 5.0).exterior.coords)
        s, n = self.to_sn(ring[:, 0], ring[:, 1])
        return shapely.make_valid(shapely.Polygon(np.column_stack([s, n])))


for _cls in (StraightFrame, CurveFrame):  # the subclasses' methods carry the base class's documentation
    for _name in ("from_sn", "to_sn", "right", "area_sn"):
        getattr(_cls, _name).__doc__ = getattr(Frame, _name).__doc__


def round_corners(points: Arr, radius: float, step_deg: float = 1.0) -> Arr:
    """A polyline with its corners rounded to ``radius`` (its ends kept).

    shapely's ``offset_curve`` with round joins out to one side and back rounds the corners that turn
    towards that side with arcs of ``radius``; done on both sides, every corner is rounded (a morphological
    closing of the line from both sides).

    Parameters
    ----------
    points : numpy.ndarray
        ``(M, 2)`` polyline (m).
    radius : float
        Radius of the rounded corners (m).
    step_deg : float
        Angle between the vertices sampled on the arcs (deg).

    Returns
    -------
    numpy.ndarray
        ``(K, 2)`` the rounded line, from the same start to the same end.
    """
    line = shapely.LineString(np.asarray(points, dtype=float))
    if radius <= 0:
        return np.asarray(line.coords)
    q = max(4, int(math.ceil(90.0 / step_deg)))
    if not line.is_simple:
        raise ValueError("the centre line crosses itself; a corridor needs a line that does not")
    for side in (1.0, -1.0):
        out = line.offset_curve(side * radius, quad_segs=q, join_style="round")
        # a radius too large for the legs splits the offset line in pieces (a MultiLineString)
        back = out.offset_curve(-side * radius, quad_segs=q, join_style="round") \
            if isinstance(out, shapely.LineString) and not out.is_empty else None
        if not isinstance(back, shapely.LineString) or back.is_empty:
            raise ValueError(f"the centre line cannot be rounded to {radius:.0f} m (a corner too tight for its legs)")
        line = back
    p = np.asarray(line.coords)
    p[0], p[-1] = np.asarray(points, dtype=float)[0], np.asarray(points, dtype=float)[-1]
    return p
