"""Results to files and back: the plan JSON (the CLI's contract, DESIGN.md §4), CSV paths, the
simulation JSON, and the whole :class:`~auvplan.sim.RunRecord` as JSON + NPZ (:func:`write_run`; read back by
:func:`read_run`, from :mod:`auvplan.io.results.readback`); every file written atomically, none of the user's
overwritten."""

from __future__ import annotations

import io
import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike

from ..files.safeio import atomic_write
from .readback import SIM_ARRAYS, read_run, scenario_sha256

if TYPE_CHECKING:  # a plan's JSON needs none of these (issue 56: `plan` imports what the plan runs)
    from ...nav.mission import NavPlan
    from ...planners.core.base import PlanResult
    from ...sim import RunRecord, SimResult
    from ...world.seabed import SeabedFit

__all__ = [
    "JsonDict",
    "plan_record",
    "sim_record",
    "run_record",
    "write_plan",
    "write_sim",
    "write_run",
    "write_navigation",
    "write_json",
    "write_path_csv",
    "write_text",
    "jsonable",
    "read_run",
    "summary_metrics",
    "fit_metrics",
]

JsonDict = dict[str, Any]
"""A JSON object."""


def jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays and non-finite floats (→ None) to plain JSON types, recursively.

    Parameters
    ----------
    value : object
        A value, possibly nested in dicts, lists and tuples.

    Returns
    -------
    object
        The same value with only JSON types (dict keys as str, enums as their value).
    """
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else None
    if hasattr(value, "value") and isinstance(value.value, str):
        return value.value
    return value


def plan_record(result: PlanResult, scenario: str, seed: int) -> JsonDict:
    """Make the plan JSON object of DESIGN.md §4.

    Parameters
    ----------
    result : PlanResult
        The plan.
    scenario : str
        Scenario name.
    seed : int
        The planner's seed.

    Returns
    -------
    dict
        Status, cost and its terms (m, J, s), evaluations, timing and message.
    """
    t = result.cost_terms
    return cast(JsonDict, jsonable({
        "scenario": scenario,
        "planner": result.planner,
        "seed": seed,
        "status": result.status.value,
        "message": result.message,
        "length_m": t.get("length_m", float("nan")),
        "energy_j": t.get("energy_j", float("nan")),
        "duration_s": t.get("duration_s", float("nan")),
        "min_clearance_m": t.get("min_clearance_m", float("nan")),
        **({"zone_clearance_min_m": t["zone_clearance_min_m"]} if "zone_clearance_min_m" in t else {}),
        "violations": int(t.get("violations", t.get("collisions", 0))),
        "collisions": int(t.get("collisions", 0)),  # deprecated alias of "violations"
        "cost": result.cost,
        "cost_terms": {k: t[k] for k in ("length", "terrain", "energy") if k in t},
        "evaluations": result.evaluations,
        "iterations": result.iterations,
        "wall_time_s": result.wall_time_s,
        "history": result.history,
        "waypoints": result.path,
        **({"times": result.times} if result.times is not None else {}),
        **({"work": result.work} if result.work else {}),
        **({"converged": result.converged, "convergence": result.convergence}
           if result.converged is not None else {}),
    }))


def write_text(path: Path, text: str | bytes) -> Path:
    """Write one result file, text (UTF-8) or bytes.

    Every writer of this module goes through here, and here through
    :func:`auvplan.io.files.safeio.atomic_write` (temp file + rename, never through a symlink).

    Parameters
    ----------
    path : pathlib.Path
        The file.
    text : str or bytes
        Its content.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(path, text)


