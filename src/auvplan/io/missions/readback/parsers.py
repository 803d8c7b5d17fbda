"""The parsers of every mission format :mod:`auvplan.io.missions.formats` writes, back to local waypoints: MOOS-IvP,
QGroundControl / ArduSub (``.plan``), GPX 1.1, ROS 2 ``nav_msgs/Path``, GeoJSON, KML and CSV.

:func:`auvplan.io.missions.readback.readers.read_mission` picks one by the file's suffix.
"""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ....errors import DataError
from ...data.geo import LocalFrame
from ..antimeridian import join_line
from .qgc_items import PlanItem, plan_items

__all__ = [
    "csv_columns",
    "GPX_NS",
    "KML_NS",
    "parse_moos",
    "parse_qgc_plan",
    "parse_gpx",
    "parse_ros_path",
    "ZERO_ALT_M",
    "ZERO_LATLON_DEG",
]

ZERO_ALT_M = 0.01
"""ArduSub stores an item's altitude in whole centimetres and reads 0 as "keep the current altitude"
(``do_nav_wp``, ``do_loiter_unlimited``): an altitude under a centimetre is not the point the file gives."""


ZERO_LATLON_DEG = 1e-7
"""ArduSub stores an item's position in 1e-7 degrees and reads latitude and longitude both 0 as "the current
position" (``do_nav_wp``, ``do_loiter_unlimited``): an item within this of (0°, 0°) is not the point the file gives."""


# the XML namespaces of GPX 1.1 and KML 2.2
GPX_NS = "http://www.topografix.com/GPX/1/1"


KML_NS = "http://www.opengis.net/kml/2.2"


# ---------------------------------------------------------------------- MOOS-IvP
def _moos_blocks(text: str) -> list[tuple[str, list[tuple[str, str]]]]:
    """``(behaviour type, [(key, value), ...])`` of every ``Behavior = X { ... }`` block."""
    text = re.sub(r"//[^\n]*", "", text)
    out = []
    pos = 0
    # linear: each header is found once and its body ends at the next '}' (blocks do not nest); a header
    # without a closing brace ends the scan, as no later header can have one either (one regex
    # ``Behavior ... \{[^}]*\}`` rescanned to the end of the text from every unclosed header: quadratic)
    while (m := _MOOS_HEADER.search(text, pos)) is not None:
        end = text.find("}", m.end())
        if end < 0:
            break
        pairs = []
        for line in text[m.end():end].splitlines():
            if "=" in line:
                k, v = line.split("=", 1)
                pairs.append((k.strip().lower(), v.strip()))
        out.append((m.group(1), pairs))
        pos = end + 1
    return out


_MOOS_HEADER = re.compile(r"Behavior[ \t\r\n\f\v]*=[ \t\r\n\f\v]*(\w+)[ \t\r\n\f\v]*\{")
"""``Behavior = TYPE {`` of a MOOS-IvP behaviour file."""


def parse_moos(text: str) -> NDArray[np.float64]:
    """Read the waypoints of a file written by :func:`to_moos`.

    Parameters
    ----------
    text : str
        The ``.bhv`` text.

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` x, y, z (m): the start (from its ``// start:`` line, when present) and every
        point with the depth its leg holds.
    """
    blocks = _moos_blocks(text)
    wpt = [dict(p) for t, p in blocks if t == "BHV_Waypoint"]
    if not wpt or "points" not in wpt[0]:
        raise DataError("no BHV_Waypoint block with 'points =' in the MOOS file")
    try:
        xy = np.array([[float(v) for v in pair.split(",")[:2]] for pair in wpt[0]["points"].split(":")])
    except ValueError as exc:
        raise DataError(f"MOOS points = {wpt[0]['points'][:60]!r}: not x,y pairs") from exc
    depth = {}
    for t, pairs in blocks:
        if t != "BHV_ConstantDepth":
            continue
        d = dict(pairs)
        found = [re.fullmatch(r"WPT_INDEX\s*==?\s*(\d+)", v) for k, v in pairs if k == "condition"]
        idx = [int(m.group(1)) for m in found if m]
        if idx and "depth" in d:
            depth[idx[0]] = float(d["depth"])
    missing = [i for i in range(len(xy)) if i not in depth]
    if missing:
        raise DataError(f"MOOS file: no BHV_ConstantDepth with condition WPT_INDEX = {missing[0]}")
    w = np.column_stack([xy, [-depth[i] for i in range(len(xy))]])
    m = re.search(r"//\s*start:\s*([-\d.eE+]+),\s*([-\d.eE+]+),\s*([-\d.eE+]+)", text)
    if m:
        w = np.vstack([[float(m.group(1)), float(m.group(2)), -float(m.group(3))], w])
    return w


