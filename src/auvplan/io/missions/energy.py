"""A mission's endurance to files: ``legs.csv`` and the energy figures of ``metrics.json``,
``sim_metrics.json`` and ``run.json`` (the contract of issue 38, ``docs/endurance.md``).

* ``legs.csv``: ``leg, t_start_s, t_end_s, energy_wh`` (predicted), then ``length_m, duration_s,
  speed_water_mps, speed_ground_mps, cumulative_wh, remaining_wh`` and, after a flight,
  ``flown_t_start_s, flown_t_end_s, flown_energy_wh``.
* ``metrics.json`` gains ``energy_wh``, ``margin_wh``, ``point_of_no_return`` (``lat``, ``lon``,
  ``t_s``, and ``x``, ``y``, ``z``, ``s_m``, ``whole_mission``, ``message``), ``energy_status``,
  ``energy_message``, ``battery_wh``, ``usable_wh``, ``reserve_wh`` and ``leg_speeds_mps``.
* ``sim_metrics.json`` gains the flown ``energy_wh``; ``run.json`` an ``energy`` object, and its
  ``status`` becomes ``RESERVE_BROKEN`` when the flight succeeded but the budget breaks the reserve.
"""

from __future__ import annotations

import csv
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..._types import Status
from ...endurance import Endurance, EnergyModel, assess, departure_endurance, mission_budget, traverse
from ...errors import DataError
from ...nav import surface_kinds
from ...nav.budget import LAUNCH_DIVE_MPS, launch_point
from ...sim import Mission, RunRecord, record_tail, with_leg_speeds
from ...world import World
from ..data.geo import LocalFrame
from ..files import limits as _limits
from ..results.records import JsonDict, jsonable, write_json, write_text
from .formats import read_mission
from .readback.dwell import read_dwells
from .readback.speeds import judged_leg_speeds
from .tail import read_tail

__all__ = ["energy_record", "legs_table", "write_energy", "read_leg_speeds", "mission_endurance",
           "mission_file_energy", "file_energy_flight", "sweep_energy", "launched_at"]

_Inverse = Callable[[Any, Any], tuple[Any, Any]]


def energy_record(e: Endurance, inverse: _Inverse | None = None) -> JsonDict:
    """The energy figures of a mission for ``metrics.json``.

    Parameters
    ----------
    e : Endurance
        The analysis.
    inverse : callable, optional
        ``inverse(x, y) -> (lon, lat)`` of the scenario's frame (lat/lon are null without it).

    Returns
    -------
    dict
        ``energy_wh``, ``margin_wh``, ``point_of_no_return`` and the battery figures (Wh, s, m).
    """
    b, p = e.budget, e.pnr
    lat = lon = None
    if inverse is not None:
        lo, la = inverse(np.array([p.position[0]]), np.array([p.position[1]]))
        lon, lat = float(np.asarray(lo).ravel()[0]), float(np.asarray(la).ravel()[0])
    return {
        "energy_wh": b.energy_wh, "margin_wh": b.margin_wh, "duration_s": b.duration_s,
        "point_of_no_return": {"lat": lat, "lon": lon, "t_s": p.t_s, "x": p.position[0], "y": p.position[1],
                               "z": p.position[2], "s_m": p.s_m, "leg": p.leg, "whole_mission": p.whole_mission,
                               "recovery": list(p.recovery), "status": p.status.value, "message": p.message},
        "energy_status": b.status.value, "energy_message": b.message,
        "battery_wh": b.model.battery_wh, "usable_wh": b.model.usable_wh, "reserve_wh": b.model.reserve_wh,
        "leg_speeds_mps": b.speed_water.tolist(), "speed_objective": e.speeds.objective,
        "speed_message": e.speeds.message,
    }


def legs_table(e: Endurance) -> list[dict[str, float]]:
    """One row per leg, predicted (and flown, after a flight).

    Parameters
    ----------
    e : Endurance
        The analysis.

    Returns
    -------
    list of dict
        ``leg, t_start_s, t_end_s, energy_wh`` first (module notes).
    """
    rows = e.budget.rows()
    if e.flown is not None:
        for i, r in enumerate(rows):
            r.update(flown_t_start_s=float(e.flown.t_start[i]), flown_t_end_s=float(e.flown.t_end[i]),
                     flown_energy_wh=float(e.flown.energy_wh[i]))
    return rows


