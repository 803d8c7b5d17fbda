"""Planners on the hard built-in scenarios at truly equal budgets, beside peer libraries.

Every method gets exactly ``--budget`` objective evaluations of the same cost (auvplan counts
them; peers are wrapped so that evaluations past the budget return ``inf``), ``--seeds`` seeds
per scenario.  Methods: each auvplan optimiser in the default ``seeded`` pipeline, alone
(``document`` pipeline) and alone coarse to fine (``progressive`` pipeline), IABC's literal
document variant, and the peers mealpy ``OriginalABC``
and pymoo ``PSO`` / ``GA`` when installed (scipy's differential evolution is ``de``).  For each
scenario: the gap of each method's median and worst cost to the best cost any method found (the
grid reference included), the seeds ending INFEASIBLE and the median CPU time per plan.  Also
the median convergence (best cost against evaluations) of the four document algorithms.

The comparison is equal in the evaluations of the swarm: the seeded pipeline's coarse lattice (which
seeds it) and its last polyline polish are not objective evaluations; their work is reported beside the
budget (median lattice nodes, seeding CPU and polish CPU per plan, all included in the CPU column).
``iabc/release`` is the default pipeline with the settings of the previous release (``RELEASE``: no
polyline polish, a 20 000-node seeding lattice), run in the same process, interleaved seed by seed with
the default, as the CPU peer; the reference is also timed with those settings (its seeded swarms are the
default pipeline's).  ``release-code`` is the previous release's CODE (``--release-code``, default
f5c6a15, :mod:`release_peer`: a git worktree and a child process), its default plan on the same
problems and seeds, asked seed by seed between today's methods, so that a speed-up of a kernel both
share counts (``--no-release-code`` leaves it out).  ``--methods`` keeps only the methods named; the
references' CPU is in each scenario's heading.  ``--figure-md NAME`` writes the default's summary
against both peers to ``docs/figures/NAME.md`` (quoted in docs/bench_hard.md).

    .venv/bin/pip install mealpy pymoo      # optional peers
    .venv/bin/python benchmarks/hard.py --seeds 10 --budget 10000 --out results/bench-hard
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from auvplan.io.scenario import loader as sc
from auvplan.optim import Problem
from auvplan.planners import plan, reference
from auvplan.planners.swarm.problem import path_terms, spline_problem
from auvplan.sim import planning_problem

try:
    from release_peer import RELEASE_COMMIT, ReleasePeer
except ImportError:  # imported as benchmarks.hard
    from benchmarks.release_peer import RELEASE_COMMIT, ReleasePeer

SCENARIOS = ("ninetyeast-ridge", "new-england-seamounts", "chagos-banks", "marcus-wake-deep", "new-england-chain",
             "mariana-arc")
RELEASE = {"polish": 0, "seed_nodes": 20_000}
"""The seeded pipeline's settings of the previous release (f5c6a15): the CPU and quality peer."""
OURS = [(f"{n}", n, "seeded", {}, {}) for n in ("iabc", "abc", "ga", "pso", "de")] + \
       [("iabc/release", "iabc", "seeded", {}, RELEASE)] + \
       [(f"{n}/document", n, "document", {}, {}) for n in ("iabc", "abc", "ga", "pso", "de")] + \
       [(f"{n}/progressive", n, "progressive", {}, {}) for n in ("iabc", "abc", "ga", "pso", "de")] + \
       [("iabc-elite/document", "iabc", "document", {"elite": 0.2, "mutation_fraction": 0.1}, {}),
        ("iabc-literal/document", "iabc", "document", {"variant": "document"}, {})]
"""(label, planner, pipeline, [planner.iabc] overrides, [planner] overrides); ``iabc-elite`` is the improved
colony with the mutation and the pull aimed at random elite sources and the worst 10 % mutated (the previous
round's robust setting for the algorithm alone); ``iabc/release`` the default with the previous release's
settings (no polyline polish)."""


def _ours(prob, spec, label, name, pipeline, iabc, over, seed):
    s = replace(spec, name=name, pipeline=pipeline, iabc=replace(spec.iabc, **iabc), **over)
    c0 = time.process_time()
    r = plan(prob, s, rng=seed)
    return {"method": label, "seed": seed, "status": r.status.value, "cost": r.cost, "evaluations": r.evaluations,
            "cpu_s": time.process_time() - c0, "trace": r.trace.tolist(), **r.work}


