"""A formation's results: the fleet's figures, and one folder per vehicle with its own mission.

Each vehicle is written as a single-vehicle run (:func:`auvplan.io.results.records.write_run` and
:func:`~auvplan.io.missions.export.write_exports`, the same files as ``auvplan run``) into ``DIR/<vehicle>/``:
its flown track, its metrics, and its *own* executable mission — the leader's the route, each
follower's its slot's swept track made executable by :func:`auvplan.guidance.mission.waypoints.build_waypoints`
(the exact envelope test against the seabed and the obstacles), so ``auvplan mission check`` passes
on every file of every vehicle.  ``DIR/formation.json`` holds the fleet's metrics, the shapes along
the route and the reshaped stretches; ``DIR/slots.csv`` every slot's track.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, cast

import numpy as np

from ...guidance.mission.waypoints import build_waypoints
from ...sim import Mission, RunRecord
from ...sim.formation import FormationRecord
from ...world import World
from ..results import records
from . import export
from .readback.mission_storage import BoardStorage

__all__ = ["FORMATION_NAMES", "vehicle_records", "formation_record", "write_formation"]

FORMATION_NAMES = ("formation.json", "slots.csv", "scenario.toml", "report.html", "terrain.npz", "source.json")
"""Files a formation run writes at the top of ``--out`` (each vehicle's files go into its folder)."""


def vehicle_records(world: World, mission: Mission, record: FormationRecord) -> list[tuple[str, RunRecord]]:
    """Split a fleet's run into one single-vehicle :class:`RunRecord` per vehicle.

    Parameters
    ----------
    world : World
        The mission's world.
    mission : Mission
        The formation mission.
    record : FormationRecord
        The plans and the fleet's run.

    Returns
    -------
    list of (str, RunRecord)
        Vehicle name and its record: its mission (checked waypoints, m) and its flight; leader first.
    """
    if record.formation is None or mission.formation is None:
        return []
    out = []
    empty = np.empty((0, 3))
    for i, name in enumerate(mission.formation.names):
        track = record.formation.tracks[i]
        route = record.formation.route if i == 0 else build_waypoints(track, world)
        sim = record.result.runs[i] if record.result is not None else None
        out.append((name, RunRecord(f"{record.scenario}/{name}", record.seed, record.plan if i == 0 else None,
                                    route, empty, sim)))
    return out


def formation_record(record: FormationRecord) -> dict[str, Any]:
    """Make the fleet's JSON object: status, metrics, shapes along the route, reshapes, events.

    Parameters
    ----------
    record : FormationRecord
        The plans and the fleet's run.

    Returns
    -------
    dict
        The JSON object (distances in m, times in s).
    """
    f = record.formation
    return cast(dict[str, Any], records.jsonable({
        "scenario": record.scenario,
        "seed": record.seed,
        "status": record.status.value,
        "plan": records.plan_record(record.plan, record.scenario, record.seed) if record.plan is not None else None,
        "formation_plan": None if f is None else {
            "status": f.status.value, "message": f.message,
            "shapes": [{"from_m": b, "shape": s} for b, s in f.breaks],
            "reshaped": [{"from_m": a, "to_m": b, "why": w} for a, b, w in f.reshaped],
            "route_length_m": f.structure.length},
        "metrics": record.result.metrics if record.result is not None else None,
        "events": [list(e) for e in record.result.events] if record.result is not None else [],
    }))


def write_formation(out_dir: Path, world: World, mission: Mission, record: FormationRecord, scenario_text: str = "",
                    full: bool = False, board: BoardStorage | None = None) -> dict[str, Any]:
    """Write the fleet's files and one folder per vehicle (run files and every mission export).

    Parameters
    ----------
    out_dir : pathlib.Path
        Results folder.
    world : World
        The mission's world.
    mission : Mission
        The formation mission.
    record : FormationRecord
        The plans and the fleet's run.
    scenario_text : str, optional
        The scenario's TOML source, copied as ``scenario.toml``.
    full : bool, optional
        Every recorded sample instead of the decimated tracks.
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a vehicle's ``.plan`` it cannot hold is refused.

    Returns
    -------
    dict
        The fleet's record (:func:`formation_record`).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rec = formation_record(record)
    records.write_json(out / "formation.json", rec)
    if scenario_text:
        records.write_text(out / "scenario.toml", scenario_text)
    if record.formation is not None:
        f = record.formation
        n, m = f.tracks.shape[:2]
        rows = np.column_stack([np.repeat(np.arange(n), m), np.tile(f.s, n), f.tracks.reshape(-1, 3)])
        records.write_path_csv(out / "slots.csv", rows, "vehicle,reference_m,x,y,z")
    origin = world.origin
    formats = [fm for fm in export.EXPORT_FORMATS if origin is not None or fm not in export.GEOGRAPHIC]
    for name, vrec in vehicle_records(world, mission, record):
        folder = out / name
        records.write_run(folder, vrec, "", full)
        export.write_exports(folder, vrec, origin, mission.vehicle.speed, formats, full, board=board)
    return rec