def write_json(path: Path, obj: Any) -> Path:
    """Write ``obj`` as indented JSON (through :func:`jsonable`).

    Parameters
    ----------
    path : pathlib.Path
        The file.
    obj : object
        A JSON-able value.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    return write_text(path, json.dumps(jsonable(obj), indent=2) + "\n")


def write_path_csv(path: Path, points: ArrayLike, header: str = "x,y,z",
                   origin: tuple[float, float] | None = None, xy: tuple[int, int] = (0, 1)) -> Path:
    """Write points ``(N, k)`` as CSV with a header line.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    points : array_like
        ``(N, k)`` rows (units as the header says; m for x, y, z).
    header : str, optional
        The header line.
    origin : tuple of 2 float, optional
        ``(lat, lon)`` of the local frame: two columns ``lat,lon`` (degrees, WGS 84, 8 decimals)
        are appended, unprojected from the columns ``xy``.
    xy : tuple of 2 int, optional
        The columns holding x and y (m).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    rows = np.asarray(points, dtype=float).reshape(-1, len(header.split(",")))
    fmt = ["%.3f"] * rows.shape[1]
    if origin is not None:
        from ..data.geo import LocalFrame  # pyproj: only for a geographic origin

        lon, lat = LocalFrame(*origin).inverse(rows[:, xy[0]], rows[:, xy[1]])
        rows = np.column_stack([rows, lat, lon])
        header, fmt = header + ",lat,lon", fmt + ["%.8f", "%.8f"]
    buf = io.StringIO()
    np.savetxt(buf, rows, delimiter=",", header=header, comments="", fmt=fmt)
    return write_text(path, buf.getvalue())


def write_plan(out_dir: Path, result: PlanResult, scenario: str, seed: int, scenario_text: str = "",
               origin: tuple[float, float] | None = None) -> JsonDict:
    """Write ``metrics.json``, ``path.csv`` and the scenario source into ``out_dir``.

    Parameters
    ----------
    out_dir : pathlib.Path
        Results folder.
    result : PlanResult
        The plan.
    scenario : str
        Scenario name.
    seed : int
        The planner's seed.
    scenario_text : str, optional
        The scenario's TOML source, copied as ``scenario.toml``.
    origin : tuple of 2 float, optional
        ``(lat, lon)`` of the local frame: ``path.csv`` gets ``lat,lon`` columns and ``metrics.json``
        ``waypoints_lat_lon`` (degrees, beside ``waypoints`` in m).

    Returns
    -------
    dict
        The plan record (:func:`plan_record`).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    record = plan_record(result, scenario, seed)
    if origin is not None and result.path.size:  # the plan's vertices in degrees beside the metres
        from ..data.geo import LocalFrame  # pyproj: only for a geographic origin

        lon, lat = LocalFrame(*origin).inverse(result.path[:, 0], result.path[:, 1])
        record["waypoints_lat_lon"] = [[round(float(a), 8), round(float(b), 8)] for a, b in zip(lat, lon)]
    write_json(out / "metrics.json", record)
    if result.path.size and result.times is not None:  # timed plans: the time at each vertex (s after start_time)
        write_path_csv(out / "path.csv", np.column_stack([result.path, result.times]), "x,y,z,time", origin)
    elif result.path.size:
        write_path_csv(out / "path.csv", result.path, origin=origin)
    if scenario_text:
        write_text(out / "scenario.toml", scenario_text)
    return record


def sim_record(result: SimResult, scenario: str, seed: int, avoidance: str = "none") -> JsonDict:
    """Make the simulate JSON object of DESIGN.md §4.

    Parameters
    ----------
    result : SimResult
        The closed-loop run.
    scenario : str
        Scenario name.
    seed : int
        The run's seed.
    avoidance : str, optional
        The local avoidance used.

    Returns
    -------
    dict
        Status, metrics (m, s) and events.
    """
    m: Mapping[str, object] = result.metrics
    keys = ("arrived", "duration_s", "distance_m", "min_altitude_m", "min_clearance_m", "min_obstacle_distance_m",
            "collisions",
            "cross_track_rms_m", "cross_track_max_m", "escapes", "wall_time_s")
    rec = {"scenario": scenario, "guidance": result.guidance, "avoidance": avoidance, "seed": seed,
           "status": result.status.value}
    rec.update({k: m[k] for k in keys})
    rec["obstacle_min_distances_m"] = m["obstacle_min_distances_m"]
    rec["events"] = [list(e) for e in result.events]
    return cast(JsonDict, jsonable(rec))


def write_sim(out_dir: Path, result: SimResult, scenario: str, seed: int, avoidance: str = "none",
              full: bool = False, origin: tuple[float, float] | None = None) -> JsonDict:
    """Write ``sim_metrics.json`` and ``track.csv`` into ``out_dir``.

    ``track.csv``: t, x, y, z, heading, speed, rudder, cross-track (s, m, rad, m/s); decimated by
    :func:`auvplan.sim.decimate` unless ``full``.

    Parameters
    ----------
    out_dir : pathlib.Path
        Results folder.
    result : SimResult
        The closed-loop run.
    scenario : str
        Scenario name.
    seed : int
        The run's seed.
    avoidance : str, optional
        The local avoidance used.
    full : bool, optional
        Every recorded sample instead of the decimated track (:func:`auvplan.sim.decimate`).
    origin : tuple of 2 float, optional
        ``(lat, lon)`` of the local frame: ``track.csv`` gets ``lat,lon`` columns.

    Returns
    -------
    dict
        The simulate record (:func:`sim_record`).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    record = sim_record(result, scenario, seed, avoidance)
    write_json(out / "sim_metrics.json", record)
    from ...sim import decimate

    result = result if full else decimate(result)
    cols = np.column_stack([result.t, result.position, result.heading, result.speed, result.rudder,
                            result.route_error])
    write_path_csv(out / "track.csv", cols, header="t,x,y,z,heading_rad,speed_mps,rudder_rad,cross_track_m",
                   origin=origin, xy=(1, 2))
    return record


