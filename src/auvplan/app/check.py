"""``mission check`` as a job: exported mission files re-flown under their format's depth semantics against a
scenario's seabed, obstacles, surface, depth band and bounds, held to the vehicle's limits and energy, and
measured against its charted no-go zones."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..guidance.mission.waypoints import MissionCheck
    from ..io.scenario.specs import Scenario
    from ..path.flyable import LimitReport
    from ..world.zones import ZoneApproach

__all__ = ["FileCheck", "check_missions"]


@dataclass(frozen=True)
class FileCheck:
    """One file's checks.

    Attributes
    ----------
    record : dict
        Its JSON record (``mission check --json``).
    check : MissionCheck
        The file re-flown under its format's depth semantics.
    vehicle : LimitReport
        The vehicle's pitch, turn and depth limits.
    energy_line : str
        The energy verdict, one line.
    deploy_line : str
        Datum, envelope, payload events and altitude legs, one line (issue 51).
    ok : bool
        Whether every check passed.
    zones : tuple of ZoneApproach
        The closest approach to each charted zone and the legs entering it (empty without zones).
    """

    record: dict[str, Any]
    check: MissionCheck
    vehicle: LimitReport
    energy_line: str
    deploy_line: str
    ok: bool
    zones: tuple[ZoneApproach, ...] = ()


def check_missions(scenario: str, files: list[str], pitch: float) -> tuple[Scenario, list[FileCheck]]:
    """Check mission files against a scenario.

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file.
    files : list of str
        Mission files (``.moos``, ``.plan``, ``.gpx``, ``.yaml``, ``.geojson``, ``.kml``, ``.csv``).
    pitch : float
        Pitch (deg) at which a depth-holding executor changes depth.

    Returns
    -------
    scenario : Scenario
        The scenario.
    checks : list of FileCheck
        One per file, in order.
    """
    from ..io.missions.deploy_read import file_deploy_check
    from ..io.missions.energy import mission_file_energy
    from ..io.missions.formats import check_mission_file, read_mission
    from ..io.scenario import loader as scenario_io
    from ..io.scenario.defaults import energy_defaults
    from ..path.flyable import check_limits
    from ..sim.pipeline import vehicle_limits

    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    out = []
    for name in files:
        check, fmt = check_mission_file(Path(name), world, pitch)
        points = read_mission(Path(name), world.origin, world.seabed if world.terrain is not None else None)[0]
        deploy, deploy_line = file_deploy_check(name, world.origin, points, fmt, check.min_altitude_m,
                                                mission.vehicle.speed)  # issue 51: datum, envelope, payload
        # a QGC plan starts from its home on the surface: the launch, not a leg of the mission
        vlimits = check_limits(points[1:] if fmt == "qgc" else points, vehicle_limits(mission.vehicle))
        energy, energy_ok, energy_line = mission_file_energy(world, mission, Path(name))
        defaults = energy_defaults(sc)  # issue 51: a verdict resting on a default names it
        energy_line += "".join(f"; {d}" for d in defaults)
        energy["defaults"] = defaults
        rec = {"file": name, "format": fmt, **check.as_dict(), "vehicle": vlimits.as_dict(), "energy": energy,
               "deploy": deploy}
        if sc.mission.confidence:  # issue 39: checked against the worst-case seabed at that confidence
            rec["clearance_confidence"] = sc.mission.confidence
        # charted no-go zones: the closest approach to each, and the legs that enter it (exact test)
        zones = world.zones.exact.approach(points[1:] if fmt == "qgc" else points) if world.zones else []
        if zones:
            rec["zones"] = [z.as_dict() for z in zones]
        zones_ok = not any(z.entered_legs for z in zones)
        out.append(FileCheck(rec, check, vlimits, energy_line, deploy_line,
                             check.ok and vlimits.ok and energy_ok and deploy["ok"] and zones_ok, tuple(zones)))
    return sc, out
