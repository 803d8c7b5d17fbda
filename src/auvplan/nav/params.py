"""Settings of the navigation error budget (``[navigation]``, issue 52; ``docs/navigation.md``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["UsblParams", "NavParams", "FIX_MODES"]

FIX_MODES = ("plan", "none")
"""The words ``fixes`` takes besides a period in seconds."""


@dataclass(frozen=True)
class UsblParams:
    """A USBL transceiver on a ship (``usbl = { lat, lon, error_pct }``): a fix at depth.

    Attributes
    ----------
    lat, lon : float
        The ship's position (degrees).
    error_pct : float
        Error of a USBL fix, % of the slant range from the ship (1σ, as ``drift_pct``).
    """

    lat: float
    lon: float
    error_pct: float

    def __post_init__(self) -> None:
        if not -90.0 <= self.lat <= 90.0 or not -180.0 <= self.lon <= 360.0:
            raise ValueError(f"usbl lat = {self.lat}, lon = {self.lon}: not a position")
        if not 0.0 < self.error_pct < 100.0:
            raise ValueError(f"usbl error_pct = {self.error_pct}: must be in (0, 100) %")


@dataclass(frozen=True)
class NavParams:
    """How the dead-reckoned position error grows and where it is reset (``[navigation]``).

    The horizontal error σ (1σ, radial RMS) grows by ``drift_pct`` % of the horizontal distance
    travelled over the ground while the DVL has bottom lock (altitude ≤ ``dvl_range_m``), by ``drift_pct_no_lock`` %
    of the horizontal distance travelled through the water without; a fix resets it to ``fix_error_m``.  The
    reported error is ``confidence`` × σ.

    Attributes
    ----------
    drift_pct : float
        Error growth with bottom lock, % of the horizontal distance travelled (e.g. 0.3).
    drift_pct_no_lock : float
        Error growth without bottom lock (water track), % of the horizontal distance travelled through the water
        (e.g. 2.0).
    dvl_range_m : float
        The DVL locks on the bottom when the altitude is at most this (m).
    fix_error_m : float
        Error (1σ) right after a surface (GPS) fix, and at the start of the mission (m).
    max_error_m : float
        The budget E: confidence × σ may not exceed it anywhere (m).
    confidence : float
        The σ multiple used for E and for the clearances, at least 1 (e.g. 2: the 2DRMS circle, 98 % for a
        circular error).
    fixes : str or float
        ``"plan"`` (fixes placed by the planner), a period in seconds (a fix every period, as
        MOOS-IvP's ``BHV_PeriodicSurface``) or ``"none"`` (the budget only).
    surface_s : float
        Time at the surface per fix (s); the exported ``.plan`` and MOOS file wait it at each surfacing.
    usbl : UsblParams or None
        Optional USBL aiding from a ship: a second kind of fix, taken at depth.
    _usbl_xy : tuple of float or None
        The ship's position in the local frame (m), set when the scenario is built (not a scenario key).
    """

    drift_pct: float = 0.3
    drift_pct_no_lock: float = 2.0
    dvl_range_m: float = 100.0
    fix_error_m: float = 5.0
    max_error_m: float = 200.0
    confidence: float = 2.0
    fixes: str | float = "plan"
    surface_s: float = 60.0
    usbl: UsblParams | None = None
    _usbl_xy: tuple[float, float] | None = None  # the ship in the local frame (m), set by the scenario build

    def __post_init__(self) -> None:
        for key in ("drift_pct", "drift_pct_no_lock"):
            v = getattr(self, key)
            if not 0.0 < v < 100.0:
                raise ValueError(f"{key} = {v}: must be in (0, 100) % of the distance travelled")
        if not self.dvl_range_m >= 0.0 or not self.fix_error_m >= 0.0 or not self.surface_s >= 0.0:
            raise ValueError("dvl_range_m, fix_error_m and surface_s must be >= 0")
        if not self.confidence >= 1.0:  # [mission] confidence is a probability: 0.95 here would be 0.95 σ (59 %)
            raise ValueError(f"confidence = {self.confidence}: a multiple of σ, at least 1 (2: the 2DRMS circle, 98 %; "
                             "3: 99.99 %), not a probability as [mission] confidence is")
        if not self.max_error_m > self.confidence * self.fix_error_m:
            raise ValueError(f"max_error_m = {self.max_error_m}: must exceed confidence × fix_error_m "
                             f"= {self.confidence * self.fix_error_m:g} m")
        if isinstance(self.fixes, str):
            if self.fixes not in FIX_MODES:
                raise ValueError(f"fixes = {self.fixes!r}: 'plan', 'none' or a period in seconds")
        elif not (math.isfinite(self.fixes) and self.fixes > 0.0):
            raise ValueError(f"fixes = {self.fixes}: a period must be > 0 s")

    def rate(self, lock: bool) -> float:
        """Error growth per metre travelled (a fraction: ``drift_pct / 100``).

        Parameters
        ----------
        lock : bool
            Bottom lock.

        Returns
        -------
        float
            σ growth per metre of horizontal distance.
        """
        return (self.drift_pct if lock else self.drift_pct_no_lock) / 100.0

    @property
    def usbl_xy(self) -> tuple[float, float] | None:
        """The USBL ship's local position (m), None without ``usbl`` (set when the scenario is built)."""
        return self._usbl_xy if self.usbl is not None else None

    @property
    def period_s(self) -> float | None:
        """The fix period (s), None unless ``fixes`` is a number."""
        return None if isinstance(self.fixes, str) else float(self.fixes)
