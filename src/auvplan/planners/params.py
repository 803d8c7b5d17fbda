"""Settings of the streamline planner (document 000), kept apart so that PlannerSpec can hold them."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["FlowParams"]


@dataclass(frozen=True)
class FlowParams:
    """Settings of the streamline planner.

    Attributes
    ----------
    field : str
        ``"exact"`` (Weiss image, default), ``"document"`` (sink + θ-dependent dipole) or ``"uniform"``
        (uniform flow + dipole, the baseline of document 000's Fig. 5: spheres only, no fixed goal).
    rankine : str
        How the body round an ellipsoid is sized: ``"line"`` (default: a fitted line distribution of
        sources and sinks, the smallest containing body found), ``"pair"`` (source/sink pair, strength
        and half-spacing both free) or ``"document"`` (document 000's: stagnation point and mid-radius
        equal to the semi-axes; the ellipsoid is not contained).
    weights : str
        ``"normalised"`` (default) or ``"document"`` (product weights).
    distance : str
        ``"true"`` (default) or ``"ray"`` (document's ellipsoid distance) for the weights.
    strength : float
        Sink strength m at the target (the streamlines' shape does not depend on it for spheres).
    h_min, h_max : float
        Step bounds (m); ``h_min = 0`` means 0.05 × the smallest obstacle size (METHODS.md §1.6).
        The step is also at most ``step_factor`` × the clearance and × the distance to the goal.
    step_factor : float
        Step as a fraction of the clearance to the nearest surface (or of the goal distance).
    arrive : float
        Arrival radius about the goal (m).
    max_steps : int
        Step limit per streamline.
    stagnation : float
        |u| below this fraction of the bare sink's speed at the same point is a stagnation event.
    """

    field: str = "exact"
    rankine: str = "line"
    weights: str = "normalised"
    distance: str = "true"
    strength: float = 1.0
    h_min: float = 0.0
    h_max: float = float("inf")
    step_factor: float = 0.5
    arrive: float = 0.5
    max_steps: int = 4000
    stagnation: float = 1e-6

    def __post_init__(self) -> None:
        if self.field not in ("exact", "document", "uniform"):
            raise ValueError(f"field = {self.field!r}: choose 'exact', 'document' or 'uniform'")
        if self.rankine not in ("line", "pair", "document"):
            raise ValueError(f"rankine = {self.rankine!r}: choose 'line', 'pair' or 'document'")
        if self.weights not in ("normalised", "document"):
            raise ValueError(f"weights = {self.weights!r}: choose 'normalised' or 'document'")
        if self.distance not in ("true", "ray"):
            raise ValueError(f"distance = {self.distance!r}: choose 'true' or 'ray'")
        if not (0 <= self.h_min <= self.h_max) or not self.arrive > 0 or self.max_steps < 1 or self.strength <= 0 \
                or not 0 < self.step_factor <= 1:
            raise ValueError("need 0 < h_min <= h_max, arrive > 0, max_steps >= 1 and strength > 0")