def _peer_rows(prob, spec, seeds: int, budget: int) -> list[dict]:
    rows = []

    def finish(label, seed, x, cpu, evals):
        t = path_terms(prob, spec, np.asarray(x)[None], exact=True)
        ok = bool(t.feasible[0])
        rows.append({"method": label, "seed": seed, "status": "EXACT" if ok else "INFEASIBLE",
                     "cost": float(t.total[0]), "evaluations": evals, "cpu_s": cpu, "trace": []})

    try:
        from pymoo.algorithms.soo.nonconvex.ga import GA as PymooGA
        from pymoo.algorithms.soo.nonconvex.pso import PSO as PymooPSO
        from pymoo.core.problem import Problem as PymooProblem
        from pymoo.optimize import minimize as pymoo_minimize

        for label, algo in (("pymoo-pso", PymooPSO), ("pymoo-ga", PymooGA)):
            for seed in range(seeds):
                p = spline_problem(prob, spec, budget)

                class PathProblem(PymooProblem):
                    def __init__(self, p: Problem):
                        super().__init__(n_var=p.dim, n_obj=1, xl=p.lower, xu=p.upper)
                        self.p = p

                    def _evaluate(self, x, out, *args, **kwargs):
                        out["F"] = self.p.evaluate(x)[:, None]

                c0 = time.process_time()
                pymoo_minimize(PathProblem(p), algo(pop_size=spec.population), ("n_evals", budget), seed=seed,
                               verbose=False)
                finish(label, seed, p.best_x, time.process_time() - c0, p.evaluations)
    except ImportError:
        pass
    try:
        from mealpy import ABC, FloatVar

        for seed in range(seeds):
            p = spline_problem(prob, spec, budget)
            problem = {"obj_func": lambda x, p=p: float(p.evaluate(np.asarray(x)[None])[0]),
                       "bounds": FloatVar(lb=p.lower.tolist(), ub=p.upper.tolist()), "minmax": "min",
                       "log_to": None}
            model = ABC.OriginalABC(epoch=100_000, pop_size=spec.population)
            c0 = time.process_time()
            model.solve(problem, seed=seed, termination={"max_fe": budget})
            finish("mealpy-abc", seed, p.best_x, time.process_time() - c0, p.evaluations)
    except ImportError:
        pass
    return rows


_WARM: list[bool] = []
"""Whether this process has run a reference (warmed the lattice's kernels) yet."""


def run(name: str, seeds: int, budget: int, peers: bool, methods: list[str] | None = None,
        release: ReleasePeer | None = None, before: ReleasePeer | None = None) -> dict:
    world, mission = sc.build(sc.load(name))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, budget=budget)
    chosen = [m for m in OURS if methods is None or m[0] in methods]
    plan(prob, spec, rng=0)  # warm-up (numba's cache), as the release's worker does
    rows = []
    for seed in range(seeds):  # interleaved: fair CPU
        rows += [_ours(prob, spec, *m, seed) for m in chosen]
        if release is not None:
            rows.append({"method": "release-code", "seed": seed, "trace": [], **release.plan(name, seed, budget)})
    if peers:
        rows += _peer_rows(prob, spec, seeds, budget)
    if before is not None and not _WARM:  # the peer's first reference is warmed up: so is ours
        reference(prob, spec)
        _WARM.append(True)
    c0 = time.process_time()
    ref = reference(prob, spec)
    cpu = time.process_time() - c0
    c0 = time.process_time()
    old = reference(prob, replace(spec, **RELEASE))
    extra = {}
    if before is not None:  # the reference of another commit's code (e.g. the branch point), same problem
        row = before.plan(name, -1, budget)
        extra = {"before_reference_cpu_s": row["cpu_s"], "before_reference_cost": row["cost"],
                 "before_commit": before.commit}
    return {"scenario": name, "rows": rows, **extra, "reference_cost": min(ref.cost, old.cost),
            "reference_status": ref.status.value if ref.cost <= old.cost else old.status.value,
            "reference_cpu_s": cpu, "release_reference_cpu_s": time.process_time() - c0,
            "release_reference_cost": old.cost, "default_reference_cost": ref.cost}


