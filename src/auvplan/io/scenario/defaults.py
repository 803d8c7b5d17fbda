"""Vehicle presets (``[vehicle] preset = "remus100" | "iver3" | "bluefin9" | "bluerov2"``) and the defaults a
verdict rests on (issue 51).

A preset fills the ``[vehicle]`` keys below from the manufacturer's published figures; every key the scenario
gives explicitly overrides it.  Figures that are not published are derived and say how (docs/missions.md,
"Vehicle presets", lists the sources):

* ``hotel_w`` = battery / published endurance at the cruise speed (3 kn = 1.543 m/s, or 2.5 kn) − the drag
  model's propulsion power there (``0.5 ρ C_D A V³ / η`` with ρ 1025, C_D 0.2 and η 0.5, the model's defaults,
  and the hull's frontal area π d² / 4);
* ``max_pitch_deg`` and ``turn_radius_m`` of the torpedo vehicles are the planning model's (20°, 10 m: fins
  ±30°, Prestero 2001) — manufacturers do not publish them; the BlueROV2 hovers (pitch 90, turn radius 0).

:func:`energy_defaults` names every energy input a verdict took from the defaults (``battery_wh = 1000
(default)``) or from a preset (``battery_wh = 1900 (preset bluefin9)``).
"""

from __future__ import annotations

from typing import Any

from ...errors import ScenarioError
from ...vehicles import VehicleParams

__all__ = ["PRESETS", "PRESET_SOURCES", "apply_preset", "energy_defaults", "ENERGY_KEYS"]

PRESETS: dict[str, dict[str, Any]] = {
    "remus100": {"speed": 1.54, "max_speed": 2.57, "battery_wh": 1000.0, "hotel_w": 24.1, "max_depth_m": 100.0,
                 "frontal_area": 0.0284, "max_pitch_deg": 20.0, "turn_radius_m": 10.0},
    "iver3": {"speed": 1.29, "max_speed": 2.06, "battery_wh": 800.0, "hotel_w": 49.8, "max_depth_m": 100.0,
              "frontal_area": 0.0170, "max_pitch_deg": 20.0, "turn_radius_m": 10.0},
    "bluefin9": {"speed": 1.54, "max_speed": 3.09, "battery_wh": 1900.0, "hotel_w": 204.0, "max_depth_m": 200.0,
                 "frontal_area": 0.0445, "max_pitch_deg": 20.0, "turn_radius_m": 10.0},
    "bluerov2": {"speed": 1.0, "max_speed": 1.5, "battery_wh": 266.0, "hotel_w": 60.0, "max_depth_m": 100.0,
                 "frontal_area": 0.0859, "drag_coefficient": 0.9, "max_pitch_deg": 90.0, "turn_radius_m": 0.0,
                 "min_speed": 0.2},
}
"""Published figures per vehicle (SI; module notes and :data:`PRESET_SOURCES`)."""

PRESET_SOURCES: dict[str, str] = {
    "remus100": "Hydroid (Kongsberg) REMUS 100 datasheet: 100 m rating, 1 kWh Li-ion, cruise 3 kn, max 5 kn, "
                "up to 22 h at 3 kn (also StrategyPage, 14 June 2010); 0.19 m hull (Prestero 2001, MIT thesis)",
    "iver3": "L3Harris (OceanServer) Iver3-580 datasheet: 100 m rating, 800 Wh standard battery, 1-4 kn, "
             "14 h at 2.5 kn; 5.8 in (0.147 m) hull",
    "bluefin9": "General Dynamics Bluefin-9 datasheet: 200 m rating, 1.9 kWh, up to 6 kn, 8 h at 3 kn; "
                "9 in (0.238 m) hull",
    "bluerov2": "Blue Robotics BlueROV2 technical details: 100 m rating, 14.8 V 18 Ah battery (266 Wh), "
                "max 1.5 m/s (3 kn), 457 x 338 x 254 mm frame (0.0859 m² frontal); hotel 60 W and C_D 0.9 (a bluff "
                "frame) estimated: no endurance at speed is published",
}
"""Where each preset's figures come from."""

ENERGY_KEYS = ("battery_wh", "usable_fraction", "reserve", "hotel_w", "speed")
"""The ``[vehicle]`` keys an energy verdict rests on."""


def apply_preset(table: Any, where: str) -> Any:
    """The ``[vehicle]`` table with its preset's figures filled in under the explicit keys.

    Parameters
    ----------
    table : Any
        The ``[vehicle]`` table as read (a dict; anything else is returned for the table check to refuse).
    where : str
        ``"<file>: [vehicle]"``, for messages.

    Returns
    -------
    Any
        The table without ``preset``, the preset's keys under the given ones.

    Raises
    ------
    ScenarioError
        For an unknown preset name.
    """
    if not isinstance(table, dict) or "preset" not in table:
        return table
    name = table["preset"]
    if name not in PRESETS:
        raise ScenarioError(f"{where} preset = {name!r}: choose one of {', '.join(PRESETS)}")
    rest = {k: v for k, v in table.items() if k != "preset"}
    return {**PRESETS[name], **rest}


def energy_defaults(sc: Any) -> list[str]:
    """``key = value (default)`` or ``(preset NAME)`` for each energy input the scenario did not give.

    Parameters
    ----------
    sc : Scenario
        The scenario (its ``raw`` ``[vehicle]`` table and the resolved ``vehicle``).

    Returns
    -------
    list of str
        One line naming the defaults, or none when every key was given (or the vehicle is a glider).
    """
    given = sc.raw.get("vehicle", {}) if isinstance(sc.raw, dict) else {}
    given = given if isinstance(given, dict) else {}
    preset = given.get("preset")
    v: VehicleParams = sc.vehicle
    if v.type == "glider":  # a glider's energy is its own ([vehicle.glider] hotel, surface and pump; docs/gliders.md)
        return []
    parts = []
    for key in ENERGY_KEYS:
        if key in given or (key == "hotel_w" and "hotel_power" in given):
            continue
        value = v.hotel_power if key == "hotel_w" else getattr(v, key)
        src = f"preset {preset}" if preset in PRESETS and key in PRESETS[preset] else "default"
        parts.append(f"{key} = {value:g} ({src})")
    return [f"energy verdict rests on {', '.join(parts)}"] if parts else []
