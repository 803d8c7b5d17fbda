"""``mission check`` as a job: exported mission files re-flown under their format's depth semantics against a
scenario's seabed, obstacles, surface, depth band and bounds, and held to the vehicle's limits and energy."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..guidance.mission.waypoints import MissionCheck
    from ..io.scenario.specs import Scenario
    from ..path.flyable import LimitReport

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
    ok : bool
        Whether every check passed.
    """

    record: dict[str, Any]
    check: MissionCheck
    vehicle: LimitReport
    energy_line: str
    ok: bool


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
    from ..io.missions.energy import mission_file_energy
    from ..io.missions.formats import check_mission_file, read_mission
    from ..io.scenario import loader as scenario_io
    from ..path.flyable import check_limits
    from ..sim.pipeline import vehicle_limits

    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    out = []
    for name in files:
        check, fmt = check_mission_file(Path(name), world, pitch)
        points = read_mission(Path(name), world.origin)[0]
        # a QGC plan starts from its home on the surface: the launch, not a leg of the mission
        vlimits = check_limits(points[1:] if fmt == "qgc" else points, vehicle_limits(mission.vehicle))
        energy, energy_ok, energy_line = mission_file_energy(world, mission, Path(name))
        rec = {"file": name, "format": fmt, **check.as_dict(), "vehicle": vlimits.as_dict(), "energy": energy}
        if sc.mission.confidence:  # issue 39: checked against the worst-case seabed at that confidence
            rec["clearance_confidence"] = sc.mission.confidence
        out.append(FileCheck(rec, check, vlimits, energy_line, check.ok and vlimits.ok and energy_ok))
    return sc, out
