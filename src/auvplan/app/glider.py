"""``run`` / ``plan`` of a scenario with ``[vehicle] type = "glider"`` as a job: the plan in dive cycles, the
closed-loop flight of it and of a nose-at-the-goal pilot, and the mission files pilots load (docs/gliders.md)."""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["GLIDER_NAMES", "glider_scenario", "glider_record", "check_glider_files"]

#: The files a glider run writes into its ``--out`` folder.
GLIDER_NAMES = ("glider.json", "surfacings.csv", "track.csv", "slocum/goto_l10.ma", "slocum/yo10.ma",
                "slocum/surfac10.ma", "slocum/surfac11.ma", "seaglider/targets")


def _pct(a: float, b: float) -> float | None:
    # None, not NaN, where undefined: glider.json refuses a NaN (a goal within the capture radius of the start: 0/0)
    return 100.0 * (b - a) / b if math.isfinite(a) and math.isfinite(b) and b > 0 else None


def glider_record(name: str, plan: Any, flown: Any, naive: Any, depart: float) -> dict[str, Any]:
    """The JSON record of a glider run.

    Parameters
    ----------
    name : str
        Scenario name.
    plan : GliderPlan
        The plan (:func:`auvplan.planners.timeopt.glider.plan_glider`).
    flown, naive : GliderTrack
        The plan flown in the closed loop, and the nose-at-the-goal pilot's flight.
    depart : float
        Departure (s).

    Returns
    -------
    dict
        ``status``, planned and flown durations (s: until the track first comes within the capture radius
        of the goal), their difference (%), the flight's last fix at the goal (s), the time saved against the
        nose-at-the-goal pilot (%), energy (J), endurance (days), cycles and surfacings.
    """
    planned = plan.arrive_s - depart
    got = flown.reach_s - depart  # both: the time the track first comes within the capture radius of the goal
    steady = naive.reach_s - depart
    return {
        "scenario": name, "vehicle": "glider",
        "status": plan.result.status.value if flown.arrived else "INFEASIBLE", "arrived": bool(flown.arrived),
        "planned_duration_s": planned, "flown_duration_s": got if flown.arrived else None,
        "fix_at_goal_s": flown.arrive_s - depart if flown.arrived else None,
        "planned_vs_flown_pct": abs(got - planned) / planned * 100.0 if flown.arrived and planned > 0 else None,
        "steady_heading_duration_s": steady if naive.arrived else None,
        "saved_vs_steady_heading_pct": _pct(got, steady) if naive.arrived and flown.arrived else None,
        "cycle_s": plan.cycle.duration_s, "cycle_speed_m_s": plan.cycle.speed,
        "surfacings_planned": len(plan.waypoints),
        "surfacings_flown": len(flown.fixes), "planned_energy_j": plan.energy_j, "flown_energy_j": flown.energy_j,
        "pump_energy_j": flown.pump_j, "inflections": flown.inflections, "endurance_days": plan.endurance_days,
        "waypoints": [[round(float(x), 1), round(float(y), 1)] for x, y in plan.waypoints],
        "headings_deg": [round(math.degrees(h) % 360.0, 1) for h in plan.headings],
        "message": plan.result.message,
    }


def _csv(header: list[str], rows: Any) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    return buf.getvalue()


