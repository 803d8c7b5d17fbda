"""One call for a mission's endurance: the budget at its departure, the point of no return, and,
given a simulated flight, the energy it drew per leg (what ``auvplan run`` reports)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._types import Status
from ..vehicles import VehicleParams
from ..world import World
from .budget import Budget, mission_budget
from .flown import FlownEnergy, flown_energy, flown_legs
from .params import EnduranceParams
from .pnr import PointOfNoReturn, point_of_no_return
from .power import EnergyModel
from .speeds import SpeedPlan, choose_speeds

__all__ = ["Endurance", "FlownLegs", "assess", "departure_endurance"]


@dataclass(frozen=True, eq=False)
class FlownLegs:
    """A simulated flight's energy and its split by leg (s, Wh).

    Attributes
    ----------
    energy : FlownEnergy
        Energy drawn along the track.
    t_start, t_end, energy_wh : numpy.ndarray
        ``(L,)`` each leg's start and end time and energy in the flight.
    """

    energy: FlownEnergy
    t_start: NDArray[np.float64]
    t_end: NDArray[np.float64]
    energy_wh: NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Endurance:
    """A mission's endurance analysis.

    Attributes
    ----------
    budget : Budget
        Per-leg budget at the departure time, with the verdict.
    pnr : PointOfNoReturn
        The point of no return for the recovery point.
    speeds : SpeedPlan
        How the leg speeds were chosen.
    flown : FlownLegs or None
        The simulated flight's energy, when a flight was given.
    """

    budget: Budget
    pnr: PointOfNoReturn
    speeds: SpeedPlan
    flown: FlownLegs | None = None

    @property
    def status(self) -> Status:
        """The budget's verdict (``EXACT``, ``RESERVE_BROKEN`` or ``INFEASIBLE``)."""
        return self.budget.status


def assess(world: World, route: ArrayLike, vehicle: VehicleParams, params: EnduranceParams | None = None,
           depart: float = 0.0, track: tuple[ArrayLike, ArrayLike, ArrayLike] | None = None,
           speeds: ArrayLike | None = None, tail: ArrayLike | None = None,
           dwell: ArrayLike | None = None) -> Endurance:
    """Budget, point of no return and (with ``track``) the flown energy of a mission route.

    Parameters
    ----------
    world : World
        Currents, seabed and obstacles.
    route : array_like
        ``(N, 3)`` mission waypoints (m).
    vehicle : VehicleParams
        Speed, speed range, power model and battery.
    params : EnduranceParams, optional
        Recovery point and speed choice (defaults: home, every leg at the vehicle's speed).
    depart : float, default 0.0
        Departure (s after the mission's start time).
    track : tuple of array_like, optional
        A simulated flight's ``(t, position, progress)`` (:class:`auvplan.sim.SimResult` arrays).
    speeds : array_like, optional
        ``(N - 1,)`` leg speeds already chosen (m/s), e.g. the ones the flight flew; chosen by
        ``params.speeds`` when omitted.
    tail : array_like of bool, optional
        ``(N - 1,)`` legs flown tail-first (the time-optimal planner's ``tail_first``; the budget times
        them with the other root of the crab equation, :func:`~auvplan.endurance.budget.traverse`).
    dwell : array_like, optional
        ``(N,)`` time held at each waypoint (s; the surface fixes' ``surface_s``, :mod:`auvplan.nav`): its
        time and hotel energy are in the budget and the point of no return.

    Returns
    -------
    Endurance
        The analysis.
    """
    p = params or EnduranceParams()
    model = EnergyModel.from_vehicle(vehicle)
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    if speeds is None:
        plan = choose_speeds(world, w, model, vehicle.speed, p.speeds, p.deadline_s, depart, p.ds_m, tail=tail)
    else:
        plan = SpeedPlan(p.speeds, np.asarray(speeds, dtype=float), math.nan, math.nan, math.nan, "as flown")
    budget = mission_budget(world, w, model, plan.speeds, depart, p.ds_m, tail, dwell)
    ret = p.return_speed or vehicle.speed
    pnr = point_of_no_return(world, budget.traverse, model, p.recovery_point(), ret, ds=p.ds_m)
    flown = None
    if track is not None:
        t, pos, progress = (np.asarray(a, dtype=float) for a in track)
        fe = flown_energy(world, t, pos, model)
        flown = FlownLegs(fe, *flown_legs(w, t, progress, fe))
    return Endurance(budget, pnr, plan, flown)


_Plan = tuple[NDArray[np.float64], float] | tuple[NDArray[np.float64], float, NDArray[np.bool_] | None]


def departure_endurance(world: World, plans: Sequence[_Plan | None], departs: ArrayLike,
                        vehicle: VehicleParams, params: EnduranceParams | None = None) -> list[dict[str, float]]:
    """Energy, margin and point of no return of each departure of a sweep.

    Parameters
    ----------
    world : World
        Currents, seabed and obstacles.
    plans : list
        Each departure's plan ``(points (M, 3), speed)`` or ``(points, speed, tail)`` (``tail``: the
        ``(M - 1,)`` legs flown tail-first, or None) or None
        (:func:`auvplan.planners.timeopt.planner.departure_sweep` ``paths``).
    departs : array_like
        The departures (s after the mission's start time).
    vehicle : VehicleParams
        Power model and battery.
    params : EnduranceParams, optional
        Recovery point and integration step.

    Returns
    -------
    list of dict
        Per departure: ``energy_wh``, ``margin_wh``, ``reserve_ok`` (1/0), ``pnr_x``, ``pnr_y``, ``pnr_z``,
        ``pnr_t_s`` (s after the start time), ``pnr_s_m`` and ``pnr_whole_mission`` (1/0); nan without a plan.
    """
    p = params or EnduranceParams()
    model = EnergyModel.from_vehicle(vehicle)
    rows = []
    for plan, d in zip(plans, np.asarray(departs, dtype=float)):
        row = dict.fromkeys(("energy_wh", "margin_wh", "reserve_ok", "pnr_x", "pnr_y", "pnr_z", "pnr_t_s", "pnr_s_m",
                             "pnr_whole_mission"), math.nan)
        if plan is not None and len(plan[0]) >= 2:
            tail = plan[2] if len(plan) > 2 else None
            b = mission_budget(world, plan[0], model, plan[1], float(d), p.ds_m, tail)
            pnr = point_of_no_return(world, b.traverse, model, p.recovery_point(), p.return_speed or plan[1],
                                     ds=p.ds_m)
            row.update(energy_wh=b.energy_wh, margin_wh=b.margin_wh, reserve_ok=float(b.status.ok),
                       pnr_x=pnr.position[0], pnr_y=pnr.position[1], pnr_z=pnr.position[2], pnr_t_s=pnr.t_s,
                       pnr_s_m=pnr.s_m, pnr_whole_mission=float(pnr.whole_mission))
        rows.append(row)
    return rows
