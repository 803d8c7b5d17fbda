"""``plan --depart-between``: the departure sweep of the time-optimal planner, and the durations and
instants of its arguments."""

from __future__ import annotations

import argparse
import dataclasses
import sys
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import AuvplanError
from ..io.safeio import atomic_write, save_figure
from .output import check_out, emit

if TYPE_CHECKING:
    from ..planners.timeopt.planner import SweepRow, SweepSummary

__all__: list[str] = ["sweep_lines"]  # handlers: CLI internals, not library API


def parse_duration(text: str, what: str) -> float:
    """Seconds of '15min', '900s', '2h', '1.5h' or a bare number of seconds."""
    units = {"s": 1.0, "sec": 1.0, "min": 60.0, "m": 60.0, "h": 3600.0, "d": 86400.0}
    t = text.strip().lower().lstrip("+")
    for unit in sorted(units, key=len, reverse=True):
        if t.endswith(unit):
            t, scale = t[: -len(unit)], units[unit]
            break
    else:
        scale = 1.0
    try:
        return float(t) * scale
    except ValueError:
        raise AuvplanError(f"{what} {text!r}: not a duration (e.g. 15min, 900s, 2h)") from None


def is_offset(text: str) -> bool:
    """Whether a departure is an offset after start_time ('+6h', '900') rather than a date-time."""
    return text.startswith("+") or text[:1].isdigit() and not any(c in text for c in "-:T")


def parse_instant(text: str, start_time: str, what: str) -> float:
    """Seconds after the mission's start_time of an ISO 8601 time or a '+6h' offset."""
    from ..io.data.tides import parse_start_time

    if is_offset(text):
        return parse_duration(text, what)
    if not start_time:
        raise AuvplanError(f"{what} {text!r}: a date-time needs [mission] start_time (or give an offset: +6h)")
    try:
        return parse_start_time(text) - parse_start_time(start_time)
    except ValueError as exc:
        raise AuvplanError(f"{what} {exc}") from None


def cmd_sweep(args: argparse.Namespace) -> int:
    """``plan --depart-between``: the time-optimal plan of every departure, its energy and the best one."""
    from ..io.missions.energy import sweep_energy
    from ..io.results import records
    from ..io.scenario import loader as scenario_io
    from ..planners.timeopt.planner import departure_sweep, sweep_summary
    from ..sim import planning_problem

    check_out(args, ("sweep.csv", "sweep_summary.json", "sweep.png"))
    sc = scenario_io.load(args.scenario)
    world, mission = scenario_io.build(sc)
    spec = replace(mission.planner, name="timeopt")
    if args.objective:
        spec = replace(spec, timeopt=replace(spec.timeopt, objective=args.objective))
    t0, t1 = (parse_instant(v, sc.mission.start_time, "--depart-between") for v in args.depart_between)
    step = parse_duration(args.step, "--step")
    if not (t1 >= t0 and step > 0 and (t1 - t0) / step <= 500):
        raise AuvplanError(f"--depart-between {args.depart_between} --step {args.step}: need T1 >= T0 and at most "
                           "500 departures")
    from ..io.scenario.build import check_plan_sizes

    b = world.bounds
    check_plan_sizes(sc, (b.xmax - b.xmin, b.ymax - b.ymin), t1 - t0, timeopt=True)  # the table: sweep + horizon
    departs = np.arange(t0, t1 + 0.5 * step, step)
    plans: list[Any] = []
    from tqdm import tqdm

    # departures done / total and an ETA on stderr; silent with -q or --json
    with tqdm(total=len(departs), desc=f"departures of {sc.name}", unit="dep", file=sys.stderr,
              disable=args.quiet or args.json, mininterval=0.5) as bar:
        rows, _ = departure_sweep(planning_problem(world, mission), spec, departs, paths=plans,
                                  progress=lambda done, total: bar.update(done - bar.n))
    energy = sweep_energy(world, mission, plans, departs)
    summary = sweep_summary(rows, energy=spec.timeopt.objective == "energy")
    if sc.mission.start_time and summary.get("feasible_departures"):
        from ..io.data.tides import parse_start_time, utc_iso

        summary["best_depart_utc"] = utc_iso(parse_start_time(sc.mission.start_time) + summary["best_depart_s"])
    table = [{**dataclasses.asdict(r), **e} for r, e in zip(rows, energy)]
    if args.out:
        out = Path(args.out)
        atomic_write(out / "sweep.csv", ",".join(table[0]) + "\n"
                     + "".join(",".join(f"{v:.6g}" for v in row.values()) + "\n" for row in table))
        records.write_json(out / "sweep_summary.json", summary)
        from ..viz.timeplots import sweep_figure

        save_figure(out / "sweep.png", sweep_figure(rows, f"{sc.name}: departure sweep"), dpi=120)
    lines = sweep_lines(sc.name, sc.mission.start_time, rows, energy, summary, t0, step)
    emit({"scenario": sc.name, "summary": summary, "rows": table}, args.json, "\n".join(lines))
    return 0 if summary.get("feasible_departures") else 1


