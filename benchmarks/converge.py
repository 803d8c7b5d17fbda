"""Convergence of the default plan on every hard problem at its own budget (issue 59), and its CPU A/B.

Three parts, each a figure in ``docs/figures/`` quoted by docs/convergence.md:

* ``converge-hard``: the eight hard problems (the six hard built-ins, ``chagos-channel`` and
  ``marcus-wake-field``), ``--seeds`` seeds each at the scenario's own budget (``[planner] budget``, or
  population × iterations): the default plan (``iabc``, seeded pipeline), IABC alone and ABC alone
  (``document`` pipeline, the same budget), interleaved seed by seed.  Gaps are to the best known cost:
  the cheapest of ``--reference`` (:func:`auvplan.planners.reference`: the lattice ladder refined to
  convergence and seeded swarms at twice the budget, each refined), ``--long-seeds`` long runs of the
  default at ``--long-factor`` times the budget, and every feasible plan of the table; the figure says
  which one it was.  The ``converged`` column counts the plans the run itself reported converged
  (``PlanResult.converged``).
* ``converge-family``: the narrow-channel family on the Chagos data (``chagos-channel`` with its depth
  ceiling at 645 and 655 m, budgets 5 000 / 10 000 / 20 000), the default plan of today's code and of
  ``--base-code`` (the branch point, before the fix), same seeds, interleaved.
* ``converge-cpu``: the median CPU of one default plan on every built-in planned by a swarm, today's code
  against ``--release-code`` (the previous release, f5c6a15) and ``--base-code``, each in a git worktree
  and a child process (:mod:`release_peer`), asked seed by seed between today's plans so that all three
  see the same load; the load average is stated.

    /work/heavy .venv/bin/python benchmarks/converge.py --seeds 10 --out results/converge   # make bench-converge
"""

from __future__ import annotations

import argparse
import json
import os
import re
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.io.scenario.builtins import resolve
from auvplan.planners import plan, reference
from auvplan.sim import planning_problem

try:
    import release_peer
except ImportError:  # imported as benchmarks.converge
    from benchmarks import release_peer

HARD = ("ninetyeast-ridge", "new-england-seamounts", "chagos-banks", "marcus-wake-deep", "new-england-chain",
        "mariana-arc", "chagos-channel", "marcus-wake-field")
METHODS = (("default", "seeded", "iabc"), ("iabc-alone", "document", "iabc"), ("abc-alone", "document", "abc"))
FAMILY = ((645.0, 5000), (645.0, 10000), (645.0, 20000), (655.0, 5000), (655.0, 10000), (655.0, 20000))
ROOT = Path(__file__).resolve().parents[1]

WORKER = r'''
import json, sys, time
from dataclasses import replace
from auvplan.io.scenario import loader as sc
from auvplan.io.scenario.builtins import resolve
from auvplan.planners import plan, reference
from auvplan.sim import planning_problem

problems = {}


def answer(ask):
    key = (ask["scenario"], ask["budget"])
    if key not in problems:
        world, mission = sc.build(sc.load(ask["scenario"]))
        prob = planning_problem(world, mission)
        spec = replace(mission.planner, budget=ask["budget"])
        plan(prob, spec, rng=0)  # warm-up: compile / load the numba cache
        problems[key] = (prob, spec)
    prob, spec = problems[key]
    c0 = time.process_time()
    r = plan(prob, spec, rng=ask["seed"])
    cpu = time.process_time() - c0
    return {"status": r.status.value, "cost": float(r.cost), "evaluations": int(r.evaluations), "cpu_s": cpu}


for line in sys.stdin:
    try:
        out = answer(json.loads(line))
    except Exception as exc:  # a scenario this code cannot read: an answer, not the end of the worker
        out = {"error": f"{type(exc).__name__}: {exc}"[:200]}
    print(json.dumps(out), flush=True)
'''
"""The peers' worker: :data:`release_peer.WORKER` (plans only) answering an error instead of ending on a
scenario the peer's code cannot read."""
release_peer.WORKER = WORKER


def _problem(source: str | Path, budget: int | None = None):
    world, mission = sc.build(sc.load(source))
    prob = planning_problem(world, mission)
    return prob, replace(mission.planner, budget=budget or mission.planner.evaluations)


def _one(prob, spec, pipeline: str, name: str, seed: int) -> dict:
    s = replace(spec, name=name, pipeline=pipeline)
    c0 = time.process_time()
    r = plan(prob, s, rng=seed)
    return {"status": r.status.value, "cost": float(r.cost), "cpu_s": time.process_time() - c0,
            "converged": r.converged, "convergence": r.convergence}


