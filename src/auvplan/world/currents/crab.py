"""The one ground-speed function: a vehicle holding a line in a current (the crab equation).

To make good a line of unit tangent ŝ at through-water speed V in a current c, the vehicle's
velocity through the water must cancel the current's cross component ``c⊥ = c − (c·ŝ) ŝ``; that
leaves two headings and two ground speeds along the line (both roots of ``|g ŝ − c| = V``):

    g₊ = c·ŝ + √(V² − |c⊥|²)     heading along the line (the near root),
    g₋ = c·ŝ − √(V² − |c⊥|²)     heading against it, *tail-first* (the far root).

**One feasibility rule.**  A line is held when ``|c⊥| ≤ hold · V`` (``hold = 1``: any heading that
cancels the cross current; the planners' searches keep :data:`HOLD` = 0.97, a 3 % margin so a line
planned at the very edge stays holdable when flown a little off the planned times).  Where it is
not held the ground speed is ``nan``.  A held line is flown forwards when ``g > 0`` (:func:`makes_headway`);
``g ≤ 0`` (only possible for the near root where the along-line current beats the vehicle) means
the vehicle is carried back on its line, which the time-optimal planner integrates in time and the
energy check and the cost model reject.  Before this module the same equation was written in five
places with three rules (a floor of 1 µm/s, a discriminant ≥ 0, the 0.97 hold factor): the floor is
gone (a speed of 0.5 µm/s is a time of years, rejected by every caller's own time limit, not by a
threshold), the discriminant rule is ``hold = 1``, the hold factor ``hold = HOLD``.
"""

from __future__ import annotations

import math

from ...runtime.jit import kernel

__all__ = ["HOLD", "crab_speed", "makes_headway"]

#: The planners' searches hold a line only with this fraction of the vehicle's speed across it.
HOLD = 0.97


@kernel
def crab_speed(u: float, v: float, w: float, ex: float, ey: float, ez: float, speed: float, tail: bool,
               hold: float) -> float:
    """Signed ground speed along a line held in a current (module notes).

    Parameters
    ----------
    u, v, w : float
        Current (m/s; east, north, up).
    ex, ey, ez : float
        Unit tangent of the line.
    speed : float
        Through-water speed V (m/s).
    tail : bool
        The far root (heading against the line) instead of the near one.
    hold : float
        Largest cross current held, as a fraction of V (1 = any; :data:`HOLD` in the searches).

    Returns
    -------
    float
        ``c·ŝ ± √(V² − |c⊥|²)`` (m/s); ``nan`` where ``|c⊥| > hold V``.
    """
    c_par = u * ex + v * ey + w * ez
    cross = max(u * u + v * v + w * w - c_par * c_par, 0.0)
    if not cross <= hold * hold * speed * speed:
        return math.nan
    root = math.sqrt(max(speed * speed - cross, 0.0))
    return c_par - root if tail else c_par + root


@kernel
def makes_headway(g: float) -> bool:
    """Whether a ground speed from :func:`crab_speed` flies the line forwards.

    Parameters
    ----------
    g : float
        Ground speed (m/s; ``nan`` where the line is not held).

    Returns
    -------
    bool
        ``g > 0`` (False for ``nan``).
    """
    return g > 0.0
