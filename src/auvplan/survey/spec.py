"""The ``[survey]`` table of a scenario (issue 37's contract): the area, the sensor, its mounting, the
overlap bounds and the line direction.  The loader checks types and ranges here; :mod:`auvplan.io`
reads the area (lat/lon list or a GeoJSON/KML/shapefile layer) into the local frame."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # imported where a survey is checked or placed (issue 56: a scenario without one needs neither)
    from .lines.placement import LineParams
    from .lines.swath import Sensor

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
        A GeoJSON, KML, shapefile or GeoPackage (any GDAL vector format, any CRS) with the area's polygon
        instead.
    layer : str
        The layer of ``file`` or ``centerline_file`` (needed when the file holds several; a file of one layer
        needs none); the largest polygon (the longest line) of the layer is used.
    centerline : tuple of (lat, lon)
        A corridor's centre line (deg, WGS 84), instead of an area; needs ``width_m`` or ``widths_m``.
    centerline_xy : tuple of (x, y)
        The centre line in the local frame (m).
    centerline_file : str
        A vector file (any CRS) with the centre line.
    width_m : float
        Full width of the corridor (m).
    widths_m : tuple of float
        Full width at every vertex of ``centerline`` / ``centerline_xy`` (m), instead of ``width_m``.
    bend_radius_m : float
        Radius the centre line's corners are rounded to (m); 0: the vehicle's turn radius plus half the
        widest corridor plus a swath, so every line parallel to it turns within the vehicle's radius.
    tie_lines : int
        Number of tie (cross) lines flown across the main lines after them, evenly spread along.
    sensor : str
        ``"multibeam"`` or ``"sidescan"``.
    opening_deg : float
        Full opening of the multibeam fan (deg).
    range_m : float
        Slant range of the side-scan per side (m).
    nadir_deg : float
        Full opening of the side-scan's blind cone under the sensor (deg): the nadir gap reaches
        ``h tan(nadir_deg / 2)`` either side at a height ``h`` over a flat seabed.
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
    centerline: tuple[tuple[float, float], ...] = ()
    centerline_xy: tuple[tuple[float, float], ...] = ()
    centerline_file: str = ""
    width_m: float = 0.0
    widths_m: tuple[float, ...] = ()
    bend_radius_m: float = 0.0
    tie_lines: int = 0
    sensor: str = "multibeam"
    opening_deg: float = 120.0
    range_m: float = 0.0
    nadir_deg: float = 90.0
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
        given = [k for k in ("polygon", "polygon_xy", "file", "centerline", "centerline_xy", "centerline_file")
                 if getattr(self, k)]
        if len(given) != 1:
            raise ValueError("give exactly one of 'polygon' ([[lat, lon], ...]), 'polygon_xy', 'file', "
                             f"'centerline', 'centerline_xy' or 'centerline_file' (got {', '.join(given) or 'none'})")
        pts = self.polygon or self.polygon_xy
        if pts and len(pts) < 3:
            raise ValueError(f"polygon = {[list(p) for p in pts]}: needs at least three corners")
        line = self.centerline or self.centerline_xy
        if line and len(line) < 2:
            raise ValueError(f"centerline = {[list(p) for p in line]}: needs at least two points")
        for key in ("polygon", "centerline"):
            for lat, lon in getattr(self, key):
                if not (-90.0 <= lat <= 90.0 and -180.0 <= lon <= 360.0):
                    raise ValueError(f"{key} = [{lat}, {lon}]: not a [lat, lon] pair in degrees")
        if self.layer and not (self.file or self.centerline_file):
            raise ValueError(f"layer = {self.layer!r}: needs 'file' or 'centerline_file'")
        self._check_corridor()
        if not 0.0 < self.nadir_deg < 180.0:
            raise ValueError(f"nadir_deg = {self.nadir_deg}: must be in (0, 180)")
        if self.tie_lines < 0:
            raise ValueError(f"tie_lines = {self.tie_lines}: must be >= 0")
        if self.heading_deg is not None and not math.isfinite(self.heading_deg):
            raise ValueError(f"heading_deg = {self.heading_deg}: must be finite")
        if self.station_m < 0 or self.step_m < 0 or self.run_in_m < 0:
            raise ValueError("station_m, step_m and run_in_m must be >= 0")
        from .lines.placement import LineParams

        self.sensor_model()
        LineParams(self.overlap[0], self.overlap[1], 1.0, self.max_bend_deg, self.pitch_max_deg)

    @property
    def corridor(self) -> bool:
        """Whether the survey is a corridor along a centre line."""
        return bool(self.centerline or self.centerline_xy or self.centerline_file)

    def _check_corridor(self) -> None:
        if not self.corridor:
            if self.width_m or self.widths_m:
                raise ValueError(f"width_m = {self.width_m or list(self.widths_m)}: needs 'centerline'")
            return
        if bool(self.width_m) == bool(self.widths_m):
            raise ValueError("a corridor needs exactly one of 'width_m' and 'widths_m' (per centre-line vertex)")
        if self.width_m and not (math.isfinite(self.width_m) and self.width_m > 0):
            raise ValueError(f"width_m = {self.width_m}: must be positive")
        if self.widths_m:
            n = len(self.centerline or self.centerline_xy)
            if len(self.widths_m) != n:
                raise ValueError(f"widths_m = {list(self.widths_m)}: needs one width per centre-line vertex ({n}; "
                                 "give width_m with centerline_file)")
            if not all(math.isfinite(w) and w > 0 for w in self.widths_m):
                raise ValueError(f"widths_m = {list(self.widths_m)}: every width must be positive")
        if not (math.isfinite(self.bend_radius_m) and self.bend_radius_m >= 0):
            raise ValueError(f"bend_radius_m = {self.bend_radius_m}: must be >= 0")

    def sensor_model(self) -> Sensor:
        """The sensor of the table.

        Returns
        -------
        Sensor
            Kind, opening or range, mounting and altitude.
        """
        from .lines.swath import Sensor

        return Sensor(self.sensor, self.opening_deg, self.range_m, self.mounting, self.altitude_m,
                      nadir_deg=self.nadir_deg)

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
        from .lines.placement import LineParams

        station = self.station_m or min(max(cell_m / 4.0, 10.0), 100.0)
        step = self.step_m or min(max(cell_m / 10.0, 1.0), 20.0)
        return LineParams(self.overlap[0], self.overlap[1], station, self.max_bend_deg, self.pitch_max_deg,
                          step_m=step)
