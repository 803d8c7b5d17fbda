"""Endurance predictions against the closed loop on real built-in scenarios (issue 38).

    .venv/bin/python benchmarks/endurance.py [--scenarios juan-de-fuca-tides showcase marcus-wake]
                                             [--speeds fixed energy] [--out results/endurance]

For each scenario (and each ``[endurance] speeds`` choice) the mission is planned and flown by the
same pipeline as ``auvplan run``; then, leg by leg, the predicted duration and energy
(:func:`auvplan.endurance.mission_budget`: the legs flown through the time-varying current from the
departure) are compared with the closed-loop flight's (:func:`auvplan.endurance.flown_energy`:
power of the reconstructed through-water speed, legs split where the progress along the route
passes each waypoint), beside the naive estimate (length / speed in still water, energy P(V) ×
that).  Errors are relative to the flight, in percent; ``legs_within_5pct`` counts the legs whose
predicted time and energy are both within 5 %.  The point of no return is printed too.  Numbers
are in ``docs/endurance.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.endurance import EnduranceParams, assess
from auvplan.io.scenario import loader as scenario
from auvplan.sim import run_mission, with_leg_speeds


def _pct(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.asarray(100.0 * (a - b) / b)


def one(name: str, speeds: str) -> dict:
    """Plan, fly and compare one scenario with one speed choice."""
    sc = scenario.load(name)
    world, mission = scenario.build(sc)
    mission = replace(mission, endurance=replace(mission.endurance, speeds=speeds))
    c0 = time.process_time()
    rec = run_mission(world, mission, sc.seed)
    cpu_run = time.process_time() - c0
    if rec.sim is None or rec.route.shape[0] < 2:
        return {"scenario": name, "speeds": speeds, "status": rec.status.value}
    sim = rec.sim
    flown_mission = with_leg_speeds(world, mission, rec.route)
    c0 = time.process_time()
    e = assess(world, rec.route, mission.vehicle, EnduranceParams(speeds=speeds), 0.0,
               (sim.t, sim.position, sim.progress), flown_mission.leg_speeds or None)
    cpu_assess = time.process_time() - c0
    b, f = e.budget, e.flown
    assert f is not None
    dur_pred, dur_flown = b.t_end - b.t_start, f.t_end - f.t_start
    v = b.speed_water
    dur_naive = b.length_m / v
    e_naive = b.model.power(v) * dur_naive / 3600.0
    ok = dur_flown > 0
    t_err, e_err = _pct(dur_pred[ok], dur_flown[ok]), _pct(b.energy_leg_wh[ok], f.energy_wh[ok])
    tn_err, en_err = _pct(dur_naive[ok], dur_flown[ok]), _pct(e_naive[ok], f.energy_wh[ok])
    within = int(np.sum((np.abs(t_err) <= 5.0) & (np.abs(e_err) <= 5.0)))
    return {
        "scenario": name, "speeds": speeds, "status": rec.status.value, "legs": int(ok.sum()),
        "length_m": float(b.length_m.sum()), "leg_speeds_min_max": [float(v.min()), float(v.max())],
        "duration_pred_s": b.duration_s, "duration_flown_s": float(sim.t[-1]),
        "duration_naive_s": float(dur_naive.sum()),
        "energy_pred_wh": b.energy_wh, "energy_flown_wh": f.energy.energy_wh, "energy_naive_wh": float(e_naive.sum()),
        "mission_time_err_pct": 100.0 * (b.duration_s - sim.t[-1]) / sim.t[-1],
        "mission_energy_err_pct": 100.0 * (b.energy_wh - f.energy.energy_wh) / f.energy.energy_wh,
        "mission_naive_energy_err_pct": 100.0 * (float(e_naive.sum()) - f.energy.energy_wh) / f.energy.energy_wh,
        "leg_time_err_pct_max": float(np.abs(t_err).max()), "leg_energy_err_pct_max": float(np.abs(e_err).max()),
        "leg_time_err_pct_median": float(np.median(np.abs(t_err))),
        "leg_naive_time_err_pct_max": float(np.abs(tn_err).max()),
        "leg_naive_energy_err_pct_max": float(np.abs(en_err).max()),
        "leg_naive_time_err_pct_median": float(np.median(np.abs(tn_err))),
        "legs_within_5pct": within, "margin_wh": b.margin_wh, "pnr": e.pnr.message,
        "cpu_run_s": cpu_run, "cpu_assess_s": cpu_assess,
        "per_leg": [{"leg": i, "length_m": float(b.length_m[i]), "pred_s": float(dur_pred[i]),
                     "flown_s": float(dur_flown[i]), "naive_s": float(dur_naive[i]),
                     "pred_wh": float(b.energy_leg_wh[i]), "flown_wh": float(f.energy_wh[i]),
                     "naive_wh": float(e_naive[i])} for i in range(v.size)],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", nargs="+", default=["juan-de-fuca-tides", "showcase", "marcus-wake"])
    ap.add_argument("--speeds", nargs="+", default=["fixed", "energy"], choices=["fixed", "energy", "time"])
    ap.add_argument("--out", default="results/endurance")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"load: {os.getloadavg()[0]:.2f} (1-min average, 2 cores shared)")
    rows = []
    for name in args.scenarios:
        for sp in args.speeds:
            r = one(name, sp)
            rows.append(r)
            if "legs" not in r:
                print(f"{name} [{sp}]: {r['status']}")
                continue
            print(f"{name} [{sp}]: {r['status']}, {r['legs']} legs, {r['length_m'] / 1000:.1f} km, speeds "
                  f"{r['leg_speeds_min_max'][0]:.3f}-{r['leg_speeds_min_max'][1]:.3f} m/s; mission time "
                  f"{r['duration_pred_s']:.0f} s predicted / {r['duration_flown_s']:.0f} s flown "
                  f"({r['mission_time_err_pct']:+.2f} %), naive {r['duration_naive_s']:.0f} s; "
                  f"energy {r['energy_pred_wh']:.1f} / {r['energy_flown_wh']:.1f} Wh "
                  f"({r['mission_energy_err_pct']:+.2f} %), naive {r['energy_naive_wh']:.1f} Wh "
                  f"({r['mission_naive_energy_err_pct']:+.1f} %); per leg |err| max "
                  f"time {r['leg_time_err_pct_max']:.2f} %, energy {r['leg_energy_err_pct_max']:.2f} % "
                  f"(naive {r['leg_naive_time_err_pct_max']:.1f} %, "
                  f"median {r['leg_naive_time_err_pct_median']:.1f} %); "
                  f"{r['legs_within_5pct']}/{r['legs']} legs within 5 %; {r['pnr']}; CPU run {r['cpu_run_s']:.1f} s, "
                  f"assess {r['cpu_assess_s']:.2f} s")
    (out / "endurance.json").write_text(json.dumps(rows, indent=1) + "\n")
    print(f"rows in {out / 'endurance.json'}")


if __name__ == "__main__":
    main()
