"""Chart conventions shared by the interactive and the static plan views: data in, numbers out.

- Isobaths at a round interval (1, 2 or 5 × 10^k m) chosen from the relief of the water shown, so a
  200 km ocean box and a 6 km shelf both get about a dozen labelled depth contours, never a blocky
  handful (:func:`isobath_levels`).
- The coastline: the 0 m contour of the seabed model, or the land polygons' shoreline where the
  scenario has them (:func:`coastline`).
- Labels that do not collide: each label takes the first candidate position whose box (in screen
  pixels) is clear of the labels already placed (:func:`place_labels`).
- A minimum drawn size: an object smaller than a few pixels at the chart's scale is also marked by a
  symbol of fixed screen size; its true outline shows on zoom (:func:`needs_marker`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import contourpy
import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from ..world import World

__all__ = ["nice_step", "scale_bar", "north_arrow", "degree_label", "graticule", "ToLonLat", "ISOBATH_STEPS",
           "isobath_levels", "contour_lines", "coastline", "place_labels", "needs_marker", "MIN_DRAWN_PX"]

ToLonLat = Callable[[Any, Any], tuple[ArrayLike, ArrayLike]]
"""Map from local ``(x, y)`` (m, arrays) to ``(lon, lat)`` (degrees): a pyproj transform."""


def nice_step(span: float, count: float = 5.0) -> float:
    """A round step (1, 2, 2.5, 5 × 10^k) that cuts ``span`` into about ``count`` parts.

    Parameters
    ----------
    span : float
        Positive length.
    count : float
        Wanted number of parts.

    Returns
    -------
    float
        The step, in the unit of ``span``.
    """
    raw = span / count
    if not (np.isfinite(raw) and raw > 0):
        return 1.0
    decade = 10.0 ** np.floor(np.log10(raw))
    return float(min((n * decade for n in (1.0, 2.0, 2.5, 5.0, 10.0)), key=lambda s: abs(s - raw)))


def scale_bar(world: World) -> tuple[float, float, float, str]:
    """The scale bar of a plan view: a round length about a fifth of the width, in the lower right corner.

    Parameters
    ----------
    world : World
        Its bounds.

    Returns
    -------
    x0, y0, length : float
        The bar's left end and its length (m).
    label : str
        ``'2 km'``, ``'500 m'``.
    """
    b = world.bounds
    w, h = b.xmax - b.xmin, b.ymax - b.ymin
    length = nice_step(w / 5.0, 1.0)
    label = f"{length / 1000:g} km" if length >= 1000 else f"{length:g} m"
    return b.xmax - 0.06 * w - length, b.ymin + 0.06 * h, length, label


def north_arrow(world: World, to_lonlat: ToLonLat | None) -> tuple[float, float, float, float]:
    """The north arrow of a plan view: its foot in the upper left corner and the direction of north there.

    North is towards increasing latitude where the local frame's geography is known (central differences
    of the latitude at the foot), else grid north (+y).

    Parameters
    ----------
    world : World
        Its bounds.
    to_lonlat : callable or None
        ``(x, y) -> (lon, lat)`` of the local frame.

    Returns
    -------
    cx, cy : float
        The arrow's foot (m).
    nx, ny : float
        Unit vector towards north.
    """
    b = world.bounds
    w, h = b.xmax - b.xmin, b.ymax - b.ymin
    nx, ny = 0.0, 1.0
    cx, cy = b.xmin + 0.06 * w, b.ymax - 0.16 * h
    if to_lonlat is not None:
        d = 1e-3 * max(w, h)
        lat = [float(np.asarray(to_lonlat(np.array([cx + dx]), np.array([cy + dy]))[1])[0])
               for dx, dy in ((d, 0.0), (-d, 0.0), (0.0, d), (0.0, -d))]
        g = np.array([lat[0] - lat[1], lat[2] - lat[3]])
        if np.linalg.norm(g) > 0:
            nx, ny = g / np.linalg.norm(g)
    return cx, cy, float(nx), float(ny)


def degree_label(value: float, axis: str, step: float) -> str:
    """``'158.5°E'``, ``'14°N'``: a longitude (``axis='lon'``) or latitude with the decimals of ``step``.

    Parameters
    ----------
    value : float
        Degrees.
    axis : {'lon', 'lat'}
        Which coordinate ``value`` is.
    step : float
        Graticule step, sets the number of decimals.

    Returns
    -------
    str
        The label, hemisphere letter after the absolute value.
    """
    decimals = max(0, int(np.ceil(-np.log10(step) - 1e-9))) if step < 1 else 0
    if step < 1 and abs(step * 10 ** decimals - round(step * 10 ** decimals)) > 1e-9:
        decimals += 1
    hemi = ("E", "W") if axis == "lon" else ("N", "S")
    return f"{abs(value):.{decimals}f}°{hemi[0] if value >= 0 else hemi[1]}"


def graticule(world: World, to_lonlat: ToLonLat, n: int = 80) -> list[tuple[str, float, NDArray[np.float64], float]]:
    """Lines of constant longitude and latitude across the bounds.

    Parameters
    ----------
    world : World
        Its bounds.
    to_lonlat : callable
        ``(x, y) -> (lon, lat)`` in degrees.
    n : int
        Sampling grid size.

    Returns
    -------
    list of (axis, value, polyline, step)
        ``axis`` is ``'lon'`` or ``'lat'``, ``value`` its degrees, ``polyline`` ``(M, 2)`` local x, y (m),
        ``step`` the graticule step (degrees).
    """
    b = world.bounds
    gx, gy = np.meshgrid(np.linspace(b.xmin, b.xmax, n), np.linspace(b.ymin, b.ymax, n))
    lon, lat = (np.asarray(a, dtype=float) for a in to_lonlat(gx, gy))
    lines = []
    for axis, field in (("lon", lon), ("lat", lat)):
        step = nice_step(float(np.ptp(field)), 4.0)
        gen = contourpy.contour_generator(gx, gy, field)
        for v in np.arange(np.ceil(field.min() / step), np.floor(field.max() / step) + 1) * step:
            for seg in gen.lines(float(v)):
                if len(seg) > 1:
                    lines.append((axis, float(v), np.asarray(seg), step))
    return lines


ISOBATH_STEPS = (1.0, 2.0, 5.0)
"""Mantissas of a chart's isobath interval (× 10^k m)."""

