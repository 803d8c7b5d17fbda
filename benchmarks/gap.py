"""Gap study: is the converged reference the best known plan?  Across the built-in planning
scenarios and the hard ones, ``--seeds`` seeds of every swarm planner (default ``seeded``
pipeline, the scenario's budget or ``--budget``) against :func:`auvplan.planners.reference`
computed once per scenario on the same cost function and budget.

For each scenario: the reference's cost and what won it, the best planner result (which planner,
which seed), and the reference's excess over it, ``100 (reference - best) / best`` — the most
negative gap any run would report.  The target is an excess ≤ 0.05 % everywhere.  Also per
planner: its best and median gap to the reference.  Rows go to ``rows.jsonl`` as they finish
(``--resume`` keeps them), the table to ``gap.md``.  The plans go to dask.distributed (``--workers N``,
default 2; ``--scheduler ADDR``; ``--retries N``: ``benchmarks/parallel_runs.py``); the rows, in task order,
are the same on 1 and N workers but for ``cpu_s`` and ``wall_s``.

    nice -n 5 .venv/bin/python benchmarks/gap.py --seeds 10 --workers 2 --out results/bench-gap
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from parallel_runs import add_arguments, run_all, where  # noqa: E402

PLANNING = ("marcus-wake", "salish-shelf", "admiralty-inlet", "dynamic-terrain", "showcase")
HARD = ("ninetyeast-ridge", "new-england-seamounts", "chagos-banks", "marcus-wake-deep")
PLANNERS = ("iabc", "abc", "ga", "pso", "de")


def _problem(scenario: str, budget: int):
    from auvplan.io.scenario import loader as sc
    from auvplan.sim import planning_problem

    world, mission = sc.build(sc.load(scenario))
    spec = mission.planner if not budget else replace(mission.planner, budget=budget)
    return planning_problem(world, mission), replace(spec, pipeline="seeded")


def run(scenario: str, planner: str, seed: int, budget: int) -> dict:
    """One plan (``planner == "reference"``: the reference)."""
    from auvplan.planners import plan, reference

    prob, spec = _problem(scenario, budget)
    c0, t0 = time.process_time(), time.perf_counter()
    r = reference(prob, spec) if planner == "reference" else plan(prob, replace(spec, name=planner), seed)
    return {"scenario": scenario, "planner": planner, "seed": seed, "status": r.status.value, "cost": r.cost,
            "evaluations": r.evaluations, "budget": spec.evaluations, "message": r.message,
            "cpu_s": time.process_time() - c0, "wall_s": time.perf_counter() - t0}


def _run(task: tuple[str, str, int, int]) -> dict:
    """:func:`run` of one task ``(scenario, planner, seed, budget)``."""
    return run(*task)


def summary(rows: list[dict]) -> list[dict]:
    """Per scenario: reference, best run and the reference's excess over it (%)."""
    out = []
    for scenario in dict.fromkeys(r["scenario"] for r in rows):
        mine = [r for r in rows if r["scenario"] == scenario]
        ref = [r for r in mine if r["planner"] == "reference"]
        runs = [r for r in mine if r["planner"] != "reference" and r["status"] == "EXACT"]
        if not ref or not runs:
            continue
        best = min(runs, key=lambda r: r["cost"])
        ref_cost = ref[0]["cost"]
        row = {"scenario": scenario, "reference": ref_cost, "won_by": ref[0]["message"].rsplit(": ", 1)[-1],
               "best_run": best["cost"], "best_by": f"{best['planner']} seed {best['seed']}",
               "excess_pct": 100.0 * (ref_cost - best["cost"]) / best["cost"], "runs": len(runs),
               "infeasible": sum(r["status"] != "EXACT" for r in mine if r["planner"] != "reference")}
        for p in PLANNERS:
            gaps = [100.0 * (r["cost"] - ref_cost) / ref_cost for r in runs if r["planner"] == p]
            if gaps:
                row[f"{p}_min_gap_pct"], row[f"{p}_median_gap_pct"] = min(gaps), float(np.median(gaps))
        out.append(row)
    return out


def table(summ: list[dict]) -> str:
    lines = ["| scenario | reference (won by) | best planner run | reference − best "
             "| min gap iabc / abc / ga / pso / de |", "|---|---|---|---|---|"]
    for s in summ:
        gaps = " / ".join(f"{s[f'{p}_min_gap_pct']:+.3f}" if f"{p}_min_gap_pct" in s else "—" for p in PLANNERS)
        lines.append(f"| {s['scenario']} | {s['reference']:.7g} ({s['won_by']}) | {s['best_run']:.7g} ({s['best_by']}) "
                     f"| {s['excess_pct']:+.3f} % | {gaps} % |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenarios", nargs="+", default=[*PLANNING, *HARD])
    ap.add_argument("--planners", nargs="+", default=list(PLANNERS))
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--budget", type=int, default=0, help="evaluations per plan (0: the scenario's)")
    ap.add_argument("--resume", action="store_true")
    ap.add_argument("--out", default="results/bench-gap")
    add_arguments(ap, workers=2)
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "rows.jsonl"
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()] \
        if args.resume and path.exists() else []
    done = {(r["scenario"], r["planner"], r["seed"]) for r in rows}
    tasks = [(s, "reference", 0) for s in args.scenarios] + \
            [(s, p, k) for s in args.scenarios for p in args.planners for k in range(args.seeds)]
    tasks = [t for t in tasks if t not in done]
    print(f"{len(tasks)} plans on {where(args)}, load {os.getloadavg()[0]:.1f}", flush=True)
    with path.open("a" if args.resume else "w") as fh:

        def arrived(r: dict) -> None:
            fh.write(json.dumps(r) + "\n")
            fh.flush()
            print(f"{r['scenario']:22s} {r['planner']:9s} {r['seed']:2d} {r['status']:10s} {r['cost']:.8g} "
                  f"{r['wall_s']:6.1f} s", flush=True)

        rows += run_all(args, _run, [(*t, args.budget) for t in tasks], arrived)
    summ = summary(rows)
    (out / "summary.json").write_text(json.dumps(summ, indent=2) + "\n")
    text = table(summ) + f"\nload average at the end: {os.getloadavg()}\n"
    (out / "gap.md").write_text(text)
    print(text)
    worst = max((s["excess_pct"] for s in summ), default=0.0)
    return 0 if worst <= 0.05 else 1


if __name__ == "__main__":
    sys.exit(main())
