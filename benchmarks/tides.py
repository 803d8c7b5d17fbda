"""Tidal currents and time-optimal planning on the built-in ``juan-de-fuca-tides`` scenario.

    .venv/bin/python benchmarks/tides.py [--hours 25] [--step 30] [--out results/tides]

Measures (CPU time by ``time.process_time``; the machine's load from ``uptime`` is printed too: it is
shared, so wall times mean little):

* one timed plan (50 km, 500 m cells, 4 depth levels, 10 min table): lattice + current table, the
  label-setting search and the refinement;
* a departure sweep over ``--hours`` every ``--step`` minutes: the best departure's duration and
  energy against the worst departure, the straight line and the steady-current plan (the plan for the
  current frozen at the departure, flown through the real one), in percent saved;
* the peer, when ``benchmarks/tides_hj.py`` has written its result (hj_reachability in its own venv,
  see that file) — the same 2D slice solved as a Hamilton–Jacobi reachability front.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import time
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as scenario
from auvplan.planners.timeopt.planner import departure_sweep, plan_timeopt, setup, sweep_summary
from auvplan.sim import planning_problem


def _slice(problem, spec, out: Path) -> dict:
    """Our planner on the peer's problem — one level at the start's depth, departure 0 — and that
    problem (current table, free mask, ends) written to ``slice.npz`` for ``tides_hj.py``."""
    flat = replace(spec, timeopt=replace(spec.timeopt, levels=1))
    c0 = time.process_time()
    ts = setup(problem, flat, 0.0, 0.0)
    r = plan_timeopt(problem, flat, ts)
    cpu = time.process_time() - c0
    lat = ts.lattice
    np.savez(out / "slice.npz", origin=lat.origin, step=lat.step, shape=np.array(lat.shape),
             free=lat.free.reshape(lat.shape)[:, :, 0], cur=ts.table.cur[:, :, :, 0, :2], t0=ts.table.t0,
             dt=ts.table.dt, start=problem.start, goal=problem.goal, speed=problem.speed)
    return {"duration_s": r.cost_terms["duration_s"], "cpu_s": cpu, "status": r.status.value,
            "nodes": int(lat.free.sum()), "shape": lat.shape}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--hours", type=float, default=25.0)
    ap.add_argument("--step", type=float, default=30.0, help="minutes")
    ap.add_argument("--out", default="results/tides")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print("load:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip(), "cpus", os.cpu_count())
    world, mission = scenario.build(scenario.load("juan-de-fuca-tides"))
    problem = planning_problem(world, mission)
    spec = mission.planner
    plan_timeopt(problem, spec)  # compile the kernels once (cached on disk afterwards)
    c0, w0 = time.process_time(), time.perf_counter()
    ts = setup(problem, spec, 0.0, 0.0)
    c1 = time.process_time()
    result = plan_timeopt(problem, spec, ts)
    c2, w2 = time.process_time(), time.perf_counter()
    one = {"lattice_shape": ts.lattice.shape, "free_nodes": int(ts.lattice.free.sum()), "legs": ts.lattice.legs,
           "table_steps": ts.table.cur.shape[0], "setup_cpu_s": c1 - c0, "search_refine_cpu_s": c2 - c1,
           "total_cpu_s": c2 - c0, "wall_s": w2 - w0, "duration_h": result.cost_terms["duration_s"] / 3600.0,
           "length_km": result.cost_terms["length_m"] / 1e3, "status": result.status.value}
    print("one plan:", json.dumps(one))
    departs = np.arange(0.0, args.hours * 3600.0 + 1.0, args.step * 60.0)
    c3, w3 = time.process_time(), time.perf_counter()
    rows, _ = departure_sweep(problem, replace(spec, name="timeopt"), departs)
    sweep = {"departures": len(rows), "cpu_s": time.process_time() - c3, "wall_s": time.perf_counter() - w3}
    summary = sweep_summary(rows)
    print("sweep:", json.dumps(sweep))
    slice2d = _slice(problem, spec, out)
    print("2D slice (peer's problem):", json.dumps(slice2d))
    print("summary:", json.dumps(summary, indent=1))
    peer = out / "hj_reachability.json"
    result_doc = {"one_plan": one, "sweep": sweep, "summary": summary, "slice_2d": slice2d,
                  "rows": [asdict(r) for r in rows]}
    if peer.is_file():
        result_doc["hj_reachability"] = json.loads(peer.read_text())
        print("hj_reachability:", peer.read_text())
    (out / "tides_bench.json").write_text(json.dumps(result_doc, indent=1))
    from auvplan.viz.timeplots import sweep_figure

    sweep_figure(rows, "juan-de-fuca-tides: departure sweep").savefig(out / "sweep.png", dpi=120)
    print("written", out / "tides_bench.json", out / "sweep.png")


if __name__ == "__main__":
    main()
