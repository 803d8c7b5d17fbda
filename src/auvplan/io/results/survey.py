"""Survey files: the ``[survey]`` area read into the local frame (a lat/lon list, or a GeoJSON, KML or
shapefile layer through pyogrio; a corridor about a centre line), and the survey's results: ``lines.csv``
(``line, kind, x, y, z, lat, lon`` of every main and tie line's waypoints), ``coverage.json``
(``coverage_pct``, ``overlap_min_pct``, ``overlap_max_pct`` and the rest) and ``gaps.geojson``."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import shapely
import shapely.affinity
from numpy.typing import NDArray

from ...errors import ScenarioError
from ...survey.lines.corridor import Corridor, build_corridor, default_bend_radius
from ...survey.mission import DEFAULT_TURN_RADIUS_M, SurveyParams, SurveyPlan
from ...survey.run import SurveyRun
from ...survey.spec import SurveySpec
from ...world import World
from ..data.geo import LocalFrame
from ..data.vector.areas import read_area_lonlat, read_line_lonlat
from ..files.safeio import atomic_write
from .records import write_json

__all__ = ["SURVEY_NAMES", "survey_params", "check_survey_size", "write_survey", "coverage_record",
           "nav_spacing_record"]

SURVEY_NAMES = ("lines.csv", "coverage.json", "gaps.geojson", "coverage.png")
"""Files a survey writes into ``--out`` besides the run files and the mission exports."""


def _path(name: str, base_dir: Path | None) -> Path:
    path = Path(name)
    return base_dir / path if not path.is_absolute() and base_dir is not None else path


def _local(spec: SurveySpec, origin: tuple[float, float] | None, base_dir: Path | None,
           where: str) -> NDArray[np.float64]:
    """The area's ring or the centre line in the local frame (m)."""
    xy = spec.polygon_xy or spec.centerline_xy
    if xy:
        return np.asarray(xy, dtype=float)
    if origin is None:
        key = next(k for k in ("polygon", "file", "centerline", "centerline_file") if getattr(spec, k))
        raise ScenarioError(f"{where} {key}: a geographic area needs [origin] lat/lon (or give polygon_xy or "
                            "centerline_xy in m)")
    frame = LocalFrame(*origin)
    if spec.polygon or spec.centerline:
        lat, lon = np.array(spec.polygon or spec.centerline).T
    elif spec.file:
        lon, lat = read_area_lonlat(_path(spec.file, base_dir), spec.layer, where).T
    else:
        lon, lat = read_line_lonlat(_path(spec.centerline_file, base_dir), spec.layer, where).T
    x, y = frame.forward(np.asarray(lon), np.asarray(lat))
    return np.column_stack([x, y])


def _corridor(spec: SurveySpec, pts: NDArray[np.float64], radius: float, where: str) -> Corridor:
    widths = np.asarray(spec.widths_m or (spec.width_m,), dtype=float)
    bend = spec.bend_radius_m or default_bend_radius(widths, radius)
    try:
        return build_corridor(pts, widths, bend)
    except ValueError as exc:
        raise ScenarioError(f"{where} centerline: {exc}") from exc


