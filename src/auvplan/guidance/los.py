"""Line-of-sight guidance baselines (Fossen): proportional LOS and integral LOS."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["LosParams"]


@dataclass(frozen=True)
class LosParams:
    """LOS settings: ``lookahead`` Δ (m), ILOS integral gain ``sigma`` (1/s), leg switch radius (m)."""

    lookahead: float = 15.0
    sigma: float = 0.02
    switch_radius: float = 10.0

    def __post_init__(self) -> None:
        if not self.lookahead > 0 or self.sigma < 0 or not self.switch_radius > 0:
            raise ValueError("lookahead and switch_radius must be positive and sigma >= 0")