MIN_DRAWN_PX = 6.0
"""Objects smaller than this on screen also get a fixed-size symbol."""


def isobath_levels(zmin: float, zmax: float, target: float = 12.0) -> tuple[NDArray[np.float64], float]:
    """Depth-contour elevations below sea level at a round interval chosen from the relief.

    Parameters
    ----------
    zmin, zmax : float
        Elevation range of the seabed shown (m, up positive).
    target : float
        About how many isobaths to draw across the relief under water.

    Returns
    -------
    levels : numpy.ndarray
        Elevations (m), increasing, every one strictly below 0 and inside ``[zmin, zmax]``.
    step : float
        The interval (m): 1, 2 or 5 × 10^k.
    """
    top = min(float(zmax), 0.0)
    relief = top - float(zmin)
    if not (np.isfinite(relief) and relief > 0):
        return np.empty(0), 1.0
    raw = relief / target
    decade = 10.0 ** np.floor(np.log10(raw))
    step = float(min((m * decade * k for m in ISOBATH_STEPS for k in (1.0, 10.0)), key=lambda s: abs(np.log(s / raw))))
    levels = np.arange(np.ceil(zmin / step), np.floor(top / step) + 1) * step
    return levels[(levels < 0.0) & (levels >= zmin) & (levels <= top)], step


