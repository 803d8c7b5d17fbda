"""``plan --depart-between``: the departure sweep's arguments to the job of :mod:`auvplan.app.sweep`, its
progress bar and its table (or one JSON object)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .output import LIVE, emit, runner_of, stage_line

if TYPE_CHECKING:
    from ..planners.timeopt.planner import SweepRow, SweepSummary

__all__: list[str] = ["sweep_lines"]  # handlers: CLI internals, not library API


def cmd_sweep(args: argparse.Namespace) -> int:
    """``plan --depart-between``: the time-optimal plan of every departure, its energy and the best one."""
    from tqdm import tqdm

    from ..app.sweep import sweep_scenario

    bar: Any = None

    def progress(name: str, done: int, total: int) -> None:  # departures done / total and an ETA on stderr
        nonlocal bar
        if bar is None:
            LIVE.end()  # the starting clock gives way to the sweep's bar (closed first: the bar takes its line)
            bar = tqdm(total=total, desc=f"departures of {name}", unit="dep", file=sys.stderr,
                       disable=args.quiet or args.json, mininterval=0.5)
            LIVE.show(bar)  # redrawn in silences (issue 56)
        bar.update(done - bar.n)

    try:
        run = sweep_scenario(args.scenario, args.depart_between, args.step, args.objective, args.out,
                             getattr(args, "force", False), progress, runner_of(args),
                             (lambda text: None) if args.quiet or args.json else stage_line)
    finally:
        if bar is not None:
            bar.close()
    sc, summary = run.scenario, run.summary
    if run.computed < len(run.rows) and not (args.quiet or args.json):
        print(f"auvplan: {len(run.rows) - run.computed} of {len(run.rows)} departures read back from the "
              "checkpoints of an unfinished run", file=sys.stderr)
    lines = sweep_lines(sc.name, sc.mission.start_time, run.rows, run.energy, summary, run.t0, run.step)
    emit({"scenario": sc.name, "summary": summary, "rows": run.table}, args.json, "\n".join(lines))
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
