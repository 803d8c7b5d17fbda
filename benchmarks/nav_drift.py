"""Planned fixes flown with a drifting navigation estimate (issue 52; ``docs/navigation.md``).

    /work/heavy .venv/bin/python benchmarks/nav_drift.py [--scenario mariana-nav] [--seeds 200]
        [--out results/nav] [--figure nav-drift]

The scenario's route (its fixed ``[mission] route``, fitted to the vehicle) is planned twice: with
``[navigation]`` as written (``fixes = "plan"``: the fewest surfacings) and with perfect navigation
(``fixes = "none"``: the same route with no fix).  Each is flown ``--seeds`` times by the closed loop
(:func:`auvplan.sim.simulate`) with a drifting estimate (``Mission.nav_drift``: the budget's own model,
drawn per seed, :mod:`auvplan.sim.drift`): the vehicle steers by its estimate, every fix resets it.
Per flight: contact with the seabed, arrival, the true error's largest value against the budget E.
Flights are appended to ``planned.jsonl`` and ``perfect.jsonl`` as they are flown (a rerun resumes;
``--part`` flies one of the two, so two processes can share the work).  Writes ``nav_drift.json`` and,
with ``--figure NAME``, ``docs/figures/NAME.md`` (quoted in docs/navigation.md).
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.missions.deploy import predicted_duration
from auvplan.io.scenario import loader as scenario
from auvplan.sim import simulate
from auvplan.sim.navigation import navigation_plan
from auvplan.sim.pipeline import planned_route


def fly(world, mission, route, kinds, seeds, log):  # type: ignore[no-untyped-def]
    """Fly the route once per seed with drift; one row per flight (also appended to ``log`` as it is flown)."""
    done = {}
    if log.exists():  # resume: the flights already flown
        for line in log.read_text().splitlines():
            row = json.loads(line)
            done[row["seed"]] = row
    rows = []
    for seed in range(seeds):
        if seed in done:
            rows.append(done[seed])
            continue
        r = simulate(world, mission, route=route, rng=seed, fix_kinds=kinds)
        row = {"seed": seed, "status": r.status.value, "arrived": bool(r.arrived),
               "contacts": int(r.metrics["collisions"]), "min_altitude_m": float(r.metrics["min_altitude_m"]),
               "nav_error_max_m": float(r.nav_error.max()) if r.nav_error is not None else 0.0,
               "duration_s": float(r.t[-1])}
        rows.append(row)
        with log.open("a") as f:
            f.write(json.dumps(row) + "\n")
    return rows


def summary(rows, budget, planned_s):  # type: ignore[no-untyped-def]
    """Counts over the flights; the flown time of the arrived ones against the planned time."""
    err = np.array([r["nav_error_max_m"] for r in rows])
    flown = np.array([r["duration_s"] for r in rows if r["arrived"] and "duration_s" in r])
    dev = (flown / planned_s - 1.0) * 100.0 if flown.size else np.array([np.nan])
    return {"planned_duration_s": planned_s, "flown_duration_dev_pct": [float(dev.min()), float(dev.max())],
            "flights": len(rows), "arrived": sum(r["arrived"] for r in rows),
            "with_contact": sum(r["contacts"] > 0 for r in rows),
            "error_within_budget": int((err <= budget).sum()), "error_max_m": float(err.max()),
            "error_p50_m": float(np.median(err)), "min_altitude_m": min(r["min_altitude_m"] for r in rows)}


def main() -> None:  # noqa: D103
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="mariana-nav")
    ap.add_argument("--seeds", type=int, default=200)
    ap.add_argument("--out", default="results/nav")
    ap.add_argument("--figure", default="")
    ap.add_argument("--part", choices=("both", "planned", "perfect", "summary"), default="both",
                    help="fly only one of the two missions (two processes), or summarise the flights flown so far")
    a = ap.parse_args()
    t0 = time.process_time()
    sc = scenario.load(a.scenario)
    world, mission = scenario.build(sc)
    nav = mission.navigation
    assert nav is not None, f"{a.scenario} has no [navigation]"
    _, route = planned_route(world, mission, sc.seed)
    assert route is not None
    plan = navigation_plan(world, mission, route)
    assert plan is not None and plan.ok, plan.message if plan else ""
    load0 = os.getloadavg()
    out_dir = Path(a.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    if a.part in ("both", "planned"):
        planned = fly(world, replace(mission, nav_drift=True), plan.points, plan.kinds, a.seeds,
                      out_dir / "planned.jsonl")
    perfect = replace(mission, navigation=replace(nav, fixes="none"), nav_drift=True)
    if a.part in ("both", "perfect"):
        naive = fly(world, perfect, route, ("",) * len(route), a.seeds, out_dir / "perfect.jsonl")
    if a.part in ("planned", "perfect"):
        return
    if a.part == "summary":  # the flights flown so far, whatever their number
        planned, naive = ([json.loads(x) for x in (out_dir / f"{k}.jsonl").read_text().splitlines()]
                          for k in ("planned", "perfect"))
    m = plan.metrics()
    # the planned times as the flights fly them: from the launch's dive at the surface (wave 18), the waits included
    t_plan = predicted_duration(world, plan.points, mission.vehicle.speed, plan.dwell_s)
    t_route = predicted_duration(world, route, mission.vehicle.speed)
    out = {"scenario": a.scenario, "seeds": a.seeds, "budget_m": nav.max_error_m, "confidence": nav.confidence,
           "route_km": float(np.hypot(*np.diff(route[:, :2], axis=0).T).sum() / 1000), **m,
           "planned": summary(planned, nav.max_error_m, t_plan),
           "perfect_navigation": summary(naive, nav.max_error_m, t_route),
           "cpu_s": time.process_time() - t0, "load": [load0, os.getloadavg()],
           "rows": {"planned": planned, "perfect_navigation": naive}}
    (out_dir / "nav_drift.json").write_text(json.dumps(out, indent=1) + "\n")
    p, q = out["planned"], out["perfect_navigation"]
    seeds = f"seeds 0-{p['flights'] - 1}" if p["flights"] == q["flights"] else \
        f"seeds 0-{p['flights'] - 1} and 0-{q['flights'] - 1}"
    fewer = 100.0 * (1 - m["fixes"] / m["fixes_fixed_period"]) if m["fixes_fixed_period"] else float("nan")
    text = (f"`{a.scenario}` ({out['route_km']:.1f} km, E = {nav.max_error_m:g} m at {nav.confidence:g} σ): "
            f"{m['fixes']} planned fixes against {m['fixes_fixed_period']} for the best fixed period "
            f"({m['fixed_period_s']:.0f} s) with the same largest predicted error {m['nav_error_max_m']:.1f} m "
            f"({fewer:.0f} % fewer); flown with drift over {p['flights']} seeds: {p['arrived']} arrived, "
            f"{p['with_contact']} with a contact, true error within E in {p['error_within_budget']} "
            f"(largest {p['error_max_m']:.1f} m, median of the largest {p['error_p50_m']:.1f} m), least altitude "
            f"{p['min_altitude_m']:.1f} m, flown time {p['flown_duration_dev_pct'][0]:+.2f} to "
            f"{p['flown_duration_dev_pct'][1]:+.2f} % of the planned {p['planned_duration_s']:.0f} s "
            f"(surface dwells held); the same route planned with perfect navigation (no fix), flown with "
            f"the same drift: {q['arrived']} arrived, {q['with_contact']} with a contact, true error within E in "
            f"{q['error_within_budget']} (largest {q['error_max_m']:.0f} m), least altitude "
            f"{q['min_altitude_m']:.1f} m; load average "
            f"{load0[0]:.2f} when summarised on 2 cores "
            f"({seeds}; `benchmarks/nav_drift.py --scenario {a.scenario} --seeds {a.seeds}`)")
    print(text)
    if a.figure:
        Path("docs/figures", f"{a.figure}.md").write_text(text + "\n")


if __name__ == "__main__":
    main()
