"""Geodesy for inputs and exports: the local metric frame about a scenario origin.

The local frame is pyproj's azimuthal equidistant projection about
``(lat0, lon0)`` on WGS 84 (x east, y north, metres).  Geographic grids are
projected once, on input (:mod:`auvplan.io.data.grids`), so that the algorithms below
never see latitudes or longitudes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from pyproj import Transformer

__all__ = ["LocalFrame", "forward_kept", "normalise_lon"]


def normalise_lon(lon: ArrayLike) -> NDArray[np.float64]:
    """Map longitudes to ``[-180, 180)``.

    Parameters
    ----------
    lon : array_like
        Longitudes (degrees).

    Returns
    -------
    numpy.ndarray
        The same longitudes in ``[-180, 180)`` (degrees).
    """
    return np.mod(np.asarray(lon, dtype=float) + 180.0, 360.0) - 180.0


@dataclass(frozen=True)
class LocalFrame:
    """Azimuthal equidistant frame about ``(lat0, lon0)`` (degrees).

    The projections (pyproj ``Transformer``) are made at the first :meth:`forward` or :meth:`inverse`: a plan
    whose files come from the readers' cache never projects, and does not import pyproj (issue 56).

    Parameters
    ----------
    lat0 : float
        Latitude of the origin (degrees).
    lon0 : float
        Longitude of the origin (degrees).
    """

    lat0: float
    lon0: float
    _fwd: Transformer | None = field(init=False, repr=False, compare=False, default=None)
    _inv: Transformer | None = field(init=False, repr=False, compare=False, default=None)

    def __post_init__(self) -> None:
        if not (-90.0 <= self.lat0 <= 90.0) or not np.isfinite(self.lon0):
            raise ValueError(f"origin must be a valid latitude/longitude, got ({self.lat0}, {self.lon0})")

    def _transformer(self, name: str) -> Any:
        """The forward (``_fwd``) or inverse (``_inv``) projection, made at its first use."""
        made = getattr(self, name)
        if made is None:
            from pyproj import Transformer

            lon0 = float(normalise_lon(self.lon0))
            proj = f"+proj=aeqd +lat_0={self.lat0} +lon_0={lon0} +datum=WGS84 +units=m +no_defs"
            ends = ("EPSG:4326", proj) if name == "_fwd" else (proj, "EPSG:4326")
            made = Transformer.from_crs(*ends, always_xy=True)
            object.__setattr__(self, name, made)
        return made

    def forward(self, lon: ArrayLike, lat: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Project longitude/latitude into the local frame.

        Parameters
        ----------
        lon, lat : array_like
            Longitude and latitude (degrees, WGS84).

        Returns
        -------
        x, y : numpy.ndarray
            East and north of the origin (m).
        """
        x, y = self._transformer("_fwd").transform(normalise_lon(lon), np.asarray(lat, dtype=float))
        return np.asarray(x), np.asarray(y)

    def inverse(self, x: ArrayLike, y: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Unproject local coordinates to longitude and latitude.

        Parameters
        ----------
        x, y : array_like
            East and north of the origin (m).

        Returns
        -------
        lon, lat : numpy.ndarray
            Longitude in ``[-180, 180)`` and latitude (degrees, WGS84).
        """
        lon, lat = self._transformer("_inv").transform(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        return normalise_lon(lon), np.asarray(lat)


def forward_kept(frame: LocalFrame, lon: ArrayLike, lat: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``frame.forward(lon, lat)``, kept in the readers' cache: pyproj's own numbers, computed once.

    The key is the frame's origin and the bits of the positions (pyproj's version is in the cache's code
    stamp), so that a scenario parsed before projects nothing and imports no pyproj (~0.1 s of a command's
    start, issue 56); with ``AUVPLAN_CACHE=0`` it is ``frame.forward``.

    Parameters
    ----------
    frame : LocalFrame
        The local frame.
    lon, lat : array_like
        Longitude and latitude (degrees, WGS84), as :meth:`LocalFrame.forward` takes them.

    Returns
    -------
    x, y : numpy.ndarray
        East and north of the origin (m): :meth:`LocalFrame.forward`'s arrays.
    """
    from .cache import cached

    lon_a, lat_a = np.asarray(lon, dtype=float), np.asarray(lat, dtype=float)

    def compute() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return frame.forward(lon, lat)

    request = (float(frame.lat0), float(frame.lon0), lon_a.shape, lon_a.tobytes().hex(), lat_a.shape,
               lat_a.tobytes().hex())
    xy: tuple[NDArray[np.float64], NDArray[np.float64]] = cached(
        "positions", request, (), compute, lambda v: ({"x": v[0], "y": v[1]}, {}), lambda a, _: (a["x"], a["y"]))
    return xy
