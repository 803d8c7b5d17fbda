"""Resolution study of the lattice reference: time, peak memory and cost versus cell size, beside
scikit-fmm on the same lattice, on marcus-wake and the hard built-in scenarios.

Each (scenario, cell) runs in a fresh process.  The process first builds the scenario and compiles
the kernels on a coarse lattice (its resident memory then is the *baseline*), then computes the
converged lattice reference alone (:func:`auvplan.planners.plan_grid`: node fields, free edges,
A* towards the start, elastic band, convergence) and records its wall time, the process's peak
resident memory (``ru_maxrss``) and the peak of numpy's buffers (tracemalloc).  Only then, in the
same process, come the peers and the extras (their memory does not count in the peak above):

* scikit-fmm (ordered-upwind eikonal solver, first order) solves |∇T| = 1 on the same free-node
  mask from the goal node over the whole lattice; beside it the reference's full cost-to-go field
  on the same lattice with the length objective (Dijkstra, no start: like for like).  The ratio
  ``field_s / skfmm_s`` compares the two field computations, ``plan_s / skfmm_s`` the whole
  converged plan (currents, path, refinement) with the peer's bare distance field.
* the lattice-bound cost (elastic band only, no convergence).

    .venv/bin/pip install scikit-fmm          # the peer, installed only for this benchmark
    nice -n 5 .venv/bin/python benchmarks/grid.py --cells 1000 500 350 250 \\
        --scenarios marcus-wake ninetyeast-ridge new-england-seamounts chagos-banks marcus-wake-deep \\
        --out results/bench-grid
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
import tracemalloc
from dataclasses import replace
from pathlib import Path

import numpy as np

REPEATS = 5
"""Field and scikit-fmm timings per (scenario, cell), interleaved; the medians are reported."""

HARD = ("ninetyeast-ridge", "new-england-seamounts", "chagos-banks", "marcus-wake-deep")


def _rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def measure(cell: float, scenario: str, repeats: int = REPEATS) -> dict:
    """One cell size on one scenario (see the module notes)."""
    from auvplan.io.scenario import loader as sc
    from auvplan.planners import GridParams, GridReference, plan_grid
    from auvplan.planners.core.common import cost_model_for, search_box
    from auvplan.planners.grid.lattice import node_fields
    from auvplan.sim import planning_problem

    world, mission = sc.build(sc.load(scenario))
    prob = planning_problem(world, mission)
    spec = replace(mission.planner, name="grid", grid=GridParams(cell=cell, max_nodes=16_000_000))
    plan_grid(prob, replace(spec, grid=GridParams(cell=8 * cell)))  # compile and load the kernels
    row: dict = {"scenario": scenario, "cell_m": cell, "baseline_rss_mib": _rss_mib()}
    t0, c0 = time.perf_counter(), time.process_time()
    r = plan_grid(prob, spec)  # timed without tracemalloc (it slows every numpy allocation)
    row["plan_s"], row["plan_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
    tracemalloc.start()
    plan_grid(prob, spec)  # the same plan again for numpy's peak (the peak RSS is the same work's)
    row["numpy_peak_mib"] = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    row["peak_rss_mib"] = _rss_mib()
    row.update(status=r.status.value, cost=r.cost, length_m=r.cost_terms.get("length_m"), edges=r.evaluations,
               reference=r.message)
    row["winner"] = r.message.rsplit(": ", 1)[-1]
    row["cost_lattice_bound"] = plan_grid(prob, replace(spec, grid=replace(spec.grid, converge=False))).cost
    row["cost_single_lattice"] = plan_grid(prob, replace(spec, grid=replace(spec.grid, ladder=False))).cost
    c0 = time.process_time()  # the ladder of the 26 directions alone (the default before wave 7), same code
    row["lattice26_ladder_cost"] = plan_grid(prob, replace(spec, grid=replace(spec.grid, also_any_angle=0))).cost
    row["lattice26_ladder_cpu_s"] = time.process_time() - c0
    lspec = replace(spec, grid=replace(spec.grid, objective="length"))
    lo, hi = search_box(prob)
    ref = GridReference(world, prob.goal, cost_model_for(prob, lspec), lo, hi, lspec.grid)
    row["nodes"], row["free_nodes"], row["shape"] = ref.nodes, int(ref.free.sum()), list(ref.shape)
    row.update(_lattice_paths(prob, spec, r))
    try:
        import skfmm
    except ImportError:
        row["skfmm"] = "not installed"
        return row
    free = ref.free

    def nearest_free(p):  # the free node nearest to p (the node nearest to a seabed-hugging end may be in the seabed)
        ids = np.flatnonzero(free)
        xyz = np.stack([ref.axes[d][i] for d, i in enumerate(np.unravel_index(ids, ref.shape))], axis=1)
        return np.unravel_index(ids[int(np.argmin(np.linalg.norm(xyz - p, axis=1)))], ref.shape)

    gi = nearest_free(prob.goal)
    phi = np.ones(ref.shape)
    phi[gi] = -1.0
    build, search, peer, mask = [], [], [], []
    for _ in range(repeats):  # interleaved, so that a change of load hits both alike
        c0 = time.process_time()
        ref = GridReference(world, prob.goal, cost_model_for(prob, lspec), lo, hi, lspec.grid)
        build.append(time.process_time() - c0)
        search.append(ref.search_cpu_s)
        c0 = time.process_time()  # what scikit-fmm must be handed: the free-node mask (terrain clearance per node)
        handed = node_fields(world, ref.axes, False)[0]
        mask.append(time.process_time() - c0)
        assert np.array_equal(handed, free)
        c0 = time.process_time()
        tt = skfmm.distance(np.ma.MaskedArray(phi, ~free), dx=[ref.cell, ref.cell, ref.cell_z])
        peer.append(time.process_time() - c0)
    row["field_cpu_s"], row["search_cpu_s"], row["skfmm_cpu_s"], row["mask_cpu_s"] = (
        float(np.median(v)) for v in (build, search, peer, mask))
    row["search_ratios"] = [a / b for a, b in zip(search, peer)]
    row["build_ratios"] = [a / b for a, b in zip(build, peer)]
    row["build_mask_ratios"] = [a / (b + c) for a, b, c in zip(build, peer, mask)]
    row["search_ratio"] = float(np.median(row["search_ratios"]))
    row["build_ratio"] = float(np.median(row["build_ratios"]))
    row["build_mask_ratio"] = float(np.median(row["build_mask_ratios"]))
    si = nearest_free(prob.start)
    row["skfmm_distance_m"] = float(tt[si])
    row["dijkstra_distance_m"] = float(ref.cost_to_go[si])
    return row


def _lattice_paths(prob, spec, converged) -> dict:
    """The raw lattice path (26 directions, and with any-angle links of 16 cells) on the planner's cost:
    its cost and length beside the converged reference's (``converged``)."""
    from auvplan.planners import plan_grid
    from auvplan.planners.core.common import cost_model_for, path_cost, search_box
    from auvplan.planners.grid.planner import GridReference as Ref

    out: dict = {}
    lo, hi = search_box(prob)
    for tag, link in (("lattice26", 0), ("anyangle16", 16)):
        g = replace(spec.grid, any_angle=link, also_any_angle=0)  # one kind of link
        ref = Ref(prob.world, prob.goal, cost_model_for(prob, replace(spec, grid=g)), lo, hi, g, prob.start)
        raw = ref.query(prob.start)
        if raw.shape[0] < 2:
            continue
        terms = path_cost(prob, replace(spec, grid=g), raw)
        out[f"{tag}_cost"], out[f"{tag}_length_m"] = float(terms["total"]), float(terms["length_m"])
        single = plan_grid(prob, replace(spec, grid=replace(g, ladder=False)), ref)
        out[f"{tag}_converged_cost"] = float(single.cost)
        out[f"{tag}_refined_length_m"] = float(single.cost_terms.get("length_m", float("nan")))
        if link:  # the ladder with the links (the default ladder's cost is the row's "cost")
            out[f"{tag}_ladder_cost"] = float(plan_grid(prob, replace(spec, grid=g)).cost)
    return out