# ---------------------------------------------------------------------- QGroundControl / ArduSub
def parse_qgc_plan(doc: dict[str, Any], frame: LocalFrame,
                   seabed: Callable[[Any, Any], Any] | None = None) -> NDArray[np.float64]:
    """Read the local waypoints of a QGC plan.

    Parameters
    ----------
    doc : dict
        The parsed ``.plan`` JSON.
    frame : LocalFrame
        The local frame.
    seabed : callable, optional
        ``seabed(x, y)`` elevation (m): items in ``MAV_FRAME_GLOBAL_TERRAIN_ALT`` (10, terrain following,
        issue 51) are placed at the seabed plus their altitude.

    Returns
    -------
    numpy.ndarray
        ``(N + 1, 3)`` (m): home (on the surface) then every position the vehicle goes to, in order
        (:func:`auvplan.io.missions.readback.qgc_items.plan_items`: waypoints, loiters without a radius, a survey's or
        corridor scan's generated waypoints; relative-altitude and terrain frames).

    Raises
    ------
    DataError
        Naming the item (``mission.items[i]``) that moves the vehicle in a way the check cannot follow
        (``DO_JUMP``, return to launch, land, a spline, an unknown command or pattern), or a bad frame.
    """
    items = [it for it in plan_items(doc) if it.moves]  # the shared walk: refuses what it cannot follow
    try:
        home = doc["mission"]["plannedHomePosition"]
        try:
            rows = [(float(home[0]), float(home[1]), 0.0)]
        except (TypeError, ValueError) as exc:
            raise DataError(f"QGC plan: mission.plannedHomePosition = {home!r}: [latitude, longitude, altitude] "
                            "must be numbers") from exc
        terrain: list[bool] = []
        for it in items:
            if it.frame not in (3, 6, 10) or (it.frame == 10 and seabed is None):
                raise DataError(f"QGC plan: {it.where}.frame = {it.frame!r}: expected 3 (relative "
                                "alt), or 10 (terrain alt) with a seabed")
            rows.append((_param(it, 4), _param(it, 5), _param(it, 6)))
            terrain.append(it.frame == 10)
    except DataError:
        raise  # names the item already (a DataError is a ValueError: not a "malformed key")
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        raise DataError(f"QGC plan: missing or malformed key ({exc})") from exc
    kept = next((it for it, r in zip(items, rows[1:], strict=True) if abs(r[2]) < ZERO_ALT_M), None)
    if kept is not None:  # stored in whole centimetres: 0 is "keep the current altitude" (do_nav_wp), not the surface
        raise DataError(f"QGC plan: {kept.where}: altitude {float(kept.params[6]):g} m: ArduSub reads an altitude "
                        f"under {ZERO_ALT_M:g} m as 'hold the current altitude' and flies there level, not to it; "
                        f"not checked (write -{ZERO_ALT_M:g} for the surface)")
    wide = next((it for it, r in zip(items, rows[1:], strict=True) if not (abs(r[0]) <= 90.0 and abs(r[1]) <= 180.0)),
                None)
    if wide is not None:  # AP_Mission's check_lat/check_lng refuse the item: the upload fails (MAV_MISSION_INVALID_
        # PARAM5_X/6_Y); read as it wraps (181° as -179°), it was checked at a place the vehicle never receives
        raise DataError(f"QGC plan: {wide.where}: latitude {float(wide.params[4]):g}, longitude "
                        f"{float(wide.params[5]):g}: outside [-90, 90] x [-180, 180], which ArduPilot refuses at "
                        "upload (AP_Mission check_lat/check_lng); not checked")
    null = next((it for it, r in zip(items, rows[1:], strict=True) if max(abs(r[0]), abs(r[1])) < ZERO_LATLON_DEG),
                None)
    if null is not None:  # stored in 1e-7 degrees: (0, 0) is "stay where you are" (do_nav_wp, do_loiter_unlimited)
        raise DataError(f"QGC plan: {null.where}: at latitude {float(null.params[4]):g}, longitude "
                        f"{float(null.params[5]):g}: ArduSub reads (0, 0) as 'the current position' and goes to the "
                        f"item's altitude where it is, not to the point; not checked (move it by {ZERO_LATLON_DEG:g}°)")
    a = np.array(rows)
    x, y = frame.forward(a[:, 1], a[:, 0])
    z = a[:, 2].copy()
    t = np.array([False, *terrain])
    if t.any() and seabed is not None:
        z[t] += np.asarray(seabed(x[t], y[t]), dtype=float)
    return np.column_stack([x, y, z])