def _patch(path: Path, extra: JsonDict) -> None:
    doc = json.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}
    doc.update(extra)
    write_json(path, doc)


def write_energy(out_dir: Path, e: Endurance, inverse: _Inverse | None = None) -> JsonDict:
    """Write ``legs.csv`` and add the energy figures to the run's JSON files in ``out_dir``.

    Parameters
    ----------
    out_dir : pathlib.Path
        A results folder written by :func:`auvplan.io.results.records.write_run`.
    e : Endurance
        The analysis.
    inverse : callable, optional
        ``inverse(x, y) -> (lon, lat)`` of the scenario's frame.

    Returns
    -------
    dict
        The record added to ``metrics.json``.
    """
    out = Path(out_dir)
    rows = legs_table(e)
    cols = list(rows[0]) if rows else ["leg", "t_start_s", "t_end_s", "energy_wh"]
    lines = [",".join(cols)] + [",".join(str(int(r[c])) if c == "leg" else f"{r[c]:.6f}" for c in cols)
                                 for r in rows]
    write_text(out / "legs.csv", "\n".join(lines) + "\n")
    rec = energy_record(e, inverse)
    _patch(out / "metrics.json", jsonable(rec))
    if e.flown is not None and (out / "sim_metrics.json").is_file():
        _patch(out / "sim_metrics.json", {"energy_wh": e.flown.energy.energy_wh})
    run = out / "run.json"
    if run.is_file():
        doc = json.loads(run.read_text(encoding="utf-8"))
        doc["energy"] = jsonable(rec)
        if doc.get("status") in (Status.EXACT.value, Status.APPROXIMATE.value) and not e.status.ok:
            doc["status"] = e.status.value
        write_json(run, doc)
    return rec


def read_leg_speeds(out_dir: Path, legs: int) -> NDArray[np.float64] | None:
    """The ``speed_water_mps`` column of ``legs.csv`` in ``out_dir``, when it has ``legs`` rows.

    Parameters
    ----------
    out_dir : pathlib.Path
        A results folder.
    legs : int
        The number of legs of its mission.

    Returns
    -------
    numpy.ndarray or None
        ``(legs,)`` speeds (m/s); None when the file is missing, malformed or for another mission.
    """
    path = Path(out_dir) / "legs.csv"
    if not path.is_file() or legs < 1:
        return None
    try:
        with path.open(encoding="utf-8") as fh:
            v = np.array([float(r["speed_water_mps"]) for r in csv.DictReader(fh)])
    except (OSError, KeyError, ValueError, TypeError, UnicodeDecodeError):
        return None
    return v if v.size == legs and np.all(np.isfinite(v)) and np.all(v > 0) else None


def mission_endurance(world: World, mission: Mission, record: RunRecord) -> Endurance | None:
    """The run's energy budget, point of no return and flown energy, at the speeds the flight flew.

    Parameters
    ----------
    world : World
        Currents, seabed and obstacles.
    mission : Mission
        Vehicle and ``[endurance]`` settings.
    record : RunRecord
        The run: its route and flight.

    Returns
    -------
    Endurance or None
        The analysis (:func:`auvplan.endurance.assess`); None without a route of two points.
    """
    if record.route.shape[0] < 2:
        return None
    _limits.check_route_endurance(f"{mission.name}: [endurance]", record.route, mission.endurance.ds_m)
    sim = record.sim
    track = (sim.t, sim.position, sim.progress) if sim is not None and sim.t.size > 1 else None
    tail = record_tail(record)  # legs the follower flew tail-first: timed with the other root
    speeds = with_leg_speeds(world, mission, record.route, tail).leg_speeds or None
    nav = record.nav  # the surface fixes' dwell (issue 52)
    dwell = nav.dwell_s if nav is not None and len(nav.dwell_s) == record.route.shape[0] else None
    return assess(world, record.route, mission.vehicle, mission.endurance, track=track, speeds=speeds, tail=tail,
                  dwell=dwell)