def run_record(record: RunRecord, avoidance: str = "") -> JsonDict:
    """Make one JSON object for a whole mission: status, the plan's and the simulation's records.

    Parameters
    ----------
    record : RunRecord
        The run: plan, route, key waypoints and flight.
    avoidance : str, optional
        The local avoidance used.

    Returns
    -------
    dict
        ``scenario``, ``seed``, ``status``, ``plan`` and ``simulation``.
    """
    sim = record.sim
    return cast(JsonDict, jsonable({
        "scenario": record.scenario,
        "seed": record.seed,
        "status": record.status.value,
        "plan": plan_record(record.plan, record.scenario, record.seed) if record.plan is not None else None,
        "simulation": sim_record(sim, record.scenario, record.seed, avoidance or sim.avoidance) if sim else None,
        "key_waypoints": record.keys,
        **({"altitude": dict(record.altitude)} if record.altitude is not None else {}),
    }))


def write_run(out_dir: Path, record: RunRecord, scenario_text: str = "", full: bool = False,
              origin: tuple[float, float] | None = None) -> JsonDict:
    """Write a mission's results into ``out_dir``.

    run.json, metrics.json (plan; a terrain-following mission's altitude band figures added,
    :func:`auvplan.sim.band.altitude_band_metrics`), path.csv, route.csv (the mission), keys.csv,
    sim_metrics.json and track.csv (decimated unless ``full``; run.npz keeps every sample).

    Parameters
    ----------
    out_dir : pathlib.Path
        Results folder.
    record : RunRecord
        The run: plan, route, key waypoints and flight.
    scenario_text : str, optional
        The scenario's TOML source, copied as ``scenario.toml``.
    full : bool, optional
        Every recorded sample instead of the decimated track (:func:`auvplan.sim.decimate`).
    origin : tuple of 2 float, optional
        ``(lat, lon)`` of the local frame: ``path.csv``, ``route.csv``, ``keys.csv`` and ``track.csv``
        get ``lat,lon`` columns.

    Returns
    -------
    dict
        The run record (:func:`run_record`).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if record.plan is not None:
        write_plan(out, record.plan, record.scenario, record.seed, origin=origin)
    if record.route.size:
        write_path_csv(out / "route.csv", record.route, origin=origin)
        write_path_csv(out / "keys.csv", record.keys, origin=origin)
    if record.sim is not None:
        write_sim(out, record.sim, record.scenario, record.seed, record.sim.avoidance, full, origin)
    if record.nav is not None:
        write_navigation(out, record.nav, origin)
    if record.altitude is not None:  # the altitude band's figures (terrain following), added to metrics.json
        path = out / "metrics.json"
        metrics = json.loads(path.read_text()) if path.exists() else {}
        write_json(path, {**metrics, **jsonable(dict(record.altitude))})
    if scenario_text:
        write_text(out / "scenario.toml", scenario_text)
    rec = run_record(record)
    if scenario_text:  # report/export refuse the folder once its scenario.toml is replaced (check_scenario)
        rec["scenario_sha256"] = scenario_sha256(scenario_text)
    write_json(out / "run.json", rec)
    arrays = {"route": record.route, "keys": record.keys}
    if record.plan is not None:
        arrays.update(plan_path=record.plan.path, plan_history=record.plan.history)
        if record.plan.tail is not None:  # the legs flown tail-first (the exports need them)
            arrays.update(plan_tail=record.plan.tail.astype(np.float64))
    if record.sim is not None:
        arrays.update({f"sim_{k}": getattr(record.sim, k) for k in SIM_ARRAYS})
    buf = io.BytesIO()
    np.savez_compressed(buf, **arrays)  # type: ignore[arg-type]
    write_text(out / "run.npz", buf.getvalue())
    return rec


def write_navigation(out_dir: Path, nav: NavPlan, origin: tuple[float, float] | None = None) -> None:
    """``fixes.csv`` (``lat, lon, t_s, kind``: one row per planned fix) and the navigation figures of
    ``metrics.json`` (``nav_error_max_m``, ``fixes``, ``fixes_fixed_period``, ``fixed_period_s``, added to
    the plan's record when there is one).

    Parameters
    ----------
    out_dir : pathlib.Path
        Results folder.
    nav : NavPlan
        The mission's fixes and budget (:mod:`auvplan.nav`).
    origin : tuple of 2 float, optional
        ``(lat, lon)`` of the local frame (without it lat and lon are left empty).
    """
    out = Path(out_dir)
    idx = [i for i, k in enumerate(nav.kinds) if k]
    p = nav.points[idx]
    if origin is not None and p.size:
        from ..data.geo import LocalFrame  # pyproj: only for a geographic origin

        lon, lat = LocalFrame(*origin).inverse(p[:, 0], p[:, 1])
    else:
        lon = lat = np.full(len(idx), np.nan)
    rows = ["lat,lon,t_s,kind"] + [",".join(["" if np.isnan(a) else f"{a:.7f}", "" if np.isnan(o) else f"{o:.7f}",
                                             f"{t:.1f}", nav.kinds[i]])
                                   for a, o, t, i in zip(lat, lon, nav.times_s, idx, strict=True)]
    write_text(out / "fixes.csv", "\n".join(rows) + "\n")
    path = out / "metrics.json"
    metrics = json.loads(path.read_text()) if path.exists() else {}
    metrics.update(nav.metrics())
    metrics["nav_status"] = "EXACT" if nav.ok else "INFEASIBLE"
    if not nav.ok:
        metrics["nav_message"] = nav.message
    write_json(path, metrics)


# ---------------------------------------------------------------------------------------- exports


def fit_metrics(fit: SeabedFit) -> JsonDict:
    """The seabed model against its data, as metrics (the report's table and ``plan --json``).

    Parameters
    ----------
    fit : SeabedFit
        How the terrain sits against its data.

    Returns
    -------
    dict
        ``terrain_method``, ``terrain_excess_max_m``, ``terrain_excess_mean_m``, ``terrain_below_data_max_m``.
    """
    return {"terrain_method": fit.method, "terrain_excess_max_m": round(fit.excess_max_m, 3),
            "terrain_excess_mean_m": round(fit.excess_mean_m, 3),
            "terrain_below_data_max_m": round(fit.deficit_max_m, 3)}


def summary_metrics(record: RunRecord) -> JsonDict:
    """Make a flat table of a mission's headline figures (report and GeoJSON properties).

    Parameters
    ----------
    record : RunRecord
        The run: plan, route, key waypoints and flight.

    Returns
    -------
    dict
        Figure name (unit in the name) → value.
    """
    rec = run_record(record)
    out = {"scenario": record.scenario, "seed": record.seed, "status": rec["status"]}
    if rec["plan"]:
        out.update({f"plan_{k}": rec["plan"][k] for k in ("planner", "cost", "length_m", "energy_j", "duration_s")})
    if rec["simulation"]:
        out.update({f"sim_{k}": rec["simulation"][k] for k in ("arrived", "duration_s", "distance_m",
                                                               "min_clearance_m", "min_obstacle_distance_m",
                                                               "collisions", "cross_track_rms_m")})
    return out
