"""``[mission] confidence``: the scenario's seabed raised to its worst case at that confidence (issue 39).

The one-sigma vertical uncertainty comes from ``[terrain] uncertainty`` (a variable of the terrain
file, read on the same grid as the elevation; or ``"slope"``, the slope rule with floor
``uncertainty_m``), ``[terrain] uncertainty_m`` alone (a constant), or ``[terrain.synthetic]
uncertainty_m``; :func:`auvplan.world.uncertainty.worst_case` raises the seabed by Φ⁻¹(confidence) σ.
Every plan, check and flight of the scenario then holds against that seabed, so the clearance it
reports is the clearance "at 95 %".
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ....errors import DataError, ScenarioError
from ....world import Terrain
from ....world.uncertainty import slope_sigma, worst_case
from ...data.bathymetry import load_terrain
from ...data.geo import LocalFrame
from ..specs import Scenario
from ..tables import table_error

__all__ = ["seabed_at_confidence", "uncertainty_layer"]


def uncertainty_layer(s: Scenario, terrain: Terrain, frame: LocalFrame | None,
                      extent: tuple[float, float, float, float] | None) -> np.ndarray:
    """The one-sigma vertical uncertainty (m) at the terrain's nodes (a scalar for a constant).

    Parameters
    ----------
    s : Scenario
        The scenario (its ``[terrain]`` or ``[terrain.synthetic]``).
    terrain : Terrain
        The nominal seabed.
    frame : LocalFrame or None
        The local frame.
    extent : tuple of 4 float or None
        The crop of the terrain (m).

    Returns
    -------
    numpy.ndarray
        ``σ`` (m): the shape of ``terrain.z``, or a 0-d array.
    """
    if s.synthetic is not None:
        return np.asarray(s.synthetic.uncertainty_m)
    t = s.terrain
    if t is None:
        return np.asarray(0.0)
    if t.uncertainty == "slope":
        return slope_sigma(terrain, t.uncertainty_m)
    if not t.uncertainty:
        return np.asarray(t.uncertainty_m)
    where = f"{s.source}: [terrain]"
    spec = replace(t, variable=t.uncertainty, positive="up", uncertainty="", uncertainty_m=0.0)
    try:
        layer = load_terrain(spec, frame, base_dir=s.base_dir, extent_m=extent)
    except DataError as exc:
        raise DataError(f"{where} uncertainty = {t.uncertainty!r}: {exc}") from exc
    if layer.z.shape != terrain.z.shape:
        raise DataError(f"{where} uncertainty = {t.uncertainty!r}: its grid {layer.z.shape} is not the "
                        f"elevation's {terrain.z.shape}")
    sigma = np.asarray(layer.z, dtype=float)
    if not np.all(np.isfinite(sigma)) or np.any(sigma < 0):
        raise DataError(f"{where} uncertainty = {t.uncertainty!r}: values must be finite and >= 0 (m)")
    return sigma


def seabed_at_confidence(s: Scenario, terrain: Terrain | None, frame: LocalFrame | None,
                         extent: tuple[float, float, float, float] | None) -> Terrain | None:
    """The scenario's seabed at ``[mission] confidence`` (the terrain itself when it is 0).

    Parameters
    ----------
    s : Scenario
        The scenario.
    terrain : Terrain or None
        The nominal seabed.
    frame : LocalFrame or None
        The local frame.
    extent : tuple of 4 float or None
        The crop (m).

    Returns
    -------
    Terrain or None
        The worst-case seabed (:func:`auvplan.world.uncertainty.worst_case`), or ``terrain``.
    """
    conf = s.mission.confidence
    if not conf:
        return terrain
    where = f"{s.source}: [mission]"
    if terrain is None:
        raise table_error(where, "confidence", conf, "needs a [terrain] with an uncertainty")
    sigma = uncertainty_layer(s, terrain, frame, extent)
    if not np.any(sigma > 0):
        raise ScenarioError(f"{where} confidence = {conf!r}: the [terrain] gives no vertical uncertainty (set "
                            "[terrain] uncertainty = \"<variable>\" | \"slope\" or uncertainty_m)")
    return worst_case(terrain, sigma, conf)

