"""The heavy documented figures (``make docs-bench``): each runs its benchmark and writes ``docs/figures/NAME.md``.

Each function returns the figure's text; the text states the command, the seeds, the settings and the
load it was measured under, so a quoted number always carries how it was made.  Registered in
``tools/docs_figures.py`` (``bench NAME``); run them one at a time on a shared machine::

    .venv/bin/python tools/docs_figures.py bench doc001-tracking     # ~5 min
    .venv/bin/python tools/docs_figures.py bench formation-chagos    # ~15 min
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from auvplan.guidance.formation.error import SETTLE_M

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # benchmarks/ is a folder of the repository, not of the package
    sys.path.insert(0, str(ROOT))

__all__ = ["tracking_table", "doc001_tracking", "formation_text", "formation_chagos", "ensemble_text", "ensemble_table",
           "ensemble_robust", "ensemble_lofoten", "kill_points", "endurance_table", "endurance_summary",
           "endurance_prediction", "HEAVY"]

Row = dict[str, Any]


def _load() -> str:
    return f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"


def _cell(rows: Sequence[Row]) -> str:
    """arrived / with a collision (DL) · RMS median / max worst · least obstacle distance · time median."""
    n_dl = sum(r["status"] == "DEADLOCK" for r in rows)
    hit = sum(bool(r["collisions"]) for r in rows)
    other = [r["status"] for r in rows if not r["arrived"] and not r["collisions"] and r["status"] != "DEADLOCK"]
    extra = [f"{n_dl} DL"] if n_dl else []
    extra += [f"{other.count(s)} {s}" for s in sorted(set(other))]
    rms = float(np.median([r["rms_m"] for r in rows]))
    worst = max(r["max_m"] for r in rows)
    dmin = min(r["min_obstacle_m"] for r in rows)
    arrived = [r["duration_s"] for r in rows if r["arrived"]]
    dist = f"{dmin:.2f}".replace("-", "−") if np.isfinite(dmin) else "—"
    dur = f"{np.median(arrived):.0f}" if arrived else "—"
    return (f"{sum(bool(r['arrived']) for r in rows)} / {hit}{' (' + ', '.join(extra) + ')' if extra else ''} · "
            f"{rms:.2f} / {worst:.1f} · {dist} · {dur}")


def tracking_table(rows: Sequence[Row], scenes: Sequence[str], laws: Sequence[str], labels: dict[str, str],
                   default: str = "corrected") -> str:
    """Document 001's condensed table: one line per law and crab angle, one column per scenario."""
    lines = ["| law | crab | " + " | ".join(f"`{s}`" for s in scenes) + " |", "|---|---" + "|---" * len(scenes) + "|"]
    for law in laws:
        for crab in (False, True):
            name = labels[law].replace("document field", "**document field**")
            if law == default and crab:
                name += " (default)"
            cells = [_cell([r for r in rows if r["scenario"] == s and r["law"] == law and r["compensation"] == crab])
                     for s in scenes]
            lines.append(f"| {name} | {'yes' if crab else 'no'} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _between(rows: Sequence[Row], laws: Sequence[str], labels: dict[str, str], seeds: int) -> str:
    parts = []
    for law in laws:
        for crab in (False, True):
            runs = [r for r in rows
                    if r["scenario"] == "track-double" and r["law"] == law and r["compensation"] == crab]
            parts.append(f"{labels[law]}{' + crab' if crab else ''} {sum(r['between'] is True for r in runs)}/{seeds}")
    return "; ".join(parts)


def doc001_tracking(seeds: int = 10) -> dict[str, str]:
    """Every law of document 001 on its four scenarios, with and without the crab angle (benchmarks/tracking.py)."""
    from benchmarks import tracking

    load0, t0, cpu0 = _load(), time.perf_counter(), time.process_time()
    _, rows = tracking.comparison(seeds)
    wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    per = sorted(r["cpu_s"] for r in rows)
    table = tracking_table(rows, tracking.SCENES, tracking.LAWS, tracking.LABEL)
    return {"doc001-tracking":
            f"{table}\n\nMeasured by `tools/docs_figures.py bench doc001-tracking` (`benchmarks/tracking.py`): "
            f"seeds 0–{seeds - 1}, every scenario's own vehicle, waves, current and `dt`; {len(rows)} runs in "
            f"{wall:.0f} s wall ({cpu:.0f} s CPU, {per[0]:.2f}–{per[-1]:.2f} s CPU per run); load {load0} at the "
            f"start, {_load()} at the end. Passed between the `track-double` pair (first reached x = 300 m with "
            f"|y| < 10 m): {_between(rows, tracking.LAWS, tracking.LABEL, seeds)}."}


def formation_text(rows: Sequence[Row], peer_us: float, seeds: int, load: str) -> str:
    """The formation Monte Carlo as a paragraph and a table (rows from benchmarks/formation.py's ``one``)."""
    ok = [r for r in rows if "arrivals" in r]
    names = sorted({k[:-6] for r in ok for k in r if k.endswith("_rms_m")})
    wide = [r for r in ok if max(r[f"{n}_set_max"] for n in names) > SETTLE_M]
    narrow = [r for r in ok if r not in wide]
    cpu = np.array([r["cpu_s"] for r in ok])
    per = float(np.median([r["cpu_s"] / r["vehicle_steps"] for r in ok])) * 1e6
    hours = float(np.median([r["duration_s"] for r in ok])) / 3600
    lines = [f"**{sum(r['arrivals'] == 3 for r in ok)}/{len(rows)} runs with all three vehicles arrived, "
             f"{sum(r['collisions'] for r in ok)} collisions** (seabed, obstacles, each other; "
             f"{sum(r['vehicle_contacts'] for r in ok)} vehicle contacts), least vehicle distance "
             f"{min(r['min_vehicle_distance_m'] for r in ok):.0f} m, least altitude "
             f"{min(r['min_altitude_m'] for r in ok):.1f} m, least obstacle distance "
             f"{min(r['min_obstacle_distance_m'] for r in ok):.1f} m; reshaped stretches per run "
             f"{sorted({r['reshaped'] for r in ok})}. Each vehicle is launched off its slot (launch scatter "
             f"{ok[0].get('start_sigma_m', 0.0):g} m per axis and {ok[0].get('start_heading_sigma_deg', 0.0):g}° "
             f"rms), so the whole run's largest error is the launch offset; *settled* is from the "
             f"first step within {SETTLE_M:g} m of the slot. Settled, {len(wide)} runs have an error above "
             f"{SETTLE_M:g} m "
             + (f"(least obstacle distance in them {max(r['min_obstacle_distance_m'] for r in wide):.1f} m or less)"
                if wide else "") + (f"; in the other {len(narrow)} no settled vehicle strayed more than "
                                    f"{max(r[f'{n}_set_max'] for r in narrow for n in names):.1f} m from its slot"
                                    if narrow else "") + ".",
             "", "| vehicle | settle time median / worst (s) | settled RMS median / worst (m) | settled p95 | "
             "settled max | whole-run RMS | whole-run p95 | whole-run max |", "|---|---|---|---|---|---|---|---|"]
    for name in names:
        def col(key: str, fmt: str, r_: list[Row] = ok, n_: str = name) -> str:
            a = np.array([r[f"{n_}_{key}"] for r in r_], dtype=float)
            return f"{np.median(a):{fmt}} / {a.max():{fmt}}"
        lines.append(f"| {name} | {col('settle_s', '.0f')} | {col('set_rms', '.2f')} | {col('set_p95', '.1f')} | "
                     f"{col('set_max', '.1f')} | {col('rms_m', '.2f')} | {col('p95_m', '.1f')} | "
                     f"{col('max_m', '.1f')} |")
    lines += ["", f"{np.median(cpu):.1f} s CPU per {hours:.1f}-hour run; {per:.1f} µs per vehicle-step against "
              f"{peer_us:.1f} µs of the single-vehicle simulator flying the same route in the same run "
              f"({per / peer_us:.1f}×). Measured by `tools/docs_figures.py bench formation-chagos` "
              f"(`benchmarks/formation.py`): `chagos-formation`, seeds 0–{seeds - 1} (seed 0 the scenario's "
              f"obstacle tracks, the others re-drawn by `perturb_moving`), one worker; load {load}."]
    return "\n".join(lines)


def formation_chagos(seeds: int = 100) -> dict[str, str]:
    """The built-in formation scenario over ``seeds`` seeds (benchmarks/formation.py)."""
    from benchmarks import formation

    load0 = _load()
    rows = [formation.one(seed) for seed in range(seeds)]
    cpu, steps = formation.peer()
    return {"formation-chagos": formation_text(rows, cpu / steps * 1e6, seeds,
                                               f"{load0} at the start, {_load()} at the end")}


def ensemble_text(summary: dict[str, Any], pairs: int, wall: float, load: str) -> dict[str, str]:
    """The two-model benchmark's outcome in one line (README, docs/ensembles.md)."""
    n = summary["pairs"]
    h = summary["replan_3600"]
    setting = (f"`lofoten-two-models`, {n} start/goal pairs 0–{pairs - 1} (pair i drawn from seed i), measured by "
               f"`tools/docs_figures.py bench ensemble-lofoten` (`benchmarks/ensemble.py`, one process): "
               f"{wall:.0f} s wall, load {load}")
    line = (f"re-planning every hour {h['arrivals']}/{n} arrivals and {100 * h['recovered_share']:.0f} % of the "
            f"open-loop loss recovered (open loop {summary['open_arrivals']}/{n}, oracle "
            f"{summary['oracle_arrivals']}/{n}; {1e3 * h['cpu_per_plan_mean_s']:.0f} ms CPU per re-plan)")
    return {"ensemble-replan": f"{line}; {setting}", "ensemble-table": ensemble_table(summary, setting),
            "ensemble-robust": ensemble_robust(summary)}


def ensemble_robust(summary: dict[str, Any]) -> str:
    """The robust plan against the nominal one over the pairs (P90 below / equal, mean gains)."""
    n = summary["pairs"]
    return (f"the robust P90 is below the nominal P90 in **{summary['robust_p90_below_nominal']} pairs**, equal in "
            f"{summary['robust_p90_equal_nominal']} (the nominal route is already the best candidate), above in "
            f"{n - summary['robust_p90_below_nominal'] - summary['robust_p90_equal_nominal']}; mean P90 gain "
            f"{summary['robust_p90_gain_mean_s']:.0f} s, mean gain in the truth "
            f"{summary['robust_truth_gain_mean_s']:.0f} s")


def _thousands(x: float) -> str:
    return f"{x:,.0f}".replace(",", " ")


def ensemble_table(summary: dict[str, Any], setting: str) -> str:
    """docs/ensembles.md's table: arrivals, successes, time over the oracle and loss recovered per scheme."""
    n = summary["pairs"]
    rows = ["| | arrivals | successes | mean time over the oracle | share of the open-loop loss recovered |",
            "| --- | --- | --- | --- | --- |",
            f"| oracle (planned on the truth) | {summary['oracle_arrivals']} / {n} | {summary['oracle_successes']} "
            "| — | — |",
            f"| open loop (forecast plan) | {summary['open_arrivals']} / {n} | {summary['open_successes']} | "
            f"+{summary['replan_3600']['mean_open_loss_pct']:.1f} % | — |"]
    for key, label in (("replan_3600", "every hour"), ("replan_1800", "every 30 min")):
        k = summary.get(key)
        if k is None:
            continue
        rows.append(f"| re-planned {label} | {k['arrivals']} / {n} | {k['successes']} | "
                    f"+{k['mean_replan_loss_pct']:.1f} % | {100 * k['recovered_share']:.0f} % "
                    f"({_thousands(k['recovered_s'])} s of {_thousands(k['open_loss_s'])} s) |")
    h = summary["replan_3600"]
    fails = summary.get("failed_pairs", {})
    failed = "".join(f"Failed pairs, {k}: {', '.join(map(str, v))}.  " for k, v in fails.items() if v and len(v) <= 5)
    return ("\n".join(rows) + f"\n\nCPU per re-plan (every hour): {1e3 * h['cpu_per_plan_mean_s']:.0f} ms mean, "
            f"{1e3 * h['cpu_per_plan_max_s']:.0f} ms at most (`time.process_time`), {h['replans_mean']:.0f} re-plans "
            f"per flight on average.  {failed}Open loop's mean time over the oracle: over the pairs where it, the "
            f"oracle and the hourly re-planned flight all arrive.  {setting[:1].upper()}{setting[1:]}.")


def ensemble_lofoten(seeds: int = 100) -> dict[str, str]:
    """Forecast vs truth on ``lofoten-two-models`` over ``seeds`` start/goal pairs (benchmarks/ensemble.py)."""
    from benchmarks import ensemble

    load0, t0 = _load(), time.perf_counter()
    intervals = (3600.0, 1800.0)
    rows = [ensemble.pair_row(i, intervals) for i in range(seeds)]
    summary = ensemble.summarise(rows, intervals)
    summary["failed_pairs"] = {"oracle": [r["pair"] for r in rows if not r.get("oracle_success", True)],
                               "open loop": [r["pair"] for r in rows if not r["open_success"]],
                               **{f"re-planned every {iv / 60:.0f} min": [r["pair"] for r in rows
                                                                          if not r[f"replan_{iv:g}"]["success"]]
                                  for iv in intervals}}
    return ensemble_text(summary, seeds, time.perf_counter() - t0, f"{load0} at the start, {_load()} at the end")


def kill_points(seeds: int = 0) -> dict[str, str]:
    """``tools/kill_points.py``: a run killed at every atomic replace (before and after), then run again.

    ``seeds`` is unused (the kill points are deterministic); it keeps the HEAVY signature.
    """
    import subprocess

    load0 = _load()
    r = subprocess.run([sys.executable, str(ROOT / "tools" / "kill_points.py")], capture_output=True, text=True,
                       check=False)
    kills = [ln for ln in r.stdout.splitlines() if ln.startswith("kill ")]
    whole = sum(ln.endswith(", whole") for ln in kills)
    if not kills:
        raise SystemExit(f"tools/kill_points.py: no kill point ran\n{r.stdout}{r.stderr}")
    return {"kill-points": f"{whole} of {len(kills)} (`auvplan run track-single` killed before and after each of "
                           f"its {len(kills) // 2} atomic replaces; load {load0})"}


def _signed(x: float, digits: int) -> str:
    return f"{x:+.{digits}f}".replace("-", "−")


def endurance_table(rows: Sequence[Row]) -> str:
    """docs/endurance.md's table: each run's predicted time and energy against its closed-loop flight."""
    out = ["| scenario, speeds | legs | mission time pred / flown | mission energy pred / flown (naive) | per-leg max "
           "error, time / energy | naive per-leg max (median) | legs within 5 % |",
           "| --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        if "legs" not in r:
            out.append(f"| `{r['scenario']}`, {r['speeds']} | {r['status']} | | | | | |")
            continue
        lo, hi = r["leg_speeds_min_max"]
        speeds = f"{lo:.1f} m/s" if hi - lo < 1e-6 else f"{lo:.2f}–{hi:.2f} m/s"
        out.append(f"| `{r['scenario']}`, {r['speeds']} {speeds} | {r['legs']} | {r['duration_pred_s']:.0f} / "
                   f"{r['duration_flown_s']:.0f} s ({_signed(r['mission_time_err_pct'], 2)} %) | "
                   f"{r['energy_pred_wh']:.1f} / {r['energy_flown_wh']:.1f} Wh (naive {r['energy_naive_wh']:.1f}, "
                   f"{_signed(r['mission_naive_energy_err_pct'], 1)} %) | {r['leg_time_err_pct_max']:.2f} / "
                   f"{r['leg_energy_err_pct_max']:.2f} % | {r['leg_naive_time_err_pct_max']:.1f} % "
                   f"({r['leg_naive_time_err_pct_median']:.1f} %) | {r['legs_within_5pct']}/{r['legs']} |")
    return "\n".join(out)


def endurance_summary(rows: Sequence[Row]) -> str:
    """The endurance table in one line (README): legs within 5 %, the worst leg and mission errors, the naive ones."""
    done = [r for r in rows if "legs" in r]
    legs, within = sum(r["legs"] for r in done), sum(r["legs_within_5pct"] for r in done)
    worst_leg = max(max(r["leg_time_err_pct_max"], r["leg_energy_err_pct_max"]) for r in done)
    worst = max(max(abs(r["mission_time_err_pct"]), abs(r["mission_energy_err_pct"])) for r in done)
    naive = [abs(r["mission_naive_energy_err_pct"]) for r in done]
    scenes = ", ".join(dict.fromkeys(f"`{r['scenario']}`" for r in done))
    return (f"{within}/{legs} legs predicted within 5 % of the closed-loop flight in time and energy (worst leg "
            f"{worst_leg:.1f} %, worst mission {worst:.2f} %) against {min(naive):.0f}–{max(naive):.0f} % off over the "
            f"mission for length / speed in still water ({scenes}, fixed and least-energy speeds, {len(done)} runs)")


def endurance_prediction(seeds: int = 0) -> dict[str, str]:
    """benchmarks/endurance.py on its three scenarios, fixed and energy speeds (deterministic: each scenario's seed).

    ``seeds`` is unused (each run takes its scenario's own seed); it keeps the HEAVY signature.
    """
    from benchmarks import endurance

    load0, t0 = _load(), time.perf_counter()
    scenes = ("juan-de-fuca-tides", "marcus-wake", "showcase")
    rows = [endurance.one(name, sp) for name in scenes for sp in ("fixed", "energy")]
    pnr = "; ".join(f"`{r['scenario']}` ({r['speeds']}): {r['pnr']}" for r in rows if "pnr" in r)
    return {"endurance-summary": endurance_summary(rows),
            "endurance-prediction": endurance_table(rows) + f"\n\nPoint of no return: {pnr}.  Measured by "
            f"`tools/docs_figures.py bench endurance-prediction` (`benchmarks/endurance.py`'s `one`, each scenario's "
            f"own seed, one process): {time.perf_counter() - t0:.0f} s wall, load {load0} at the start, {_load()} at "
            f"the end."}


HEAVY: dict[str, Callable[..., dict[str, str]]] = {
    "endurance-prediction": endurance_prediction,
    "doc001-tracking": doc001_tracking,
    "formation-chagos": formation_chagos,
    "kill-points": kill_points,
    "ensemble-lofoten": ensemble_lofoten,
}
"""Heavy measurements by name: ``make docs-bench`` runs each (one at a time); each returns its figures,
``{figure name: text}``, written to docs/figures/NAME.md.  Each takes ``seeds`` (its default is the
documented setting)."""
