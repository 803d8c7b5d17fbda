"""Mission exports of a run: GeoJSON (RFC 7946), KML, CSV, MOOS-IvP, QGroundControl ``.plan``, GPX 1.1,
ROS 2 ``nav_msgs/Path`` (the writers and readers are in :mod:`auvplan.io.missions.formats`; the results files
themselves in :mod:`auvplan.io.results.records`)."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Iterator
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...errors import DataError
from ...path import arc_length
from ...sim import Mission, RunRecord, decimate, record_tail
from ...world import World
from ..data.geo import LocalFrame
from ..files.manifest import disown
from ..results.records import JsonDict, jsonable, summary_metrics, write_text
from . import antimeridian
from . import deploy_formats as dfmt
from . import formats as mfmt
from .deploy import DeployInfo, deploy_info
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

def _frame(origin: tuple[float, float] | None) -> LocalFrame:
    if origin is None:
        raise DataError("this scenario has no [origin] lat/lon, so it cannot be exported in geographic "
                        "coordinates (GeoJSON, KML); add an [origin] table or use --format csv/moos")
    return LocalFrame(*origin)


def _track(record: RunRecord, full: bool = False) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The flown track (decimated unless ``full``; or the plan when there is no flight) and its times (s)."""
    if record.sim is not None and record.sim.t.size:
        sim = record.sim if full else decimate(record.sim)
        return sim.position, sim.t
    path = record.plan.path if record.plan is not None else record.route
    if record.plan is not None and record.plan.times is not None and len(record.plan.times) == len(path):
        return path, record.plan.times
    s = arc_length(path)
    dur = record.plan.cost_terms.get("duration_s", np.nan) if record.plan is not None else np.nan
    return path, s / s[-1] * dur if s[-1] > 0 and np.isfinite(dur) else np.full(len(path), np.nan)


def mission_waypoints(record: RunRecord) -> NDArray[np.float64]:
    """Return the executable mission of a run: the route it flew (the plan's path without one).

    Parameters
    ----------
    record : RunRecord
        The run: plan, route, key waypoints and flight.

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m).
    """
    if record.route.size:
        return record.route
    if record.plan is not None and record.plan.path.size:
        return record.plan.path
    raise DataError("this run has neither a route nor a planned path to export")


def to_geojson(record: RunRecord, origin: tuple[float, float] | None, full: bool = False,
               deploy: DeployInfo | None = None) -> JsonDict:
    """Make an RFC 7946 FeatureCollection of a run.

    The flown track (decimated unless ``full``), the planned path, the key waypoints and the
    executable mission (``name = "mission"``) as LineStrings / MultiPoint with ``[lon, lat, z]``
    (z the elevation: negative below the surface).

    Parameters
    ----------
    record : RunRecord
        The run: plan, route, key waypoints and flight.
    origin : tuple of float or None
        ``(lat, lon)`` of the local frame (degrees); geographic formats need it.
    full : bool, optional
        Every recorded sample instead of the decimated track (:func:`auvplan.sim.decimate`).
    deploy : DeployInfo, optional
        The envelope (``envelope`` and ``exclusion`` polygon features), datum, payload and altitudes (the
        mission feature's properties; :mod:`auvplan.io.missions.deploy_formats`).

    Returns
    -------
    dict
        The GeoJSON document.
    """
    frame = _frame(origin)
    track, _ = _track(record, full)
    props = {"name": "track" if record.sim is not None else "plan", **jsonable(summary_metrics(record))}
    feats = [{"type": "Feature", "geometry": _geojson_line(frame, track), "properties": props}]
    if record.plan is not None and record.plan.path.shape[0] >= 2 and record.sim is not None:
        feats.append({"type": "Feature", "geometry": _geojson_line(frame, record.plan.path),
                      "properties": {"name": "global plan", "planner": record.plan.planner}})
    if record.keys.size:
        keys = {"type": "MultiPoint", "coordinates": _coords(frame, record.keys)}
        feats.append({"type": "Feature", "geometry": keys, "properties": {"name": "key waypoints"}})
    mission = _geojson_line(frame, mission_waypoints(record))
    mp: JsonDict = {"name": "mission", "depth_semantics": "linear along each leg"}
    tail = record_tail(record)
    if tail is not None and any_tail(tail):
        mp["tail_first_legs"] = [int(i) for i in np.flatnonzero(tail)]  # (auvplan.io.missions.tail)
    mp.update(dfmt.mission_props(deploy))
    feats.append({"type": "Feature", "geometry": mission, "properties": mp})
    for kind, rings in _envelope_pieces(deploy, frame):
        parts = [[[[round(float(a), 9), round(float(b), 9)] for a, b in r]] for r in rings]  # [lon, lat]
        geometry = ({"type": "Polygon", "coordinates": parts[0]} if len(parts) == 1
                    else {"type": "MultiPolygon", "coordinates": parts})
        props = dfmt.envelope_props(deploy.envelope) if kind == "envelope" else {"name": kind}  # type: ignore[union-attr, arg-type]
        feats.append({"type": "Feature", "geometry": geometry, "properties": props})
    return {"type": "FeatureCollection", "features": feats}


