"""Document 001 compared like with like over seeds, and the simulator's speed.

    nice -n 5 .venv/bin/python benchmarks/tracking.py --seeds 10 --out results/bench-tracking

On the four document scenarios (``track-arc``, ``track-single``, ``track-double``, ``track-multi``)
every law is flown with and without crab-angle current compensation: the document's hybrid field
as written (``[guidance.hybrid] variant = "document"``: eqs. 3–8, goal-distance factor uncapped, no
lateral bias), the corrected field (capped factor, lateral bias), the corrected field without its
lateral bias (an ablation: which addition matters), LOS and ILOS
(``[guidance.los] current_compensation``).  Everything else is the scenario's own (vehicle, waves,
current, ``dt``).  Writes ``summary.md`` (one table per scenario: arrivals, runs with a collision
and where, cross-track RMS / max median and worst, least obstacle distance, flight time, CPU per
run), ``rows.csv`` (one row per run) and the wall time of a 1-hour mission (5.4 km straight route
at 1.5 m/s, dt = 0.1 s, waves on) against a plain numpy loop of the same step count measured in
the same run, with the machine's load average.
"""

from __future__ import annotations

import argparse
import csv
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.sim import Mission, simulate
from auvplan.vehicles import VehicleParams
from auvplan.world import Bounds, UniformCurrent, World

SCENES = ("track-arc", "track-single", "track-double", "track-multi")
LAWS = ("document", "corrected", "capped", "los", "ilos")
LABEL = {"document": "hybrid, document field", "corrected": "hybrid, corrected field",
         "capped": "hybrid, capped factor, no bias (ablation)", "los": "LOS", "ilos": "ILOS"}

GAP = (300.0, 10.0)
"""track-double's obstacles at x = 300 m, y = ±10 m: a run passes between them when it first reaches
x = 300 m with |y| < 10 m (document 001's double-obstacle claim)."""


def configure(mission: Mission, law: str, compensate: bool) -> tuple[Mission, str]:
    """The mission flown by ``law`` with or without current compensation, and the guidance name."""
    if law in ("document", "corrected", "capped"):
        hp = replace(mission.hybrid, variant="corrected" if law == "capped" else law, current_compensation=compensate,
                     lateral_bias=0.0 if law == "capped" else mission.hybrid.lateral_bias)
        return replace(mission, hybrid=hp), "hybrid"
    return replace(mission, los=replace(mission.los, current_compensation=compensate)), law


def fly(name: str, law: str, compensate: bool, seeds: int) -> list[dict]:
    """One row per seed: the run's metrics, its CPU time and the first collision's text."""
    world, mission = sc.build(sc.load(name))
    m, guidance = configure(mission, law, compensate)
    rows = []
    for seed in range(seeds):
        t0 = time.process_time()
        r = simulate(world, m, guidance=guidance, rng=seed)
        cpu = time.process_time() - t0
        mt = r.metrics
        hit = next((e[2] for e in r.events if e[1] in ("collision", "unavoidable")), "")
        ahead = np.flatnonzero(r.position[:, 0] >= GAP[0])  # track-double: through the gap at x = 300?
        between = bool(ahead.size) and bool(abs(r.position[ahead[0], 1]) < GAP[1])
        rows.append({"scenario": name, "law": law, "compensation": compensate, "seed": seed, "status": mt["status"],
                     "arrived": mt["arrived"], "collisions": mt["collisions"], "rms_m": mt["cross_track_rms_m"],
                     "max_m": mt["cross_track_max_m"], "min_obstacle_m": mt["min_obstacle_distance_m"],
                     "duration_s": mt["duration_s"], "cpu_s": cpu, "collision": hit,
                     "between": between if name == "track-double" else ""})
    return rows


def _f(v: float, fmt: str = ".2f") -> str:
    return "—" if not np.isfinite(v) else format(v, fmt)