def sweep_lines(name: str, start_time: str, rows: Sequence[SweepRow], energy: Sequence[dict[str, float]],
                summary: SweepSummary, t0: float, step: float) -> list[str]:
    """The human table of a departure sweep: one line per departure, then the best one.

    Parameters
    ----------
    name : str
        The scenario's name.
    start_time : str
        Its ``[mission] start_time`` (empty: t = 0).
    rows : sequence
        The sweep's rows (:func:`auvplan.planners.timeopt.planner.departure_sweep`).
    energy : sequence of dict
        Each departure's energy figures (:func:`auvplan.io.missions.energy.sweep_energy`).
    summary : dict
        :func:`auvplan.planners.timeopt.planner.sweep_summary` of the rows.
    t0, step : float
        First departure and step (s).

    Returns
    -------
    list of str
        The lines.
    """
    lines = [f"{name}: {len(rows)} departures every {step / 60:.0f} min from {t0 / 3600:+.2f} h "
             f"(after {start_time or 't = 0'})",
             f"{'depart h':>9} {'timed h':>8} {'steady h':>9} {'straight h':>10} {'timed MJ':>9} {'energy Wh':>9} "
             f"{'margin Wh':>9} {'PNR h':>6} {'PNR km':>6}"]
    lines += [f"{r.depart_s / 3600:9.2f} {r.duration_s / 3600:8.2f} {r.steady_duration_s / 3600:9.2f} "
              f"{r.straight_duration_s / 3600:10.2f} {r.energy_j / 1e6:9.3f} {e['energy_wh']:9.1f} "
              f"{e['margin_wh']:9.1f} {e['pnr_t_s'] / 3600:6.2f} {e['pnr_s_m'] / 1000:6.1f}"
              + (" (whole mission)" if e["pnr_whole_mission"] == 1 else "")
              + ("" if np.isfinite(e["energy_wh"]) or not np.isfinite(r.duration_s) else
                 " (a cross current beats the vehicle on the plan's track: PNR up to there)")
              for r, e in zip(rows, energy)]
    if summary.get("feasible_departures"):
        lines.append(f"best departure {summary['best_depart_s'] / 3600:+.2f} h: "
                     f"{summary['best_duration_s'] / 3600:.2f} h, saves {summary['saved_vs_worst_pct']:.1f} % "
                     "against the worst departure, "
                     f"{summary['saved_vs_steady_pct']:.1f} % against the steady-current plan and "
                     f"{summary['saved_vs_straight_pct']:.1f} % against the straight line"
                     + (f"\n  fly it: [mission] start_time = \"{summary['best_depart_utc']}\""
                        if "best_depart_utc" in summary else ""))
    return lines
