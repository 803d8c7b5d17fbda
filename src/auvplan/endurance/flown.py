"""The energy a simulated flight drew, from its recorded track, and its split by leg.

The closed loop (:mod:`auvplan.sim.loop`) moves the vehicle by ``(u d + c) dt`` each step, with
``u`` its surge speed through the water along its body axis ``d`` and ``c`` the current at the
step's start.  Over a block of recorded rows (about ``block_s`` seconds) the mean through-water
speed is therefore ``|Δp / Δt − c̄|``, with ``c̄`` the current at the block's middle position and
time (second order in the block length; exact in a steady uniform current).  The power drawn is
``P(u) = P_hotel + k u³`` (:class:`~auvplan.endurance.power.EnergyModel`) and the energy its
integral over time.  With the wave disturbance on, the sway it adds is counted as through-water
motion, a slight overestimate.

The flight enters leg ``i`` when its progress along the route (horizontal distance made good,
:attr:`auvplan.sim.SimResult.progress`) first reaches the horizontal length of the legs before it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..world import World
from .power import WH, EnergyModel

__all__ = ["FlownEnergy", "flown_energy", "flown_legs"]

F64 = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class FlownEnergy:
    """The energy drawn along a recorded flight.

    Attributes
    ----------
    t : numpy.ndarray
        ``(B + 1,)`` block boundaries (s).
    cumulative_wh : numpy.ndarray
        ``(B + 1,)`` energy drawn by each boundary (Wh).
    speed_water : numpy.ndarray
        ``(B,)`` mean through-water speed of each block (m/s).
    """

    t: F64
    cumulative_wh: F64
    speed_water: F64

    @property
    def energy_wh(self) -> float:
        """Energy of the whole flight (Wh)."""
        return float(self.cumulative_wh[-1]) if self.cumulative_wh.size else 0.0

    def at(self, t: ArrayLike) -> F64:
        """Energy drawn by times ``t`` (Wh, linear between block boundaries).

        Parameters
        ----------
        t : array_like
            Times (s).

        Returns
        -------
        numpy.ndarray
            Energy (Wh), same shape.
        """
        return np.asarray(np.interp(np.asarray(t, dtype=np.float64), self.t, self.cumulative_wh), dtype=np.float64)


def flown_energy(world: World, t: ArrayLike, position: ArrayLike, model: EnergyModel,
                 block_s: float = 1.0) -> FlownEnergy:
    """Energy drawn along a recorded track (module notes).

    Parameters
    ----------
    world : World
        Its currents.
    t : array_like
        ``(N,)`` recorded times (s after the start time), increasing.
    position : array_like
        ``(N, 3)`` recorded positions (m).
    model : EnergyModel
        Power model.
    block_s : float, default 1.0
        Length of the blocks over which the through-water speed is averaged (s).

    Returns
    -------
    FlownEnergy
        Cumulative energy at the block boundaries.
    """
    tt = np.asarray(t, dtype=float)
    p = np.asarray(position, dtype=float).reshape(-1, 3)
    if tt.size < 2:
        return FlownEnergy(tt[:1].copy(), np.zeros(min(tt.size, 1)), np.empty(0))
    step = float(np.median(np.diff(tt)))
    every = max(1, int(round(block_s / step))) if step > 0 else 1
    idx = np.unique(np.r_[np.arange(0, tt.size, every), tt.size - 1])
    tb, pb = tt[idx], p[idx]
    dt = np.diff(tb)
    mid_p, mid_t = 0.5 * (pb[:-1] + pb[1:]), 0.5 * (tb[:-1] + tb[1:])
    cur = world.currents.velocity_at(mid_p, mid_t)  # one call for the whole track (issue 56: was one per block)
    water = np.linalg.norm(np.diff(pb, axis=0) / np.where(dt > 0, dt, 1.0)[:, None] - cur, axis=1)
    water = np.where(dt > 0, water, 0.0)
    energy = np.asarray(model.power(water), dtype=float) * dt / WH
    return FlownEnergy(tb, np.r_[0.0, np.cumsum(energy)], water)


def flown_legs(route: ArrayLike, t: ArrayLike, progress: ArrayLike,
               flown: FlownEnergy) -> tuple[F64, F64, F64]:
    """Each leg's start and end time and energy in a recorded flight (module notes).

    Parameters
    ----------
    route : array_like
        ``(N, 3)`` the route flown (m).
    t : array_like
        ``(M,)`` recorded times (s).
    progress : array_like
        ``(M,)`` horizontal distance made good along the route (m).
    flown : FlownEnergy
        The flight's energy (:func:`flown_energy`).

    Returns
    -------
    t_start, t_end, energy_wh : numpy.ndarray
        ``(N - 1,)`` each; a leg never reached starts and ends at the last recorded time.
    """
    w = np.asarray(route, dtype=float).reshape(-1, 3)
    tt = np.asarray(t, dtype=float)
    best = np.maximum.accumulate(np.asarray(progress, dtype=float))
    edges = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(w[:, :2], axis=0), axis=1))]
    k = np.minimum(np.searchsorted(best, edges[1:-1], side="left"), tt.size - 1)
    bounds = np.r_[tt[0], tt[k], tt[-1]]
    e = flown.at(bounds)
    return bounds[:-1], bounds[1:], np.diff(e)
