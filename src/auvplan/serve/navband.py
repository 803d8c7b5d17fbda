"""The navigation error band of the mission being edited (issue 52 item 6): the horizontal band within the
predicted error (``[navigation]`` confidence × σ) along the waypoints, its surface waypoints taken as the
GPS fixes, as the page draws it (one ring list, rings separated by nulls), simplified to a metre.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from ..nav import error_profile, surface_kinds
from ..nav.band import error_band
from ..sim import Mission
from ..world import World

__all__ = ["nav_band", "SIMPLIFY_M"]

SIMPLIFY_M = 1.0
"""Tolerance of the drawn outline (m): the band drawn is within this of the exact union of its discs."""


def nav_band(world: World, mission: Mission, w: NDArray[np.float64]) -> dict[str, Any] | None:
    """The error band of waypoints ``w`` for the page (None without ``[navigation]``).

    Parameters
    ----------
    world : World
        The seabed (lock states).
    mission : Mission
        Its ``navigation``.
    w : numpy.ndarray
        ``(N, 3)`` waypoints (m).

    Returns
    -------
    dict or None
        ``x`` and ``y`` (the outline, rings separated by None; m), ``max_error_m`` (the largest
        predicted error), ``budget_m`` (``max_error_m`` of the scenario), ``confidence`` and ``fixes``.
    """
    nav = mission.navigation
    if nav is None or w.shape[0] < 2:
        return None
    kinds = surface_kinds(w)
    profile = error_profile(world, w, kinds, nav, nav.usbl_xy)
    band = shapely.simplify(error_band(profile), SIMPLIFY_M)
    xs: list[float | None] = []
    ys: list[float | None] = []
    for poly in getattr(band, "geoms", [band]):
        for ring in [poly.exterior, *poly.interiors]:
            c = np.asarray(ring.coords)
            xs += [*np.round(c[:, 0], 2).tolist(), None]
            ys += [*np.round(c[:, 1], 2).tolist(), None]
    return {"x": xs, "y": ys, "max_error_m": round(float(profile.before_m.max()), 2), "budget_m": nav.max_error_m,
            "confidence": nav.confidence, "fixes": sum(1 for k in kinds if k)}