def hard(name: str, seeds: int, long_seeds: int, long_factor: int) -> dict:
    """One hard problem: the three methods interleaved seed by seed, then the best known."""
    prob, spec = _problem(name)
    plan(prob, spec, rng=0)  # warm-up
    rows = []
    for seed in range(seeds):
        for label, pipeline, planner in METHODS:
            rows.append({"method": label, "seed": seed, **_one(prob, spec, pipeline, planner, seed)})
    c0 = time.process_time()
    ref = reference(prob, spec)
    known = [(float(ref.cost), "`--reference`")] if ref.status.ok else []
    long_spec = replace(spec, budget=long_factor * spec.evaluations)
    for seed in range(long_seeds):
        r = plan(prob, long_spec, rng=10_000 + seed)
        if r.status.ok:
            known.append((float(r.cost), f"a long run ({long_factor}× budget)"))
    known += [(r["cost"], f"the table's {r['method']} seed {r['seed']}") for r in rows if r["status"] == "EXACT"]
    best, how = min(known)
    return {"scenario": name, "budget": spec.evaluations, "rows": rows, "best": best, "best_how": how,
            "reference_cost": float(ref.cost), "best_known_cpu_s": time.process_time() - c0}


def alone(known: list[dict], seeds: int) -> list[dict]:
    """IABC and ABC alone coarse to fine (``progressive`` pipeline: no lattice seed, no polish), interleaved seed
    by seed, against the best known of the ``hard`` part (``hard.json``)."""
    out = []
    for res in known:
        prob, spec = _problem(res["scenario"])
        rows = []
        for seed in range(seeds):
            for label, planner in (("iabc-progressive", "iabc"), ("abc-progressive", "abc")):
                rows.append({"method": label, "seed": seed, **_one(prob, spec, "progressive", planner, seed)})
        best = min([res["best"]] + [r["cost"] for r in rows if r["status"] == "EXACT"])
        out.append({"scenario": res["scenario"], "budget": spec.evaluations, "rows": rows, "best": best,
                    "best_how": res["best_how"] if best == res["best"] else "a plan of this table"})
        print(alone_figure(out[-1:], seeds).splitlines()[-1], flush=True)
    return out


def alone_figure(results: list[dict], seeds: int) -> str:
    lines = [f"`benchmarks/converge.py --parts alone --seeds {seeds}` (the colonies alone coarse to fine, "
             f"`progressive` pipeline, at each scenario's own budget, seeds 0–{seeds - 1}; gaps to the best known "
             "of the table above, median / worst, infeasible seeds in brackets)", "",
             "| problem | budget | IABC alone, progressive | ABC alone, progressive | IABC ahead of ABC |",
             "|---|---|---|---|---|"]
    for res in results:
        sel = {m: [r for r in res["rows"] if r["method"] == m] for m in ("iabc-progressive", "abc-progressive")}
        med = {m: float(np.median([r["cost"] for r in v])) for m, v in sel.items()}
        lines.append(f"| {res['scenario']} | {res['budget']} | {_gaps(sel['iabc-progressive'], res['best'])} | "
                     f"{_gaps(sel['abc-progressive'], res['best'])} | "
                     f"{'yes' if med['iabc-progressive'] < med['abc-progressive'] else 'no'} |")
    return "\n".join(lines) + "\n"


def _family_file(folder: Path, ceiling: float) -> Path:
    text = release_peer.portable_scenario("chagos-channel", folder).read_text()
    out = folder / f"chagos-channel-{ceiling:.0f}.toml"
    out.write_text(re.sub(r"^min_depth_m\s*=.*$", f"min_depth_m = {ceiling}", text, flags=re.M))
    return out


def family(seeds: int, base: release_peer.ReleasePeer | None, folder: Path) -> list[dict]:
    """The narrow-channel family: today's default and the base code's, same seeds, interleaved."""
    out = []
    for ceiling, budget in FAMILY:
        path = _family_file(folder, ceiling)
        prob, spec = _problem(path, budget)
        plan(prob, spec, rng=0)
        rows = []
        for seed in range(seeds):
            rows.append({"code": "today", "seed": seed, **_one(prob, spec, "seeded", "iabc", seed)})
            if base is not None:
                base._files[str(path)] = path
                rows.append({"code": "base", "seed": seed, **base.plan(str(path), seed, budget)})
        ref = reference(prob, replace(spec, budget=20000))
        feasible = [r["cost"] for r in rows if r.get("status") == "EXACT"]
        out.append({"ceiling": ceiling, "budget": budget, "rows": rows,
                    "best": min(feasible + ([float(ref.cost)] if ref.status.ok else []))})
        print(f"family {ceiling} {budget}: {_gaps([r for r in rows if r['code'] == 'today'], out[-1]['best'])}",
              flush=True)
    return out


