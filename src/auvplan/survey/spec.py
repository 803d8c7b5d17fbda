"""The ``[survey]`` table of a scenario (issue 37's contract): the area, the sensor, its mounting, the
overlap bounds and the line direction.  The loader checks types and ranges here; :mod:`auvplan.io`
reads the area (lat/lon list or a GeoJSON/KML/shapefile layer) into the local frame."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .lines import LineParams
from .swath import Sensor

__all__ = ["SurveySpec"]


@dataclass(frozen=True)
class SurveySpec:
    """``[survey]``: a coverage survey of an area.

    Attributes
    ----------
    polygon : tuple of (lat, lon)
        The area's corners (deg, WGS 84); needs ``[origin]``.
    polygon_xy : tuple of (x, y)
        The area's corners in the local frame (m), for scenes without ``[origin]``.
    file : str
        A GeoJSON, KML or shapefile (or any GDAL vector format) with the area's polygon instead.
    layer : str
        The layer of ``file`` (default: the first); the largest polygon of the layer is surveyed.
    sensor : str
        ``"multibeam"`` or ``"sidescan"``.
    opening_deg : float
        Full opening of the multibeam fan (deg).
    range_m : float
        Slant range of the side-scan per side (m).
    mounting : str
        ``"surface"`` (the swath from the water depth) or ``"auv"`` (from the altitude held).
    altitude_m : float
        Altitude held above the seabed with the AUV mounting (m).
    overlap : tuple of float
        ``[min, max]`` overlap of adjacent swaths, fractions of the narrower swath.
    heading_deg : float or None
        Compass heading of the lines (deg); absent: chosen for the shortest survey.
    station_m : float
        Distance between stations along the lines (m); 0: a quarter of the terrain cell, within [10, 100] m.
    step_m : float
        Sampling step of the seabed under the swath (m); 0: a tenth of the terrain cell, within [1, 20] m.
    max_bend_deg : float
        Largest angle of a line off its nominal heading, where it follows the seabed (deg).
    pitch_max_deg : float
        Steepest climb or dive while holding the altitude (deg).
    run_in_m : float
        Straight run beyond the area at both ends of every line (m).
    """

    polygon: tuple[tuple[float, float], ...] = ()
    polygon_xy: tuple[tuple[float, float], ...] = ()
    file: str = ""
    layer: str = ""
    sensor: str = "multibeam"
    opening_deg: float = 120.0
    range_m: float = 0.0
    mounting: str = "surface"
    altitude_m: float = 0.0
    overlap: tuple[float, float] = (0.10, 0.20)
    heading_deg: float | None = None
    station_m: float = 0.0
    step_m: float = 0.0
    max_bend_deg: float = 15.0
    pitch_max_deg: float = 15.0
    run_in_m: float = 60.0

    def __post_init__(self) -> None:
        given = [k for k in ("polygon", "polygon_xy", "file") if getattr(self, k)]
        if len(given) != 1:
            raise ValueError("give exactly one of 'polygon' ([[lat, lon], ...]), 'polygon_xy' or 'file' "
                             f"(got {', '.join(given) or 'none'})")
        pts = self.polygon or self.polygon_xy
        if pts and len(pts) < 3:
            raise ValueError(f"polygon = {[list(p) for p in pts]}: needs at least three corners")
        for lat, lon in self.polygon:
            if not (-90.0 <= lat <= 90.0 and -180.0 <= lon <= 360.0):
                raise ValueError(f"polygon = [{lat}, {lon}]: not a [lat, lon] pair in degrees")
        if self.layer and not self.file:
            raise ValueError(f"layer = {self.layer!r}: needs 'file'")
        if self.heading_deg is not None and not math.isfinite(self.heading_deg):
            raise ValueError(f"heading_deg = {self.heading_deg}: must be finite")
        if self.station_m < 0 or self.step_m < 0 or self.run_in_m < 0:
            raise ValueError("station_m, step_m and run_in_m must be >= 0")
        self.sensor_model()
        LineParams(self.overlap[0], self.overlap[1], 1.0, self.max_bend_deg, self.pitch_max_deg)

    def sensor_model(self) -> Sensor:
        """The sensor of the table.

        Returns
        -------
        Sensor
            Kind, opening or range, mounting and altitude.
        """
        return Sensor(self.sensor, self.opening_deg, self.range_m, self.mounting, self.altitude_m)

    def line_params(self, cell_m: float) -> LineParams:
        """The line placement parameters of the table.

        Parameters
        ----------
        cell_m : float
            Terrain cell (m), for the default station spacing and sampling step.

        Returns
        -------
        LineParams
            Overlap bounds, stations, sampling, bend and pitch limits.
        """
        station = self.station_m or min(max(cell_m / 4.0, 10.0), 100.0)
        step = self.step_m or min(max(cell_m / 10.0, 1.0), 20.0)
        return LineParams(self.overlap[0], self.overlap[1], station, self.max_bend_deg, self.pitch_max_deg,
                          step_m=step)
