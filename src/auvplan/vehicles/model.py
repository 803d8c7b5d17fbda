"""Under-actuated AUV: surge, first-order Nomoto yaw, depth by pitch, drift in the current.

State (Fossen's symbols where they belong): position η = (x, y, z) in the local frame, compass
heading ψ, yaw rate r, rudder angle δ, surge speed u through the water, pitch θ, and two
first-order Gauss–Markov wave disturbances (sway velocity v_w and yaw rate r_w).

* surge: u̇ = (u_c − u) / T_u
* yaw (Nomoto, first order): T ṙ + r = K δ, ψ̇ = r + r_w; rudder angle and rate limited
* pitch: θ̇ = (θ_c − θ) / T_θ, |θ| ≤ θ_max; depth changes by u sin θ
* kinematics: η̇ = u (cos θ sin ψ, cos θ cos ψ, sin θ) + v_w (cos ψ, −sin ψ, 0) + current(η, t)

The linear first-order parts are discretised exactly for a zero-order-hold input, so the step
response matches the analytic solution at every sample.  The heading autopilot is a PD law
placed by pole placement on the Nomoto model: natural frequency ω_n and damping ζ give
K_p = ω_n² T / K and K_d = (2 ζ ω_n T − 1) / K.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from .glider import GliderParams

if TYPE_CHECKING:
    from .._types import FloatArray

__all__ = ["VehicleParams", "VehicleState", "Vehicle"]


@dataclass(frozen=True)
class VehicleParams:
    """REMUS-100-class parameters (SI units, angles in degrees where the name says so).

    Sources: REMUS 100 cruise speed 1.5 m/s (max ~2.3 m/s) and fin limits ±30°
    (Hydroid spec sheet; Prestero 2001, MIT thesis); the Nomoto gain is chosen
    so the steady turning radius at full rudder is ~10 m
    (R = U / (K δ_max)); hull drag from Prestero (C_D ≈ 0.2 on the 0.19 m
    diameter frontal area) with 50 % propulsive efficiency; hotel load 15 W.
    Wave disturbance off by default (``wave_sigma_*`` = 0).

    Attributes
    ----------
    speed : float
        Cruise speed through the water (m/s).
    max_speed : float
        Largest surge speed the vehicle can be commanded (m/s); at least ``speed``.
    surge_time_constant : float
        Time constant T_u of the first-order surge response (s).
    nomoto_T : float
        Nomoto time constant T of the yaw response (s).
    nomoto_K : float
        Nomoto gain K: steady yaw rate per rudder angle (1/s).
    rudder_max_deg : float
        Rudder angle limit δ_max (degrees, below 90).
    rudder_rate_deg_s : float
        Rudder rate limit (degrees/s).
    heading_wn : float
        Natural frequency ω_n of the closed heading loop (rad/s).
    heading_zeta : float
        Damping ratio ζ of the closed heading loop.
    pitch_max_deg : float
        Pitch limit θ_max (degrees, below 90).
    pitch_time_constant : float
        Time constant T_θ of the first-order pitch response (s).
    depth_gain : float
        Proportional depth-to-pitch gain (rad/m).
    hotel_power : float
        Hotel load: electronics and sensors (W).
    drag_coefficient : float
        Hull drag coefficient C_D on the frontal area.
    frontal_area : float
        Frontal area A (m²).
    propulsive_efficiency : float
        Propulsive efficiency η, in (0, 1].
    water_density : float
        Sea-water density ρ (kg/m³).
    wave_sigma_r : float
        Standard deviation of the wave yaw-rate disturbance r_w (rad/s); 0 switches it off.
    wave_sigma_v : float
        Standard deviation of the wave sway disturbance v_w (m/s); 0 switches it off.
    wave_tau : float
        Correlation time of the Gauss–Markov wave disturbances (s).
    max_pitch_deg : float
        Largest pitch a plan or mission may ask of the vehicle (degrees, in (0, 90]; 90: no limit,
        a point vehicle): every planner's result, the mission builder and ``mission check``
        enforce it (20°, within the 15–25° operators plan REMUS-class vehicles at).
    turn_radius_m : float
        Least fly-by turn radius (m; 0 switches the turn check off): 10 m, the steady turn of
        this model at full rudder (``turning_radius``).
    max_depth_m : float
        Depth rating (m): 6000 m, the REMUS 6000's (a REMUS 100 is rated to 100 m, a REMUS 600 to
        600 m); the mission's depth band is clipped to it.
    battery_wh : float
        Nominal battery capacity (Wh); the REMUS 100 carries 1 kWh.
    usable_fraction : float
        Share of ``battery_wh`` that can be drawn (cold, ageing), in (0, 1].
    reserve : float
        Share of ``battery_wh`` to keep at the end of the mission, in [0, ``usable_fraction``).
    min_speed : float
        Slowest through-water speed a leg may be planned at (m/s; steerage); a cruise ``speed`` below
        it lowers it to ``speed``.
    hotel_w : float or None
        The hotel load under the name of the energy contract (W); when given it sets ``hotel_power``.
    power_table : tuple of (float, float)
        Measured (speed m/s, power W) pairs: when given, ``hotel_power`` (unless ``hotel_w`` is given)
        and the drag coefficient are fitted to ``P = P_hotel + k V³`` by least squares
        (:func:`auvplan.vehicles.power_fit.fit_power`), so every planner and budget uses the fitted model.
    type : str
        ``"auv"`` (this model) or ``"glider"``: a buoyancy glider flown by its steady-glide model in
        dive cycles (``[vehicle.glider]``, :class:`auvplan.vehicles.glider.GliderParams`; docs/gliders.md).
    glider : GliderParams
        The glider's flight model, yos, surfacing and power (``[vehicle.glider]``; used when ``type = "glider"``).
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
    max_pitch_deg: float = 20.0
    turn_radius_m: float = 10.0
    max_depth_m: float = 6000.0
    battery_wh: float = 1000.0
    usable_fraction: float = 0.9
    reserve: float = 0.2
    min_speed: float = 0.5
    hotel_w: float | None = None
    power_table: tuple[tuple[float, float], ...] = ()
    type: str = "auv"
    glider: GliderParams = field(default_factory=GliderParams)

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
        if not 0 < self.max_pitch_deg <= 90:
            raise ValueError(f"max_pitch_deg = {self.max_pitch_deg}: must lie in (0, 90] (90: no pitch limit)")
        if self.type not in ("auv", "glider"):
            raise ValueError(f"type = {self.type!r}: choose 'auv' or 'glider'")
        if self.turn_radius_m < 0 or not self.max_depth_m > 0:
            raise ValueError("turn_radius_m must be >= 0 and max_depth_m > 0")
        self._energy_checks()

    def _energy_checks(self) -> None:
        """Battery, reserve and speed range; ``hotel_w`` and ``power_table`` resolved into the power model."""
        if not self.battery_wh > 0 or not 0 < self.usable_fraction <= 1 or not 0 <= self.reserve < self.usable_fraction:
            raise ValueError(f"battery_wh = {self.battery_wh}, usable_fraction = {self.usable_fraction}, reserve = "
                             f"{self.reserve}: need battery_wh > 0, 0 < usable_fraction <= 1 and 0 <= reserve < "
                             "usable_fraction")
        if not 0 < self.min_speed <= self.max_speed:
            raise ValueError(f"min_speed = {self.min_speed}: must be positive and at most max_speed = {self.max_speed}")
        if self.hotel_w is not None:
            if self.hotel_w < 0:
                raise ValueError(f"hotel_w = {self.hotel_w}: must be >= 0")
            object.__setattr__(self, "hotel_power", float(self.hotel_w))
        if self.power_table:
            from .power_fit import fit_power

            v, p = zip(*self.power_table, strict=True)
            fit = fit_power(v, p, self.hotel_w)
            object.__setattr__(self, "hotel_power", fit.hotel_w)
            c = fit.k * self.propulsive_efficiency  # k = c / η and c = ½ ρ C_D A
            object.__setattr__(self, "drag_coefficient", 2.0 * c / (self.water_density * self.frontal_area))

    @property
    def drag_k(self) -> float:
        """Drag factor k in P_propulsion = k V³ (W s³/m³): ½ ρ C_D A / η."""
        return 0.5 * self.water_density * self.drag_coefficient * self.frontal_area / self.propulsive_efficiency

    @property
    def turning_radius(self) -> float:
        """Steady turning radius at full rudder and cruise speed (m)."""
        return self.speed / (self.nomoto_K * math.radians(self.rudder_max_deg))

    @property
    def heading_gains(self) -> tuple[float, float]:
        """PD autopilot gains (K_p, K_d) from pole placement on the Nomoto model."""
        wn, z, T, K = self.heading_wn, self.heading_zeta, self.nomoto_T, self.nomoto_K
        return wn * wn * T / K, max(2.0 * z * wn * T - 1.0, 0.0) / K


