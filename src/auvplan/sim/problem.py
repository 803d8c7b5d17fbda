"""A mission's planning problem and its vehicle's limits: what ``plan`` needs of :mod:`auvplan.sim`, apart from
the simulation's modules (issue 56: a plan imports no guidance, dynamics or pipeline)."""

from __future__ import annotations

import numpy as np

from ..path.flyable import VehicleLimits
from ..planners.core.base import PlanningProblem
from ..vehicles import VehicleParams
from ..world import World
from .mission import Mission

__all__ = ["planning_problem", "vehicle_limits"]


def planning_problem(world: World, mission: Mission) -> PlanningProblem:
    """Build the global planning problem of a mission in a world.

    Parameters
    ----------
    world : World
        Environment.
    mission : Mission
        End points and vehicle figures (speed, hotel power, drag).

    Returns
    -------
    PlanningProblem
        Start, goal (m), speed (m/s), hotel power (W), drag factor (W s³/m³) and the vehicle's
        limits (pitch, turn radius, depth rating) in the world.
    """
    v = mission.vehicle
    return PlanningProblem(world, np.asarray(mission.start, dtype=float), np.asarray(mission.goal, dtype=float),
                           v.speed, v.hotel_power, v.drag_k, vehicle_limits(v))


def vehicle_limits(vehicle: VehicleParams) -> VehicleLimits:
    """The limits a vehicle's plans and missions are held to.

    Parameters
    ----------
    vehicle : VehicleParams
        The ``[vehicle]`` table.

    Returns
    -------
    VehicleLimits
        ``max_pitch_deg``, ``turn_radius_m`` and ``max_depth_m``.
    """
    return VehicleLimits(vehicle.max_pitch_deg, vehicle.turn_radius_m, vehicle.max_depth_m)
