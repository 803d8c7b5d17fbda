"""Settings of the time-dependent planner (``[planner.timeopt]``), kept apart so that PlannerSpec can hold them."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["TimeoptParams"]


@dataclass(frozen=True)
class TimeoptParams:
    """Settings of the time-optimal planner in currents that change with time.

    Attributes
    ----------
    objective : str
        ``"time"`` (earliest arrival at the vehicle's speed) or ``"energy"`` (least energy over
        the through-water speeds ``speeds`` × the vehicle's speed, each time-optimal).
    depart_s : float
        Departure time (s after the mission's ``start_time``).
    cell : float
        Horizontal lattice cell (m); 0 = 1/100 of the larger horizontal side of the search box.
    levels : int
        Depth levels of the lattice across the allowed depth band (1 = the start's depth only).
    dt : float
        Time step of the current table the search reads (s).
    horizon_s : float
        Longest mission the table covers (s); 0 = 1.5 × the still-water straight-line time + 2 h
        (doubled, up to twice, when a plan runs past it).
    substep : float
        Longest sub-step of the travel-time integration along a segment (m); 0 = cell / 2.
    relax_iterations : int
        Sweeps of the time-aware elastic band after the lattice search (0 = none).
    speeds : tuple of float
        Fractions of the vehicle's speed tried by the ``"energy"`` objective.
    """

    objective: str = "time"
    depart_s: float = 0.0
    cell: float = 0.0
    levels: int = 5
    dt: float = 600.0
    horizon_s: float = 0.0
    substep: float = 0.0
    relax_iterations: int = 60
    speeds: tuple[float, ...] = (0.5, 0.6, 0.7, 0.8, 0.9, 1.0)

    def __post_init__(self) -> None:
        if self.objective not in ("time", "energy"):
            raise ValueError(f"objective = {self.objective!r}: choose 'time' or 'energy'")
        if self.cell < 0 or self.substep < 0 or self.horizon_s < 0:
            raise ValueError("cell, substep and horizon_s must be >= 0 (0 = automatic)")
        if self.levels < 1:
            raise ValueError(f"levels = {self.levels}: must be >= 1")
        if not self.dt > 0:
            raise ValueError(f"dt = {self.dt}: must be > 0")
        if self.relax_iterations < 0:
            raise ValueError("relax_iterations must be >= 0")
        if not self.speeds or any(not 0.0 < s <= 1.0 for s in self.speeds):
            raise ValueError(f"speeds = {list(self.speeds)}: fractions in (0, 1]")