def swarm_builtins() -> list[str]:
    """Every built-in scenario whose planner is a swarm planner."""
    names = []
    for f in sorted((ROOT / "src" / "auvplan" / "data" / "scenarios").glob("*.toml")):
        _, mission = sc.build(sc.load(f.stem))
        if mission.planner.name in ("iabc", "abc", "ga", "pso", "de") and mission.planner.robust == "none":
            names.append(f.stem)
    return names


def cpu(names: list[str], seeds: int, peers: dict[str, release_peer.ReleasePeer]) -> list[dict]:
    """Median CPU per default plan, today's code against each peer, interleaved seed by seed."""
    out = []
    for name in names:
        prob, spec = _problem(name)
        plan(prob, spec, rng=0)
        rows: dict[str, list[dict]] = {"today": [], **{k: [] for k in peers}}
        for seed in range(seeds):
            rows["today"].append(_one(prob, spec, spec.pipeline, spec.name, seed))
            for label, peer in peers.items():
                if name not in peer._files:
                    peer._files[name] = _peer_file(name, label, Path(peer._tmp.name))
                rows[label].append(peer.plan(name, seed, spec.evaluations))
        out.append({"scenario": name, "budget": spec.evaluations, "rows": rows})
        med = {k: _median_cpu(v) for k, v in rows.items()}
        print(f"cpu {name}: " + ", ".join(f"{k} {v:.3f}" for k, v in med.items()), flush=True)
    return out


def _peer_file(name: str, label: str, folder: Path) -> Path:
    """The scenario file a peer reads: the branch point reads today's file in place (relative data paths);
    the release reads a copy with its built-in terrain named by file when that terrain is a NetCDF file (a
    terrain it may not ship), today's file otherwise."""
    if label != "base":
        try:
            return release_peer.portable_scenario(name, folder)
        except Exception:  # a built-in terrain that is not a file (matplotlib's topobathy): the name as it is
            pass
    return resolve(name)


def _median_cpu(rows: list[dict]) -> float:
    ok = [r["cpu_s"] for r in rows if "cpu_s" in r]
    return float(np.median(ok)) if ok else float("nan")


def _gaps(rows: list[dict], best: float) -> str:
    c = np.array([r["cost"] for r in rows])
    bad = sum(r["status"] != "EXACT" for r in rows)
    return f"{100 * (np.median(c) / best - 1):+.2f} / {100 * (c.max() / best - 1):+.2f} % ({bad}/{len(rows)})"


def hard_figure(results: list[dict], args: argparse.Namespace, load: tuple[float, float]) -> str:
    lines = [f"`benchmarks/converge.py --seeds {args.seeds}` (seeds 0–{args.seeds - 1} at each scenario's own "
             f"budget; gaps to the best known, median / worst, infeasible seeds in brackets; load average "
             f"{load[0]:.1f} at the start, {load[1]:.1f} at the end, {os.cpu_count()} shared cores)", "",
             "| problem | budget | best known (how found) | default | converged (own verdict) "
             "| IABC alone | ABC alone | IABC ahead of ABC |", "|---|---|---|---|---|---|---|---|"]
    for res in results:
        sel = {m: [r for r in res["rows"] if r["method"] == m] for m, _, _ in METHODS}
        conv = sum(r["converged"] is True for r in sel["default"])
        med = {m: float(np.median([r["cost"] for r in v])) for m, v in sel.items()}
        lines.append(f"| {res['scenario']} | {res['budget']} | {res['best']:.0f} ({res['best_how']}) | "
                     f"{_gaps(sel['default'], res['best'])} | {conv}/{len(sel['default'])} | "
                     f"{_gaps(sel['iabc-alone'], res['best'])} | {_gaps(sel['abc-alone'], res['best'])} | "
                     f"{'yes' if med['iabc-alone'] < med['abc-alone'] else 'no'} |")
    return "\n".join(lines) + "\n"


def family_figure(results: list[dict], args: argparse.Namespace) -> str:
    lines = [f"`benchmarks/converge.py --family-seeds {args.family_seeds}` (`chagos-channel` with the depth "
             f"ceiling changed; default plan, median / worst gap to the best known, infeasible seeds in "
             f"brackets; before = the code at {args.base_code}, the branch point)", "",
             "| ceiling | budget | before | after | after: converged |", "|---|---|---|---|---|"]
    for res in results:
        today = [r for r in res["rows"] if r["code"] == "today"]
        base = [r for r in res["rows"] if r["code"] == "base" and "cost" in r]
        conv = sum(r["converged"] is True for r in today)
        lines.append(f"| {res['ceiling']:.0f} m | {res['budget']} | {_gaps(base, res['best']) if base else '-'} | "
                     f"{_gaps(today, res['best'])} | {conv}/{len(today)} |")
    return "\n".join(lines) + "\n"