def _param(item: PlanItem, k: int) -> float:
    """An item's position parameter, a JSON number: ``true`` was read as latitude 1° (a mission near the equator
    checked and failed), a string as whatever ``float`` made of it, where QGC reads both as 0."""
    v = item.params[k]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise DataError(f"QGC plan: {item.where}.params[{k}] = {json.dumps(v)[:40]}: expected a number "
                        f"({('latitude', 'longitude', 'altitude')[k - 4]})")
    return float(v)


# ---------------------------------------------------------------------- GPX 1.1, KML
def parse_gpx(text: str, frame: LocalFrame) -> NDArray[np.float64]:
    """Read the local waypoints of the first route of a GPX 1.1 document.

    Parameters
    ----------
    text : str
        The GPX XML text.
    frame : LocalFrame
        The local frame.

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m).
    """
    root = _xml(text, "GPX")
    pts = root.findall(f"{{{GPX_NS}}}rte/{{{GPX_NS}}}rtept")
    if not pts:
        raise DataError("GPX: no rte/rtept route points")
    try:
        a = np.array([(float(p.get("lon")), float(p.get("lat")),  # type: ignore[arg-type]
                       float(p.find(f"{{{GPX_NS}}}ele").text)) for p in pts])  # type: ignore[union-attr, arg-type]
    except (TypeError, ValueError, AttributeError) as exc:
        raise DataError(f"GPX: a route point lacks lat, lon or ele ({exc})") from exc
    x, y = frame.forward(a[:, 0], a[:, 1])
    return np.column_stack([x, y, a[:, 2]])


def _xml(text: str, what: str) -> ET.Element:
    try:
        return ET.fromstring(text)
    except ET.ParseError as exc:
        raise DataError(f"{what}: not well-formed XML ({exc})") from exc


# ---------------------------------------------------------------------- ROS 2 nav_msgs/Path
def parse_ros_path(text: str) -> NDArray[np.float64]:
    """Read the waypoints of a ``nav_msgs/Path`` YAML document (PyYAML).

    Parameters
    ----------
    text : str
        The YAML text.

    Returns
    -------
    numpy.ndarray
        ``(N, 3)`` waypoints (m).
    """
    import yaml

    try:
        doc = yaml.safe_load(text)
        return np.array([[float(ps["pose"]["position"][k]) for k in "xyz"] for ps in doc["poses"]])
    except (yaml.YAMLError, KeyError, TypeError, ValueError) as exc:
        raise DataError(f"nav_msgs/Path YAML: missing or malformed poses ({exc})") from exc


# ---------------------------------------------------------------------- GeoJSON, KML
def _lon_lat_alt(c: NDArray[np.float64], frame: LocalFrame, what: str, project: bool = True) -> NDArray[np.float64]:
    """``(N, 3)`` lon, lat, altitude (a line of points) projected to the local frame (as read unless ``project``);
    anything else named."""
    if c.ndim != 2:
        shape = {0: "not a list of points", 1: "one point"}.get(c.ndim, f"nested {c.ndim} deep (a polygon?)")
        raise DataError(f"the {what} coordinates are {shape}; a mission is a line of [lon, lat, altitude] points")
    if c.shape[1] == 2:
        raise DataError(f"the {what} coordinates are lon,lat without an altitude (point 0: "
                        f"{c[0, 0]:.6g},{c[0, 1]:.6g}); a mission needs each waypoint's altitude (negative: depth "
                        "below the surface) as a third value")
    if c.shape[1] != 3:
        raise DataError(f"the {what} coordinates have {c.shape[1]} values per point; expected lon, lat, altitude")
    if not (np.all(np.abs(c[:, 1]) <= 90.0) and np.all(np.abs(c[:, 0]) <= 360.0)):
        bad = int(np.flatnonzero(~((np.abs(c[:, 1]) <= 90.0) & (np.abs(c[:, 0]) <= 360.0)))[0])
        raise DataError(f"the {what} point {bad} = {c[bad].tolist()}: not a lon, lat in degrees")
    if not project:
        return c
    x, y = frame.forward(c[:, 0], c[:, 1])
    return np.column_stack([x, y, c[:, 2]])


