"""The page's navigation error band (issue 52 item 6): the horizontal band within the predicted error along the
mission, as the page draws it (:func:`nav_band`)."""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from ..app.page.budget import leg_water_m
from ..nav import error_profile, surface_kinds
from ..nav.band import error_band
from ..sim import Mission
from ..sim.navigation import launch_flight
from ..world import World

__all__ = ["SIMPLIFY_M", "nav_band"]

SIMPLIFY_M = 1.0
"""Tolerance of the drawn navigation error band (m): within this of the exact union of its discs."""


def nav_band(world: World, mission: Mission, w: NDArray[np.float64],
             speeds: float | NDArray[np.float64] | None = None) -> dict[str, Any] | None:
    """The navigation error band of waypoints ``w`` for the page (None without ``[navigation]``).

    Issue 52 item 6: the horizontal band within the predicted error (confidence × σ), its surface waypoints
    taken as the GPS fixes, as the page draws it (one ring list, rings separated by None), simplified to
    :data:`SIMPLIFY_M`.

    Parameters
    ----------
    world : World
        The seabed (lock states).
    mission : Mission
        Its ``navigation``.
    w : numpy.ndarray
        ``(N, 3)`` waypoints (m).
    speeds : float or numpy.ndarray, optional
        Each leg's through-water speed (m/s; default the vehicle's): the legs flown through the current give the
        drift without bottom lock over their water distance (:meth:`auvplan.endurance.Traverse.leg_water_m`), the
        launch's dive from the surface above the first waypoint counted (:func:`auvplan.sim.navigation.launch_flight`).

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
    v = mission.vehicle.speed if speeds is None else speeds
    dwell = np.array([nav.surface_s if k else 0.0 for k in kinds])
    flown = launch_flight(world, w, v, dwell=dwell)  # launched from the surface, as the exported .plan is checked
    water, launch = (leg_water_m(world, w, v, dwell), None) if flown is None else (flown[1], flown[0])
    profile = error_profile(world, w, kinds, nav, nav.usbl_xy, water_m=water, launch_water_m=launch)
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
