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

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # benchmarks/ is a folder of the repository, not of the package
    sys.path.insert(0, str(ROOT))

__all__ = ["tracking_table", "doc001_tracking", "formation_text", "formation_chagos", "HEAVY"]

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
    wide = [r for r in ok if max(r[f"{n}_max_m"] for n in names) > 10.0]
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
             f"{sorted({r['reshaped'] for r in ok})}. {len(wide)} runs have a largest formation error above 10 m "
             + (f"(least obstacle distance in them {max(r['min_obstacle_distance_m'] for r in wide):.1f} m or less)"
                if wide else "") + (f"; in the other {len(narrow)} no vehicle strayed more than "
                                    f"{max(r[f'{n}_max_m'] for r in narrow for n in names):.1f} m from its slot"
                                    if narrow else "") + ".",
             "", "| vehicle | formation error RMS median / worst (m) | max median / worst (m) |", "|---|---|---|"]
    for name in names:
        rms = np.array([r[f"{name}_rms_m"] for r in ok])
        mx = np.array([r[f"{name}_max_m"] for r in ok])
        lines.append(f"| {name} | {np.median(rms):.2f} / {rms.max():.2f} | {np.median(mx):.1f} / {mx.max():.1f} |")
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
    return {"ensemble-replan": f"{line}; {setting}"}


def ensemble_lofoten(seeds: int = 100) -> dict[str, str]:
    """Forecast vs truth on ``lofoten-two-models`` over ``seeds`` start/goal pairs (benchmarks/ensemble.py)."""
    from benchmarks import ensemble

    load0, t0 = _load(), time.perf_counter()
    intervals = (3600.0, 1800.0)
    rows = [ensemble.pair_row(i, intervals) for i in range(seeds)]
    summary = ensemble.summarise(rows, intervals)
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


HEAVY: dict[str, Callable[..., dict[str, str]]] = {
    "doc001-tracking": doc001_tracking,
    "formation-chagos": formation_chagos,
    "kill-points": kill_points,
    "ensemble-lofoten": ensemble_lofoten,
}
"""Heavy measurements by name: ``make docs-bench`` runs each (one at a time); each returns its figures,
``{figure name: text}``, written to docs/figures/NAME.md.  Each takes ``seeds`` (its default is the
documented setting)."""