def _geojson_mission(doc: dict[str, Any], frame: LocalFrame) -> NDArray[np.float64]:
    features = doc.get("features", []) if isinstance(doc, dict) else None
    if not isinstance(features, list):
        raise DataError("GeoJSON: 'features' is not a list of features")
    for f in features:
        if isinstance(f, dict) and (f.get("properties") or {}).get("name") == "mission":
            geometry = f.get("geometry") or {}
            if not isinstance(geometry, dict) or "coordinates" not in geometry:
                raise DataError("GeoJSON: the feature 'mission' has no geometry coordinates")
            what = f"GeoJSON feature 'mission' ({geometry.get('type', '?')})"
            if geometry.get("type") == "MultiLineString":  # cut at the antimeridian (RFC 7946 §3.1.9): joined
                pieces = geometry["coordinates"]
                if not isinstance(pieces, list) or not pieces:
                    raise DataError(f"the {what} coordinates are not a list of lines")
                c = join_line([_lon_lat_alt(np.asarray(q, dtype=float), frame, what, project=False) for q in pieces])
            else:
                c = np.asarray(geometry["coordinates"], dtype=float)
            return _lon_lat_alt(c, frame, what)
    raise DataError("GeoJSON: no feature with properties.name = 'mission'")


def _kml_mission(text: str, frame: LocalFrame) -> np.ndarray:
    ns = {"k": KML_NS}
    for pm in _xml(text, "KML").iter(f"{{{KML_NS}}}Placemark"):
        if (pm.findtext("k:name", namespaces=ns) or "") == "mission":
            what = "KML Placemark 'mission'"
            # a MultiGeometry of LineStrings: the line cut at the antimeridian (auvplan.io.missions.antimeridian)
            lines = pm.findall("k:LineString/k:coordinates", ns) or pm.findall("k:MultiGeometry/k:LineString/"
                                                                              "k:coordinates", ns)
            if not lines or not all((c.text or "").strip() for c in lines):
                raise DataError("KML: the Placemark 'mission' has no LineString coordinates")
            rows = [[[float(v) for v in s.split(",")] for s in (c.text or "").split()] for c in lines]
            if len({len(r) for q in rows for r in q}) > 1:
                raise DataError("KML: the Placemark 'mission' mixes points with and without an altitude")
            if len(rows) == 1:
                return _lon_lat_alt(np.array(rows[0], dtype=float), frame, what)
            joined = join_line([_lon_lat_alt(np.array(q, dtype=float), frame, what, project=False) for q in rows])
            return _lon_lat_alt(joined, frame, what)
    raise DataError("KML: no Placemark named 'mission'")

def csv_columns(text: str, wanted: tuple[str, ...], empty: float | None = None) -> dict[str, NDArray[np.float64]]:
    """The named numeric columns of a CSV mission's text (the header names them; those absent are left out).

    A spreadsheet's byte-order mark made the first column ``\ufeffx`` ('no field of name x'), and 10⁶ columns
    took numpy's named reader 3 minutes per read: here only the wanted columns are converted.

    Parameters
    ----------
    text : str
        The file's text (universal newlines).
    wanted : tuple of str
        Column names.
    empty : float, optional
        The value of an empty cell (None: an empty cell is not a number).

    Returns
    -------
    dict of str to numpy.ndarray
        One float array per wanted column the header has, a value per data row.

    Raises
    ------
    ValueError
        On a row shorter than a wanted column's place, or a value that is not a number.
    """
    lines = [ln for ln in text.lstrip("\ufeff").split("\n") if ln.strip() and not ln.lstrip().startswith("#")]
    names = [n.strip().strip('"') for n in lines[0].split(",")] if lines else []
    cols = {k: names.index(k) for k in wanted if k in names}
    rows = [ln.split(",") for ln in lines[1:]]
    short = next((i for i, r in enumerate(rows) if len(r) <= max(cols.values(), default=-1)), None)
    if short is not None:
        raise ValueError(f"line {short + 2} has {len(rows[short])} fields; the header has {len(names)}")
    def num(cell: str, line: int, name: str) -> float:
        if empty is not None and not cell.strip():
            return empty
        try:
            return float(cell)
        except ValueError:
            raise ValueError(f"line {line}: {name} = {cell.strip()!r} is not a number") from None

    return {k: np.array([num(r[c], i + 2, k) for i, r in enumerate(rows)], dtype=float) for k, c in cols.items()}


def _csv_mission(text: str) -> NDArray[np.float64]:
    """The ``x, y, z`` waypoints of a CSV mission (:func:`csv_columns`)."""
    cols = csv_columns(text, ("x", "y", "z"))
    missing = next((k for k in ("x", "y", "z") if k not in cols), None)
    if missing is not None:
        raise ValueError(f"no field of name {missing}")
    return np.column_stack([cols["x"], cols["y"], cols["z"]]).reshape(-1, 3)