def _write(folder: Path, origin: tuple[float, float] | None, plan: Any, flown: Any, rec: dict[str, Any],
           glider: Any, min_altitude: float) -> None:
    from ..io.files.safeio import atomic_write
    from ..io.missions.glider import seaglider_targets, slocum_files

    atomic_write(folder / "glider.json", json.dumps(rec, indent=1, allow_nan=False, default=str) + "\n")
    times = plan.times
    heads = plan.headings
    head = ["t_s", "x_m", "y_m", "heading_deg", "dac_east_m_s", "dac_north_m_s"]
    atomic_write(folder / "surfacings.csv", _csv(head, (
        [f"{t:.0f}", f"{p[0]:.1f}", f"{p[1]:.1f}", f"{math.degrees(h) % 360:.1f}", f"{c[0]:.4f}", f"{c[1]:.4f}"]
        for t, p, h, c in zip(times, plan.waypoints, heads, plan.currents, strict=True))))
    step = max(1, len(flown.t) // 20000)
    atomic_write(folder / "track.csv", _csv(["t_s", "x_m", "y_m", "z_m", "phase"], (
        [f"{t:.0f}", f"{p[0]:.1f}", f"{p[1]:.1f}", f"{p[2]:.1f}", int(ph)]
        for t, p, ph in zip(flown.t[::step], flown.xyz[::step], flown.phase[::step], strict=True))))
    if origin is None:
        return
    (folder / "slocum").mkdir(exist_ok=True)
    (folder / "seaglider").mkdir(exist_ok=True)
    for n, text in slocum_files(plan.waypoints, origin, glider, min_altitude, yos=plan.cycle.yos,
                                underwater_s=plan.cycle.underwater_s).items():
        atomic_write(folder / "slocum" / n, text)
    atomic_write(folder / "seaglider" / "targets", seaglider_targets(plan.waypoints, origin, glider.capture_radius_m))


def glider_scenario(scenario: str, out: str | None = None, force: bool = False,
                    say: Callable[[str], None] = lambda text: None) -> tuple[Any, dict[str, Any]]:
    """Plan and fly a glider scenario; with ``out``, its record, surfacings, track and mission files.

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file (``[vehicle] type = "glider"``).
    out : str, optional
        The results folder (checked before any work).
    force : bool
        Replace the folder's result files.
    say : callable
        Progress lines.

    Returns
    -------
    (Scenario, dict)
        The scenario and the record (:func:`glider_record`).
    """
    from ..io.files.safeio import prepare_out
    from ..io.scenario import loader as scenario_io
    from ..planners.timeopt.glider import plan_glider
    from ..sim.glider import fly_glider

    if out:
        prepare_out(out, GLIDER_NAMES, force=force, job="glider", inputs=(scenario,))
    sc = scenario_io.load(scenario)
    world, mission = scenario_io.build(sc)
    g = mission.vehicle.glider
    alt = sc.mission.min_altitude_m
    depart = mission.planner.timeopt.depart_s
    say(f"planning {sc.name} in dive cycles against the depth-averaged current")
    plan = plan_glider(world, g, mission.start, mission.goal, depart, alt, mission.planner.timeopt)
    if not len(plan.waypoints):
        return sc, {"scenario": sc.name, "vehicle": "glider", "status": plan.result.status.value,
                    "message": plan.result.message, "arrived": False}
    say("flying the plan and the nose-at-the-goal pilot through the current at every depth")
    limit = 4.0 * (plan.arrive_s - depart) + 86400.0
    flown = fly_glider(world, g, mission.start, plan.waypoints, depart, min_altitude=alt, dac0=plan.currents[0],
                       max_s=limit)
    naive = fly_glider(world, g, mission.start, [mission.goal[:2]], depart, min_altitude=alt, correct_current=False,
                       max_s=limit)
    rec = glider_record(sc.name, plan, flown, naive, depart)
    if out:
        say(f"writing the record, the surfacings, the track and the Slocum and Seaglider files into {out}")
        _write(Path(out), world.origin, plan, flown, rec, g, alt)
    return sc, rec


def check_glider_files(scenario: str, names: list[str]) -> list[dict[str, Any]]:
    """``mission check`` of Slocum ``goto_lNN.ma`` and Seaglider ``targets`` files against a glider scenario.

    Each file's waypoints are read back (:func:`auvplan.io.missions.glider.read_glider_waypoints`); every
    waypoint must leave room for a yo (seabed at least ``climb_depth_m`` + ``min_altitude_m`` deep) and every
    leg must be free at ``climb_depth_m`` (land, obstacles); beside a ``goto_lNN.ma`` the ``yoNN.ma`` is
    read too (its dive altitude at least the scenario's ``min_altitude_m``); and the scenario's glider flies
    the waypoints in the closed loop from the mission's start: it must arrive, on its battery.

    Parameters
    ----------
    scenario : str
        Built-in name or TOML file (its glider, seabed, current and start).
    names : list of str
        The files.

    Returns
    -------
    list of dict
        Per file ``file``, ``format``, ``waypoints``, ``radius_m``, ``shallow_waypoints`` (the file's from 1: the
        start is waypoint 0), ``blocked_legs`` (leg k leaves waypoint k, from 0: leg 0 from the start), ``yo`` (the
        yo file's arguments, when read),
        ``arrived``, ``flown_duration_s`` (until within the capture radius of the last waypoint),
        ``energy_wh``, ``battery_wh``, ``ok`` and ``message``.
    """
    from ..errors import DataError
    from ..io.missions.glider import read_glider_waypoints
    from ..io.scenario import loader as scenario_io

    sc = scenario_io.load(scenario)
    if sc.origin is None:
        raise DataError(f"{sc.source}: [origin] is needed to read the geographic positions of {names[0]}")
    read = [read_glider_waypoints(Path(n), (sc.origin.lat, sc.origin.lon)) for n in names]  # bad files first
    world, mission = scenario_io.build(sc)
    return [_check_file(world, mission, sc.mission.min_altitude_m, Path(n), *r) for n, r in zip(names, read,
                                                                                                   strict=True)]


def _yo_glider(g: Any, yo: dict[str, float], max_depth: float, name: str) -> tuple[Any, list[str]]:
    """The scenario's glider flying the yo file's depths and yos (as the glider reads them), or why it cannot.

    The file's ``d_target_depth`` must lie within the scenario's depth band (``[mission]`` / ``[vehicle]``
    ``max_depth_m``); its ``d_target_depth``, ``c_target_depth`` and ``num_half_cycles_to_do`` replace the
    scenario's ``dive_depth_m``, ``climb_depth_m`` and ``yos`` for the flight (a yo file checked only for its
    altitude let a 900 m dive through a 300 m band and flew the scenario's yos instead of the file's); a file that
    counts its half cycles is flown at that count, the scenario's ``surface_every_s`` dropped (a Slocum flies
    ``num_half_cycles_to_do`` whatever the time: :func:`auvplan.vehicles.glider.yos_per_cycle`)."""
    from dataclasses import replace

    dive = yo.get("d_target_depth", g.dive_depth_m)
    if dive > max_depth:
        return g, [f"{name}: d_target_depth {dive:g} m is deeper than the depth band's {max_depth:g} m"]
    try:
        counted = "num_half_cycles_to_do" in yo
        return replace(g, dive_depth_m=dive, climb_depth_m=yo.get("c_target_depth", g.climb_depth_m),
                       yos=max(1, int(yo["num_half_cycles_to_do"]) // 2) if counted else g.yos,
                       surface_every_s=0.0 if counted else g.surface_every_s), []
    except ValueError as exc:
        return g, [f"{name}: {exc}"]


def _check_file(world: Any, mission: Any, alt: float, path: Path, wps: Any, radius: float,
                fmt: str) -> dict[str, Any]:
    """One file of :func:`check_glider_files`."""
    from ..io.missions.glider import read_ma
    from ..sim.glider import fly_glider

    g = mission.vehicle.glider
    problems: list[str] = []
    b = world.bounds
    outside = [int(k) + 1 for k in np.flatnonzero((wps[:, 0] < b.xmin) | (wps[:, 0] > b.xmax) | (wps[:, 1] < b.ymin)
                                             | (wps[:, 1] > b.ymax))]
    if outside:
        problems.append(f"waypoints {outside} lie outside the scenario's bounds")
        wps = np.clip(wps, [b.xmin, b.ymin], [b.xmax, b.ymax])  # (the seabed and legs checked at the edge)
    depth = -world.seabed(wps[:, 0], wps[:, 1]) if world.terrain is not None else np.full(len(wps), np.inf)
    shallow = [int(k) + 1 for k in np.flatnonzero(depth < g.climb_depth_m + alt)]
    if shallow:
        problems.append(f"waypoints {shallow} leave no room for a yo (seabed shallower than "
                        f"{g.climb_depth_m + alt:g} m)")
    z = -g.climb_depth_m
    pts = np.vstack([np.asarray(mission.start, dtype=float)[:2], wps])
    seg = np.stack([np.c_[pts[:-1], np.full(len(wps), z)], np.c_[pts[1:], np.full(len(wps), z)]], axis=1)
    # leg k leaves waypoint k, from 0 (docs/missions.md "Leg numbers"): leg 0 leaves the start, waypoint 0, as a
    # .plan's home; the file's waypoints are 1 on, as their limits name them
    blocked = [int(k) for k in np.flatnonzero(~world.segments_free(seg, moving=False))]
    if blocked:
        problems.append(f"legs {blocked} cross land, the seabed or an obstacle at {g.climb_depth_m:g} m")
    yo: dict[str, float] = {}
    if fmt == "slocum":
        yo_file = path.with_name(path.name.replace("goto_l", "yo"))
        if yo_file.exists():
            yo = read_ma(yo_file.read_text())[1]
            if yo.get("d_target_altitude", alt) < alt:
                problems.append(f"{yo_file.name}: d_target_altitude {yo['d_target_altitude']:g} m is below "
                                f"min_altitude_m {alt:g} m")
            g, why = _yo_glider(g, yo, world.margins.max_depth, yo_file.name)
            problems += why
    rec = {"file": str(path), "format": fmt, "waypoints": len(wps), "radius_m": radius, "outside_waypoints": outside,
           "shallow_waypoints": shallow, "blocked_legs": blocked, "yo": yo, "arrived": False, "flown_duration_s": None,
           "energy_wh": None, "battery_wh": g.battery_wh}
    if problems:  # not flown: the waypoints themselves are wrong
        return {**rec, "ok": False, "message": "; ".join(problems) + " (not flown)"}
    from ..planners.timeopt.glider import cycle

    depart = mission.planner.timeopt.depart_s
    limit = 3.0 * float(np.hypot(*np.diff(pts, axis=0).T).sum()) / cycle(g).speed + 86400.0
    flown = fly_glider(world, g, mission.start, wps, depart, min_altitude=alt, max_s=limit)
    energy_wh = flown.energy_j / 3600.0
    if not flown.arrived:
        problems.append("the glider flying these waypoints through the scenario's current " + (
            "runs aground" if flown.reason == "grounded" else f"does not arrive within {limit / 86400:.1f} days"))
    if energy_wh > g.battery_wh:
        problems.append(f"the flight needs {energy_wh:.0f} Wh, more than the battery's {g.battery_wh:.0f} Wh")
    return {**rec, "arrived": flown.arrived, "flown_duration_s": flown.reach_s - depart if flown.arrived else None,
            "energy_wh": energy_wh, "ok": not problems, "message": "; ".join(problems)}