def table(result: dict) -> list[str]:
    rows = result["rows"]
    feasible = [r["cost"] for r in rows if r["status"] == "EXACT"]
    best = min(feasible + ([result["reference_cost"]] if result["reference_status"] == "EXACT" else []))
    ref_cpu = (f", {result['reference_cpu_s']:.2f} s CPU, with the release's settings "
               f"{result['release_reference_cpu_s']:.2f} s" if "reference_cpu_s" in result else "")
    lines = [f"\n**{result['scenario']}** (best cost found {best:.0f}; grid reference {result['reference_cost']:.0f}, "
             f"{100 * (result['reference_cost'] / best - 1):+.2f} %{ref_cpu})\n",
             "| method | median gap | worst gap | infeasible | median evaluations | median CPU s | seeding: lattice "
             "nodes, CPU s | polish CPU s |",
             "|---|---|---|---|---|---|---|---|"]
    for method in dict.fromkeys(r["method"] for r in rows):
        sel = [r for r in rows if r["method"] == method]
        c = np.array([r["cost"] for r in sel])
        bad = sum(r["status"] != "EXACT" for r in sel)
        lines.append(f"| {method} | {100 * (np.median(c) / best - 1):+.2f} % | {100 * (c.max() / best - 1):+.2f} % | "
                     f"{bad}/{len(sel)} | {int(np.median([r['evaluations'] for r in sel]))} | "
                     f"{np.median([r['cpu_s'] for r in sel]):.3f} | {_work(sel)} |")
    return lines


def _work(sel: list[dict]) -> str:
    """Median work outside the evaluation budget: the seeding lattice and the polish ('-' where none)."""
    seeding = (f"{np.median([r['seeding_lattice_nodes'] for r in sel]):.0f}, "
               f"{np.median([r['seeding_cpu_s'] for r in sel]):.3f}") if "seeding_cpu_s" in sel[0] else "-"
    polish = f"{np.median([r['polish_cpu_s'] for r in sel]):.3f}" if "polish_cpu_s" in sel[0] else "-"
    return f"{seeding} | {polish}"