def contour_lines(x: NDArray[np.float64], y: NDArray[np.float64], z: NDArray[np.float64],
                  level: float) -> list[NDArray[np.float64]]:
    """Polylines ``(M, 2)`` of one contour of a gridded field (contourpy).

    Parameters
    ----------
    x, y : numpy.ndarray
        Grid axes (N,), (M,).
    z : numpy.ndarray
        Field (M, N).
    level : float
        Contour value.

    Returns
    -------
    list of numpy.ndarray
        The contour's pieces, each ``(K, 2)`` with ``K >= 2``.
    """
    gen = contourpy.contour_generator(x, y, np.asarray(z, dtype=float))
    return [np.asarray(s, dtype=float) for s in gen.lines(float(level)) if len(s) > 1]


def coastline(world: World, x: NDArray[np.float64], y: NDArray[np.float64],
              z: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """The shoreline inside the bounds: the land polygons' boundary if the world has land, else the 0 m
    contour of the seabed grid.

    Parameters
    ----------
    world : World
        Its land and bounds.
    x, y, z : numpy.ndarray
        The seabed grid drawn (axes and elevation, m).

    Returns
    -------
    list of numpy.ndarray
        Polylines ``(K, 2)`` in the local frame (m); empty for an area without coast.
    """
    b = world.bounds
    if world.land is not None and not world.land.is_empty:
        box = shapely.box(b.xmin, b.ymin, b.xmax, b.ymax)
        shore = shapely.intersection(shapely.boundary(world.land.geometry), box)
        lines = [np.asarray(g.coords, dtype=float)[:, :2] for g in shapely.get_parts(shore)
                 if shapely.get_type_id(g) in (1, 2) and len(g.coords) > 1]
        if lines:
            return lines
    if not (np.nanmin(z) < 0.0 < np.nanmax(z)):
        return []
    return contour_lines(x, y, z, 0.0)


def _overlap(a: NDArray[np.float64], b: NDArray[np.float64]) -> bool:
    return bool(a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3])


def place_labels(candidates: Sequence[Sequence[tuple[float, float]]], sizes: Sequence[tuple[float, float]],
                 px_per_unit: tuple[float, float], pad: float = 2.0,
                 taken: Sequence[tuple[float, float, float, float]] = ()) -> list[int | None]:
    """Choose for each label the first candidate position whose box is clear of those placed before.

    Parameters
    ----------
    candidates : sequence of sequences of (x, y)
        For each label, its positions in data units in order of preference (the box is centred there).
    sizes : sequence of (width, height)
        Each label's box in pixels.
    px_per_unit : (float, float)
        Pixels per data unit along x and y.
    pad : float
        Clear margin around each box (px).
    taken : sequence of (x0, y0, x1, y1)
        Boxes already occupied (px).

    Returns
    -------
    list of int or None
        Index of the chosen candidate per label, or None where every candidate collides (the label is
        left out rather than drawn over another).
    """
    placed = [np.asarray(t, dtype=float) for t in taken]
    out: list[int | None] = []
    kx, ky = px_per_unit
    for cands, (w, h) in zip(candidates, sizes):
        choice = None
        for i, (cx, cy) in enumerate(cands):
            box = np.array([cx * kx - w / 2 - pad, cy * ky - h / 2 - pad, cx * kx + w / 2 + pad, cy * ky + h / 2 + pad])
            if not any(_overlap(box, p) for p in placed):
                placed.append(box)
                choice = i
                break
        out.append(choice)
    return out


def needs_marker(size_m: float, px_per_m: float) -> bool:
    """Whether an object of ``size_m`` (its diameter) is drawn smaller than :data:`MIN_DRAWN_PX`.

    Parameters
    ----------
    size_m : float
        The object's horizontal size (m).
    px_per_m : float
        Screen pixels per metre at the chart's full extent.

    Returns
    -------
    bool
        True when a fixed-size symbol must mark it.
    """
    return bool(size_m * px_per_m < MIN_DRAWN_PX)
