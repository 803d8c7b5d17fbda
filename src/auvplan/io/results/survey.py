"""Survey files: the ``[survey]`` area read into the local frame (a lat/lon list, or a GeoJSON, KML or
shapefile layer through pyogrio), and the survey's results: ``lines.csv`` (``line, x, y, z, lat, lon`` of
every line's waypoints), ``coverage.json`` (``coverage_pct``, ``overlap_min_pct``, ``overlap_max_pct`` and
the rest) and ``gaps.geojson``."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from pyproj import CRS, Transformer

from ...errors import ScenarioError
from ...survey.mission import DEFAULT_TURN_RADIUS_M, SurveyParams
from ...survey.run import SurveyRun
from ...survey.spec import SurveySpec
from ...world import World
from ..data.geo import LocalFrame
from ..safeio import atomic_write
from .records import write_json

__all__ = ["SURVEY_NAMES", "survey_params", "check_survey_size", "read_area", "write_survey", "coverage_record"]

SURVEY_NAMES = ("lines.csv", "coverage.json", "gaps.geojson", "coverage.png")
"""Files a survey writes into ``--out`` besides the run files and the mission exports."""


def read_area(path: Path, layer: str, where: str) -> tuple[shapely.Polygon, CRS]:
    """The largest polygon of a vector file's layer and the file's CRS (WGS 84 when it has none).

    Parameters
    ----------
    path : pathlib.Path
        GeoJSON, KML, shapefile or any vector format GDAL reads.
    layer : str
        Layer name ('' for the first).
    where : str
        ``file: [survey]`` for messages.

    Returns
    -------
    tuple
        The polygon (in the file's coordinates) and its ``pyproj.CRS``.
    """
    import pyogrio

    if not path.is_file():
        raise ScenarioError(f"{where} file = {str(path)!r}: not found")
    try:
        meta, _, wkb, _ = pyogrio.raw.read(path, layer=layer or None, read_geometry=True, columns=[])
    except Exception as exc:  # GDAL raises several types for unreadable files and missing layers
        raise ScenarioError(f"{where} file = {str(path)!r}: cannot read as a vector file"
                            f"{f' (layer {layer!r})' if layer else ''} ({exc})") from exc
    geoms = [g for g in (shapely.from_wkb(wkb) if wkb is not None else []) if g is not None and not g.is_empty]
    polys = [p for g in geoms for p in shapely.get_parts(g) if isinstance(p, shapely.Polygon)]
    if not polys:
        raise ScenarioError(f"{where} file = {str(path)!r}: no polygon in "
                            f"{f'layer {layer!r}' if layer else 'its first layer'}")
    try:
        crs = CRS.from_user_input(meta.get("crs") or "EPSG:4326")
    except Exception as exc:  # pyproj's CRSError
        raise ScenarioError(f"{where} file = {str(path)!r}: crs {meta.get('crs')!r} is not usable ({exc})") from exc
    return max(polys, key=lambda p: p.area), crs


def _local_area(spec: SurveySpec, origin: tuple[float, float] | None, base_dir: Path | None,
                where: str) -> shapely.Polygon:
    if spec.polygon_xy:
        return shapely.Polygon(spec.polygon_xy)
    if origin is None:
        key = "polygon" if spec.polygon else "file"
        raise ScenarioError(f"{where} {key}: a geographic area needs [origin] lat/lon (or give polygon_xy in m)")
    frame = LocalFrame(*origin)
    if spec.polygon:
        lat, lon = np.array(spec.polygon).T
    else:
        path = Path(spec.file)
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        poly, crs = read_area(path, spec.layer, where)
        xy = np.asarray(poly.exterior.coords)[:, :2]
        lon, lat = Transformer.from_crs(crs, "EPSG:4326", always_xy=True).transform(xy[:, 0], xy[:, 1])
    x, y = frame.forward(np.asarray(lon), np.asarray(lat))
    return shapely.Polygon(np.column_stack([x, y]))


def survey_params(spec: SurveySpec, world: World, vehicle: Any, base_dir: Path | None,
                  where: str) -> SurveyParams:
    """The :class:`~auvplan.survey.mission.SurveyParams` of a scenario's ``[survey]`` in its world.

    Parameters
    ----------
    spec : SurveySpec
        The ``[survey]`` table.
    world : World
        The scenario's world (origin, bounds, terrain cell).
    vehicle : VehicleParams
        The vehicle; its ``turn_radius_m`` when it has one, else :data:`DEFAULT_TURN_RADIUS_M`.
    base_dir : pathlib.Path or None
        Folder that a relative ``file`` resolves against.
    where : str
        ``file: [survey]`` for messages.

    Returns
    -------
    SurveyParams
        The survey in the local frame.
    """
    area = shapely.make_valid(_local_area(spec, world.origin, base_dir, where))
    if not isinstance(area, shapely.Polygon) or area.area <= 0:
        raise ScenarioError(f"{where} polygon: not a simple polygon with an area (self-intersecting?)")
    b = world.bounds
    if not shapely.box(b.xmin, b.ymin, b.xmax, b.ymax).contains(area):
        x0, y0, x1, y1 = area.bounds
        raise ScenarioError(f"{where} polygon: the area x [{x0:.0f}, {x1:.0f}] y [{y0:.0f}, {y1:.0f}] m is not "
                            f"inside the [bounds] x [{b.xmin:.0f}, {b.xmax:.0f}] y [{b.ymin:.0f}, {b.ymax:.0f}]")
    if world.terrain is None:
        raise ScenarioError(f"{where}: a survey needs a seabed ([terrain])")
    radius = getattr(vehicle, "turn_radius_m", None) or DEFAULT_TURN_RADIUS_M
    params = SurveyParams(area, spec.sensor_model(), spec.line_params(min(world.terrain.dx, world.terrain.dy)),
                          spec.heading_deg, float(radius), spec.run_in_m)
    check_survey_size(params, world, where)
    return params


def check_survey_size(params: SurveyParams, world: World, where: str) -> None:
    """The survey's lines, stations and swath samples against the ceilings and the budget, before planning.

    The swath is estimated from the seabed on a 48 × 48 sample of the area (the sensor's reach over a flat
    seabed at each depth); the line count is the area's diagonal over the mean spacing those swaths allow
    at the largest overlap (an upper bound for any heading).

    Parameters
    ----------
    params : SurveyParams
        The survey in the local frame.
    world : World
        Its seabed.
    where : str
        ``file: [survey]`` for messages.
    """
    from .. import limits as _limits

    x0, y0, x1, y1 = params.area.bounds
    gx, gy = np.meshgrid(np.linspace(x0, x1, 48), np.linspace(y0, y1, 48))
    inside = shapely.contains_xy(params.area, gx, gy)
    depth = -world.seabed(gx[inside], gy[inside]) if inside.any() else np.array([])
    depth = depth[np.isfinite(depth) & (depth > 0)]
    sensor, lines = params.sensor, params.lines
    if depth.size == 0:
        raise ScenarioError(f"{where} polygon: no water under the area (the seabed is above the surface there)")
    height = np.full(depth.shape, sensor.altitude_m) if sensor.mounting == "auv" else depth
    reach = np.asarray(sensor.flat_reach(height), dtype=float)
    spacing = 2.0 * reach * (1.0 - lines.overlap_max)
    mean_spacing = 1.0 / float(np.mean(1.0 / np.maximum(spacing, 1e-300)))
    diag = math.hypot(x1 - x0, y1 - y0)
    _limits.check_survey(_limits.current(), where, diag, diag, mean_spacing, lines.station_m, lines.step_m,
                         2.0 * float(reach.max()))


def coverage_record(run: SurveyRun, params: SurveyParams) -> dict[str, Any]:
    """``coverage.json``: the flown coverage (the plan's without a flight), the plan's, the lawnmower's.

    Parameters
    ----------
    run : SurveyRun
        The survey.
    params : SurveyParams
        Its parameters.

    Returns
    -------
    dict
        ``coverage_pct``, ``overlap_min_pct``, ``overlap_max_pct`` (of the flight, else of the plan), then
        the plan's and the flight's per-pair overlaps, lengths, times, turns and the lawnmower comparison.
    """
    plan, planned, flown, mower = run.plan, run.planned, run.flown, run.lawnmower
    main = flown or planned
    n = len(plan.lines.lines)
    return {
        "coverage_pct": main.coverage_pct,
        "overlap_min_pct": main.overlap_min_pct,
        "overlap_max_pct": main.overlap_max_pct,
        "measured_on": "flight" if flown is not None else "plan",
        "status": plan.status.value if run.record.sim is None else run.record.status.value,
        "message": plan.message,
        "overlap_bounds_pct": [100 * params.lines.overlap_min, 100 * params.lines.overlap_max],
        "lines": n,
        "heading_deg": math.degrees(plan.lines.heading) % 360.0,
        "area_m2": planned.area_m2,
        "planned": {"coverage_pct": planned.coverage_pct, "overlap_min_pct": planned.overlap_min_pct,
                    "overlap_max_pct": planned.overlap_max_pct, "pairs": planned.pair_stats(),
                    "gap_area_m2": planned.gap_area_m2},
        "flown": None if flown is None else {
            "coverage_pct": flown.coverage_pct, "overlap_min_pct": flown.overlap_min_pct,
            "overlap_max_pct": flown.overlap_max_pct, "pairs": flown.pair_stats(),
            "gaps": len(flown.gaps), "gap_area_m2": flown.gap_area_m2},
        "survey_length_m": plan.survey_length_m,
        "mission_length_m": plan.length_m,
        "survey_time_s": run.survey_time_s,
        "mission_time_s": float(run.record.sim.t[-1]) if run.record.sim is not None else math.nan,
        "turns": {"radius_m": params.turn_radius_m, "least_radius_m": plan.min_turn_radius_m,
                  "omega": sum(w in ("LRL", "RLR") for w in plan.turn_words), "count": len(plan.turn_words)},
        "max_pitch_deg": plan.max_pitch_deg,
        "lawnmower": {"lines": mower.lines, "spacing_m": mower.spacing_m, "line_length_m": mower.line_length_m,
                      "shallowest_m": mower.shallowest_m, "lines_saved": mower.lines - n,
                      "line_length_saved_m": mower.line_length_m - _line_length(run)},
    }


def _line_length(run: SurveyRun) -> float:
    return float(sum(np.linalg.norm(np.diff(p, axis=0), axis=1).sum() for p in run.plan.line_waypoints()))


def _feature(geom: shapely.Geometry, frame: LocalFrame | None, props: dict[str, Any]) -> dict[str, Any]:
    if frame is not None:
        geom = shapely.transform(geom, lambda xy: np.column_stack(frame.inverse(xy[:, 0], xy[:, 1])))
    return {"type": "Feature", "properties": props, "geometry": shapely.geometry.mapping(geom)}


def write_survey(out: Path, run: SurveyRun, params: SurveyParams, origin: tuple[float, float] | None) -> list[Path]:
    """Write ``lines.csv``, ``coverage.json`` and ``gaps.geojson`` into ``out``.

    Parameters
    ----------
    out : pathlib.Path
        Results folder (checked by :func:`~auvplan.io.safeio.prepare_out`).
    run : SurveyRun
        The survey.
    params : SurveyParams
        Its parameters.
    origin : tuple of float or None
        ``(lat, lon)`` of the local origin; without it ``lat, lon`` are empty and the GeoJSON is in metres.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    frame = LocalFrame(*origin) if origin is not None else None
    rows = ["line,x,y,z,lat,lon"]
    for k, p in enumerate(run.plan.line_waypoints()):
        lon, lat = frame.inverse(p[:, 0], p[:, 1]) if frame is not None else (None, None)
        for i, (x, y, z) in enumerate(p):
            geo = f"{lat[i]:.8f},{lon[i]:.8f}" if lat is not None and lon is not None else ","
            rows.append(f"{k},{x:.3f},{y:.3f},{z:.3f},{geo}")
    paths = [atomic_write(out / "lines.csv", "\n".join(rows) + "\n")]
    paths.append(write_json(out / "coverage.json", coverage_record(run, params)))
    cov = run.flown or run.planned
    feats = [_feature(g, frame, {"kind": "gap", "area_m2": g.area}) for g in cov.gaps]
    feats.append(_feature(params.area, frame, {"kind": "area", "area_m2": params.area.area}))
    paths.append(atomic_write(out / "gaps.geojson", json.dumps({"type": "FeatureCollection", "features": feats})))
    return paths
