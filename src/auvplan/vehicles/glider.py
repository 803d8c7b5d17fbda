"""Buoyancy-driven glider: the steady-state flight model of Merckelbach et al. (2010).

A glider changes its volume by a pumped ballast ΔV (cc) and its pitch θ by moving its battery;
in a steady glide the net buoyancy, the lift and the drag balance (Merckelbach, Smeed and
Griffiths 2010, *Vertical water velocities from underwater gliders*, J. Atmos. Oceanic Technol.
27, 547–563, eqs. 1–7; the same model as Graver 2005, PhD thesis, Princeton, ch. 4, and the
``gliderflight`` package's ``SteadyStateGliderModel``):

* net buoyancy  F = g (ρ (V_g (1 − ε p) + ΔV) − m_g)
* lift  L = ½ ρ S (a_h + a_w) α U²,  drag  D = ½ ρ S (C_D0 + C_D1 α²) U²
* along and across the glide path (glide angle γ = θ + α):  D = F sin γ,  L = F cos γ, so the
  angle of attack α solves  α = (C_D0 + C_D1 α²) / ((a_h + a_w) tan(θ + α))  and
  U² = 2 F sin γ / (ρ S (C_D0 + C_D1 α²))
* vertical and horizontal speed through the water: w = U sin γ, u = U cos γ
* the wing's lift slope (Whicker and Fehlner 1958) a_w = 2π A / (2 + √(A² (1 + tan² Ω) + 4)) and
  induced drag C_D1 = a_w² / (π e A) + C_D1,hull, for aspect ratio A, sweep Ω and Oswald factor e.

Reference values (Merckelbach et al. 2010, table 2, Slocum G1/G2 shallow): S = 0.1 m², A = 7,
Ω = 43°, e = 0.8, a_h = 3.8 rad⁻¹, C_D1,hull = 9.7 rad⁻², C_D0 = 0.15, ε = 5·10⁻¹⁰ Pa⁻¹.

A dive cycle (a *yo*) dives from ``climb_depth_m`` to ``dive_depth_m`` (or ``min_altitude_m``
above the seabed, whichever is shallower) with ΔV = −``ballast_cc`` at pitch −``pitch_deg`` and
climbs back with +``ballast_cc`` at +``pitch_deg``; the glider surfaces after ``yos`` yos or at the first top at or
after ``surface_every_s`` underwater (:func:`yos_per_cycle`), and stays ``surface_time_s`` at the surface (GPS fix,
Iridium).
Energy: hotel power all the time, ``surface_power_w`` more at the surface, and the pump's work
p ΔV / η_pump at every inflection at depth (the climb's pumping against the pressure).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._types import ArrayLike, FloatArray
from ..errors import DataError

__all__ = ["GliderParams", "Glide", "steady_glide", "attack_angle", "pitch_for_speed", "YoTiming", "yo_timing",
           "yos_per_cycle", "G", "crab_heading"]

#: Gravity (m/s²).
G = 9.81


@dataclass(frozen=True)
class GliderParams:
    """A buoyancy-driven glider (``[vehicle] type = "glider"``, ``[vehicle.glider]``): Slocum G2 shallow defaults.

    Attributes
    ----------
    mass_kg : float
        Glider mass m_g (kg; a Slocum G2 weighs about 60 kg).
    neutral_density : float
        Water density (kg/m³) in which the glider is neutral with no ballast pumped: fixes the
        volume V_g = m_g / ρ_n (trimmed before deployment).
    cd0 : float
        Parasitic drag coefficient C_D0 (on the wing area).
    wing_area_m2 : float
        Wing area S (m²).
    aspect_ratio : float
        Wing aspect ratio A.
    sweep_deg : float
        Wing sweep Ω (degrees).
    oswald : float
        Oswald efficiency e.
    hull_lift : float
        Hull lift slope a_h (1/rad).
    hull_cd1 : float
        Hull induced drag C_D1,hull (1/rad²).
    compressibility : float
        Hull compressibility ε (1/Pa).
    ballast_cc : float
        Ballast pumped each way (cc; ±230 cc on a shallow Slocum).
    pitch_deg : float
        Pitch held on the dive and the climb (degrees; 26° is Slocum's usual).
    dive_depth_m : float
        Deepest point of a yo (m).
    climb_depth_m : float
        Shallowest point of a yo between surfacings (m).
    yos : int
        Yos between surfacings.
    surface_every_s : float
        Surface at the first yo top at or after this long underwater, the first dive from the surface included
        (s; at most ``yos`` yos, at least one: :func:`yos_per_cycle`); 0: by ``yos`` only.
    surface_time_s : float
        Time at the surface per surfacing (s): fix, data, new waypoints.
    hotel_w : float
        Hotel load: computer, sensors, altimeter (W).
    surface_power_w : float
        Extra load at the surface: GPS and Iridium (W).
    pump_efficiency : float
        Buoyancy pump efficiency η_pump in (0, 1].
    battery_wh : float
        Battery capacity (Wh; a G2 alkaline pack holds about 7.2 MJ = 2000 Wh).
    capture_radius_m : float
        A waypoint is reached at a surfacing within this distance (m).
    """

    mass_kg: float = 60.0
    neutral_density: float = 1025.0
    cd0: float = 0.15
    wing_area_m2: float = 0.1
    aspect_ratio: float = 7.0
    sweep_deg: float = 43.0
    oswald: float = 0.8
    hull_lift: float = 3.8
    hull_cd1: float = 9.7
    compressibility: float = 5e-10
    ballast_cc: float = 230.0
    pitch_deg: float = 26.0
    dive_depth_m: float = 200.0
    climb_depth_m: float = 10.0
    yos: int = 3
    surface_every_s: float = 0.0
    surface_time_s: float = 600.0
    hotel_w: float = 1.0
    surface_power_w: float = 3.0
    pump_efficiency: float = 0.3
    battery_wh: float = 2000.0
    capture_radius_m: float = 1000.0

    def __post_init__(self) -> None:
        for k in ("mass_kg", "neutral_density", "cd0", "wing_area_m2", "aspect_ratio", "oswald", "hull_lift",
                  "ballast_cc", "pitch_deg", "dive_depth_m", "pump_efficiency", "battery_wh", "capture_radius_m"):
            if not getattr(self, k) > 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be positive")
        for k in ("hull_cd1", "compressibility", "climb_depth_m", "surface_every_s", "surface_time_s", "hotel_w",
                  "surface_power_w"):
            if getattr(self, k) < 0:
                raise ValueError(f"{k} = {getattr(self, k)}: must be >= 0")
        if not 0 < self.pitch_deg < 80 or not 0 <= self.sweep_deg < 80:
            raise ValueError(f"pitch_deg = {self.pitch_deg}, sweep_deg = {self.sweep_deg}: need 0 < pitch_deg < 80 "
                             "and 0 <= sweep_deg < 80")
        if self.climb_depth_m >= self.dive_depth_m:
            raise ValueError(f"climb_depth_m = {self.climb_depth_m}: must be shallower than dive_depth_m = "
                             f"{self.dive_depth_m}")
        if self.yos < 1:
            raise ValueError(f"yos = {self.yos}: must be >= 1")
        if self.pump_efficiency > 1:
            raise ValueError(f"pump_efficiency = {self.pump_efficiency}: must be <= 1")
        shrink = self.compressibility * self.neutral_density * G * self.dive_depth_m
        if shrink > 0.1:  # 1/Pa made the hull's volume negative at depth: a ZeroDivisionError in the yo's timing
            raise ValueError(f"compressibility = {self.compressibility:g} /Pa: the hull would shrink by "
                             f"{shrink:.3g} of its volume at dive_depth_m = {self.dive_depth_m:g} (at most 0.1)")
        th = math.radians(self.pitch_deg)  # the deepest yo's mid depth: where the hull is the most compressed
        mid = self.neutral_density * G * 0.5 * (self.climb_depth_m + self.dive_depth_m)
        w = steady_glide(self, np.array([-th, th]), np.array([-self.ballast_cc, self.ballast_cc]),
                         self.neutral_density, mid).w
        if not float(w[0]) < 0.0 < float(w[1]):
            raise ValueError(f"ballast_cc = {self.ballast_cc:g}, compressibility = {self.compressibility:g} /Pa: the "
                             f"glider cannot {'climb' if w[1] <= 0 else 'dive'} at the mid depth of its yo "
                             f"({0.5 * (self.climb_depth_m + self.dive_depth_m):g} m; vertical speeds "
                             f"{float(w[0]):.3g} / {float(w[1]):.3g} m/s)")

    @property
    def volume_m3(self) -> float:
        """Hull volume V_g = m_g / ρ_n (m³)."""
        return self.mass_kg / self.neutral_density

    @property
    def wing_lift(self) -> float:
        """Wing lift slope a_w (1/rad), Whicker and Fehlner's swept-wing formula."""
        a, om = self.aspect_ratio, math.radians(self.sweep_deg)
        return 2.0 * math.pi * a / (2.0 + math.sqrt(a * a * (1.0 + math.tan(om) ** 2) + 4.0))

    @property
    def cd1(self) -> float:
        """Induced drag coefficient C_D1 = a_w² / (π e A) + C_D1,hull (1/rad²)."""
        return self.wing_lift**2 / (math.pi * self.oswald * self.aspect_ratio) + self.hull_cd1


@dataclass(frozen=True)
class Glide:
    """A steady glide (arrays broadcast over the inputs; signs follow the pitch: negative on a dive).

    Attributes
    ----------
    speed : ndarray
        Speed through the water along the glide path U (m/s).
    w : ndarray
        Vertical speed through the water (m/s, up positive).
    u : ndarray
        Horizontal speed through the water (m/s, ≥ 0).
    alpha : ndarray
        Angle of attack (rad).
    gamma : ndarray
        Glide angle θ + α (rad).
    """

    speed: FloatArray
    w: FloatArray
    u: FloatArray
    alpha: FloatArray
    gamma: FloatArray


def attack_angle(pitch: ArrayLike, cd0: float, cd1: float, lift: float) -> FloatArray:
    """The angle of attack of a steady glide at a pitch (Merckelbach et al. 2010, eq. 7).

    Solves ``(C_D0 + C_D1 α²) = a α tan(θ + α)`` by Newton's method on |θ| (the root is unique in
    (0, π/2 − |θ|) and has the pitch's sign).

    Parameters
    ----------
    pitch : array_like
        Pitch θ (rad, nonzero, |θ| < π/2).
    cd0, cd1 : float
        Drag coefficients C_D0 and C_D1 (1/rad²).
    lift : float
        Total lift slope a_h + a_w (1/rad).

    Returns
    -------
    numpy.ndarray
        α (rad), with the sign of θ.
    """
    th = np.abs(np.asarray(pitch, dtype=float))
    th = np.where(th > 1e-6, th, np.nan)
    a = np.clip(cd0 / (lift * np.tan(th)), 0.0, 0.5 * (0.5 * np.pi - th))
    for _ in range(60):
        t = np.tan(th + a)
        f = cd0 + cd1 * a * a - lift * a * t
        df = 2.0 * cd1 * a - lift * t - lift * a * (1.0 + t * t)
        step = f / df
        a = np.clip(a - step, 0.0, 0.5 * np.pi - th - 1e-9)
        if np.nanmax(np.abs(step), initial=0.0) < 1e-13:
            break
    return np.asarray(np.sign(np.asarray(pitch, dtype=float)) * a)


def steady_glide(params: GliderParams, pitch: ArrayLike, ballast_cc: ArrayLike, density: ArrayLike = 1025.0,
                 pressure_pa: ArrayLike = 0.0) -> Glide:
    """Speed, vertical and horizontal speed of the steady glide (module notes; Merckelbach et al. 2010).

    Parameters
    ----------
    params : GliderParams
        Mass, volume, wing and drag figures.
    pitch : array_like
        Pitch θ (rad; negative nose down).
    ballast_cc : array_like
        Ballast pumped ΔV (cc; negative: heavier).
    density : array_like, default 1025.0
        In-situ density ρ (kg/m³).
    pressure_pa : array_like, default 0.0
        Gauge pressure p (Pa), for the hull's compressibility.

    Returns
    -------
    Glide
        The glide; where the buoyancy does not agree with the pitch (a nose-down glider that is
        buoyant) the speed is 0 (a stall, as the model cannot fly it).
    """
    p = params
    th = np.asarray(pitch, dtype=float)
    rho = np.asarray(density, dtype=float)
    fb = G * (rho * (p.volume_m3 * (1.0 - p.compressibility * np.asarray(pressure_pa, dtype=float))
                     + 1e-6 * np.asarray(ballast_cc, dtype=float)) - p.mass_kg)
    lift = p.hull_lift + p.wing_lift
    alpha = attack_angle(th, p.cd0, p.cd1, lift)
    gamma = th + alpha
    cd = p.cd0 + p.cd1 * alpha * alpha
    u2 = 2.0 * fb * np.sin(gamma) / (rho * p.wing_area_m2 * cd)
    speed = np.sqrt(np.where(np.isfinite(u2) & (u2 > 0), u2, 0.0))
    return Glide(speed, speed * np.sin(gamma), speed * np.cos(gamma), alpha, gamma)


def pitch_for_speed(params: GliderParams, w: ArrayLike, ballast_cc: ArrayLike, density: ArrayLike = 1025.0,
                    pressure_pa: ArrayLike = 0.0) -> FloatArray:
    """The pitch at which the steady glide has a vertical speed (the model inverted, by bisection).

    Parameters
    ----------
    params : GliderParams
        The glider.
    w : array_like
        Vertical speed through the water (m/s; its sign is the ballast's).
    ballast_cc, density, pressure_pa : array_like
        As :func:`steady_glide`.

    Returns
    -------
    numpy.ndarray
        Pitch (rad) with the sign of ``w``; NaN where no pitch in (0.5°, 80°) gives that speed
        (|w| grows with |θ| over that range for gliders of this kind, so the root is unique).
    """
    w = np.asarray(w, dtype=float)
    s = np.sign(w)
    lo = np.full(w.shape, math.radians(0.5))
    hi = np.full(w.shape, math.radians(80.0))
    target = np.abs(w)

    def vz(theta: FloatArray) -> FloatArray:
        return np.abs(steady_glide(params, s * theta, ballast_cc, density, pressure_pa).w)

    ok = (vz(lo) <= target) & (target <= vz(hi))
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        up = vz(mid) < target
        lo, hi = np.where(up, mid, lo), np.where(up, hi, mid)
    return np.asarray(np.where(ok & (s != 0), s * 0.5 * (lo + hi), np.nan))


@dataclass(frozen=True)
class YoTiming:
    """One dive and climb between two depths in still water at the nominal ballast and pitch.

    Attributes
    ----------
    dive_s, climb_s : float
        Durations (s).
    distance_m : float
        Horizontal distance through the water (m).
    pump_j : float
        Pump energy at the bottom inflection (J).
    w_dive, w_climb, u_dive, u_climb : float
        Vertical (m/s, signed) and horizontal speeds (m/s).
    """

    dive_s: float
    climb_s: float
    distance_m: float
    pump_j: float
    w_dive: float
    w_climb: float
    u_dive: float
    u_climb: float

    @property
    def speed(self) -> float:
        """Mean horizontal speed through the water over the yo (m/s)."""
        return self.distance_m / (self.dive_s + self.climb_s)


def yo_timing(params: GliderParams, top_m: float, bottom_m: float, density: float = 1025.0) -> YoTiming:
    """Durations, distance and pump energy of a yo from ``top_m`` to ``bottom_m`` depth (m).

    Parameters
    ----------
    params : GliderParams
        The glider (its ballast and pitch).
    top_m, bottom_m : float
        Depths of the top and the bottom of the yo (m, ``bottom_m > top_m``).
    density : float, default 1025.0
        Water density (kg/m³).

    Returns
    -------
    YoTiming
        The yo (the flight model at the yo's mid depth).
    """
    th = math.radians(params.pitch_deg)
    p_mid = density * G * 0.5 * (top_m + bottom_m)
    gl = steady_glide(params, np.array([-th, th]), np.array([-params.ballast_cc, params.ballast_cc]), density, p_mid)
    w_d, w_c = float(gl.w[0]), float(gl.w[1])
    u_d, u_c = float(gl.u[0]), float(gl.u[1])
    span = bottom_m - top_m
    if not w_d < 0.0 < w_c:  # the ballast cannot offset the hull's compression (or the water's density) there
        raise DataError(f"the glider cannot {'climb' if w_c <= 0 else 'dive'} between {top_m:g} and {bottom_m:g} m "
                        f"in water of {density:g} kg/m³ (vertical speeds {w_d:.3g} / {w_c:.3g} m/s): more "
                        "ballast_cc, or a stiffer hull (compressibility)")
    dive_s, climb_s = span / -w_d, span / w_c
    pump = density * G * bottom_m * 2e-6 * params.ballast_cc / params.pump_efficiency
    return YoTiming(dive_s, climb_s, u_d * dive_s + u_c * climb_s, pump, w_d, w_c, u_d, u_c)


def yos_per_cycle(params: GliderParams, yo: YoTiming) -> int:
    """Yos between two surfacings: the one rule of the planner's cycle, the flight and the Slocum ``yoNN.ma``.

    A cycle leaves the surface, dives to the bottom, climbs to ``climb_depth_m`` (the top of yo 1), and so on;
    the top of yo k is reached ``climb_depth_m / |w_dive| + k (dive_s + climb_s)`` after leaving the surface.
    With ``surface_every_s`` the glider surfaces at the first top at or after that long underwater (a top within
    10⁻⁹ yo of it counts as at it), at most ``yos`` yos and at least one; without it after ``yos`` yos.  A Slocum
    flies the count written into ``num_half_cycles_to_do`` (twice this), whatever the time.

    Parameters
    ----------
    params : GliderParams
        The glider (``yos``, ``surface_every_s``, ``climb_depth_m``).
    yo : YoTiming
        Its yo between ``climb_depth_m`` and the bottom (:func:`yo_timing`).

    Returns
    -------
    int
        Yos per cycle, in ``[1, yos]``.
    """
    if params.surface_every_s <= 0:
        return params.yos
    first_s = params.climb_depth_m / -yo.w_dive  # the first dive, from the surface down to climb_depth_m
    k = math.ceil((params.surface_every_s - first_s) / (yo.dive_s + yo.climb_s) - 1e-9)
    return min(params.yos, max(1, k))


def crab_heading(bearing: float, speed: float, current: ArrayLike) -> float:
    """Compass heading (rad) that holds a course ``bearing`` at through-water ``speed`` in ``current``.

    Parameters
    ----------
    bearing : float
        Course to make good (compass, rad).
    speed : float
        Through-water horizontal speed (m/s).
    current : array_like
        East and north current (m/s).

    Returns
    -------
    float
        The heading; straight into the cross current when it is faster than ``speed``.
    """
    c = np.asarray(current, dtype=float)
    cross = c[0] * math.cos(bearing) - c[1] * math.sin(bearing)  # to the right of the course
    return bearing - math.asin(max(-1.0, min(1.0, cross / speed)))