def _coords(frame: LocalFrame, p: NDArray[np.float64]) -> list[list[float]]:
    """GeoJSON positions of local points ``(N, 3)`` (:func:`_lon_lat_z`)."""
    lon, lat = frame.inverse(p[:, 0], p[:, 1])
    return [_lon_lat_z(a, b, z) for a, b, z in zip(lon, lat, p[:, 2])]


def _geojson_line(frame: LocalFrame, p: NDArray[np.float64]) -> JsonDict:
    """A LineString, or a MultiLineString cut at the antimeridian (RFC 7946 §3.1.9; :mod:`.antimeridian`)."""
    c = _coords(frame, p)
    pieces = antimeridian.cut_line(c)
    if len(pieces) == 1:
        return {"type": "LineString", "coordinates": c}
    return {"type": "MultiLineString", "coordinates": [[_lon_lat_z(*c) for c in q] for q in pieces]}


def _envelope_pieces(deploy: DeployInfo | None,
                     frame: LocalFrame) -> Iterator[tuple[str, list[NDArray[np.float64]]]]:
    """Each ring of the envelope and its exclusions (:func:`~.deploy_formats.envelope_rings`) as closed rings
    ``[lon, lat]``, cut at the antimeridian (:func:`~.antimeridian.cut_ring`: one ring when it does not cross)."""
    for kind, ring in dfmt.envelope_rings(deploy, frame):
        yield kind, [np.vstack([r, r[:1]]) for r in antimeridian.cut_ring(ring[:, 1], ring[:, 0])]


def _lon_lat_z(lon: float, lat: float, z: float) -> list[float]:
    """A GeoJSON position: 1e-9 degree, 1 mm, never -0.0 (a surface point is at 0.0)."""
    return [round(float(lon), 9), round(float(lat), 9), round(float(z), 3) + 0.0]


def to_kml(record: RunRecord, origin: tuple[float, float] | None, full: bool = False,
           deploy: DeployInfo | None = None) -> str:
    """Make a KML document of a run.

    The track (decimated unless ``full``), the plan and the executable mission (placemark
    ``mission``) as LineStrings with absolute altitude (m, negative below sea level) and the key
    waypoints as placemarks.

    Parameters
    ----------
    record : RunRecord
        The run: plan, route, key waypoints and flight.
    origin : tuple of float or None
        ``(lat, lon)`` of the local frame (degrees); geographic formats need it.
    full : bool, optional
        Every recorded sample instead of the decimated track (:func:`auvplan.sim.decimate`).
    deploy : DeployInfo, optional
        The envelope (placemarks ``envelope`` and ``exclusion`` with a Polygon and ``ExtendedData``), datum,
        payload and altitudes (the mission placemark's ``ExtendedData``).

    Returns
    -------
    str
        The KML XML text.
    """
    frame = _frame(origin)
    ns = "http://www.opengis.net/kml/2.2"
    ET.register_namespace("", ns)
    root = ET.Element(f"{{{ns}}}kml")
    doc = ET.SubElement(root, f"{{{ns}}}Document")
    ET.SubElement(doc, f"{{{ns}}}name").text = f"auvplan {record.scenario} seed {record.seed}"
    track, _ = _track(record, full)
    _kml_line(doc, ns, frame, "track" if record.sim is not None else "plan", track)
    if record.plan is not None and record.sim is not None and record.plan.path.shape[0] >= 2:
        _kml_line(doc, ns, frame, "global plan", record.plan.path)
    _kml_line(doc, ns, frame, "mission", mission_waypoints(record))
    tail = record_tail(record)
    extra = {k: _kml_value(v) for k, v in dfmt.mission_props(deploy).items()}
    if tail is not None and any_tail(tail):  # (auvplan.io.missions.tail)
        extra["tail_first_legs"] = " ".join(str(int(i)) for i in np.flatnonzero(tail))
    if extra:
        _extended(doc.findall(f"{{{ns}}}Placemark")[-1], extra, ns)
    for kind, rings in _envelope_pieces(deploy, frame):
        pm = ET.SubElement(doc, f"{{{ns}}}Placemark")
        ET.SubElement(pm, f"{{{ns}}}name").text = kind
        if kind == "envelope":
            _extended(pm, {k: str(v) for k, v in dfmt.envelope_props(deploy.envelope).items()  # type: ignore[union-attr, arg-type]
                           if k != "name"}, ns)
        _kml_polygons(pm, ns, rings)
    for i, k in enumerate(record.keys):
        pm = ET.SubElement(doc, f"{{{ns}}}Placemark")
        ET.SubElement(pm, f"{{{ns}}}name").text = f"key {i}"
        pt = ET.SubElement(pm, f"{{{ns}}}Point")
        ET.SubElement(pt, f"{{{ns}}}altitudeMode").text = "absolute"
        ET.SubElement(pt, f"{{{ns}}}coordinates").text = _kml_text(_kml_rounded(frame, k[None]))
    return ET.tostring(root, encoding="unicode", xml_declaration=True)


