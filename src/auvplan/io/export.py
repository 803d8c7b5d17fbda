"""Results to files: plan JSON (the CLI's contract, DESIGN.md §4), CSV paths."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..planners.base import PlanResult
from ..sim import RunRecord, SimResult

__all__ = [
    "plan_record",
    "sim_record",
    "run_record",
    "write_plan",
    "write_sim",
    "write_run",
    "write_json",
    "write_path_csv",
    "jsonable",
]


def jsonable(value):
    """Plain JSON types for numpy scalars/arrays and non-finite floats (→ None)."""
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


def plan_record(result: PlanResult, scenario: str, seed: int) -> dict:
    """The plan JSON object of DESIGN.md §4."""
    t = result.cost_terms
    return jsonable({
        "scenario": scenario,
        "planner": result.planner,
        "seed": seed,
        "status": result.status.value,
        "message": result.message,
        "length_m": t.get("length_m", float("nan")),
        "energy_j": t.get("energy_j", float("nan")),
        "duration_s": t.get("duration_s", float("nan")),
        "min_clearance_m": t.get("min_clearance_m", float("nan")),
        "collisions": int(t.get("collisions", 0)),
        "cost": result.cost,
        "cost_terms": {k: t[k] for k in ("length", "terrain", "energy") if k in t},
        "evaluations": result.evaluations,
        "iterations": result.iterations,
        "wall_time_s": result.wall_time_s,
        "history": result.history,
        "waypoints": result.path,
    })


def write_json(path: Path, obj) -> Path:
    """Write ``obj`` as indented JSON."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(jsonable(obj), indent=2) + "\n", encoding="utf-8")
    return path


def write_path_csv(path: Path, points, header: str = "x,y,z") -> Path:
    """Write points ``(N, k)`` as CSV with a header line."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, np.asarray(points, dtype=float), delimiter=",", header=header, comments="", fmt="%.3f")
    return path


def write_plan(out_dir: Path, result: PlanResult, scenario: str, seed: int, scenario_text: str = "") -> dict:
    """Write ``metrics.json``, ``path.csv`` and the scenario source into ``out_dir``; return the record."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    record = plan_record(result, scenario, seed)
    write_json(out / "metrics.json", record)
    if result.path.size:
        write_path_csv(out / "path.csv", result.path)
    if scenario_text:
        (out / "scenario.toml").write_text(scenario_text, encoding="utf-8")
    return record


def sim_record(result: SimResult, scenario: str, seed: int, avoidance: str = "none") -> dict:
    """The simulate JSON object of DESIGN.md §4."""
    m = result.metrics
    keys = ("arrived", "duration_s", "distance_m", "min_clearance_m", "min_obstacle_distance_m", "collisions",
            "cross_track_rms_m", "cross_track_max_m", "escapes", "wall_time_s")
    rec = {"scenario": scenario, "guidance": result.guidance, "avoidance": avoidance, "seed": seed,
           "status": result.status.value}
    rec.update({k: m[k] for k in keys})
    rec["obstacle_min_distances_m"] = m["obstacle_min_distances_m"]
    rec["events"] = [list(e) for e in result.events]
    return jsonable(rec)


def write_sim(out_dir: Path, result: SimResult, scenario: str, seed: int, avoidance: str = "none") -> dict:
    """Write ``metrics.json`` and ``track.csv`` (t, x, y, z, heading, speed, rudder, cross-track) into ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    record = sim_record(result, scenario, seed, avoidance)
    write_json(out / "sim_metrics.json", record)
    cols = np.column_stack([result.t, result.position, result.heading, result.speed, result.rudder,
                            result.route_error])
    write_path_csv(out / "track.csv", cols, header="t,x,y,z,heading_rad,speed_mps,rudder_rad,cross_track_m")
    return record


def run_record(record: RunRecord, avoidance: str = "") -> dict:
    """One JSON object for a whole mission: status, the plan's and the simulation's records."""
    sim = record.sim
    return jsonable({
        "scenario": record.scenario,
        "seed": record.seed,
        "status": record.status.value,
        "plan": plan_record(record.plan, record.scenario, record.seed) if record.plan is not None else None,
        "simulation": sim_record(sim, record.scenario, record.seed, avoidance or sim.avoidance) if sim else None,
        "key_waypoints": record.keys,
    })


def write_run(out_dir: Path, record: RunRecord, scenario_text: str = "") -> dict:
    """Write a mission's results: run.json, metrics.json (plan), path.csv, route.csv, keys.csv,
    sim_metrics.json and track.csv."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if record.plan is not None:
        write_plan(out, record.plan, record.scenario, record.seed)
    if record.route.size:
        write_path_csv(out / "route.csv", record.route)
        write_path_csv(out / "keys.csv", record.keys)
    if record.sim is not None:
        write_sim(out, record.sim, record.scenario, record.seed, record.sim.avoidance)
    if scenario_text:
        (out / "scenario.toml").write_text(scenario_text, encoding="utf-8")
    rec = run_record(record)
    write_json(out / "run.json", rec)
    return rec
