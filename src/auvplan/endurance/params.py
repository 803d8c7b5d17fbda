"""Settings of the endurance analysis (``[endurance]``): recovery point, rally points, speed choice."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["RallyPoint", "EnduranceParams", "DS_M_RANGE"]

DS_M_RANGE = (0.1, 100_000.0)
"""Floor and ceiling of ``[endurance] ds_m`` (m): below 0.1 m a 100 km mission is 10⁶ Python steps."""


@dataclass(frozen=True)
class RallyPoint:
    """A named recovery point (``[[endurance.rally]]``).

    Attributes
    ----------
    name : str
        Its name, which ``recovery`` refers to.
    point : tuple of float
        ``(x, y, z)`` in the local frame (m).
    """

    name: str
    point: tuple[float, float, float]

    def __post_init__(self) -> None:
        if not self.name or self.name == "home":
            raise ValueError(f"rally point name {self.name!r}: must be non-empty and not 'home'")


@dataclass(frozen=True)
class EnduranceParams:
    """Where to recover the vehicle and how to choose the speed of each leg.

    Attributes
    ----------
    recovery : str
        ``"home"`` (the mission's start, default) or the name of a rally point: the point of no
        return is computed for it.
    rally : tuple of RallyPoint
        Named recovery points.
    speeds : str
        ``"fixed"`` (every leg at the vehicle's ``speed``, default), ``"energy"`` (least energy,
        arriving by ``deadline_s`` when given) or ``"time"`` (earliest arrival that keeps the
        reserve): each leg's through-water speed within ``[min_speed, max_speed]``.
    deadline_s : float
        Latest arrival (s after the mission's start time) for ``speeds = "energy"``; 0 = none.
    return_speed : float
        Through-water speed of the return from the point of no return (m/s); 0 = the vehicle's ``speed``.
    ds_m : float
        Longest integration sub-step along a leg (m).
    """

    recovery: str = "home"
    rally: tuple[RallyPoint, ...] = ()
    speeds: str = "fixed"
    deadline_s: float = 0.0
    return_speed: float = 0.0
    ds_m: float = 100.0

    def __post_init__(self) -> None:
        names = [r.name for r in self.rally]
        if len(set(names)) != len(names):
            raise ValueError(f"rally names {names}: must be unique")
        if self.recovery != "home" and self.recovery not in names:
            raise ValueError(f"recovery = {self.recovery!r}: 'home' or one of the rally names {names}")
        if self.speeds not in ("fixed", "energy", "time"):
            raise ValueError(f"speeds = {self.speeds!r}: choose 'fixed', 'energy' or 'time'")
        if not self.deadline_s >= 0:
            raise ValueError(f"deadline_s = {self.deadline_s}: must be >= 0")
        if not self.return_speed >= 0:
            raise ValueError(f"return_speed = {self.return_speed}: must be >= 0")
        if not DS_M_RANGE[0] <= self.ds_m <= DS_M_RANGE[1]:
            raise ValueError(f"ds_m = {self.ds_m:g}: must lie in [{DS_M_RANGE[0]:g}, {DS_M_RANGE[1]:g}] m (an "
                             "integration sub-step; each one is a step of Python work)")

    def recovery_point(self) -> tuple[float, float, float] | None:
        """The recovery point, None for home.

        Returns
        -------
        tuple of float or None
            ``(x, y, z)`` of the named rally point (m), None when ``recovery`` is ``"home"``.
        """
        for r in self.rally:
            if r.name == self.recovery:
                return r.point
        return None