def _kml_rounded(frame: LocalFrame, p: NDArray[np.float64]) -> NDArray[np.float64]:
    """``[lon, lat, z]`` of local points ``(N, 3)``: 1e-9 degree, 1 mm, never -0.000."""
    lon, lat = frame.inverse(p[:, 0], p[:, 1])
    return np.column_stack([np.round(lon, 9), np.round(lat, 9), np.round(p[:, 2], 3) + 0.0])  # no -0.000


def _kml_text(c: NDArray[np.float64]) -> str:
    """KML ``coordinates`` text of ``[lon, lat, z]`` rows."""
    return " ".join(f"{a:.9f},{b:.9f},{z:.3f}" for a, b, z in c)


def _kml_line(doc: ET.Element, ns: str, frame: LocalFrame, name: str, p: NDArray[np.float64]) -> None:
    """A placemark ``name``: a LineString, or a MultiGeometry of LineStrings cut at the antimeridian
    (:mod:`.antimeridian`)."""
    pm = ET.SubElement(doc, f"{{{ns}}}Placemark")
    ET.SubElement(pm, f"{{{ns}}}name").text = name
    pieces = antimeridian.cut_line(_kml_rounded(frame, p))
    parent = pm if len(pieces) == 1 else ET.SubElement(pm, f"{{{ns}}}MultiGeometry")
    for q in pieces:
        ls = ET.SubElement(parent, f"{{{ns}}}LineString")
        ET.SubElement(ls, f"{{{ns}}}altitudeMode").text = "absolute"
        ET.SubElement(ls, f"{{{ns}}}coordinates").text = _kml_text(q)


def _kml_polygons(pm: ET.Element, ns: str, rings: list[NDArray[np.float64]]) -> None:
    """A placemark's Polygon of one closed ring ``[lon, lat]``, or a MultiGeometry of those cut at the antimeridian
    (:func:`_envelope_pieces`)."""
    parent = pm if len(rings) == 1 else ET.SubElement(pm, f"{{{ns}}}MultiGeometry")
    for r in rings:
        outer = ET.SubElement(ET.SubElement(ET.SubElement(parent, f"{{{ns}}}Polygon"),
                                            f"{{{ns}}}outerBoundaryIs"), f"{{{ns}}}LinearRing")
        ET.SubElement(outer, f"{{{ns}}}coordinates").text = " ".join(f"{a:.9f},{b:.9f}" for a, b in r)


def _kml_value(v: object) -> str:
    """A mission property as KML ``Data`` text: lists space-separated, events as ``waypoint:on|off``."""
    if isinstance(v, dict):
        return " ".join(f"{k}={v[k]}" for k in v)
    if isinstance(v, list):
        return " ".join(f"{e['waypoint']}:{e['sensor']}" if isinstance(e, dict) else str(e) for e in v)
    return str(v)


def _extended(pm: ET.Element, data: dict[str, str], ns: str) -> None:
    """``ExtendedData`` of a placemark: one ``Data`` per key."""
    ext = ET.SubElement(pm, f"{{{ns}}}ExtendedData")
    for k, v in data.items():
        ET.SubElement(ET.SubElement(ext, f"{{{ns}}}Data", name=k), f"{{{ns}}}value").text = v


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
