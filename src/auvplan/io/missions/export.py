"""Mission exports of a run: GeoJSON (RFC 7946), KML, CSV, MOOS-IvP, QGroundControl ``.plan``, GPX 1.1,
ROS 2 ``nav_msgs/Path`` (the writers and readers are in :mod:`auvplan.io.missions.formats`, the map layers GeoJSON
and KML in :mod:`auvplan.io.missions.geo_exports`; the results files in :mod:`auvplan.io.results.records`)."""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...errors import DataError
from ...sim import Mission, RunRecord, record_tail
from ...world import World
from ..files.manifest import disown
from ..results.records import write_text
from . import formats as mfmt
from .deploy import DeployInfo, deploy_info
from .geo_exports import _frame, _track, mission_waypoints, to_geojson, to_kml
from .readback.mission_storage import BoardStorage, board_refusal
from .tail import TAIL_FORMATS, any_tail, refusal

__all__ = [
    "EXPORT_FORMATS",
    "GEOGRAPHIC",
    "to_geojson",
    "to_kml",
    "mission_waypoints",
    "exportable",
    "write_exports",
    "write_mission_files",
    "deploy_for",
    "survey_payload",
]

EXPORT_FORMATS = ("geojson", "kml", "csv", "moos", "plan", "gpx", "yaml")
"""Mission export formats of :func:`write_exports` (file suffixes: ``mission.<format>``)."""
GEOGRAPHIC = ("geojson", "kml", "plan", "gpx")
"""Formats that need the scenario's ``[origin]``."""

def deploy_for(world: World, mission: Mission, record: RunRecord, speed: float | ArrayLike,
               payload: ArrayLike | None = None) -> DeployInfo:
    """The datum, envelope, payload and altitudes the exports of a run carry
    (:func:`auvplan.io.missions.deploy.deploy_info`).

    Parameters
    ----------
    world : World
        Bounds, seabed, land, margins and origin.
    mission : Mission
        The vehicle's depth rating and ``follow_altitude_m``.
    record : RunRecord
        The run (its mission, its surface fixes' waits, its tail-first legs and the flight's duration: the time-out
        rests on the longer of that flight and :func:`~auvplan.io.missions.deploy.predicted_duration`).
    speed : float or array_like
        Planned speed, or one per leg (m/s).
    payload : array_like of bool, optional
        ``(N - 1,)`` sensor state per leg of a survey (:func:`auvplan.io.missions.deploy.payload_from_labels`).

    Returns
    -------
    DeployInfo
        What the exports carry.
    """
    flown = float(record.sim.t[-1]) if record.sim is not None and record.sim.t.size else None
    waypoints = mission_waypoints(record)
    nav = record.nav  # the waits at the surface fixes: flown time, as the exports hold them (write_exports)
    dwell = nav.dwell_s if nav is not None and len(nav.points) == len(waypoints) else None
    tail = record_tail(record) if record.route.size else None
    return deploy_info(world, mission, waypoints, speed, flown, payload, dwell, tail)


def survey_payload(out_dir: Path, record: RunRecord) -> NDArray[np.bool_] | None:
    """The sensor state per leg of a survey's results folder: a leg whose two ends are consecutive waypoints
    of one line of ``lines.csv`` (within 1 mm) is on; None without ``lines.csv``.

    Parameters
    ----------
    out_dir : pathlib.Path
        The results folder of ``auvplan survey``.
    record : RunRecord
        Its run (the route).

    Returns
    -------
    numpy.ndarray of bool or None
        ``(N - 1,)`` per leg.
    """
    path = Path(out_dir) / "lines.csv"
    w = mission_waypoints(record) if (record.route.size or record.plan is not None) else np.empty((0, 3))
    if not path.is_file() or len(w) < 2:
        return None
    rows = np.atleast_1d(np.genfromtxt(path, delimiter=",", names=True))
    pairs: set[tuple[tuple[float, ...], tuple[float, ...]]] = set()
    for k in np.unique(rows["line"]):
        p = np.column_stack([rows["x"], rows["y"]])[rows["line"] == k]
        pairs.update(zip(map(tuple, np.round(p[:-1], 3)), map(tuple, np.round(p[1:], 3))))
    r = np.round(w[:, :2], 3)
    return np.array([(tuple(a), tuple(b)) in pairs for a, b in zip(r[:-1], r[1:])], dtype=bool)