def cpu_figure(results: list[dict], args: argparse.Namespace, load: tuple[float, float]) -> str:
    lines = [f"`benchmarks/converge.py --cpu-seeds {args.cpu_seeds}` (median `time.process_time()` of one "
             f"default plan at the scenario's budget, seeds 0–{args.cpu_seeds - 1}, today's code and "
             f"{' and '.join(args.cpu_peers)} interleaved seed by seed; release = {args.release_code}, "
             f"base = {args.base_code}; load average "
             f"{load[0]:.1f} at the start, {load[1]:.1f} at the end, {os.cpu_count()} shared cores)", "",
             "| scenario | budget | today s | release s (ratio) | base s (ratio) |", "|---|---|---|---|---|"]
    for res in results:
        med = {k: _median_cpu(v) for k, v in res["rows"].items()}

        def ratio(k: str, med: dict[str, float] = med) -> str:
            return f"{med[k]:.3f} ({med['today'] / med[k]:.2f})" if np.isfinite(med.get(k, np.nan)) else "n/a"

        lines.append(f"| {res['scenario']} | {res['budget']} | {med['today']:.3f} | {ratio('release')} | "
                     f"{ratio('base') if 'base' in med else 'not run'} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--family-seeds", type=int, default=6)
    ap.add_argument("--cpu-seeds", type=int, default=5)
    ap.add_argument("--long-seeds", type=int, default=2)
    ap.add_argument("--long-factor", type=int, default=4)
    ap.add_argument("--scenarios", nargs="+", default=list(HARD))
    ap.add_argument("--parts", nargs="+", default=["hard", "alone", "family", "cpu"])
    ap.add_argument("--cpu-scenarios", nargs="+", help="the CPU part on these only (default: every swarm built-in)")
    ap.add_argument("--release-code", default=release_peer.RELEASE_COMMIT)
    ap.add_argument("--base-code", default="986d447", help="the branch point (the default before issue 59)")
    ap.add_argument("--cpu-peers", nargs="+", default=["release", "base"], choices=["release", "base"],
                    help="the codes the CPU part times against today's (default both)")
    ap.add_argument("--out", default="results/converge")
    ap.add_argument("--figures", action="store_true", help="write docs/figures/converge-*.md")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    figures = ROOT / "docs" / "figures"

    def done(name: str, text: str) -> None:  # each part's figure as soon as it is measured
        (out / f"{name}.md").write_text(text)
        if args.figures:
            (figures / f"{name}.md").write_text(text)
        print(text, flush=True)

    if "hard" in args.parts:
        l0, res = os.getloadavg()[0], []
        for name in args.scenarios:
            res.append(hard(name, args.seeds, args.long_seeds, args.long_factor))
            print(hard_figure(res[-1:], args, (l0, os.getloadavg()[0])).splitlines()[-1], flush=True)
            (out / "hard.json").write_text(json.dumps(res))
        done("converge-hard", hard_figure(res, args, (l0, os.getloadavg()[0])))
    if "alone" in args.parts:
        known = json.loads((out / "hard.json").read_text())
        res_alone = alone([r for r in known if r["scenario"] in args.scenarios], args.seeds)
        (out / "alone.json").write_text(json.dumps(res_alone))
        done("converge-alone", alone_figure(res_alone, args.seeds))
    peers = {}
    try:
        if "family" in args.parts:
            if "base" not in peers:
                peers["base"] = release_peer.ReleasePeer(args.base_code)
            fam = family(args.family_seeds, peers["base"], out)
            (out / "family.json").write_text(json.dumps(fam))
            done("converge-family", family_figure(fam, args))
        if "cpu" in args.parts:
            if "base" in args.cpu_peers and "base" not in peers:
                peers["base"] = release_peer.ReleasePeer(args.base_code)
            peers["release"] = release_peer.ReleasePeer(args.release_code)
            l0 = os.getloadavg()[0]
            names = args.cpu_scenarios or swarm_builtins()
            res_cpu = cpu(names, args.cpu_seeds, {k: peers[k] for k in args.cpu_peers})
            (out / "cpu.json").write_text(json.dumps(res_cpu))
            done("converge-cpu", cpu_figure(res_cpu, args, (l0, os.getloadavg()[0])))
    finally:
        for peer in peers.values():
            peer.close()

if __name__ == "__main__":
    main()
