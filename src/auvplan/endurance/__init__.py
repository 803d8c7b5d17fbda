"""Endurance in currents: the vehicle's energy model, a mission's per-leg energy budget, its point of no
return and the through-water speed of each leg (issue 38; ``docs/endurance.md``).

* :mod:`~auvplan.endurance.power`: ``P = P_hotel + c V³ / η``, the battery, the fit to a speed/power table;
* :mod:`~auvplan.endurance.budget`: legs flown through the time-varying currents, energy, margin, verdict;
* :mod:`~auvplan.endurance.pnr`: the last point from which a recovery point is reached with the reserve;
* :mod:`~auvplan.endurance.speeds`: the speed of each leg for least energy by a deadline or least time;
* :mod:`~auvplan.endurance.flown`: the energy a simulated flight drew, per leg.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..runtime.lazy import lazy_attributes

if TYPE_CHECKING:  # pragma: no cover - for type checkers only
    from .assess import Endurance, FlownLegs, assess, departure_endurance
    from .budget import Budget, Traverse, ground_speed, mission_budget, traverse
    from .flown import FlownEnergy, flown_energy, flown_legs
    from .params import EnduranceParams, RallyPoint
    from .pnr import PointOfNoReturn, point_of_no_return, return_route
    from .power import WH, EnergyModel, PowerFit, fit_power, optimal_speed
    from .speeds import SpeedPlan, choose_speeds, leg_speeds

__all__ = ["WH", "EnergyModel", "PowerFit", "fit_power", "optimal_speed", "Budget", "Traverse", "ground_speed",
           "mission_budget", "traverse", "FlownEnergy", "flown_energy", "flown_legs", "EnduranceParams", "RallyPoint",
           "PointOfNoReturn", "point_of_no_return", "return_route", "SpeedPlan", "choose_speeds", "leg_speeds",
           "Endurance", "FlownLegs", "assess", "departure_endurance"]

_LAZY = {
    **{name: "auvplan.endurance.assess" for name in ("Endurance", "FlownLegs", "assess", "departure_endurance")},
    **{name: "auvplan.endurance.budget" for name in (
        "Budget", "Traverse", "ground_speed", "mission_budget", "traverse"
    )},
    **{name: "auvplan.endurance.flown" for name in ("FlownEnergy", "flown_energy", "flown_legs")},
    **{name: "auvplan.endurance.params" for name in ("EnduranceParams", "RallyPoint")},
    **{name: "auvplan.endurance.pnr" for name in ("PointOfNoReturn", "point_of_no_return", "return_route")},
    **{name: "auvplan.endurance.power" for name in ("WH", "EnergyModel", "PowerFit", "fit_power", "optimal_speed")},
    **{name: "auvplan.endurance.speeds" for name in ("SpeedPlan", "choose_speeds", "leg_speeds")},
}
"""Loaded on first access: a plan's mission holds :class:`EnduranceParams` and assesses nothing (issue 56)."""

__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, __all__)
