"""The sensor's swath on the seabed: how far a multibeam fan or a side-scan range reaches across the track
over the real seabed under it.

A multibeam of full opening angle ``θ`` looks ``β = θ/2`` either side of the vertical: its outer beam is
the ray ``z(t) = z_s - t cot β`` (``t`` the horizontal distance across the track) and the swath edge is the
ray's first meeting with the seabed ``zb(p + t u)``.  A side-scan of slant range ``R`` reaches the first
seabed point whose slant distance ``sqrt(t² + (z_s - zb)²)`` is ``R``.  Both edges are found on the seabed
profile sampled every ``step`` metres with a linear interpolation of the crossing, which is exact on a
plane (ray and seabed are then both linear in ``t``) — the analytic case of the 2023 CUMCM problem B.

The sensor is at the sea surface (``mounting = "surface"``, a survey vessel: the swath grows with the water
depth) or on the vehicle (``mounting = "auv"``: the swath grows with the altitude held).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["Seabed", "Sensor", "swath_reach", "SENSORS", "MOUNTINGS"]

Seabed = Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]]
"""Seabed elevation ``zb(x, y)`` (m, negative under water), vectorised over arrays of any shape."""

SENSORS = ("multibeam", "sidescan")
MOUNTINGS = ("surface", "auv")


@dataclass(frozen=True)
class Sensor:
    """A swath sensor and where it is mounted.

    Attributes
    ----------
    kind : str
        ``"multibeam"`` (fan of full opening ``opening_deg``) or ``"sidescan"`` (slant range ``range_m``).
    opening_deg : float
        Full fan opening of a multibeam (deg), in (0, 180).
    range_m : float
        Slant range of a side-scan per side (m).
    mounting : str
        ``"surface"`` (on a vessel at the surface: swath from the water depth) or ``"auv"`` (on the
        vehicle: swath from the altitude).
    altitude_m : float
        Altitude the vehicle holds above the seabed with the AUV mounting (m).
    max_reach_factor : float
        A fan that never meets the seabed (it dips away faster than the beam) is cut at this many times
        its flat-seabed reach.
    nadir_deg : float
        Full opening of a side-scan's blind cone under the sensor (deg): its nadir gap reaches where a ray
        at ``nadir_deg / 2`` from the vertical meets the seabed (``h tan(nadir_deg / 2)`` on a flat seabed
        ``h`` below).
    """

    kind: str = "multibeam"
    opening_deg: float = 120.0
    range_m: float = 0.0
    mounting: str = "surface"
    altitude_m: float = 0.0
    max_reach_factor: float = 4.0
    nadir_deg: float = 90.0

    def __post_init__(self) -> None:
        if self.kind not in SENSORS:
            raise ValueError(f"sensor = {self.kind!r}: choose multibeam or sidescan")
        if self.mounting not in MOUNTINGS:
            raise ValueError(f"mounting = {self.mounting!r}: choose surface or auv")
        if self.kind == "multibeam" and not 0.0 < self.opening_deg < 180.0:
            raise ValueError(f"opening_deg = {self.opening_deg}: must be in (0, 180)")
        if self.kind == "sidescan" and not self.range_m > 0:
            raise ValueError(f"range_m = {self.range_m}: a side-scan needs a positive slant range")
        if self.mounting == "auv" and not self.altitude_m > 0:
            raise ValueError(f"altitude_m = {self.altitude_m}: the AUV mounting needs a positive altitude")
        if self.kind == "sidescan" and self.mounting == "auv" and self.range_m <= self.altitude_m:
            raise ValueError(f"range_m = {self.range_m}: must exceed altitude_m = {self.altitude_m}")
        if not 0.0 < self.nadir_deg < 180.0:
            raise ValueError(f"nadir_deg = {self.nadir_deg}: must be in (0, 180)")
        if not self.max_reach_factor >= 1.0:
            raise ValueError(f"max_reach_factor = {self.max_reach_factor}: must be >= 1")

    @property
    def gap(self) -> Sensor | None:
        """The blind cone of a side-scan as a fan (its reach is the nadir gap); None for a multibeam."""
        if self.kind != "sidescan":
            return None
        return Sensor("multibeam", self.nadir_deg, 0.0, self.mounting, self.altitude_m, self.max_reach_factor)

    @property
    def half_angle(self) -> float:
        """Half the multibeam opening (rad)."""
        return math.radians(self.opening_deg) / 2.0

    def flat_reach(self, height: NDArray[np.float64] | float) -> NDArray[np.float64]:
        """Reach on one side over a flat seabed ``height`` metres below the sensor.

        Parameters
        ----------
        height : float or numpy.ndarray
            Height of the sensor above the seabed (m).

        Returns
        -------
        numpy.ndarray
            Horizontal reach (m).
        """
        h = np.maximum(np.asarray(height, dtype=float), 0.0)
        if self.kind == "multibeam":
            return np.asarray(h * math.tan(self.half_angle))
        return np.asarray(np.sqrt(np.maximum(self.range_m**2 - h**2, 0.0)))


def swath_reach(seabed: Seabed, sensor: Sensor, xy: NDArray[np.float64], z_sensor: NDArray[np.float64],
                across: NDArray[np.float64], step: float) -> NDArray[np.float64]:
    """Horizontal reach of the swath from sensor positions along across-track directions.

    Parameters
    ----------
    seabed : callable
        ``zb(x, y)`` (m).
    sensor : Sensor
        The sensor.
    xy : numpy.ndarray
        ``(N, 2)`` horizontal sensor positions (m).
    z_sensor : numpy.ndarray
        ``(N,)`` sensor elevations (m, z up; 0 at the surface).
    across : numpy.ndarray
        ``(N, 2)`` unit horizontal directions of the side looked at.
    step : float
        Sampling step of the seabed profile (m).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` horizontal distance from the sensor to the swath edge (m); 0 where the sensor is at or
        under the seabed (or a side-scan is higher than its range).
    """
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    zs = np.asarray(z_sensor, dtype=float).reshape(-1)
    u = np.asarray(across, dtype=float).reshape(-1, 2)
    n = xy.shape[0]
    if n == 0:
        return np.zeros(0)
    z0 = seabed(xy[:, 0], xy[:, 1])
    height = zs - z0
    cap = sensor.max_reach_factor * sensor.flat_reach(height) if sensor.kind == "multibeam" else \
        np.full(n, sensor.range_m)
    t_max = float(np.max(cap)) if n else 0.0
    m = max(2, int(math.ceil(t_max / step)) + 1)
    t = np.linspace(0.0, (m - 1) * step, m)
    px = xy[:, :1] + t[None, :] * u[:, :1]
    py = xy[:, 1:] + t[None, :] * u[:, 1:]
    zb = seabed(px, py)
    if sensor.kind == "multibeam":
        f = zs[:, None] - t[None, :] / math.tan(sensor.half_angle) - zb  # > 0 while the beam is above the seabed
    else:
        f = sensor.range_m**2 - t[None, :] ** 2 - (zs[:, None] - zb) ** 2  # > 0 while within the range
    below = f <= 0.0
    below[:, 0] |= height <= 0.0
    first = np.where(below.any(axis=1), np.argmax(below, axis=1), m)
    reach = np.empty(n)
    hit = (first > 0) & (first < m)
    j = first[hit]
    rows = np.flatnonzero(hit)
    fa, fb = f[rows, j - 1], f[rows, j]
    reach[rows] = t[j - 1] + step * fa / (fa - fb)
    reach[first == 0] = 0.0
    reach[first == m] = t[-1]
    return np.minimum(reach, cap)