def convergence_figure(result: dict, budget: int, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grid = np.linspace(0, budget, 201)[1:]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    methods = ("iabc-literal/document", "iabc/document", "abc/document", "ga/document", "pso/document")
    best = min([r["cost"] for r in result["rows"] if r["status"] == "EXACT"]
               + ([result["reference_cost"]] if result["reference_status"] == "EXACT" else []))  # as in the table
    finals = []
    for method in methods:
        curves = []
        for r in result["rows"]:
            if r["method"] == method and r["trace"]:
                t = np.asarray(r["trace"])
                idx = np.searchsorted(t[:, 0], grid, side="right") - 1
                curves.append(np.where(idx >= 0, t[np.maximum(idx, 0), 1], np.nan))
        med = np.nanmedian(np.array(curves), axis=0)
        finals.append(med[-1])
        name = method.replace("/document", "").upper().replace("-LITERAL", " (document variant)")
        label = "IABC (improved)" if method == "iabc/document" else name
        ax.plot(grid, med, label=f"{label}: {100 * (med[-1] / best - 1):+.1f} % at the end")
    ax.set_ylim(best * 0.99, best * min(max(1.1, 1.05 * max(finals) / best), 1.6))
    ax.set_xlabel("objective evaluations")
    ax.set_ylabel("median best cost over seeds (equivalent m)")
    ax.axhline(best, color="k", lw=0.8, ls=":")
    ax.set_title(f"{result['scenario']}: equal budget, algorithms alone (document pipeline)")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def replot(rows_json: str, budget: int, figure: str) -> None:
    """Redraw the convergence figure of the first scenario from a run's ``rows.json``."""
    convergence_figure(json.loads(Path(rows_json).read_text())[0], budget, Path(figure))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--budget", type=int, default=10_000)
    ap.add_argument("--scenarios", nargs="+", default=list(SCENARIOS))
    ap.add_argument("--no-peers", action="store_true")
    ap.add_argument("--methods", nargs="+", help="only these methods (labels of the table), e.g. iabc iabc/release")
    ap.add_argument("--figure", default="docs/convergence_hard.png")
    ap.add_argument("--release-code", default=RELEASE_COMMIT, help="the previous release's commit (its code a peer)")
    ap.add_argument("--no-release-code", action="store_true", help="leave the release's code out")
    ap.add_argument("--figure-md", help="write the default against both peers to docs/figures/NAME.md")
    ap.add_argument("--reference-peer", help="also time the --reference of this commit's code (e.g. the branch point)")
    ap.add_argument("--out", default="results/bench-hard")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    load = os.getloadavg()
    text = [f"# Planners on the hard scenarios: {args.budget} evaluations, {args.seeds} seeds",
            f"\nload average at start {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} on {os.cpu_count()} cores "
            "(shared machine: CPU times are inflated)"]
    results = []
    release = None if args.no_release_code else ReleasePeer(args.release_code)
    before = ReleasePeer(args.reference_peer) if args.reference_peer else None
    try:
        _run_all(args, out, text, results, release, before)
    finally:
        for peer in (release, before):
            if peer is not None:
                peer.close()
    if args.figure_md:
        figure = Path(__file__).resolve().parents[1] / "docs" / "figures" / f"{args.figure_md}.md"
        figure.write_text(summary_figure(results, args, load))
        print(f"wrote {figure}")


def _run_all(args: argparse.Namespace, out: Path, text: list[str], results: list[dict],
             release: ReleasePeer | None, before: ReleasePeer | None) -> None:
    for name in args.scenarios:
        res = run(name, args.seeds, args.budget, not args.no_peers, args.methods, release, before)
        results.append(res)
        text += table(res)
        print("\n".join(table(res)), flush=True)
        (out / "rows.json").write_text(json.dumps(results))
        (out / "summary.md").write_text("\n".join(text) + "\n")
        if name == args.scenarios[0] and any(r["method"] == "iabc/document" for r in res["rows"]):
            convergence_figure(res, args.budget, Path(args.figure))
    load = os.getloadavg()
    args.load_end = load
    text.append(f"\nload average at end {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f}")
    (out / "summary.md").write_text("\n".join(text) + "\n")
    (out / "rows.json").write_text(json.dumps(results))
    print(f"wrote {out / 'summary.md'}, {args.figure}")


def summary_figure(results: list[dict], args: argparse.Namespace, load0: tuple[float, ...]) -> str:
    """The default (``iabc``) against the best known and both CPU peers, one row a scenario (Markdown)."""
    end = getattr(args, "load_end", (float("nan"),) * 3)
    before = f" --reference-peer {args.reference_peer}" if args.reference_peer else ""
    lines = [f"`benchmarks/hard.py --seeds {args.seeds} --budget {args.budget} --release-code {args.release_code}"
             f"{before}` "
             f"(seeds 0–{args.seeds - 1}; CPU per plan = median `time.process_time()` of one plan, seeding and "
             f"polish included; load average {load0[0]:.1f} at the start, {end[0]:.1f} at the end, "
             f"{os.cpu_count()} shared cores; the three columns interleaved seed by seed)", "",
             "| scenario | best known | default median / worst gap | infeasible | release-code median / worst gap "
             "| CPU s per plan: default / release code (ratio) | release settings on today's code (ratio) "
             "| polish CPU s | `--reference` CPU s: now / before (ratio) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for res in results:
        rows = res["rows"]
        best = min([r["cost"] for r in rows if r["status"] == "EXACT"]
                   + ([res["reference_cost"]] if res["reference_status"] == "EXACT" else []))

        def col(method: str, rows: list[dict] = rows, best: float = best) -> tuple[str, float, int]:
            sel = [r for r in rows if r["method"] == method]
            if not sel:
                return "-", float("nan"), 0
            c = np.array([r["cost"] for r in sel])
            gap = f"{100 * (np.median(c) / best - 1):+.2f} / {100 * (c.max() / best - 1):+.2f} %"
            return gap, float(np.median([r["cpu_s"] for r in sel])), sum(r["status"] != "EXACT" for r in sel)

        (g, cpu, bad), (gr, cpur, _), (_, cpus, _) = col("iabc"), col("release-code"), col("iabc/release")
        polish = np.median([r.get("polish_cpu_s", 0.0) for r in rows if r["method"] == "iabc"])
        ref = (f"{res['reference_cpu_s']:.2f} / {res['before_reference_cpu_s']:.2f} "
               f"({res['reference_cpu_s'] / res['before_reference_cpu_s']:.2f})" if "before_reference_cpu_s" in res
               else f"{res['reference_cpu_s']:.2f} / -")
        lines.append(f"| {res['scenario']} | {best:.0f} | {g} | {bad}/{args.seeds} | {gr} | {cpu:.3f} / {cpur:.3f} "
                     f"({cpu / cpur:.2f}) | {cpus:.3f} ({cpu / cpus:.2f}) | {polish:.3f} | {ref} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
