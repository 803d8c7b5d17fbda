"""The vehicle's energy model: power against through-water speed, and the battery it draws from.

Power (electrical, W) at through-water speed V:

    P(V) = P_hotel + c V³ / η = P_hotel + k V³,    c = ½ ρ C_D A,   k = c / η

(steady flight: thrust balances the quadratic hull drag ½ ρ C_D A V², the propulsion chain turns
electrical power into thrust power with efficiency η; Fossen 2021, *Handbook of Marine Craft
Hydrodynamics*, §6.4.1).  The REMUS-100-class defaults of :class:`auvplan.vehicles.VehicleParams`
(C_D 0.2 on 0.0284 m², η 0.5, hotel 15 W, Prestero 2001) give k ≈ 5.8 W s³/m³, about 35 W at
the 1.5 m/s cruise speed; a 1 kWh battery (the REMUS 100's) then lasts about a day.

Energy per metre at speed V in still water is P(V) / V; it is least where its derivative is zero:

    v* = (P_hotel / (2 k))^(1/3)

(slower, the hotel load dominates; faster, the drag).  :func:`fit_power` fits ``P_hotel`` and
``k`` to a user's table of speed against measured power by linear least squares.

Battery: ``battery_wh`` nominal, of which ``usable_fraction`` can be drawn; the mission must end
with at least ``reserve`` × ``battery_wh`` still in it.  The mission's *budget* is
``battery_wh (usable_fraction − reserve)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..vehicles.power_fit import PowerFit, fit_power

if TYPE_CHECKING:
    from ..vehicles import VehicleParams

__all__ = ["WH", "EnergyModel", "PowerFit", "fit_power", "optimal_speed"]

WH = 3600.0
"""Joules in one watt-hour."""


def optimal_speed(hotel_w: float, k: float) -> float:
    """The still-water speed of least energy per metre, v* = (P_hotel / (2 k))^(1/3).

    Parameters
    ----------
    hotel_w : float
        Hotel load (W).
    k : float
        Propulsion factor c / η (W s³/m³), positive.

    Returns
    -------
    float
        v* (m/s); 0 without a hotel load.
    """
    return float((hotel_w / (2.0 * k)) ** (1.0 / 3.0))


@dataclass(frozen=True)
class EnergyModel:
    """Power model and battery of one vehicle (W, Wh, m/s).

    Attributes
    ----------
    hotel_w : float
        Hotel load (W).
    k : float
        Propulsion factor c / η (W s³/m³).
    battery_wh : float
        Nominal battery capacity (Wh).
    usable_fraction : float
        Share of the nominal capacity that can be drawn, in (0, 1].
    reserve : float
        Share of the nominal capacity to keep at the end of the mission, in [0, usable_fraction).
    min_speed, max_speed : float
        Range of through-water speeds the vehicle can be commanded (m/s).
    """

    hotel_w: float = 15.0
    k: float = 5.82
    battery_wh: float = 1000.0
    usable_fraction: float = 0.9
    reserve: float = 0.2
    min_speed: float = 0.5
    max_speed: float = 2.5

    def __post_init__(self) -> None:
        if self.hotel_w < 0 or not self.k > 0 or not self.battery_wh > 0:
            raise ValueError("hotel_w must be >= 0, k and battery_wh positive")
        if not 0 < self.usable_fraction <= 1 or not 0 <= self.reserve < self.usable_fraction:
            raise ValueError(f"usable_fraction = {self.usable_fraction}, reserve = {self.reserve}: need "
                             "0 < usable_fraction <= 1 and 0 <= reserve < usable_fraction")
        if not 0 < self.min_speed <= self.max_speed:
            raise ValueError(f"speed range [{self.min_speed}, {self.max_speed}]: need 0 < min <= max")

    @classmethod
    def from_vehicle(cls, vehicle: VehicleParams) -> EnergyModel:
        """The energy model of a vehicle's ``[vehicle]`` parameters.

        Parameters
        ----------
        vehicle : VehicleParams
            Hotel load, drag factor, battery, usable fraction, reserve and speed range.

        Returns
        -------
        EnergyModel
            Its power model and battery.
        """
        return cls(vehicle.hotel_power, vehicle.drag_k, vehicle.battery_wh, vehicle.usable_fraction,
                   vehicle.reserve, min(vehicle.min_speed, vehicle.speed), vehicle.max_speed)

    def power(self, speed: ArrayLike) -> np.ndarray:
        """Electrical power at through-water speed ``speed`` (W): P_hotel + k V³.

        Parameters
        ----------
        speed : array_like
            Through-water speed (m/s).

        Returns
        -------
        numpy.ndarray
            Power (W), same shape.
        """
        v = np.asarray(speed, dtype=float)
        return np.asarray(self.hotel_w + self.k * v**3)

    @property
    def usable_wh(self) -> float:
        """Energy that can be drawn from a full battery (Wh)."""
        return self.battery_wh * self.usable_fraction

    @property
    def reserve_wh(self) -> float:
        """Energy to keep at the end of the mission (Wh)."""
        return self.battery_wh * self.reserve

    @property
    def budget_wh(self) -> float:
        """Energy the mission may spend: usable minus reserve (Wh)."""
        return self.usable_wh - self.reserve_wh

    @property
    def best_speed(self) -> float:
        """Still-water speed of least energy per metre, clipped to the speed range (m/s)."""
        v = optimal_speed(self.hotel_w, self.k)
        return float(min(max(v, self.min_speed), self.max_speed)) if math.isfinite(v) else self.min_speed
