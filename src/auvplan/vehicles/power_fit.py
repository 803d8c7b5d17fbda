"""The drag-based power law of a vehicle, fitted to a user's table of speed against power.

``P = P_hotel + k V³`` with ``k = c / η`` (:mod:`auvplan.endurance.power` budgets with it; the vehicle
model, :class:`auvplan.vehicles.VehicleParams`, resolves a ``power_table`` through :func:`fit_power`).
A module of its own below both, so the vehicle and the energy budget do not import each other.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["PowerFit", "fit_power"]


@dataclass(frozen=True)
class PowerFit:
    """Least-squares fit of ``P = P_hotel + k V³`` to a table of speed against power.

    Attributes
    ----------
    hotel_w : float
        Hotel load P_hotel (W): fitted, or the value held fixed.
    k : float
        Propulsion factor k = c / η (W s³/m³).
    rms_w : float
        Root-mean-square residual of the fit (W).
    """

    hotel_w: float
    k: float
    rms_w: float


def fit_power(speeds: ArrayLike, powers: ArrayLike, hotel_w: float | None = None) -> PowerFit:
    """Fit ``P = P_hotel + k V³`` to measured (speed, power) pairs by linear least squares.

    The model is linear in its coefficients, so the fit is the exact least-squares solution
    (:func:`numpy.linalg.lstsq` on the columns 1 and V³); with ``hotel_w`` given, only ``k`` is
    fitted, to ``P − P_hotel``.

    Parameters
    ----------
    speeds : array_like
        Through-water speeds (m/s), positive.
    powers : array_like
        Electrical power drawn at each speed (W), the hotel load included.
    hotel_w : float, optional
        A known hotel load (W) to hold fixed.

    Returns
    -------
    PowerFit
        The coefficients and the RMS residual.

    Raises
    ------
    ValueError
        Fewer pairs than coefficients, a non-positive speed, or a fit that is not physical
        (k ≤ 0 or a negative hotel load).
    """
    v = np.asarray(speeds, dtype=float).ravel()
    p = np.asarray(powers, dtype=float).ravel()
    need = 1 if hotel_w is not None else 2
    if v.size != p.size or v.size < need or len(set(v.tolist())) < need:
        raise ValueError(f"need at least {need} (speed, power) pairs with distinct speeds, got {v.size}")
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(p)) and np.all(v > 0)):
        raise ValueError("speeds must be positive and powers finite")
    v3 = v**3
    if hotel_w is not None:
        k = float(v3 @ (p - hotel_w) / (v3 @ v3))
        hotel = float(hotel_w)
    else:
        coef = np.linalg.lstsq(np.column_stack([np.ones_like(v3), v3]), p, rcond=None)[0]
        hotel, k = float(coef[0]), float(coef[1])
    if not k > 0 or hotel < 0:
        raise ValueError(f"the table gives hotel {hotel:.4g} W and k {k:.4g} W s³/m³: need hotel >= 0 and k > 0 "
                         "(power should rise with the cube of the speed)")
    rms = float(np.sqrt(np.mean((hotel + k * v3 - p) ** 2)))
    return PowerFit(hotel, k, rms)
