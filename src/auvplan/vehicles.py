"""Under-actuated AUV: surge, first-order Nomoto yaw, depth by pitch."""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["VehicleParams"]


@dataclass(frozen=True)
class VehicleParams:
    """REMUS-100-class parameters (SI units, angles in degrees where the name says so).

    Sources: REMUS 100 cruise speed 1.5 m/s (max ~2.3 m/s) and fin limits ±30°
    (Hydroid spec sheet; Prestero 2001, MIT thesis); the Nomoto gain is chosen
    so the steady turning radius at full rudder is ~10 m
    (R = U / (K δ_max)); hull drag from Prestero (C_D ≈ 0.2 on the 0.19 m
    diameter frontal area) with 50 % propulsive efficiency; hotel load 15 W.
    """

    speed: float = 1.5
    max_speed: float = 2.5
    surge_time_constant: float = 5.0
    nomoto_T: float = 1.5
    nomoto_K: float = 0.2865
    rudder_max_deg: float = 30.0
    rudder_rate_deg_s: float = 60.0
    heading_wn: float = 0.6
    heading_zeta: float = 0.9
    pitch_max_deg: float = 30.0
    pitch_time_constant: float = 2.0
    depth_gain: float = 0.1
    hotel_power: float = 15.0
    drag_coefficient: float = 0.2
    frontal_area: float = 0.0284
    propulsive_efficiency: float = 0.5
    water_density: float = 1025.0
    wave_sigma_r: float = 0.0
    wave_sigma_v: float = 0.0
    wave_tau: float = 5.0

    def __post_init__(self) -> None:
        positive = ("speed", "max_speed", "surge_time_constant", "nomoto_T", "nomoto_K", "rudder_max_deg",
                    "rudder_rate_deg_s", "heading_wn", "heading_zeta", "pitch_max_deg", "pitch_time_constant",
                    "depth_gain", "drag_coefficient", "frontal_area", "propulsive_efficiency", "water_density",
                    "wave_tau")
        for k in positive:
            if not getattr(self, k) > 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be positive")
        for k in ("hotel_power", "wave_sigma_r", "wave_sigma_v"):
            if getattr(self, k) < 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be >= 0")
        if self.speed > self.max_speed:
            raise ValueError(f"speed = {self.speed}: exceeds max_speed = {self.max_speed}")
        if self.rudder_max_deg >= 90 or self.pitch_max_deg >= 90:
            raise ValueError("rudder_max_deg and pitch_max_deg must be below 90")
        if self.propulsive_efficiency > 1:
            raise ValueError(f"propulsive_efficiency = {self.propulsive_efficiency}: must be <= 1")

    @property
    def drag_k(self) -> float:
        """k in P_propulsion = k V³ (W s³/m³): ½ ρ C_D A / η."""
        return 0.5 * self.water_density * self.drag_coefficient * self.frontal_area / self.propulsive_efficiency

    @property
    def turning_radius(self) -> float:
        """Steady turning radius at full rudder and cruise speed (m)."""
        return self.speed / (self.nomoto_K * math.radians(self.rudder_max_deg))