def exportable(record: RunRecord, formats: Iterable[str]) -> tuple[list[str], list[str]]:
    """The formats a run's mission can be written in, and why the others cannot.

    Parameters
    ----------
    record : RunRecord
        The run (its tail-first legs: :func:`auvplan.sim.record_tail`).
    formats : iterable of str
        Format names (``EXPORT_FORMATS``).

    Returns
    -------
    kept : list of str
        The formats that carry the mission as it is flown.
    notes : list of str
        One line per format left out (:func:`auvplan.io.missions.tail.refusal`).
    """
    tail = record_tail(record)
    fmts = list(formats)
    if not any_tail(tail):
        return fmts, []
    assert tail is not None
    return [f for f in fmts if f in TAIL_FORMATS], [refusal(f, tail) for f in fmts if f not in TAIL_FORMATS]


def write_exports(out_dir: Path, record: RunRecord, origin: tuple[float, float] | None, speed: float | ArrayLike,
                  formats: Iterable[str] = EXPORT_FORMATS, full: bool = False,
                  deploy: DeployInfo | None = None, board: BoardStorage | None = None) -> list[Path]:
    """Write the chosen mission exports into ``out_dir`` (``mission.<suffix>``, see
    :mod:`auvplan.io.missions.formats`): each carries the run's executable mission; GeoJSON, KML and GPX
    also the flown track, decimated (:func:`auvplan.sim.decimate`) unless ``full``.

    Parameters
    ----------
    out_dir : pathlib.Path
        Results folder.
    record : RunRecord
        The run: plan, route, key waypoints and flight.
    origin : tuple of float or None
        ``(lat, lon)`` of the local frame (degrees); geographic formats need it.
    speed : float or array_like
        Planned speed (m/s), for the formats' arrival times; or one per leg of the mission (MOOS, QGC
        and CSV then carry the speed of each leg).
    formats : iterable of str, optional
        Format names (``EXPORT_FORMATS``).
    full : bool, optional
        Every recorded sample instead of the decimated track (:func:`auvplan.sim.decimate`).
    deploy : DeployInfo, optional
        Datum, safety envelope, payload events and terrain-following altitudes (:func:`deploy_for`); without
        it the files carry the datum only.
    board : BoardStorage, optional
        The operator's board (``--board-storage``): a ``.plan`` it cannot hold is refused
        (:func:`~auvplan.io.missions.readback.mission_storage.board_refusal`); without it, only one no board holds.

    Returns
    -------
    list of pathlib.Path
        The files written.

    Raises
    ------
    DataError
        For an unknown format, a geographic one without an origin, one that cannot carry the mission's
        tail-first legs (:func:`exportable`), a mission with USBL fixes and no ``fixes.csv`` beside it, or a
        ``.plan`` over the mission storage (``board``'s, else any board's), before its file is written.
    """
    out = Path(out_dir)
    written = []
    waypoints = mission_waypoints(record)
    tail = record_tail(record) if record.route.size else None
    deploy = deploy if deploy is not None else DeployInfo(origin)
    dwell, times = _fix_stops(out, record, waypoints)
    if times is None and deploy.times_s is not None and len(deploy.times_s) == len(waypoints):
        times = deploy.times_s  # without fixes: the flight through the current all the same (deploy.flown_times)
    for fmt in formats:
        _check_format(fmt, tail, origin)
        text = _export_text(fmt, record, waypoints, origin, speed, full, deploy, tail, dwell, times)
        if fmt == "plan" and board is not None:
            _fits_board(out / "mission.plan", text, board)
        written.append(write_text(out / f"mission.{fmt}", text))
    return written


def _fix_stops(out: Path, record: RunRecord,
               waypoints: NDArray[np.float64]) -> tuple[NDArray[np.float64] | None, NDArray[np.float64] | None]:
    """Each waypoint's wait (a surface fix's ``surface_s``: held in .plan and .moos, in the times of .csv and .yaml)
    and the times as the mission is flown through the current (fixes.csv's), when the navigation plan is the
    mission's; refused when the mission has USBL fixes and the folder no ``fixes.csv`` (no format holds one)."""
    nav = record.nav
    dwell = nav.dwell_s if nav is not None and len(nav.points) == len(waypoints) else None
    times = nav.vertex_times_s if dwell is not None and nav is not None and nav.vertex_times_s is not None else None
    if nav is not None and "usbl" in nav.kinds and not (out / "fixes.csv").exists():
        raise DataError(f"{out}: the mission's USBL fixes are kept only in fixes.csv, which the folder lacks (a plan "
                        "without a flight): `auvplan run` the scenario to export them")
    return dwell, times


def _fits_board(path: Path, text: str, board: BoardStorage) -> None:
    """Refuse a ``.plan`` (its ``text``) that the operator's board cannot hold: not written (the home is command 0)."""
    commands = len(json.loads(text)["mission"]["items"]) + 1
    why = board_refusal(path, commands, board)
    if why:
        raise DataError(why)


