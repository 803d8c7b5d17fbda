"""Two ocean models over one sea (issue 39): robust plans over the ensemble, and re-planning in flight.

    .venv/bin/python benchmarks/ensemble.py [--pairs 100] [--intervals 3600 1800] [--out results/ensemble]
                                            [--workers N] [--figures docs/img]

Built-in scenario ``lofoten-two-models``: MET Norway's Arctic-20km forecast (the vehicle's forecast, the
nominal member) and its Nordic-4km hindcast (the truth) off Lofoten, 2-4 February 2016.  ``--pairs``
start/goal pairs at 50 m depth, more than 20 km apart, in free water, are drawn with a seeded generator
(seed = pair index); each is

* planned robustly (:func:`auvplan.sim.ensemble.robust.plan_robust`, ``p90``) and nominally (on the forecast), both
  flown in both members: the P90 over the two members and the arrival in the other member (the truth);
* flown through the truth (:mod:`auvplan.sim.ensemble.replan`): the oracle (planned on the truth), open loop
  (the forecast's plan flown to its end, then a fix and homing) and re-planned on the forecast from a fix
  every ``interval`` seconds; the loss is open loop minus oracle, the recovered share
  (open loop − re-planned) / loss, summed over the pairs where the open loop arrives.

The pairs run on dask.distributed with ``--workers N`` (a local cluster, one thread a worker; each pair
is seeded by its index, so the rows do not depend on the worker count).  Writes ``summary.json`` and
``pairs.json`` to ``--out`` and, with ``--figures``, the figures of ``docs/ensembles.md``: the flights of
one pair, the nominal and robust routes, and the spread of the forecast plan's tracks and arrival times
flown in a 20-member perturbation ensemble of the forecast.  Numbers are in ``docs/ensembles.md``.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as scenario
from auvplan.io.scenario.inputs.members import scenario_members
from auvplan.sim.ensemble.replan import ReplanParams, fly_open_loop, fly_replanning
from auvplan.sim.ensemble.robust import plan_robust
from auvplan.world.currents.ensemble import PerturbedCurrent


@functools.lru_cache(maxsize=1)
def context():
    """The built-in scenario's world, mission and members (once per process: each dask worker reads them once)."""
    sc = scenario.load("lofoten-two-models")
    world, mission = scenario.build(sc)
    return world, mission, scenario_members(sc, world)


def pair_row(i: int, intervals: tuple[float, ...]) -> dict:
    """Pair i (from seed i) planned, scored and flown: the unit of work of a sweep."""
    world, mission, members = context()
    a, g = pairs(world, i + 1, first=i)[0]
    return {"pair": i, **one(world, mission, members, a, g, intervals)}


def pairs(world, n: int, depth: float = -50.0, min_gap: float = 20000.0,
          first: int = 0) -> list[tuple[np.ndarray, np.ndarray]]:
    """Seeded start/goal pairs in free water (pair i from seed i)."""
    b = world.bounds
    out = []
    for i in range(first, n):
        rng = np.random.default_rng(i)
        while True:
            a = np.r_[rng.uniform(b.xmin + 2000, b.xmax - 2000), rng.uniform(b.ymin + 2000, b.ymax - 2000), depth]
            g = np.r_[rng.uniform(b.xmin + 2000, b.xmax - 2000), rng.uniform(b.ymin + 2000, b.ymax - 2000), depth]
            if np.linalg.norm(a - g) > min_gap and world.is_free(np.stack([a, g])).all():
                out.append((a, g))
                break
    return out


def one(world, mission, members, a, g, intervals) -> dict:
    """Robust vs nominal, and open loop vs re-planned, for one pair."""
    m = replace(mission, start=tuple(a), goal=tuple(g))
    forecast, truth_field = members[0][1], members[1][1]
    truth = replace(world, currents=truth_field)
    row: dict = {"start": a.tolist(), "goal": g.tolist()}
    r = plan_robust(world, m, members, "p90", seed=1)
    if r.nominal.score is None or r.chosen.score is None:
        row["robust"] = None
    else:
        row["robust"] = {"candidate": r.chosen.label,
                         "nominal_p90_s": r.nominal.score.arrival_p90_s, "robust_p90_s": r.chosen.score.arrival_p90_s,
                         "nominal_truth_s": r.nominal.score.members[1].arrival_s,
                         "robust_truth_s": r.chosen.score.members[1].arrival_s}
    oracle = fly_open_loop(truth, truth_field, m, ReplanParams(), seed=1)
    ol = fly_open_loop(truth, forecast, m, ReplanParams(), seed=1)
    row["oracle_s"], row["open_s"], row["open_status"] = oracle.arrival_s, ol.arrival_s, ol.status.value
    row["open_success"], row["oracle_success"] = ol.success, oracle.success
    for iv in intervals:
        t0 = time.process_time()
        rp = fly_replanning(truth, forecast, m, ReplanParams(interval_s=iv), seed=1)
        row[f"replan_{iv:g}"] = {"arrival_s": rp.arrival_s, "status": rp.status.value, "success": rp.success,
                                 "replans": rp.replans, "cpu_per_plan_s": float(np.mean(rp.plan_cpu_s)),
                                 "cpu_max_s": float(np.max(rp.plan_cpu_s)), "cpu_s": time.process_time() - t0}
    return row