def figure(rows: list[dict], path: Path, repeats: int, argv: str = "", optimum: dict | None = None) -> None:
    """The lattice table as a docs figure (quoted by ``<!-- figure: NAME -->`` markers); ``optimum``: the
    independent polyline optimum of one scenario (``benchmarks/grid_optimum.py``), stated under the table."""
    loads, nan = [r["load_1min"] for r in rows], float("nan")
    lines = [f"`nice -n 5 .venv/bin/python benchmarks/grid.py {argv}` "
             f"(load average {min(loads):.1f}–{max(loads):.1f} on the shared 2-core host; CPU times are process "
             "times; field and scikit-fmm interleaved, median of the repeats; the field is the full cost-to-go "
             "of the length objective from the goal over the whole lattice, scikit-fmm's distance on the same "
             "free-node mask and cells; the mask is what scikit-fmm must be handed, the free nodes of the "
             "World's static clearances per node, timed as the build computes it, `node_fields`; the default "
             "ladder searches every rung with the 26 directions and with any-angle links of 16 cells and refines the "
             "better, `docs/lattice.md`; the single-kind columns set `also_any_angle = 0`)", "",
             "| scenario | cell m | nodes | raw lattice path cost: 26-dir / any-angle 16 "
             "| its length / refined length (any-angle) "
             "| single lattice converged: 26-dir / any-angle 16 | ladder: 26-dir / any-angle 16 "
             "| **default ladder** (both kinds) | its winner | ladder CPU s: default / 26-dir (ratio) "
             "| search CPU s | whole build CPU s | scikit-fmm CPU s "
             "| search / skfmm (median, per repeat) | mask CPU s | build / skfmm | build / (skfmm + mask) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ratios = ", ".join(f"{x:.2f}" for x in r.get("search_ratios", []))
        lines.append(
            f"| {r['scenario']} | {r['cell_m']:g} | {r['nodes']:,} | {r.get('lattice26_cost', float('nan')):,.1f} / "
            f"{r.get('anyangle16_cost', float('nan')):,.1f} | {r.get('anyangle16_length_m', float('nan')):,.0f} / "
            f"{r.get('anyangle16_refined_length_m', float('nan')):,.0f} "
            f"({100 * (r.get('anyangle16_length_m', 0) / r.get('anyangle16_refined_length_m', 1) - 1):+.2f} %) | "
            f"{r.get('lattice26_converged_cost', nan):,.2f} / {r.get('anyangle16_converged_cost', nan):,.2f} | "
            f"{r.get('lattice26_ladder_cost', nan):,.2f} / {r.get('anyangle16_ladder_cost', nan):,.2f} | "
            f"**{r['cost']:,.2f}** | {r.get('winner', '')} | {r['plan_cpu_s']:.2f} / "
            f"{r.get('lattice26_ladder_cpu_s', float('nan')):.2f} "
            f"({r['plan_cpu_s'] / r.get('lattice26_ladder_cpu_s', float('nan')):.2f}) | "
            f"{r.get('search_cpu_s', float('nan')):.3f} | "
            f"{r.get('field_cpu_s', float('nan')):.3f} | {r.get('skfmm_cpu_s', float('nan')):.3f} | "
            f"**{r.get('search_ratio', float('nan')):.2f}** ({ratios}) | {r.get('mask_cpu_s', float('nan')):.3f} | "
            f"{r.get('build_ratio', float('nan')):.2f} | **{r.get('build_mask_ratio', float('nan')):.2f}** |")
    if optimum is not None:
        best = min(r["cost"] for r in rows if r["scenario"] == optimum["scenario"])
        lines += ["", f"Optimality on {optimum['scenario']}: an independent optimum with no lattice and no "
                  f"elastic band (`benchmarks/grid_optimum.py {optimum['scenario']} --segments {optimum['segments']}`: "
                  f"scipy's L-BFGS-B over the {optimum['segments'] - 1} interior vertices of a polyline started on the "
                  f"straight line, same cost function) costs {optimum['cost']:,.2f} "
                  f"({'free' if optimum['free'] else 'NOT FREE'}, {optimum['cpu_s']:.0f} s CPU), "
                  f"{100 * (optimum['cost'] / best - 1):+.5f} % from the default ladder's best {best:,.2f}: the "
                  "reference is the problem's optimum to that precision, so a flat ladder is the best a finer lattice "
                  "can do there."]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")


def _print(r: dict) -> None:
    print(f"{r['scenario']:22s} {r['cell_m']:6.0f} m  nodes {r['nodes']:>9d}  plan {r['plan_s']:6.2f} s "
          f"(cpu {r['plan_cpu_s']:6.2f} s)  "
          f"peak RSS {r['peak_rss_mib']:6.0f} MiB (baseline {r['baseline_rss_mib']:4.0f}, "
          f"numpy {r['numpy_peak_mib']:5.0f})"
          f"  cost {r['cost']:.7g} (this lattice alone {r['cost_single_lattice']:.7g}, lattice-bound "
          f"{r['cost_lattice_bound']:.7g})  field cpu {r['field_cpu_s']:5.2f} s  "
          f"search cpu {r.get('search_cpu_s', float('nan')):5.3f} s  "
          f"skfmm cpu {r.get('skfmm_cpu_s', float('nan')):5.3f} s  "
          f"search/skfmm {r.get('search_ratio', float('nan')):.2f}"
          f"  build/skfmm {r.get('build_ratio', float('nan')):.2f}", flush=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cells", type=float, nargs="+", default=[1000, 500, 350, 250])
    ap.add_argument("--scenarios", nargs="+", default=["marcus-wake", *HARD])
    ap.add_argument("--out", default="results/bench-grid")
    ap.add_argument("--repeats", type=int, default=REPEATS, help="field / scikit-fmm timings per case (median)")
    ap.add_argument("--figure", type=Path, help="also write the lattice table to this docs figure file")
    ap.add_argument("--optimum", help="also state this scenario's independent polyline optimum under the figure")
    ap.add_argument("--segments", type=int, default=81, help="polyline segments of --optimum")
    ap.add_argument("--from-json", action="store_true", help="rewrite the figure from --out's JSON (no measuring)")
    ap.add_argument("--one", type=float, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(measure(args.one, args.scenarios[0], args.repeats)))
        return 0
    command = " ".join(a for a in (sys.argv[1:] if argv is None else argv) if a != "--from-json")
    if args.from_json:
        rows = json.loads((Path(args.out) / "grid.json").read_text())
        figure(rows, args.figure, args.repeats, command, _optimum(args))
        return 0
    rows = []
    Path(args.out).mkdir(parents=True, exist_ok=True)
    for cell, scenario in ((c, s) for c in args.cells for s in args.scenarios):  # coarse cells first
        load = os.getloadavg()[0]
        out = subprocess.run([sys.executable, __file__, "--one", str(cell), "--scenarios", scenario,
                              "--repeats", str(args.repeats)],
                             capture_output=True, text=True)
        if out.returncode:
            print(f"{scenario} {cell:g} m failed: {out.stderr.strip().splitlines()[-1]}", flush=True)
            continue
        rows.append({**json.loads(out.stdout.strip().splitlines()[-1]), "load_1min": load})
        _print(rows[-1])
        (Path(args.out) / "grid.json").write_text(json.dumps(rows, indent=2) + "\n")
        if args.figure is not None:
            figure(rows, args.figure, args.repeats, command)
    if args.figure is not None and args.optimum:
        figure(rows, args.figure, args.repeats, command, _optimum(args))
    return 0


def _optimum(args: argparse.Namespace) -> dict | None:
    """``--optimum``'s polyline optimum (stored beside the rows: ``--from-json`` re-uses it)."""
    if not args.optimum:
        return None
    store = Path(args.out) / f"optimum-{args.optimum}-{args.segments}.json"
    if not store.exists():
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from grid_optimum import optimum

        cost, free, cpu = optimum(args.optimum, args.segments)
        store.write_text(json.dumps({"scenario": args.optimum, "segments": args.segments, "cost": cost,
                                     "free": free, "cpu_s": cpu}) + "\n")
    return dict(json.loads(store.read_text()))


if __name__ == "__main__":
    sys.exit(main())