def _check_seabed(area: shapely.Polygon, world: World, where: str) -> None:
    """Every point of the area over the terrain's data and under water."""
    assert world.terrain is not None
    x0, x1, y0, y1 = world.terrain.extent
    ax0, ay0, ax1, ay1 = area.bounds
    if ax0 < x0 or ax1 > x1 or ay0 < y0 or ay1 > y1:
        raise ScenarioError(f"{where} area x [{ax0:.0f}, {ax1:.0f}] y [{ay0:.0f}, {ay1:.0f}] m: beyond the terrain's "
                            f"data x [{x0:.0f}, {x1:.0f}] y [{y0:.0f}, {y1:.0f}]")
    ring = np.asarray(shapely.segmentize(area, max(math.sqrt(area.area) / 50.0, 1.0)).exterior.coords)
    # about 40 x 40 samples over a compact area, never more than 400 x 400 over its box (a corridor 1e-9 m
    # wide asked for 1e8 x 1e8: 'out of memory (90.1 PiB)' after 19 s, naming no key)
    g = max(math.sqrt(area.area) / 40.0, max(ax1 - ax0, ay1 - ay0) / 400.0)
    gx, gy = np.meshgrid(np.arange(ax0, ax1 + g, g), np.arange(ay0, ay1 + g, g))
    inside = shapely.contains_xy(area, gx, gy)
    px, py = np.r_[ring[:, 0], gx[inside]], np.r_[ring[:, 1], gy[inside]]
    below = -max(world.margins.min_depth, 0.0)
    if bool(np.all(_seabed_bounds(world, px, py)[1] < below)):  # under water even at the bound: no kernel needed
        return
    zb = world.seabed(px, py)  # perhaps not: the compiled seabed decides, and names the point
    bad = ~np.isfinite(zb) | (zb >= below)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ScenarioError(f"{where} area: the seabed at ({px[i]:.0f}, {py[i]:.0f}) m is {zb[i]:.1f} m, not under "
                            f"water below the sensor ({int(bad.sum())} of {bad.size} sampled points)")


def survey_params(spec: SurveySpec, world: World, vehicle: Any, base_dir: Path | None,
                  where: str) -> SurveyParams:
    """The :class:`~auvplan.survey.mission.SurveyParams` of a scenario's ``[survey]`` in its world.

    Every check the survey makes before planning: the area or centre line read, the corridor built, the
    area inside the bounds and over the terrain's data, under water everywhere.

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
    if world.terrain is None:
        raise ScenarioError(f"{where}: a survey needs a seabed ([terrain])")
    radius = float(getattr(vehicle, "turn_radius_m", None) or DEFAULT_TURN_RADIUS_M)
    pts = _local(spec, world.origin, base_dir, where)
    corridor = _corridor(spec, pts, radius, where) if spec.corridor else None
    area = corridor.area if corridor is not None else shapely.make_valid(shapely.Polygon(pts))
    key = "centerline" if corridor is not None else "polygon"
    if not isinstance(area, shapely.Polygon) or area.area <= 0:
        raise ScenarioError(f"{where} {key}: not a simple polygon with an area (self-intersecting?)")
    b = world.bounds
    if not shapely.box(b.xmin, b.ymin, b.xmax, b.ymax).contains(area):
        x0, y0, x1, y1 = area.bounds
        raise ScenarioError(f"{where} {key}: the area x [{x0:.0f}, {x1:.0f}] y [{y0:.0f}, {y1:.0f}] m is not "
                            f"inside the [bounds] x [{b.xmin:.0f}, {b.xmax:.0f}] y [{b.ymin:.0f}, {b.ymax:.0f}]")
    _check_seabed(area, world, where)
    params = SurveyParams(area, spec.sensor_model(), spec.line_params(min(world.terrain.dx, world.terrain.dy)),
                          spec.heading_deg, radius, spec.run_in_m,
                          frame=corridor.frame if corridor is not None else None, tie_lines=spec.tie_lines)
    check_survey_size(params, world, where)  # (first: an altitude of 1e-6 m is refused for its line count)
    if spec.mounting == "auv" and spec.altitude_m < world.margins.min_altitude:  # every line under the limit
        raise ScenarioError(f"{where} altitude_m = {spec.altitude_m:g}: below [mission] min_altitude_m = "
                            f"{world.margins.min_altitude:g} (every line would fly closer to the seabed than allowed)")
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
    from ..files import limits as _limits

    x0, y0, x1, y1 = params.area.bounds
    gx, gy = np.meshgrid(np.linspace(x0, x1, 48), np.linspace(y0, y1, 48))
    inside = shapely.contains_xy(params.area, gx, gy)
    lines, diag = params.lines, math.hypot(x1 - x0, y1 - y0)
    within = _swath_bounds(params, world, gx[inside], gy[inside])
    if within is not None:
        try:  # within the ceilings at the least spacing and the widest swath: so at the seabed's own (monotone)
            _limits.check_survey(_limits.current(), where, diag, diag, within[0], lines.station_m, lines.step_m,
                                 within[1])
            return
        except ScenarioError:
            pass  # perhaps over: the compiled seabed decides, and words the message
    depth = -world.seabed(gx[inside], gy[inside]) if inside.any() else np.array([])
    depth = depth[np.isfinite(depth) & (depth > 0)]
    if depth.size == 0:
        raise ScenarioError(f"{where} polygon: no water under the area (the seabed is above the surface there)")
    spacing, swath = _swath(params, depth)
    _limits.check_survey(_limits.current(), where, diag, diag, spacing, lines.station_m, lines.step_m, swath)


def _swath(params: SurveyParams, depth: NDArray[np.float64]) -> tuple[float, float]:
    """The mean line spacing and the widest swath over the water ``depth`` (m, > 0) of the samples."""
    sensor = params.sensor
    height = np.full(depth.shape, sensor.altitude_m) if sensor.mounting == "auv" else depth
    reach = np.asarray(sensor.flat_reach(height), dtype=float)
    spacing = 2.0 * reach * (1.0 - params.lines.overlap_max)
    return 1.0 / float(np.mean(1.0 / np.maximum(spacing, 1e-300))), 2.0 * float(reach.max())


def _swath_bounds(params: SurveyParams, world: World, x: NDArray[np.float64],
                  y: NDArray[np.float64]) -> tuple[float, float] | None:
    """A lower bound of :func:`_swath`'s spacing and an upper bound of its swath over the compiled seabed at
    ``x, y``, from the seabed in numpy (:func:`_seabed_bounds`); None when a sample may be dry or wet.

    Every step of :func:`_swath` is monotone in each depth (a reach grows or shrinks with the height, the
    harmonic mean grows with each spacing; IEEE rounding keeps that order), so the least of the reaches at
    the two ends of each depth's interval bounds the spacing below and the greatest the swath above."""
    if x.size == 0:
        return None
    lo, hi = _seabed_bounds(world, x, y)
    wet, dry = hi < 0.0, lo >= 0.0  # depth > 0 at either end, or at neither (a NaN is neither: None)
    if not bool(np.all(wet | dry)) or not wet.any():
        return None
    ends = [_swath(params, -z[wet]) for z in (lo, hi)]  # one sensor: every reach is least at the same end
    return min(s for s, _ in ends), max(w for _, w in ends)