def mission_file_energy(world: World, mission: Mission, path: Path) -> tuple[JsonDict, bool, str]:
    """:func:`file_energy_flight`'s verdict alone (its first three values).

    Parameters
    ----------
    world : World
        Currents (and the origin of geographic formats).
    mission : Mission
        Vehicle, power model, battery and ``[endurance] ds_m``.
    path : pathlib.Path
        The mission file.

    Returns
    -------
    record : dict
        As :func:`file_energy_flight`.
    ok : bool
        Whether the reserve is kept.
    line : str
        The verdict in one line.
    """
    rec, ok, line, _, _ = file_energy_flight(world, mission, path)
    return rec, ok, line


def file_energy_flight(world: World, mission: Mission, path: Path) -> tuple[
        JsonDict, bool, str, NDArray[np.float64] | None, NDArray[np.float64] | None]:
    """A mission file's energy budget from the scenario's start time, at the speeds the file carries, with the
    time a ``.plan`` holds at a waypoint or a timed loiter (:func:`read_holds`, the last item's included) spent
    holding the item against the current there.

    Parameters
    ----------
    world : World
        Currents (and the origin of geographic formats).
    mission : Mission
        Vehicle (speed when the file carries none, power model, battery) and ``[endurance] ds_m``.
    path : pathlib.Path
        The mission file.

    Returns
    -------
    record : dict
        ``energy_status``, ``energy_wh``, ``margin_wh``, ``duration_s``, ``energy_message``, ``leg_speeds_mps``,
        ``speed_assumed_legs`` and ``speed_assumed_line`` (the legs whose speed the file does not carry, judged at
        the vehicle's speed: :func:`~auvplan.io.missions.readback.speeds.judged_leg_speeds`).
    ok : bool
        Whether the reserve is kept.
    line : str
        The verdict in one line.
    held_water_m : numpy.ndarray or None
        ``(N,)`` the distance the vehicle moves through the water holding each waypoint against the current (the
        hold's time × the current's mean speed there, m; the navigation budget's drift without bottom lock,
        :func:`auvplan.nav.budget.hold_drift`); None without a hold.
    water_m : numpy.ndarray or None
        ``(N - 1,)`` each leg's horizontal distance through the water as flown
        (:meth:`auvplan.endurance.Traverse.leg_water_m`: the navigation budget's drift without bottom lock);
        None where the current beats the vehicle.

    Notes
    -----
    The wait at a surface fix (``[navigation]``) is the file's where the format carries one (a ``.plan``'s hold, a
    MOOS ``BHV_StationKeep``: :func:`~auvplan.io.missions.readback.dwell.read_dwells`), spent adrift at hotel power
    as the plan budgets it; else the scenario's ``surface_s``.  A ``.plan``'s hold elsewhere is held on station.
    Under ``[navigation]`` a file that starts at its first waypoint (every format but a ``.plan``, whose home leg is
    its launch) departs it when the launch's dive from the surface ends (:func:`launched_at`), the navigation
    budget's clock: in a current that changes in time its legs fly the planned current.
    """
    waypoints = read_mission(path, world.origin, world.seabed if world.terrain is not None else None)[0]
    if waypoints.shape[0] < 2:
        return {"energy_status": "EXACT", "energy_wh": 0.0}, True, "energy: a single point, nothing to fly", None, None
    if not np.isfinite(waypoints).all():
        raise DataError(f"{path}: the mission has a waypoint that is not finite")
    _limits.check_route_endurance(f"{path}: energy at [endurance]", waypoints, mission.endurance.ds_m)
    model = EnergyModel.from_vehicle(mission.vehicle)
    # the vehicle's speed where not carried; a .plan's commanded (horizontal) speed as WPNav flies it along each leg
    judged = judged_leg_speeds(path, waypoints.shape[0] - 1, mission.vehicle.speed, waypoints)
    tail = read_tail(path, waypoints.shape[0] - 1)  # legs the file says are flown tail-first
    dwell, held, station = _file_waits(path, waypoints, mission)
    # ArduSub holds the item against the current (its position controller): the power of that current's speed
    depart = 0.0 if mission.navigation is None or path.suffix.lower() == ".plan" else launched_at(world, waypoints)
    b = mission_budget(world, waypoints, model, judged.speeds, depart, mission.endurance.ds_m, tail, dwell, station)
    water = b.traverse.hold_water
    moved = None if held is None or water.shape[0] != held.size else held * water.mean(axis=1)
    flown = b.traverse.leg_water_m() if b.traverse.ok else None
    rec = {"energy_status": b.status.value, "energy_wh": b.energy_wh, "margin_wh": b.margin_wh,
           "duration_s": b.duration_s, "energy_message": b.message, "leg_speeds_mps": b.speed_water.tolist(),
           "speed_assumed_legs": list(judged.assumed_legs), "speed_assumed_line": judged.line}
    return rec, b.status.ok, f"energy {b.status.value} — {b.message}", moved, flown