def cell(rows: list[dict]) -> str:
    """One markdown table row for the runs of one law and compensation on one scenario."""
    n = len(rows)
    rms = np.array([r["rms_m"] for r in rows])
    mx = np.array([r["max_m"] for r in rows])
    dmin = np.array([r["min_obstacle_m"] for r in rows])
    arrived = [r for r in rows if r["arrived"]]
    dur = np.median([r["duration_s"] for r in arrived]) if arrived else float("nan")
    hit = [r["seed"] for r in rows if r["collisions"]]
    left = [r["status"] for r in rows if not r["arrived"] and not r["collisions"]]
    other = [f"{left.count(s)} {s}" for s in sorted(set(left))]
    r0 = rows[0]
    return (f"| {LABEL[r0['law']]} | {'yes' if r0['compensation'] else 'no'} | {len(arrived)}/{n} | "
            f"{len(hit)}/{n}{' (seeds ' + ', '.join(map(str, hit)) + ')' if hit else ''}"
            f"{' + ' + ', '.join(other) if other else ''} | {np.median(rms):.2f} / {rms.max():.2f} | "
            f"{np.median(mx):.2f} / {mx.max():.2f} | {_f(float(np.median(dmin)))} / {_f(float(dmin.min()))} | "
            f"{_f(float(dur), '.0f')} | {np.median([r['cpu_s'] for r in rows]):.2f} |")


HEADER = ("| law | current compensation | arrived | runs with a collision | cross-track RMS median / worst (m) | "
          "cross-track max median / worst (m) | least obstacle distance median / worst (m) | "
          "flight time median (s) | CPU per run median (s) |\n|---|---|---|---|---|---|---|---|---|")


def comparison(seeds: int, scenes=SCENES) -> tuple[str, list[dict]]:
    """The markdown tables (one per scenario) and every run's row."""
    parts, every = [], []
    for name in scenes:
        lines, gap = [f"### {name}\n", HEADER], []
        for law in LAWS:
            for compensate in (False, True):
                rows = fly(name, law, compensate, seeds)
                every += rows
                lines.append(cell(rows))
                gap.append(f"{LABEL[law]}{' + crab' if compensate else ''} {sum(r['between'] is True for r in rows)}")
        hits = [r for r in every if r["scenario"] == name and r["collision"] and r["law"] not in ("los", "ilos")]
        if hits:
            lines.append("\nHybrid-field collisions: " + "; ".join(
                f"{r['law']}{' + crab' if r['compensation'] else ''} seed {r['seed']}: {r['collision']}" for r in hits))
        if name == "track-double":
            lines.append(f"\nPassed between the two obstacles (first reached x = 300 m with |y| < 10 m), of {seeds}: "
                         + ", ".join(gap))
        parts.append("\n".join(lines))
    return "\n\n".join(parts), every


def hour_mission() -> tuple[float, float, int]:
    length = 1.5 * 3600.0
    world = World(Bounds(-100, length + 100, -500, 500, -100, 0), currents=UniformCurrent((0.0, 0.2, 0.0)))
    mission = Mission("hour", (0, 0, -20), (length, 0, -20), route=((0, 0, -20), (length, 0, -20)),
                      vehicle=VehicleParams(wave_sigma_r=0.01, wave_sigma_v=0.05))
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        r = simulate(world, mission, guidance="hybrid", rng=0)
        best = min(best, time.perf_counter() - t0)
    steps = r.t.size
    # peer in the same run: the bare cost of a Python loop doing one numpy call per step
    t0 = time.perf_counter()
    x = np.zeros(3)
    for _ in range(steps):
        x = x + 0.1
    loop = time.perf_counter() - t0
    return best, loop, steps


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--scenarios", nargs="+", default=list(SCENES), choices=SCENES)
    ap.add_argument("--no-hour", action="store_true", help="skip the 1-hour mission timing")
    ap.add_argument("--out", default="results/bench-tracking")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    tables, rows = comparison(args.seeds, args.scenarios)
    wall = time.perf_counter() - t0
    with open(out / "rows.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    text = (f"# Document 001 compared like with like, {args.seeds} seeds\n\n"
            f"{len(rows)} runs in {wall:.0f} s wall; load average {load0:.1f} at the start, "
            f"{os.getloadavg()[0]:.1f} at the end (shared 2-core machine).\n\n{tables}\n")
    if not args.no_hour:
        hw, loop, steps = hour_mission()
        text += (f"\n1-hour mission ({steps} steps of 0.1 s): {hw:.2f} s wall ({hw / steps * 1e6:.1f} µs per step; "
                 f"a bare one-numpy-op loop of the same length: {loop:.3f} s, ratio {hw / loop:.1f}x; "
                 f"load average {os.getloadavg()[0]:.1f})\n")
    (out / "summary.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
