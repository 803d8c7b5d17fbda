"""The built-in formation scenario over many seeds: arrivals, collisions, formation error.

    nice -n 5 .venv/bin/python benchmarks/formation.py --seeds 100 --workers 2 --out results/bench-formation

``chagos-formation`` (three vehicles, 600 m line abreast, reshaped to a column through the channel
saddle, re-formed, then a wedge; Lamb–Oseen eddy; three moving obstacles).  Seed 0 flies the
scenario's obstacle tracks; every other seed re-draws them (:func:`auvplan.app.bench.sweep.perturb_moving`:
speeds ×0.6–1.2, starts shifted ±150 m along and across, the circle's phase anywhere).  Writes
``rows.csv`` (one row per seed) and ``summary.md``: arrivals, collisions with the seabed, obstacles
and each other, least vehicle distance, altitude and obstacle distance, formation error RMS/max per
vehicle (median and worst over seeds), and the CPU per vehicle-step against the single-vehicle
simulator flying the same route in the same run (the peer), with the machine's load.  The seeds go to
dask.distributed (``--workers N``, default 1; ``--scheduler ADDR``; ``--retries N``:
``benchmarks/parallel_runs.py``); the rows are the same on 1 and N workers but for ``cpu_s``.
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from pathlib import Path

import numpy as np

from auvplan.app.bench.sweep import perturb_moving
from auvplan.guidance.formation.error import SETTLE_M
from auvplan.io.scenario import loader as sc
from auvplan.sim import simulate
from auvplan.sim.formation import run_formation

sys.path.insert(0, str(Path(__file__).resolve().parent))
from parallel_runs import add_arguments, run_all  # noqa: E402

SCENARIO = "chagos-formation"


def one(seed: int) -> dict:
    world, mission = sc.build(sc.load(SCENARIO))
    if seed:
        world = perturb_moving(world, seed)
    t0 = time.process_time()
    rec = run_formation(world, mission, rng=seed)
    cpu = time.process_time() - t0
    row = {"seed": seed, "status": rec.status.value, "cpu_s": round(cpu, 3)}
    if rec.result is None:
        return row
    m = rec.result.metrics
    steps = sum(r.t.size for r in rec.result.runs)
    row.update({k: m[k] for k in ("arrivals", "collisions", "vehicle_contacts", "min_vehicle_distance_m",
                                  "min_altitude_m", "min_obstacle_distance_m", "duration_s")})
    row["vehicle_steps"] = steps
    if mission.formation is not None:  # the launch scatter the seed draws
        fp = mission.formation.params
        row["start_sigma_m"], row["start_heading_sigma_deg"] = fp.start_sigma_m, fp.start_heading_sigma_deg
    row["reshaped"] = len(rec.formation.reshaped) if rec.formation is not None else 0
    row["events"] = "; ".join(e[2] for e in rec.result.events if e[1] != "arrival")
    for name, v in m["per_vehicle"].items():
        row[f"{name}_rms_m"] = v["formation_error_rms_m"]
        row[f"{name}_max_m"] = v["formation_error_max_m"]
        row[f"{name}_p95_m"] = v["formation_error_p95_m"]
        row[f"{name}_settle_s"] = v["settle_time_s"]
        for k in ("rms", "p95", "max"):  # settled: from the first step within SETTLE_M of the slot
            row[f"{name}_set_{k}"] = v[f"settled_error_{k}_m"]
    return row


def peer() -> tuple[float, int]:
    """CPU and steps of the single-vehicle simulator (hybrid field) flying the same route."""
    world, mission = sc.build(sc.load(SCENARIO))
    t0 = time.process_time()
    res = simulate(world, mission, guidance="hybrid", avoidance="none", rng=0)
    return time.process_time() - t0, res.t.size


def summary(rows: list[dict], peer_cpu: float, peer_steps: int, load: str) -> str:
    n = len(rows)
    ok = [r for r in rows if "arrivals" in r]
    names = sorted({k[:-6] for r in ok for k in r if k.endswith("_rms_m")})
    lines = [f"# {SCENARIO}: {n} seeds", "",
             f"- all three vehicles arrived: {sum(r['arrivals'] == 3 for r in ok)}/{n}; statuses: "
             + ", ".join(f"{s} {sum(r['status'] == s for r in rows)}" for s in sorted({r['status'] for r in rows})),
             f"- collisions (seabed, obstacles, each other): {sum(r['collisions'] for r in ok)} "
             f"(vehicle contacts {sum(r['vehicle_contacts'] for r in ok)})",
             f"- least vehicle distance {min(r['min_vehicle_distance_m'] for r in ok):.1f} m, least altitude "
             f"{min(r['min_altitude_m'] for r in ok):.2f} m, least obstacle distance "
             f"{min(r['min_obstacle_distance_m'] for r in ok):.2f} m",
             f"- reshaped stretches per run: {sorted({r['reshaped'] for r in ok})}", "",
             "| vehicle | formation error RMS median (m) | RMS worst | max median (m) | max worst |",
             "|---|---|---|---|---|"]
    for name in names:
        rms = np.array([r[f"{name}_rms_m"] for r in ok])
        mx = np.array([r[f"{name}_max_m"] for r in ok])
        lines.append(f"| {name} | {np.median(rms):.2f} | {rms.max():.2f} | {np.median(mx):.2f} | {mx.max():.2f} |")
    lines += ["", f"Settled (from the first step within {SETTLE_M:g} m of the slot; the launch scatter before):", "",
              "| vehicle | settle time median / worst (s) | RMS median / worst (m) | p95 median / worst (m) "
              "| max median / worst (m) |", "|---|---|---|---|---|"]
    for name in names:
        st = np.array([r[f"{name}_settle_s"] for r in ok])
        cols = [np.array([r[f"{name}_set_{k}"] for r in ok]) for k in ("rms", "p95", "max")]
        lines.append(f"| {name} | {np.median(st):.0f} / {st.max():.0f} | "
                     + " | ".join(f"{np.median(c):.2f} / {c.max():.2f}" for c in cols) + " |")
    cpu = np.array([r["cpu_s"] for r in ok])
    per = np.array([r["cpu_s"] / r["vehicle_steps"] for r in ok]) * 1e6
    lines += ["", f"CPU per run: median {np.median(cpu):.2f} s; per vehicle-step median {np.median(per):.1f} µs "
              f"against the single-vehicle simulator's {peer_cpu / peer_steps * 1e6:.1f} µs on the same route "
              f"({np.median(per) / (peer_cpu / peer_steps * 1e6):.2f}×), measured in the same run; load average "
              f"{load} (a 2-core machine shared with other jobs)."]
    bad = [r for r in rows if r["status"] != "EXACT"]
    if bad:
        lines += ["", "Failures:"] + [f"- seed {r['seed']}: {r['status']} {r.get('events', '')}" for r in bad]
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--out", default="results/bench-formation")
    add_arguments(ap, workers=1)
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    load0 = os.getloadavg()
    rows = run_all(args, one, range(args.seeds))  # in seed order, whatever order they finish in
    peer_cpu, peer_steps = peer()
    load1 = os.getloadavg()
    keys = sorted({k for r in rows for k in r}, key=lambda k: (k != "seed", k))
    with (out / "rows.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    text = summary(rows, peer_cpu, peer_steps, f"{load0[0]:.1f} → {load1[0]:.1f}")
    (out / "summary.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