def _file_waits(path: Path, waypoints: NDArray[np.float64],
                mission: Mission) -> tuple[NDArray[np.float64] | None, NDArray[np.float64] | None,
                                           NDArray[np.bool_] | None]:
    """Each waypoint's wait: the file's own (a .plan's holds, a MOOS station keep) or, under ``[navigation]``, a
    surface fix's ``surface_s`` (issue 52: adrift at hotel power); the holds away from the surface fixes and where
    they are held on station (the last item's too: the budget flies it before the end), None without one."""
    nav = mission.navigation
    surface = np.array([k == "gps" for k in surface_kinds(waypoints)]) if nav is not None \
        else np.zeros(waypoints.shape[0], dtype=bool)
    waits = read_dwells(path, waypoints.shape[0])
    dwell: NDArray[np.float64] | None = None if nav is None else np.where(surface, nav.surface_s, 0.0)
    if waits is not None:
        dwell = waits
    held = None if waits is None or not np.any(waits * ~surface) else np.where(surface, 0.0, waits)
    return dwell, held, None if held is None else held > 0

def launched_at(world: World, waypoints: NDArray[np.float64]) -> float:
    """When a mission that starts at its first waypoint reaches it (s after the start time): launched at the surface
    above it, after the dive at :data:`~auvplan.nav.budget.LAUNCH_DIVE_MPS` held over the point — the flight the
    navigation budget counts (:func:`auvplan.sim.navigation.launch_flight`), whose legs fly the current of that time.

    Parameters
    ----------
    world : World
        Its currents.
    waypoints : numpy.ndarray
        ``(N, 3)`` the mission (m).

    Returns
    -------
    float
        The dive's duration (s); 0 for a first waypoint at the surface or a dive the current beats.
    """
    if not waypoints[0, 2] < -1e-9:
        return 0.0
    tr = traverse(world, np.vstack([launch_point(waypoints), waypoints[:1]]), LAUNCH_DIVE_MPS)
    return float(tr.times[-1] - tr.times[0]) if tr.ok else 0.0


def sweep_energy(world: World, mission: Mission, plans: list[Any],
                 departs: NDArray[np.float64]) -> list[dict[str, float]]:
    """Energy, margin and point of no return (with its lat/lon) of every departure of a sweep.

    Parameters
    ----------
    world : World
        Currents, seabed, obstacles and origin.
    mission : Mission
        Vehicle and ``[endurance]`` settings.
    plans : list
        Each departure's ``(points, speed, tail)`` or None (``departure_sweep(..., paths=plans)``).
    departs : numpy.ndarray
        The departures (s after the start time).

    Returns
    -------
    list of dict
        :func:`auvplan.endurance.departure_endurance`'s rows, with ``pnr_lat`` and ``pnr_lon``.
    """
    rows = departure_endurance(world, plans, departs, mission.vehicle, mission.endurance)
    if world.origin is not None:
        inverse = LocalFrame(*world.origin).inverse
        for r in rows:
            lon, lat = inverse(np.array([r["pnr_x"]]), np.array([r["pnr_y"]]))
            r["pnr_lat"], r["pnr_lon"] = float(np.ravel(lat)[0]), float(np.ravel(lon)[0])
    return rows
