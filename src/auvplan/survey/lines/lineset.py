"""A survey's lines as data: how they are placed (:class:`LineParams`), each line's offset, depth and swath at every
station (:class:`SurveyLine`) and the set (:class:`SurveyLines`), with the overlap of two adjacent swaths
(:func:`pair_overlap`, a side-scan's :func:`sidescan_overlap`) and the straight line frame's coordinates
(:func:`to_sn`, :func:`from_sn`).  Where the lines go: :mod:`.placement`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .frame import Frame, StraightFrame

__all__ = ["LineParams", "SurveyLine", "SurveyLines", "pair_overlap", "sidescan_overlap", "to_sn", "from_sn"]


@dataclass(frozen=True)
class LineParams:
    """How the lines are placed.

    Attributes
    ----------
    overlap_min, overlap_max : float
        Bounds of the overlap between adjacent swaths (fractions of the narrower swath).
    station_m : float
        Distance between stations along the lines (m).
    max_bend_deg : float
        Largest angle between a line and its nominal heading (deg); 0 keeps the lines straight.
    pitch_max_deg : float
        Steepest climb or dive along a line with the AUV mounting (deg).
    surface_z : float
        Elevation of the sensor with the surface mounting (m, 0 at the sea surface).
    step_m : float
        Sampling step of the seabed profiles under the swath (m).
    max_lines : int
        Give up after this many lines.
    overlap_margin : float
        Added to ``overlap_min`` where the lines are placed, so the flown overlap keeps the minimum when
        the vehicle crabs in a cross-current (:func:`auvplan.survey.ties.crab_margin`); the outermost
        swaths reach the area's edges with their reach shortened by the same fraction.
    nav_rel_per_m : float
        Relative navigation error of two adjacent lines per metre flown between their passes at a
        station (confidence × the dead-reckoning drift rate, issue 52; 0: exact navigation).  Each next
        line is brought closer by that error at every station (:func:`nav_margin`).
    nav_turn_m : float
        Longest path flown between the end of one line and the start of the next beyond the lines (m;
        the run-ins and the turn): part of the distance between the passes.
    """

    overlap_min: float = 0.10
    overlap_max: float = 0.20
    station_m: float = 50.0
    max_bend_deg: float = 15.0
    pitch_max_deg: float = 15.0
    surface_z: float = 0.0
    step_m: float = 5.0
    max_lines: int = 500
    overlap_margin: float = 0.0
    nav_rel_per_m: float = 0.0
    nav_turn_m: float = 0.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.overlap_min < self.overlap_max < 1.0:
            raise ValueError(f"overlap = [{self.overlap_min}, {self.overlap_max}]: need 0 <= min < max < 1")
        if not self.station_m > 0 or not self.step_m > 0:
            raise ValueError("station_m and step_m must be positive")
        if not 0.0 <= self.max_bend_deg < 60.0:
            raise ValueError(f"max_bend_deg = {self.max_bend_deg}: must be in [0, 60)")
        if not 0.0 < self.pitch_max_deg < 60.0:
            raise ValueError(f"pitch_max_deg = {self.pitch_max_deg}: must be in (0, 60)")
        if not 0.0 <= self.overlap_margin < 1.0 - self.overlap_min:
            raise ValueError(f"overlap_margin = {self.overlap_margin}: must be in [0, 1 - overlap_min)")
        if self.max_lines < 1:
            raise ValueError(f"max_lines = {self.max_lines}: must be >= 1")
        if not (0.0 <= self.nav_rel_per_m < 1.0 and 0.0 <= self.nav_turn_m < math.inf):
            raise ValueError(f"nav_rel_per_m = {self.nav_rel_per_m}, nav_turn_m = {self.nav_turn_m}: must be >= 0")


@dataclass(frozen=True)
class SurveyLine:
    """One line: its offset, depth and swath at every station, and the stations it is flown over.

    Attributes
    ----------
    c, z : numpy.ndarray
        ``(K,)`` across offset and sensor elevation (m) at every station.
    left, right : numpy.ndarray
        ``(K,)`` swath reach to the left (``-n``) and to the right (``+n``) (m); NaN off the line.
    first, last : int
        The stations ``first..last`` (inclusive) the line is flown over.
    gap_left, gap_right : numpy.ndarray or None
        ``(K,)`` a side-scan's nadir gap either side (m); None for a multibeam.
    nav_margin : numpy.ndarray or None
        ``(K,)`` how much closer the line was brought to the one before for their relative navigation
        error at each station (m; :func:`nav_margin`); None without one.
    """

    c: NDArray[np.float64]
    z: NDArray[np.float64]
    left: NDArray[np.float64]
    right: NDArray[np.float64]
    first: int
    last: int
    gap_left: NDArray[np.float64] | None = None
    gap_right: NDArray[np.float64] | None = None
    nav_margin: NDArray[np.float64] | None = None

    @property
    def nadir(self) -> NDArray[np.float64]:
        """``(K,)`` across offset of the middle of the nadir gap (the line itself for a multibeam) (m)."""
        if self.gap_left is None or self.gap_right is None:
            return self.c
        return np.asarray(self.c + 0.5 * (self.gap_right - self.gap_left))

    @property
    def active(self) -> slice:
        """The stations of the line."""
        return slice(self.first, self.last + 1)


@dataclass(frozen=True)
class SurveyLines:
    """The planned lines of one survey.

    Attributes
    ----------
    heading : float
        Nominal compass heading of the lines (rad).
    stations : numpy.ndarray
        ``(K,)`` along-line coordinates of the stations (m).
    area_lo, area_hi : numpy.ndarray
        ``(K,)`` the area's cross-section at every station (m across; NaN where the area is absent).
    lines : tuple of SurveyLine
        The lines, in placement order (left to right).
    complete : bool
        Whether the swaths reach the area's far edge everywhere (False: ``max_lines`` reached).
    frame : Frame or None
        The line frame (None: straight along ``heading``); a corridor's follows its centre line.
    """

    heading: float
    stations: NDArray[np.float64]
    area_lo: NDArray[np.float64]
    area_hi: NDArray[np.float64]
    lines: tuple[SurveyLine, ...]
    complete: bool
    frame: Frame | None = None

    @property
    def geom(self) -> Frame:
        """The line frame."""
        return self.frame if self.frame is not None else StraightFrame(self.heading)

    def waypoints(self, i: int) -> NDArray[np.float64]:
        """Waypoints of one line in the world frame, in increasing station order.

        Parameters
        ----------
        i : int
            The line (placement order).

        Returns
        -------
        numpy.ndarray
            ``(M, 3)`` waypoints (m).
        """
        ln = self.lines[i]
        a = ln.active
        x, y = self.geom.from_sn(self.stations[a], ln.c[a])
        return np.column_stack([x, y, ln.z[a]])

    def overlaps(self) -> list[NDArray[np.float64]]:
        """Overlap fraction of each adjacent pair at the stations they share where their seam is in the area.

        Returns
        -------
        list of numpy.ndarray
            One array of fractions per pair.
        """
        out = []
        for a, b in zip(self.lines[:-1], self.lines[1:], strict=True):
            k = np.zeros(self.stations.size, dtype=bool)
            k[max(a.first, b.first):min(a.last, b.last) + 1] = True
            ea, eb = a.c + a.right, b.c - b.left
            k &= np.isfinite(self.area_hi) & (eb < self.area_hi) & (ea > self.area_lo)
            out.append(pair_overlap(ea, eb, a.left + a.right, b.left + b.right, a, b)[k])
        return out


def pair_overlap(ea: NDArray[np.float64], eb: NDArray[np.float64], wa: NDArray[np.float64], wb: NDArray[np.float64],
                 a: SurveyLine | None = None, b: SurveyLine | None = None) -> NDArray[np.float64]:
    """Overlap of two adjacent swaths across the track, a share of the narrower swath.

    A multibeam: ``(E+_a - E-_b) / min(W_a, W_b)``, the shared width over the narrower swath.  A side-scan
    (both lines with a nadir gap): each line's gap is covered by its neighbours, so the overlap is how far
    each swath reaches past the other line's nadir, ``min(E+_a - m_b, m_a - E-_b)``, over the narrower of
    the two facing one-side swaths (``E+_a - m_a - g+_a`` and ``m_b - E-_b - g-_b``).

    Parameters
    ----------
    ea, eb : numpy.ndarray
        Right edge of swath ``a``, left edge of swath ``b`` (m across).
    wa, wb : numpy.ndarray
        Widths of the two swaths (multibeam) (m).
    a, b : SurveyLine, optional
        The lines, for a side-scan's gaps.

    Returns
    -------
    numpy.ndarray
        The overlap fractions.
    """
    if a is None or b is None or a.gap_right is None or b.gap_left is None:
        return np.asarray((ea - eb) / np.minimum(wa, wb))
    assert a.gap_left is not None and b.gap_right is not None
    return sidescan_overlap(ea, a.nadir, a.gap_right, eb, b.nadir, b.gap_left, a.c, b.c)


def sidescan_overlap(ea: NDArray[np.float64], ma: NDArray[np.float64], gra: NDArray[np.float64],
                     eb: NDArray[np.float64], mb: NDArray[np.float64], glb: NDArray[np.float64],
                     ca: NDArray[np.float64], cb: NDArray[np.float64]) -> NDArray[np.float64]:
    """A side-scan pair's overlap: how far each swath reaches past the other's nadir, over the narrower band.

    Parameters
    ----------
    ea, ma, gra : numpy.ndarray
        Line ``a``'s right swath edge, nadir (gap middle) and right gap reach (m).
    eb, mb, glb : numpy.ndarray
        Line ``b``'s left swath edge, nadir and left gap reach (m).
    ca, cb : numpy.ndarray
        The two lines' offsets (m).

    Returns
    -------
    numpy.ndarray
        The overlap fractions.
    """
    band = np.minimum(ea - (ca + gra), (cb - glb) - eb)
    return np.asarray(np.minimum(ea - mb, ma - eb) / band)


def to_sn(x: NDArray[np.float64], y: NDArray[np.float64], heading: float) -> tuple[NDArray[np.float64],
                                                                                   NDArray[np.float64]]:
    """World ``(x, y)`` to line coordinates ``(s, n)``.

    Parameters
    ----------
    x, y : numpy.ndarray
        World coordinates (m).
    heading : float
        Compass heading of the lines (rad).

    Returns
    -------
    tuple of numpy.ndarray
        ``s`` along and ``n`` across (to the right) (m).
    """
    sh, ch = math.sin(heading), math.cos(heading)
    return x * sh + y * ch, x * ch - y * sh


def from_sn(s: NDArray[np.float64], n: NDArray[np.float64], heading: float) -> tuple[NDArray[np.float64],
                                                                                     NDArray[np.float64]]:
    """Line coordinates ``(s, n)`` back to world ``(x, y)`` (the inverse of :func:`to_sn`).

    Parameters
    ----------
    s, n : numpy.ndarray
        Along and across coordinates (m).
    heading : float
        Compass heading of the lines (rad).

    Returns
    -------
    tuple of numpy.ndarray
        ``x`` and ``y`` (m).
    """
    sh, ch = math.sin(heading), math.cos(heading)
    return s * sh + n * ch, s * ch - n * sh