def _seabed_bounds(world: World, x: NDArray[np.float64], y: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                                                           NDArray[np.float64]]:
    """``(lo, hi)``: the compiled seabed :meth:`World.seabed` at ``x, y`` lies within, from the numpy one
    (:meth:`Terrain.elevation_bounds`, a rounding further out each side): no compiled kernel (issue 56)."""
    if world.terrain is None:
        inf = np.full(np.shape(x), -np.inf)
        return inf, inf
    zb, err = world.terrain.elevation_bounds(x, y)
    return np.nextafter(zb - err, -np.inf), np.nextafter(zb + err, np.inf)


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
        "overlap_definition": "share of the narrower swath, across the track (side-scan: how far each swath "
                              "reaches past the neighbour's nadir, over the narrower facing band)",
        "overlap_margin_pct": 100 * plan.overlap_margin,
        "nav_spacing": nav_spacing_record(plan, params),
        "tie_lines": len(plan.tie_waypoints()),
        "corridor": params.frame is not None,
        "lines": n,
        "heading_deg": math.degrees(plan.lines.heading) % 360.0,
        "area_m2": planned.area_m2 + planned.no_go_m2,
        "no_go_m2": planned.no_go_m2,
        "coverage_of": "the area less its part inside charted no-go zones (no_go_m2; not a zone whose depth band "
                       "the lines fly over): not surveyed, so neither covered nor a gap",
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
        geom = _lonlat(geom, frame)
    return {"type": "Feature", "properties": props, "geometry": shapely.geometry.mapping(geom)}


