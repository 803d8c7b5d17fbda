"""The run's mission and track as map layers: RFC 7946 GeoJSON (:func:`to_geojson`) and KML (:func:`to_kml`), each
line and polygon cut at ±180° (:mod:`auvplan.io.missions.antimeridian`), with the deployment's envelope and
properties (:mod:`auvplan.io.missions.deploy_formats`); the executable mission of a run (:func:`mission_waypoints`)
and its flown track (:func:`_track`), which the other exports share (:mod:`auvplan.io.missions.export`)."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterator

import numpy as np
from numpy.typing import NDArray

from ...errors import DataError
from ...path import arc_length
from ...sim import RunRecord, decimate, record_tail
from ..data.geo import LocalFrame
from ..results.records import JsonDict, jsonable, summary_metrics
from . import antimeridian
from . import deploy_formats as dfmt
from .deploy import DeployInfo
from .tail import any_tail

__all__ = ["mission_waypoints", "to_geojson", "to_kml"]


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
