"""A segment's energy in the current field: the compiled kernel and its vectorised front (:mod:`auvplan.cost`).

The current is taken at each segment's midpoint: one vectorised call of the field, or the one vector of a
uniform field.
"""

from __future__ import annotations

import math

import numpy as np

from .._types import ArrayLike, BoolArray, FloatArray
from ..runtime.jit import jit_enabled, kernel
from ..world import UniformCurrent, World
from ..world.currents.crab import crab_speed, makes_headway
from .model import CostModel, energy_mode, propulsion_power

__all__ = ["segment_energy", "energy_kernel"]


def segment_energy(world: World, a: ArrayLike, b: ArrayLike, model: CostModel,
                   current: ArrayLike | None = None) -> tuple[FloatArray, FloatArray, FloatArray, BoolArray]:
    """Energy of straight segments at the vehicle's speed in the current field.

    The current is taken at each segment's midpoint (see the module notes for the two models),
    or given as ``current``.

    Parameters
    ----------
    world : World
        Source of the current field.
    a, b : array_like
        Segment starts and ends ``(..., 3)`` (m); broadcast together.
    model : CostModel
        Speed, power model and energy model.
    current : array_like, optional
        Current per segment ``(..., 3)`` (m/s) instead of the field at the midpoints.

    Returns
    -------
    units : ndarray
        Energy in the model's own units (J for ``"physical"``), before ``model.scale``.
    energy_j, duration_s : ndarray
        Physical energy (J) and travel time (s) of each segment.
    blocked : ndarray of bool
        Where the current beats the vehicle (no ground speed along the segment).
    """
    arrays = [np.asarray(v, dtype=float) for v in ((a, b) if current is None else (a, b, current))]
    if len(arrays) == 2 and arrays[0].shape == arrays[1].shape:  # nothing to broadcast (the elastic band's case)
        lead = arrays[0].shape[:-1]
        a, b, *given = (np.ascontiguousarray(v.reshape(-1, 3)) for v in arrays)
    else:
        lead = np.broadcast_shapes(*(v.shape[:-1] for v in arrays))
        a, b, *given = (np.ascontiguousarray(np.broadcast_to(v, lead + (3,)).reshape(-1, 3)) for v in arrays)
    c = _midpoint_currents(world, a[None], b[None])[0] if current is None else given[0]  # (N, 3) or (1, 3)
    units, energy_j, dt = (np.empty(a.shape[0]) for _ in range(3))
    blocked = np.empty(a.shape[0], dtype=bool)
    _segment_energies(_read_only(a), _read_only(b), _read_only(c), float(model.speed), propulsion_power(model),
                      energy_mode(model), units, energy_j, dt, blocked)
    return units.reshape(lead), energy_j.reshape(lead), dt.reshape(lead), blocked.reshape(lead)


@kernel
def energy_kernel(ex: float, ey: float, ez: float, ds: float, cx: float, cy: float, cz: float, speed: float,
                  power: float, document: int) -> tuple[float, float, float, bool]:
    """Energy of one segment in a current (compiled; module notes).

    Track tangent ŝ, c∥ = c·ŝ, c⊥² = |c|² - c∥², ground speed c∥ + √(V² - c⊥²), time, energy.

    Parameters
    ----------
    ex, ey, ez : float
        Segment vector (m).
    ds : float
        Its length (m).
    cx, cy, cz : float
        Current on the segment (m/s).
    speed : float
        Through-water speed V (m/s).
    power : float
        Electrical power at that speed (W).
    document : int or bool
        :func:`energy_mode`: 0 (False) joules for ``units``; 1 (True) document 002's energy
        (eqs. 16–17) divided by the current's speed; 2 the same divided by the vehicle's speed V.

    Returns
    -------
    tuple
        ``(units, joules, seconds, blocked)``; blocked where V < c⊥ or the ground speed is not
        positive (the time then assumes the still-water speed).
    """
    c_par = (cx * ex + cy * ey + cz * ez) / ds if ds > 0.0 else 0.0
    c2 = cx * cx + cy * cy + cz * cz
    g = crab_speed(cx, cy, cz, ex / ds, ey / ds, ez / ds, speed, False, 1.0) if ds > 0.0 else c_par + speed
    vg = g if g == g else c_par  # (no heading holds the line: the along-line current alone, as before)
    blocked = not makes_headway(g) and ds > 0.0
    t = ds / (speed if (blocked or vg <= 0.0) else vg) if ds > 0.0 else 0.0
    if document == 2:
        units = abs(vg) ** 3 * ds / speed
    elif document:
        units = abs(vg) ** 3 * ds / max(math.sqrt(c2), 1e-3)
    else:
        units = power * t
    return units, power * t, t, blocked


@kernel
def _segment_energies(a: FloatArray, b: FloatArray, c: FloatArray, speed: float, power: float, document: int,
                      units: FloatArray, energy_j: FloatArray, dt: FloatArray, blocked: BoolArray) -> None:
    for k in range(a.shape[0]):
        ex, ey, ez = b[k, 0] - a[k, 0], b[k, 1] - a[k, 1], b[k, 2] - a[k, 2]
        ds = math.sqrt(ex * ex + ey * ey + ez * ez)
        kc = 0 if c.shape[0] == 1 else k  # (1, 3): one uniform current
        units[k], energy_j[k], dt[k], blocked[k] = energy_kernel(ex, ey, ez, ds, c[kc, 0], c[kc, 1], c[kc, 2],
                                                                  speed, power, document)


def _midpoint_currents(world: World, a: FloatArray, b: FloatArray) -> FloatArray:
    """The current at the midpoints of the segments ``a -> b (P, S - 1, 3)``, or ``(1, 1, 3)`` when the
    field is a :class:`~auvplan.world.UniformCurrent` (the same vector everywhere: no array to fill)."""
    if type(world.currents) is UniformCurrent:
        return np.array(world.currents.vector, dtype=float).reshape(1, 1, 3)
    if jit_enabled() and a.ndim == 3:
        mid = np.empty(a.shape)
        _midpoints(a, b, mid)  # 0.5 (a + b) without numpy's temporaries
    else:
        mid = 0.5 * (a + b)
    current: FloatArray = np.ascontiguousarray(world.currents.velocity(mid))
    return current


@kernel
def _midpoints(a: FloatArray, b: FloatArray, out: FloatArray) -> None:
    for i in range(a.shape[0]):
        for s in range(a.shape[1]):
            for d in range(3):
                out[i, s, d] = 0.5 * (a[i, s, d] + b[i, s, d])


def _read_only(a: FloatArray) -> FloatArray:
    """A read-only view of ``a`` (no copy): a kernel's input typed the same whether or not the caller's array was
    writable, so that it is compiled once."""
    view = a.view()
    view.setflags(write=False)
    return view