def summarise(rows: list[dict], intervals) -> dict:
    """Arrivals, successes, losses and the recovered share."""
    n = len(rows)
    rob = [r["robust"] for r in rows if r["robust"] is not None]
    s: dict = {"pairs": n,
               "robust_p90_below_nominal": sum(x["robust_p90_s"] < x["nominal_p90_s"] - 1e-6 for x in rob),
               "robust_p90_equal_nominal": sum(abs(x["robust_p90_s"] - x["nominal_p90_s"]) <= 1e-6 for x in rob),
               "robust_p90_gain_mean_s": float(np.mean([x["nominal_p90_s"] - x["robust_p90_s"] for x in rob])),
               "robust_truth_gain_mean_s": float(np.mean([x["nominal_truth_s"] - x["robust_truth_s"] for x in rob])),
               "oracle_arrivals": sum(math.isfinite(r["oracle_s"]) for r in rows),
               "open_arrivals": sum(math.isfinite(r["open_s"]) for r in rows),
               "open_successes": sum(r["open_success"] for r in rows),
               "oracle_successes": sum(r.get("oracle_success", False) for r in rows)}
    for iv in intervals:
        k = f"replan_{iv:g}"
        both = [r for r in rows if math.isfinite(r["open_s"]) and math.isfinite(r[k]["arrival_s"])
                and math.isfinite(r["oracle_s"])]
        loss = sum(r["open_s"] - r["oracle_s"] for r in both)
        gain = sum(r["open_s"] - r[k]["arrival_s"] for r in both)
        s[k] = {"arrivals": sum(math.isfinite(r[k]["arrival_s"]) for r in rows),
                "successes": sum(r[k]["success"] for r in rows),
                "open_loss_s": loss, "recovered_s": gain, "recovered_share": gain / loss if loss > 0 else math.nan,
                "mean_open_loss_pct": float(np.mean([100 * (r["open_s"] / r["oracle_s"] - 1) for r in both])),
                "mean_replan_loss_pct": float(np.mean([100 * (r[k]["arrival_s"] / r["oracle_s"] - 1) for r in both])),
                "cpu_per_plan_mean_s": float(np.mean([r[k]["cpu_per_plan_s"] for r in rows])),
                "cpu_per_plan_max_s": float(np.max([r[k]["cpu_max_s"] for r in rows])),
                "replans_mean": float(np.mean([r[k]["replans"] for r in rows]))}
    return s


def _axes(world, members, title):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 6))
    t = world.terrain
    pc = ax.pcolormesh(t.x / 1000, t.y / 1000, t.z, cmap="Blues_r", shading="auto")
    fig.colorbar(pc, ax=ax, label="seabed elevation (m)")
    xx, yy = np.meshgrid(np.linspace(world.bounds.xmin, world.bounds.xmax, 12),
                         np.linspace(world.bounds.ymin, world.bounds.ymax, 12))
    pts = np.c_[xx.ravel(), yy.ravel(), np.full(xx.size, -50.0)]
    for (name, f), col in zip(members, ("tab:orange", "k")):
        c = f.velocity(pts, 43200.0)
        ax.quiver(xx / 1000, yy / 1000, c[:, 0], c[:, 1], color=col, scale=3, width=0.003, label=f"{name} at +12 h")
    ax.set(xlabel="x east (km)", ylabel="y north (km)", title=title)
    return fig, ax


