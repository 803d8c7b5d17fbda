"""One colour convention for every figure, interactive or static.

Bathymetry uses the water half of cmocean's ``topo`` map (Thyng et al. 2016) and a chart's land
colours (sand to brown, :data:`LAND_COLORS`), split at 0 m the GMT way: the water part is stretched
over the seabed shown (up to 0 m) and the land part over ``[0, zmax]``, so that a depth has one
colour in the 3D view, the plan view and the PNG figures of a mission, land is never a shade of
water, and the break sits exactly at the coastline. The water stops at ``topo``'s aquamarine,
short of its pale green, so a shelf never reads as land. Current speed uses cmocean's ``speed``.

:func:`bathymetry_stops` is the one definition; :func:`bathymetry_colorscale` (plotly) and
:func:`bathymetry_cmap` (matplotlib) are two views of it.
"""

from __future__ import annotations

import html

import cmocean
import numpy as np
from matplotlib.colors import LinearSegmentedColormap, Normalize

__all__ = ["plotly_text", "mpl_text", "BATHY_CMAP", "SPEED_CMAP", "LAND_COLORS", "ROLE", "ALTITUDE_COLORSCALE",
           "bathymetry_stops", "bathymetry_colorscale", "bathymetry_cmap", "speed_colorscale", "SEA_LEVEL_M"]

BATHY_CMAP = cmocean.cm.topo
"""Colour map of seabed and land elevation: lower half water, upper half land."""

SPEED_CMAP = cmocean.cm.speed
"""Colour map of current speed."""

LAND_COLORS = ("#efe4c0", "#d9c38f", "#b39461", "#7d6440")
"""Land from the shore up, as on a chart: sand to brown, never a colour of the water scale (the pale
upper water of ``topo`` is green, and its land half starts dark green: a shelf read as land)."""

ROLE = {"path": "#ff7f0e", "track": "#1a1a1a", "vehicle": "#1a1a1a", "keys": "#ffd700", "start": "#32cd32",
        "goal": "#ffffff", "static": "#5f5f5f", "moving": "#7b3294", "coast": "#2b2b2b", "isobath": "rgba(0,0,0,0.33)",
        "limit": "#d7301f", "pnr": "#e7298a", "nav": "#b15928"}
"""One colour per role in every figure: red only means "too low" (the altitude scale's low end and the
``min_altitude_m`` line); obstacles are grey (static) and purple (moving), the vehicle and its track
near-black, the global path orange, key waypoints gold, the start green, the goal white, the point of
no return magenta (``viz/energy.py``), the navigation error band and the fixes brown (``viz/navview.py``)."""

ALTITUDE_COLORSCALE = "YlOrRd_r"
"""Track altitude above the seabed: dark red low, pale yellow high."""

SEA_LEVEL_M = 0.0
"""Elevation of the break between water and land colours."""

_N = 24
"""Stops on each side of the break."""

_WATER_TOP = 0.38
_WATER_OFFSHORE = 0.34


def plotly_text(text: str) -> str:
    """A label (a scenario's, a planner's, a zone's name) as plotly draws it: literally.

    Plotly reads a subset of HTML in its texts (``<b>``, ``<br>``, ``<a href>``, entities): a name holding
    ``<b>`` set the rest of a legend in bold.  Its ``<``, ``>`` and ``&`` are written as entities, which plotly
    draws as the characters.

    Parameters
    ----------
    text : str
        The label.

    Returns
    -------
    str
        The label with ``<``, ``>`` and ``&`` escaped.
    """
    return html.escape(text, quote=False)


def mpl_text(text: str) -> str:
    """A label as matplotlib draws it: literally (``$`` escaped; between two ``$`` it is mathtext, which fails to
    draw on a malformed formula).

    Parameters
    ----------
    text : str
        The label.

    Returns
    -------
    str
        The label with every ``$`` escaped.
    """
    return text.replace("$", r"\$")


def _hex(rgba: np.ndarray) -> list[str]:
    c = np.clip(np.round(np.asarray(rgba)[:, :3] * 255), 0, 255).astype(int)
    return [f"#{r:02x}{g:02x}{b:02x}" for r, g, b in c]


