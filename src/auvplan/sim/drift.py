"""A drifting navigation estimate for the closed loop (issue 52; ``docs/navigation.md``).

The same model as the budget (:mod:`auvplan.nav.budget`), drawn: at the launch and at every fix the
error restarts from the fix's own error ``e_fix`` (each axis normal with variance ``σ_fix² / 2``) and a
drift direction ``u`` is drawn (each axis normal with variance ``1 / 2``); between fixes the error is the
random walk whose every step is ``rate · Δs · u``: with bottom lock (the DVL sees the true seabed) ``rate`` the
bottom-lock share and ``Δs`` the horizontal distance over the ground, without it (water track) the no-lock share
and ``Δs`` the horizontal distance through the water (the step's ground displacement less the current's), as the
budget counts them.  So ``e(s) = e_fix + D(s) u`` with ``D = Σ rate Δs``, and ``E|e|² = σ_fix² + D²``: exactly the
budget's σ².  A step held between fixes (a
heading or scale bias, as a DVL's is) is what makes σ linear in distance; white steps would grow as
√distance and flatter the budget.
"""

from __future__ import annotations

import math

import numpy as np

from ..nav.budget import fix_sigma
from ..nav.params import NavParams

__all__ = ["NavDrift"]


class NavDrift:
    """The error of a vehicle's position estimate along one flight.

    Parameters
    ----------
    nav : NavParams
        The error model.
    rng : numpy.random.Generator
        The flight's own generator for the drift.
    """

    def __init__(self, nav: NavParams, rng: np.random.Generator) -> None:
        self.nav = nav
        self.rng = rng
        self.error = np.zeros(2)
        self.u = np.zeros(2)
        self.fixes = 0
        self.reset(nav.fix_error_m)
        self.fixes = 0

    def reset(self, sigma_fix: float) -> None:
        """A fix: the error restarts from the fix's own and a new drift direction is drawn.

        Parameters
        ----------
        sigma_fix : float
            σ of the fix (m).
        """
        draw = self.rng.standard_normal(4) * math.sqrt(0.5)
        self.error = sigma_fix * draw[:2]
        self.u = draw[2:]
        self.fixes += 1

    def fix(self, kind: str, point: tuple[float, float, float]) -> None:
        """Take a fix of ``kind`` at the true ``point``.

        Parameters
        ----------
        kind : {'gps', 'usbl'}
            The fix.
        point : tuple of float
            Where the vehicle is (m).
        """
        self.reset(fix_sigma(self.nav, kind, point, self.nav.usbl_xy))

    def advance(self, distance: float, altitude: float, water: float | None = None) -> None:
        """Move ``distance`` metres horizontally over the ground, ``water`` through the water, at ``altitude`` above
        the seabed.

        Parameters
        ----------
        distance : float
            Horizontal distance travelled over the ground (m): the drift with bottom lock.
        altitude : float
            True altitude above the seabed (m): bottom lock within ``dvl_range_m``.
        water : float, optional
            Horizontal distance travelled through the water (m): the drift without bottom lock; default
            ``distance`` (still water).
        """
        lock = altitude <= self.nav.dvl_range_m
        run = distance if lock or water is None else water
        self.error = self.error + self.nav.rate(lock) * run * self.u