def _lonlat(geom: shapely.Geometry, frame: LocalFrame) -> shapely.Geometry:
    """A polygon of the local frame in lon/lat, cut at the antimeridian (RFC 7946 §3.1.9) where it crosses it.

    ``LocalFrame.inverse`` gives longitudes in [-180, 180]: an area across the antimeridian was written 179.99 beside
    -179.99, a polygon 359.99° wide that viewers draw round the Earth.  The longitudes are taken continuous about the
    origin's, the pieces either side of ±180° cut out and moved back by 360°, as the mission exports do.
    """
    ref = float(frame.lon0)

    def inverse(xy: NDArray[np.float64]) -> NDArray[np.float64]:
        lon, lat = frame.inverse(xy[:, 0], xy[:, 1])
        return np.column_stack([ref + (np.asarray(lon) - ref + 180.0) % 360.0 - 180.0, lat])

    un = shapely.transform(geom, inverse)
    x0, _, x1, _ = un.bounds
    if -180.0 <= x0 and x1 <= 180.0:
        return un
    parts = []
    for k in (-360.0, 0.0, 360.0):
        cut = shapely.intersection(un, shapely.box(-180.0 + k, -90.0, 180.0 + k, 90.0))
        parts += [shapely.affinity.translate(g, -k) for g in shapely.get_parts(cut)
                  if isinstance(g, shapely.Polygon) and g.area > 0.0]
    return shapely.MultiPolygon(parts)


def write_survey(out: Path, run: SurveyRun, params: SurveyParams, origin: tuple[float, float] | None) -> list[Path]:
    """Write ``lines.csv``, ``coverage.json`` and ``gaps.geojson`` into ``out``.

    Parameters
    ----------
    out : pathlib.Path
        Results folder (checked by :func:`~auvplan.io.files.safeio.prepare_out`).
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
    rows = ["line,kind,x,y,z,lat,lon"]
    main = run.plan.line_waypoints()
    for k, p in enumerate(main + run.plan.tie_waypoints()):
        lon, lat = frame.inverse(p[:, 0], p[:, 1]) if frame is not None else (None, None)
        kind = "main" if k < len(main) else "tie"
        for i, (x, y, z) in enumerate(p):
            geo = f"{lat[i]:.8f},{lon[i]:.8f}" if lat is not None and lon is not None else ","
            rows.append(f"{k},{kind},{x:.3f},{y:.3f},{z:.3f},{geo}")
    paths = [atomic_write(out / "lines.csv", "\n".join(rows) + "\n")]
    paths.append(write_json(out / "coverage.json", coverage_record(run, params)))
    cov = run.flown or run.planned
    feats = [_feature(g, frame, {"kind": "gap", "area_m2": g.area}) for g in cov.gaps]
    feats.append(_feature(params.area, frame, {"kind": "area", "area_m2": params.area.area}))
    paths.append(atomic_write(out / "gaps.geojson", json.dumps({"type": "FeatureCollection", "features": feats})))
    return paths


def nav_spacing_record(plan: SurveyPlan, params: SurveyParams) -> dict[str, Any] | None:
    """How the line spacing was brought in for the relative navigation error of adjacent lines (issue 52):
    None when it was not (no ``[navigation]``, or a surface mounting with GPS).

    Parameters
    ----------
    plan : SurveyPlan
        The survey's plan.
    params : SurveyParams
        Its parameters.

    Returns
    -------
    dict or None
        ``relative_error_max_m`` and ``relative_error_median_m`` (over every station of every pair; at the
        ``[navigation]`` confidence) and ``text``, the sentence the report states.
    """
    m = [ln.nav_margin[ln.active] for ln in plan.lines.lines[1:] if ln.nav_margin is not None]
    vals = np.concatenate(m) if m else np.empty(0)
    vals = vals[np.isfinite(vals)]
    if not vals.size:
        return None
    text = (f"line spacing reduced by the relative navigation error of adjacent lines: "
            f"{float(np.median(vals)):.1f} m median, {float(vals.max()):.1f} m at most (the drift grown between "
            f"the two passes at each station; the overlap floor {100 * params.lines.overlap_min:g} % holds under it)")
    return {"relative_error_max_m": float(vals.max()), "relative_error_median_m": float(np.median(vals)),
            "text": text}