def _check_format(fmt: str, tail: NDArray[np.bool_] | None, origin: tuple[float, float] | None) -> None:
    """Refuse an unknown format, one that cannot carry the tail-first legs, or a geographic one without an origin."""
    if fmt not in EXPORT_FORMATS:
        raise DataError(f"unknown export format {fmt!r}; choose from {', '.join(EXPORT_FORMATS)}")
    if any_tail(tail) and fmt not in TAIL_FORMATS:
        assert tail is not None
        raise DataError(refusal(fmt, tail))
    if fmt in GEOGRAPHIC:
        _frame(origin)


def _export_text(fmt: str, record: RunRecord, waypoints: NDArray[np.float64], origin: tuple[float, float] | None,
                 speed: float | ArrayLike, full: bool, deploy: DeployInfo, tail: NDArray[np.bool_] | None,
                 dwell: NDArray[np.float64] | None, times: NDArray[np.float64] | None) -> str:
    """The text of the mission in the format ``fmt`` (checked by :func:`_check_format`)."""
    nav = record.nav
    if fmt == "geojson":
        return json.dumps(to_geojson(record, origin, full, deploy)) + "\n"
    if fmt == "kml":
        return to_kml(record, origin, full, deploy)
    if fmt == "csv":
        return mfmt.mission_csv(waypoints, origin, speed, tail, deploy, nav.check.budget.error_m
                                if nav is not None and len(nav.points) == len(waypoints) else None, dwell, times)
    if fmt == "moos":
        return mfmt.to_moos(waypoints, speed, deploy=deploy, dwell=dwell)
    if fmt == "plan":
        assert origin is not None  # _frame(origin) raised otherwise
        return json.dumps(mfmt.to_qgc_plan(waypoints, origin, speed, deploy=deploy, dwell=dwell), indent=1) + "\n"
    if fmt == "gpx":
        assert origin is not None  # _frame(origin) raised otherwise
        return mfmt.to_gpx(waypoints, origin, _track(record, full)[0] if record.sim is not None else None)
    return mfmt.to_ros_path(waypoints, speed, tail=tail, deploy=deploy, dwell=dwell, times=times)


def write_mission_files(out_dir: Path, record: RunRecord, origin: tuple[float, float] | None,
                        speed: float | ArrayLike, formats: Iterable[str], full: bool = False,
                        deploy: DeployInfo | None = None, board: BoardStorage | None = None) -> list[str]:
    """Every export of a results folder, as ``run``, ``report`` and ``survey`` write them.

    ``formats`` (those the mission can be written in, :func:`exportable`) through :func:`write_exports`, the
    ``.plan`` last and left out, with a note, when ArduPilot or the operator's board cannot hold it or its fence
    crosses ±180°.  Then every ``mission.<suffix>`` auvplan wrote into the folder before and did not write now is
    removed (:func:`auvplan.io.files.manifest.disown`; a note says so): an earlier run's file of another mission,
    or of one with an ``[origin]`` where this one has none, is never left beside this mission's files to be
    uploaded in its place.  A user's file is left alone.

    Parameters
    ----------
    out_dir : pathlib.Path
        The results folder.
    record : RunRecord
        The run.
    origin : tuple of float or None
        ``(lat, lon)`` of the local frame (None: no geographic format).
    speed : float or array_like
        Planned speed, or one per leg (m/s).
    formats : iterable of str
        The formats to write (``EXPORT_FORMATS`` names).
    full : bool, optional
        Write the flown track undecimated.
    deploy : DeployInfo, optional
        Datum, envelope, payload and altitudes.
    board : BoardStorage, optional
        The operator's board (``--board-storage``).

    Returns
    -------
    list of str
        The notes: the ``.plan`` left out and why, the earlier files removed.
    """
    fmts, notes = list(formats), []
    done = write_exports(out_dir, record, origin, speed, [f for f in fmts if f != "plan"], full, deploy)
    if "plan" in fmts:
        try:
            done += write_exports(out_dir, record, origin, speed, ["plan"], full, deploy, board)
        except DataError as exc:  # ArduPilot (or the --board-storage named) cannot hold it, a fence across ±180°
            notes.append(f"mission.plan left out: {exc}")
    now = {p.name for p in done}
    stale = disown(Path(out_dir), [f"mission.{f}" for f in EXPORT_FORMATS if f"mission.{f}" not in now])
    if stale:
        notes.append(f"{', '.join(stale)} of an earlier run removed from {out_dir} (not written for this mission)")
    return notes