def bathymetry_stops(zmin: float, zmax: float) -> tuple[np.ndarray, list[str]]:
    """Positions in ``[0, 1]`` over ``[zmin, zmax]`` and colours of the bathymetry scale.

    Parameters
    ----------
    zmin, zmax : float
        Elevation range shown (m, up positive); ``zmin < zmax``.

    Returns
    -------
    positions : numpy.ndarray
        Increasing stop positions, ``0`` at ``zmin`` and ``1`` at ``zmax``.
    colors : list of str
        ``#rrggbb`` colour at each stop. Where the range spans sea level, two stops share the
        position of 0 m: the shallowest water colour and the lowest land colour (a hard break).
    """
    zmin, zmax = float(zmin), float(zmax)
    if not zmax > zmin:
        zmax = zmin + 1.0
    span = zmax - zmin
    pos: list[np.ndarray] = []
    frac: list[np.ndarray] = []
    if zmin < SEA_LEVEL_M:
        top = min(zmax, SEA_LEVEL_M)
        z = np.linspace(zmin, top, _N)
        pos.append((z - zmin) / span)
        # The water half spans the seabed shown; the palest, coastal colours are kept for
        # scenes that reach the coast, so deep water never looks shallow.
        lightest = _WATER_TOP if zmax >= SEA_LEVEL_M else _WATER_OFFSHORE
        frac.append(lightest * (z - zmin) / (top - zmin))
    if zmax > SEA_LEVEL_M:
        bottom = max(zmin, SEA_LEVEL_M)
        z = np.linspace(bottom, zmax, _N)
        pos.append((z - zmin) / span)
        frac.append(-1.0 - (z - SEA_LEVEL_M) / (zmax - SEA_LEVEL_M))  # negative: the land ramp
    p = np.concatenate(pos)
    p[0], p[-1] = 0.0, 1.0
    f = np.concatenate(frac)
    land = LinearSegmentedColormap.from_list("auvplan-land", list(LAND_COLORS))
    rgba = np.where((f >= 0)[:, None], BATHY_CMAP(np.clip(f, 0, 1)), land(np.clip(-1.0 - f, 0, 1)))
    return p, _hex(rgba)


def bathymetry_colorscale(zmin: float, zmax: float) -> list[list[float | str]]:
    """Plotly colourscale of :func:`bathymetry_stops`; use it with ``cmin=zmin, cmax=zmax``.

    Parameters
    ----------
    zmin, zmax : float
        Elevation range (m).

    Returns
    -------
    list of [float, str]
        ``[[position, colour], ...]``.
    """
    p, c = bathymetry_stops(zmin, zmax)
    return [[float(a), b] for a, b in zip(p, c)]


def bathymetry_cmap(zmin: float, zmax: float) -> tuple[LinearSegmentedColormap, Normalize]:
    """Matplotlib colour map and norm of :func:`bathymetry_stops`.

    Parameters
    ----------
    zmin, zmax : float
        Elevation range (m).

    Returns
    -------
    cmap : matplotlib.colors.LinearSegmentedColormap
        The colours of :func:`bathymetry_stops` over ``[0, 1]``.
    norm : matplotlib.colors.Normalize
        Linear over ``[zmin, zmax]``.
    """
    p, c = bathymetry_stops(zmin, zmax)
    cmap = LinearSegmentedColormap.from_list("auvplan-bathymetry", list(zip(p, c)), N=512)
    return cmap, Normalize(vmin=float(zmin), vmax=float(max(zmax, zmin + 1.0)))


def speed_colorscale(n: int = 16) -> list[list[float | str]]:
    """Plotly colourscale of current speed (cmocean ``speed``).

    Parameters
    ----------
    n : int
        Number of stops.

    Returns
    -------
    list of [float, str]
        ``[[position, colour], ...]`` over speeds scaled to ``[0, 1]``.
    """
    p = np.linspace(0.0, 1.0, n)
    return [[float(a), b] for a, b in zip(p, _hex(SPEED_CMAP(p)))]