def figures(world, mission, members, out: Path) -> None:
    """Tracks of the oracle, the open loop and the re-planned flight of one pair over the seabed; the nominal
    and the robust routes of the scenario's own mission."""
    a, g = np.array([-15000.0, -15000.0, -50.0]), np.array([15000.0, 15000.0, -50.0])
    m = replace(mission, start=tuple(a), goal=tuple(g))
    truth = replace(world, currents=members[1][1])
    flights = {"oracle (planned on the truth)": fly_open_loop(truth, members[1][1], m, seed=1),
               "open loop (forecast plan)": fly_open_loop(truth, members[0][1], m, seed=1),
               "re-planned every hour": fly_replanning(truth, members[0][1], m, seed=1)}
    fig, ax = _axes(world, members, "truth Nordic-4km, forecast Arctic-20km: flights")
    for (label, fl), col in zip(flights.items(), ("k", "tab:red", "tab:green")):
        ax.plot(fl.track[:, 0] / 1000, fl.track[:, 1] / 1000, color=col,
                label=f"{label}: {fl.arrival_s / 3600:.1f} h" if fl.arrived else f"{label}: {fl.status.value}")
    ax.plot(*(np.c_[a, g][:2] / 1000), "o", color="m")
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(out / "ensembles_tracks.png", dpi=110)
    r = plan_robust(world, mission, members, "p90", seed=1)
    fig, ax = _axes(world, members, "lofoten-two-models: nominal and robust (p90) routes")
    for c, col in ((r.nominal, "tab:red"), (r.chosen, "tab:green")):
        times = ", ".join(f"{x.name} {x.arrival_s / 3600:.1f} h" for x in c.score.members)
        ax.plot(c.route[:, 0] / 1000, c.route[:, 1] / 1000, color=col, lw=2,
                label=f"{'nominal' if c is r.nominal else 'robust'} ({c.label}): {times}; "
                      f"P90 {c.score.arrival_p90_s / 3600:.1f} h")
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(out / "ensembles_robust.png", dpi=110)


def spread(world, mission, members, out: Path, count: int = 20) -> dict:
    """The forecast's plan flown open loop in a perturbation ensemble of the forecast (spread 0.1 m/s, 10 km):
    the spread of its tracks and arrival times, beside the same plan in the truth."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    a, g = np.array([-15000.0, -15000.0, -50.0]), np.array([15000.0, 15000.0, -50.0])
    m = replace(mission, start=tuple(a), goal=tuple(g))
    forecast = members[0][1]
    ens = [PerturbedCurrent(forecast, 0.1, 10000.0, seed=j) for j in range(count)]
    flights = [fly_open_loop(replace(world, currents=f), forecast, m, seed=1) for f in ens]
    truth = fly_open_loop(replace(world, currents=members[1][1]), forecast, m, seed=1)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 5))
    t = world.terrain
    ax.pcolormesh(t.x / 1000, t.y / 1000, t.z, cmap="Blues_r", shading="auto")
    for f in flights:
        ax.plot(f.track[:, 0] / 1000, f.track[:, 1] / 1000, color="tab:orange", lw=0.8, alpha=0.8)
    ax.plot(truth.track[:, 0] / 1000, truth.track[:, 1] / 1000, color="k", lw=1.5, label="in the truth (Nordic-4km)")
    ax.plot([], [], color="tab:orange", label=f"in {count} perturbed forecasts (σ 0.1 m/s, L 10 km)")
    ax.set(xlabel="x east (km)", ylabel="y north (km)", title="the forecast's plan flown open loop")
    ax.legend(fontsize=7, loc="lower right")
    arr = np.array([f.arrival_s for f in flights]) / 3600
    ok = np.isfinite(arr)
    bx.hist(arr[ok], bins=10, color="tab:orange")
    if truth.arrived:
        bx.axvline(truth.arrival_s / 3600, color="k", label="in the truth")
    bx.set(xlabel="arrival (h)", ylabel="members", title=f"arrivals: {ok.sum()} of {count} members")
    fig.tight_layout()
    fig.savefig(out / "ensembles_spread.png", dpi=110)
    return {"members": count, "arrived": int(ok.sum()), "p50_h": float(np.percentile(arr[ok], 50)),
            "p90_h": float(np.percentile(arr[ok], 90)), "truth_h": truth.arrival_s / 3600,
            "successes": sum(f.success for f in flights)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pairs", type=int, default=100)
    ap.add_argument("--intervals", type=float, nargs="+", default=[3600.0, 1800.0])
    ap.add_argument("--out", default="results/ensemble")
    ap.add_argument("--figures", default="", help="folder for the figures (docs/img)")
    ap.add_argument("--workers", type=int, default=0, help="dask.distributed local workers (0: in this process)")
    args = ap.parse_args()
    world, mission, members = context()
    if args.pairs == 0:  # the figures alone
        figures(world, mission, members, Path(args.figures or "."))
        print(json.dumps(spread(world, mission, members, Path(args.figures or "."))))
        return
    intervals = tuple(args.intervals)
    t0 = time.perf_counter()
    from auvplan.runtime.parallel import Runner  # 0 workers: in this process

    rows = Runner(workers=args.workers).map(functools.partial(pair_row, intervals=intervals), list(range(args.pairs)),
                                            on_result=lambda i, row: print(i, json.dumps(row), flush=True)).results
    summary = summarise(rows, args.intervals)
    summary["wall_s"] = time.perf_counter() - t0
    summary["load"] = os.getloadavg()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "pairs.json").write_text(json.dumps(rows, indent=1))
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    print(json.dumps(summary, indent=1))
    if args.figures:
        figures(world, mission, members, Path(args.figures))
        summary["spread"] = spread(world, mission, members, Path(args.figures))
        (out / "summary.json").write_text(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
