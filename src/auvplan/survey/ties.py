"""Tie lines across the main lines (the cross lines of multibeam quality control), and the overlap margin
that the vehicle's crab angle in a cross-current takes away.

**Tie lines.** ``count`` lines across the main lines, along the cut across the nominal direction (the
centre line's normal for a corridor) at stations evenly spread along the survey, each at the station
nearest its even share where every main line is flown (where one line fewer is, and so on, when those
stations span less than half the survey: a line only at a corridor's bend), from ``run_in`` before the first
main line to ``run_in`` past the last: each crosses every main line flown there.  They are flown after the
main lines, starting from the end where the last main line ends, in alternating directions.

**Crab margin.** In a current ``v`` across the track the vehicle holds the line by heading into it, at a
crab angle ``ψ = asin(v / U)`` (``U`` its speed through the water); the fan turns with the heading, so its
reach across the track shrinks to ``r cos ψ``.  Both edges of a seam move in by ``r (1 - cos ψ)``, so the
overlap (a share of the swath, ``≈ 2 r``) drops by ``1 - cos ψ``: the lines are placed with that margin
on the least overlap, ``ψ`` from the largest cross-track current over the area and half a day.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import NDArray

from ..world.currents.fields import CurrentField
from .lines.frame import Frame, StraightFrame
from .lines.placement import SurveyLines
from .lines.swath import Seabed

__all__ = ["tie_lines", "tie_stations", "crab_margin"]


def tie_stations(lines: SurveyLines, count: int) -> list[int]:
    """The stations of the tie lines: evenly spread, each moved to the nearest station where the most lines are
    flown (every line, unless the stations where every line is flown span less than half the survey).

    Parameters
    ----------
    lines : SurveyLines
        The main lines.
    count : int
        Number of tie lines.

    Returns
    -------
    list of int
        Station indices, increasing (fewer than ``count`` when stations are shared).
    """
    k = lines.stations.size
    if count <= 0 or not lines.lines or k < 2:
        return []
    flown = np.zeros(k, dtype=int)
    for ln in lines.lines:
        flown[ln.active] += 1
    # the stations where the most lines are flown, unless they span less than half the survey: a line added
    # only at a corridor's bend (its outer wedge) put all three ties of a 3.5 km corridor within 2.2 km of it,
    # two of them 50 m apart; then the stations where one line fewer is flown, and so on
    for m in range(int(flown.max()), 0, -1):
        best = np.flatnonzero(flown >= m)
        if best[-1] - best[0] >= 0.5 * (k - 1):
            break
    target = (np.arange(count) + 0.5) / count * (k - 1)
    return sorted({int(best[np.argmin(np.abs(best - t))]) for t in target})


def tie_lines(lines: SurveyLines, count: int, run_in: float, from_end: bool, step: float) -> list[NDArray[np.float64]]:
    """The tie lines' waypoints in flying order.

    Parameters
    ----------
    lines : SurveyLines
        The main lines.
    count : int
        Number of tie lines.
    run_in : float
        Run beyond the outermost main lines (m).
    from_end : bool
        Start with the tie line nearest the stations' end (where the last main line ends).
    step : float
        Largest distance between waypoints along a tie line (m).

    Returns
    -------
    list of numpy.ndarray
        ``(M, 3)`` waypoints of each tie line (z: the main lines' sensor elevation there).
    """
    fr = lines.geom
    idx = tie_stations(lines, count)
    if from_end:
        idx = idx[::-1]
    out = []
    for j, i in enumerate(idx):
        on = [ln for ln in lines.lines if ln.first <= i <= ln.last]
        c = np.array([ln.c[i] for ln in on])
        z = float(np.mean([ln.z[i] for ln in on]))
        n0, n1 = float(c.min()) - run_in, float(c.max()) + run_in
        n = np.linspace(n0, n1, max(2, int(math.ceil((n1 - n0) / step)) + 1))
        if j % 2 == 0:  # the last main line is the rightmost: the first tie line starts on the right
            n = n[::-1]
        x, y = fr.from_sn(np.full(n.size, lines.stations[i]), n)
        out.append(np.column_stack([x, y, np.full(n.size, z)]))
    return out


def crab_margin(currents: CurrentField, area: shapely.Polygon, z: float, speed: float, frame: Frame | None,
                heading: float, cap: float, hours: float = 12.0, seabed: Seabed | None = None,
                altitude: float = 0.0) -> float:
    """The overlap margin ``1 - cos ψ`` of the largest crab angle over the area.

    Parameters
    ----------
    currents : CurrentField
        The currents.
    area : shapely.Polygon
        The survey area (m).
    z : float
        Elevation the current is read at (m).
    speed : float
        The vehicle's speed through the water (m/s).
    frame : Frame or None
        The line frame (None: straight along ``heading``).
    heading : float
        Compass heading of straight lines (rad).
    cap : float
        Largest margin returned.
    hours : float
        The current is read every hour over this many hours (tides).
    seabed : callable, optional
        ``zb(x, y)``: with it the current is read at ``altitude`` above the seabed (no higher than ``z``), where
        an AUV-mounted sensor flies (it was read at ``z``, the surface, whatever the mounting: an undercurrent
        across the lines left them no margin).
    altitude : float
        The altitude held above the seabed (m), with ``seabed``.

    Returns
    -------
    float
        The margin (fraction of the swath).
    """
    fr = frame if frame is not None else StraightFrame(heading)
    x0, y0, x1, y1 = area.bounds
    g = math.sqrt(area.area) / 12.0
    gx, gy = np.meshgrid(np.arange(x0, x1 + g, g), np.arange(y0, y1 + g, g))
    inside = shapely.contains_xy(area, gx, gy)
    px, py = np.r_[gx[inside], area.centroid.x], np.r_[gy[inside], area.centroid.y]
    pz = np.full(px.size, z) if seabed is None else np.minimum(np.asarray(seabed(px, py)) + altitude, z)
    pts = np.column_stack([px, py, pz])
    right = fr.right(fr.to_sn(px, py)[0])
    cross = 0.0
    for t in np.arange(0.0, hours * 3600.0 + 1.0, 3600.0):
        v = np.asarray(currents.velocity(pts, float(t)))[:, :2]
        cross = max(cross, float(np.nanmax(np.abs((v * right).sum(axis=1)))))
    sin_psi = min(cross / speed, 0.95) if speed > 0 else 0.0
    return float(min(1.0 - math.sqrt(1.0 - sin_psi**2), cap))
