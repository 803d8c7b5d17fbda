"""The vehicle: the under-actuated AUV model (:mod:`.model`) and its drag-based power law fitted to a table
(:mod:`.power_fit`).  The model's names are re-exported here (``from auvplan.vehicles import Vehicle``)."""

from __future__ import annotations

from .model import Vehicle, VehicleParams, VehicleState

__all__ = ["VehicleParams", "VehicleState", "Vehicle"]
