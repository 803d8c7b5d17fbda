"""The energy budget of a mission held in memory, re-flying only the legs an edit changed.

In a steady current (uniform, Lamb–Oseen vortices, a gridded field without a time axis) a leg's flight
through the current (:func:`auvplan.endurance.budget.traverse`) depends on its two ends and its
through-water speed only, not on when it starts: the legs' durations are cached by those, and the
budget is :func:`auvplan.endurance.budget.budget_of` the route assembled from them, equal to
:func:`auvplan.endurance.mission_budget` to rounding.  A time-varying current, or a leg the current
beats (for the exact message), is flown whole.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ...endurance import EnergyModel, mission_budget
from ...endurance.budget import Budget, Traverse, budget_of, traverse
from ...world import CurrentField, World
from .lru import LruCache

__all__ = ["steady", "IncrementalBudget", "leg_water_m"]

_F64 = NDArray[np.float64]
"""Array of float64 (m, m/s)."""


def steady(field: CurrentField | None) -> bool:
    """Whether a current field does not change with time (:attr:`CurrentField.steady`: the kinds known to be).

    Parameters
    ----------
    field : CurrentField or None
        The world's current.

    Returns
    -------
    bool
        True for none, uniform, Lamb–Oseen vortices and a gridded field with at most one time.
    """
    return field is None or field.steady


class IncrementalBudget:
    """:func:`~auvplan.endurance.mission_budget` from 0 s with the legs' flights cached across edits.

    Parameters
    ----------
    world : World
        Its currents.
    model : EnergyModel
        Power model and battery.
    ds : float
        Longest integration sub-step (m).
    """

    def __init__(self, world: World, model: EnergyModel, ds: float) -> None:
        self.world, self.model, self.ds = world, model, ds
        self._legs = LruCache()

    def run(self, waypoints: _F64, speeds: float | _F64) -> tuple[Budget, int]:
        """The mission's budget.

        Parameters
        ----------
        waypoints : numpy.ndarray
            ``(N, 3)`` mission (m), N >= 2.
        speeds : float or numpy.ndarray
            Through-water speed per leg or for all (m/s).

        Returns
        -------
        budget : Budget
            As ``mission_budget(world, waypoints, model, speeds, 0.0, ds)``.
        computed : int
            Legs flown for this call (the rest came from the cache).
        """
        p = np.asarray(waypoints, dtype=float).reshape(-1, 3)
        n = p.shape[0] - 1
        v = np.broadcast_to(np.asarray(speeds, dtype=float), (n,)).copy()
        if not steady(self.world.currents):
            return mission_budget(self.world, p, self.model, v, 0.0, self.ds), n
        ends = np.ascontiguousarray(np.concatenate([p[:-1], p[1:], v[:, None]], axis=1))
        keys = [row.tobytes() for row in ends]
        found, missing = self._legs.get_many(keys)
        for i in missing:
            tr = traverse(self.world, p[i:i + 2], v[i], 0.0, self.ds)
            if not tr.ok:  # the current beats the vehicle: the whole flight, for its exact message
                return mission_budget(self.world, p, self.model, v, 0.0, self.ds), n
            value = (float(tr.times[1]),)
            self._legs.put(keys[i], value)
            found[i] = value
        times = np.concatenate([[0.0], np.cumsum([f[0] for f in found if f is not None])])
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
        tr = Traverse(p, v, times, p.copy(), s, times.copy(), np.r_[0, np.arange(n)].astype(np.int64))
        return budget_of(tr, self.model), len(missing)


def leg_water_m(world: World, w: NDArray[np.float64], speeds: float | NDArray[np.float64],
                dwell: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """Each leg's horizontal distance through the water, the mission flown through the current at its legs' speeds
    (:meth:`auvplan.endurance.Traverse.leg_water_m`; the page's navigation band, ``docs/navigation.md``).

    Parameters
    ----------
    world : World
        Its currents.
    w : numpy.ndarray
        ``(N, 3)`` waypoints (m).
    speeds : float or numpy.ndarray
        Through-water speed, one or one per leg (m/s).
    dwell : numpy.ndarray
        ``(N,)`` time held at each waypoint (s).

    Returns
    -------
    numpy.ndarray or None
        ``(N - 1,)`` (m); None where the current beats the vehicle.
    """
    flown = traverse(world, w, speeds, dwell=dwell)
    return flown.leg_water_m() if flown.ok else None
