"""The zone itself: one no-go prism (:class:`Zone`, a footprint times a depth band) and how a polyline passes
it (:class:`ZoneApproach`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import shapely

from ...errors import DataError

__all__ = ["Zone", "ZoneApproach"]


@dataclass(frozen=True, eq=False)
class Zone:
    """One no-go prism.

    Parameters
    ----------
    name : str
        Name used in messages and drawings (a chart's object name, a cable's name …).
    footprint : shapely Polygon or MultiPolygon
        Horizontal extent in the local frame (m).
    top : float, default 0.0
        Depth of the top face (m, positive down); 0 is the sea surface.
    bottom : float, default inf
        Depth of the bottom face (m, positive down); ``inf`` reaches the seabed.
    above_seabed : float or None
        When given, the band is from the seabed up to this height (m) and ``top``/``bottom`` are
        not used.

    Raises
    ------
    DataError
        If the footprint is not polygonal or is empty, or the band is empty or negative.
    """

    name: str
    footprint: shapely.Geometry
    top: float = 0.0
    bottom: float = math.inf
    above_seabed: float | None = None

    def __post_init__(self) -> None:
        g = self.footprint
        if not isinstance(g, shapely.Geometry) or shapely.get_type_id(g) not in (3, 6) or g.is_empty:
            raise DataError(f"zone {self.name!r}: expected a non-empty polygon footprint, got "
                            f"{getattr(g, 'geom_type', type(g).__name__)}")
        if not shapely.is_valid(g):
            object.__setattr__(self, "footprint", shapely.make_valid(g))
        if self.above_seabed is not None:
            if not (math.isfinite(self.above_seabed) and self.above_seabed > 0):
                raise DataError(f"zone {self.name!r}: above_seabed_m must be positive, got {self.above_seabed}")
        elif not (self.top >= 0 and self.bottom > self.top):
            raise DataError(f"zone {self.name!r}: need 0 <= top_m < bottom_m, got top_m = {self.top}, "
                            f"bottom_m = {self.bottom}")

    @property
    def band(self) -> str:
        """The vertical band in words (for messages and drawings).

        Returns
        -------
        str
            E.g. ``"surface to seabed"``, ``"20-80 m deep"``, ``"seabed + 15 m"``.
        """
        if self.above_seabed is not None:
            return f"seabed + {self.above_seabed:g} m"
        top = "surface" if self.top == 0 else f"{self.top:g} m"
        bottom = "seabed" if math.isinf(self.bottom) else f"{self.bottom:g} m deep"
        return f"{top} to {bottom}"


@dataclass(frozen=True)
class ZoneApproach:
    """How a polyline passes one zone (:meth:`Zones.approach`).

    Attributes
    ----------
    name : str
        The zone.
    closest_m : float
        Least distance of the polyline to the prism (m); ≤ 0 when a leg enters it.
    entered_legs : tuple of int
        The legs (from 1) that enter it (exact test); empty when none does.
    """

    name: str
    closest_m: float
    entered_legs: tuple[int, ...]

    def as_dict(self) -> dict[str, object]:
        """The approach as JSON-ready values.

        Returns
        -------
        dict
            ``name``, ``closest_m``, ``entered_legs``.
        """
        return {"name": self.name, "closest_m": self.closest_m, "entered_legs": list(self.entered_legs)}
