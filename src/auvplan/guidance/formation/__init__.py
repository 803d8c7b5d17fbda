"""Formations of several vehicles in document 001's hybrid field: the slots and shapes along the route
(:mod:`.route`, :mod:`.keeping`), every slot's swept track checked (:mod:`.plan`), each vehicle's heading and
speed command to its slot (:mod:`.steer`) and the formation error figures (:mod:`.error`).  The closed loop
of the fleet is :mod:`auvplan.sim.formation` (it runs the simulator); its files are
:mod:`auvplan.io.missions.formation`, its figures :mod:`auvplan.viz.formation`.

The names of :mod:`.keeping` are re-exported here (``from auvplan.guidance.formation import Formation``).
"""

from __future__ import annotations

from .keeping import (
    SHAPES,
    VEHICLE_NAME,
    Formation,
    FormationParams,
    FormationRoute,
    Schedule,
    ShapeChange,
    VehicleSpec,
    shape_offsets,
)

__all__ = ["SHAPES", "ShapeChange", "FormationParams", "VehicleSpec", "VEHICLE_NAME", "Formation", "shape_offsets",
           "Schedule", "FormationRoute"]