@dataclass
class VehicleState:
    """Mutable state of the vehicle (SI units, radians).

    Attributes
    ----------
    x, y, z : float
        Position η in the local frame: east, north, up (m).
    psi : float
        Compass heading ψ, clockwise from north (rad).
    u : float
        Surge speed through the water (m/s).
    r : float
        Yaw rate (rad/s).
    delta : float
        Rudder angle δ (rad).
    theta : float
        Pitch θ, positive nose up (rad).
    v_wave : float
        Wave sway-velocity disturbance v_w (m/s).
    r_wave : float
        Wave yaw-rate disturbance r_w (rad/s).
    """

    x: float
    y: float
    z: float
    psi: float
    u: float
    r: float = 0.0
    delta: float = 0.0
    theta: float = 0.0
    v_wave: float = 0.0
    r_wave: float = 0.0


class Vehicle:
    """Discrete-time vehicle model with a heading autopilot (small stateful class, ``reset()``).

    Parameters
    ----------
    params : VehicleParams
        The vehicle's parameters.
    dt : float
        Time step (s), positive.
    """

    def __init__(self, params: VehicleParams, dt: float) -> None:
        if not dt > 0:
            raise ValueError(f"dt must be positive, got {dt}")
        self.p = params
        self.dt = dt
        self.kp, self.kd = params.heading_gains
        self._a_r = math.exp(-dt / params.nomoto_T)
        self._a_u = math.exp(-dt / params.surge_time_constant)
        self._a_th = math.exp(-dt / params.pitch_time_constant)
        self._a_w = math.exp(-dt / params.wave_tau)
        self._s_w = math.sqrt(1.0 - self._a_w**2)
        self._dmax = math.radians(params.rudder_max_deg)
        self._drate = math.radians(params.rudder_rate_deg_s) * dt
        self._thmax = math.radians(params.pitch_max_deg)

    def rudder_command(self, s: VehicleState, psi_d: float) -> float:
        """PD heading autopilot: rudder angle command before the rudder limits.

        Parameters
        ----------
        s : VehicleState
            Current state (heading and yaw rate are used).
        psi_d : float
            Desired compass heading (rad).

        Returns
        -------
        float
            Rudder angle command (rad).
        """
        e = (psi_d - s.psi + math.pi) % (2.0 * math.pi) - math.pi
        return self.kp * e - self.kd * s.r

    def step(self, s: VehicleState, psi_d: float, theta_c: float, u_c: float, current: Sequence[float] | FloatArray,
             noise: Sequence[float] | FloatArray) -> tuple[float, float, float]:
        """Advance ``s`` by one step in place; returns the ground velocity (m/s).

        Parameters
        ----------
        s : VehicleState
            State, updated in place.
        psi_d, theta_c, u_c : float
            Heading (compass, rad), pitch (rad) and speed (m/s) commands.
        current : sequence of 3 float
            Current velocity at the vehicle (m/s).
        noise : sequence of 2 float
            Two standard normal draws for the wave disturbances.

        Returns
        -------
        tuple of 3 float
            Ground velocity (vx, vy, vz) over the step (m/s).
        """
        p = self.p
        d_c = self.rudder_command(s, psi_d)
        d_c = min(max(d_c, -self._dmax), self._dmax)
        s.delta += min(max(d_c - s.delta, -self._drate), self._drate)
        # exact ZOH step of T ṙ + r = K δ, heading by the trapezoid of r
        r_old = s.r
        s.r = self._a_r * s.r + (1.0 - self._a_r) * p.nomoto_K * s.delta
        s.psi = (s.psi + 0.5 * (r_old + s.r) * self.dt + s.r_wave * self.dt) % (2.0 * math.pi)
        s.u = self._a_u * s.u + (1.0 - self._a_u) * min(max(u_c, 0.0), p.max_speed)
        theta_c = min(max(theta_c, -self._thmax), self._thmax)
        s.theta = self._a_th * s.theta + (1.0 - self._a_th) * theta_c
        # Python floats, not numpy scalars: a numpy scalar here made the whole state numpy scalars and
        # every later step's arithmetic (guidance, events) several times slower; the values are the same
        n0, n1 = float(noise[0]), float(noise[1])
        s.v_wave = self._a_w * s.v_wave + p.wave_sigma_v * self._s_w * n0
        s.r_wave = self._a_w * s.r_wave + p.wave_sigma_r * self._s_w * n1
        sp, cp = math.sin(s.psi), math.cos(s.psi)
        ct = math.cos(s.theta)
        vx = s.u * ct * sp + s.v_wave * cp + float(current[0])
        vy = s.u * ct * cp - s.v_wave * sp + float(current[1])
        vz = s.u * math.sin(s.theta) + float(current[2])
        s.x += vx * self.dt
        s.y += vy * self.dt
        s.z += vz * self.dt
        return vx, vy, vz
