"""Charted no-go zones (issue 53): the Must-show figures.

``montecarlo``: random missions in random worlds with random zones (polygons, cable corridors, wrecks;
flat bands and seabed bands) planned by every planner that accepts zones; every leg of every plan
reported feasible is checked against every prism by an *independent* test (shapely's
``intersection`` of the leg's trace with the footprint, then the leg's depths over each piece against
the band; a seabed band by the altitude sampled every metre along the pieces).  Reports the entries
(must be 0) and how many plans were feasible.

``cpu``: CPU time of the default plan of a built-in with no zones and with 1 000 random zones away
from the start and goal (median of repeats, JIT warmed up first), and the ratio.

``gap``: the default plan against ``--reference`` on ``chagos-reefs`` (same zones), in percent.

``stall``: IABC's stop of a swarm stalled behind its lattice corridor against the same plans with it off (the
default budget given explicitly): on the ``cpu`` problem with several zone counts and on the built-ins, how many
plans stopped, how many kept the same path, the worst cost change and the evaluations spent.

``passes``: the zones' pass over the swarm's populations alone (``Zones.polyline_slack``, most of the zones'
part of a plan), measured at a few per cent instead of the plans' ±0.2 in the ratio: the populations the
cost asks about in ``--plans`` default plans of the ``cpu`` problem are recorded, then replayed (best of
``--repeats``), with a digest of the answers so two versions of the code can be compared on the same
populations (``--save FILE`` keeps them, ``--load FILE`` replays them).

    python benchmarks/zones.py montecarlo --missions 1000 --planners iabc grid timeopt
    python benchmarks/zones.py cpu --scenario marcus-wake --zones 1000
    python benchmarks/zones.py gap
    python benchmarks/zones.py stall --zones 100 300 500 700 1000 1500 --seeds 24
    python benchmarks/zones.py passes --save /tmp/pops.npz   # then, on another version: --load /tmp/pops.npz
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import time
from dataclasses import replace

import numpy as np
import shapely

from auvplan.planners import PlannerSpec, PlanningProblem, PlanResult, plan, reference
from auvplan.planners.core.params import GridParams, TimeoptParams
from auvplan.world import Bounds, Margins, Terrain, UniformCurrent, World, Zone, Zones

SIZE = 3000.0


def random_world(rng: np.random.Generator, n_zones: int) -> World:
    """A 3 km square of hills (120-300 m deep) with ``n_zones`` random zones and a weak current."""
    x = np.linspace(0.0, SIZE, 31)
    gx, gy = np.meshgrid(x, x)
    z = np.full_like(gx, -rng.uniform(200.0, 300.0))
    for _ in range(3):
        c = rng.uniform(0.0, SIZE, 2)
        width = rng.uniform(200.0, 600.0)
        z += rng.uniform(30.0, 100.0) * np.exp(-((gx - c[0]) ** 2 + (gy - c[1]) ** 2) / (2 * width**2))
    terrain = Terrain(x, x, z, name="hills")
    zones = [random_zone(rng, f"z{i}") for i in range(n_zones)]
    return World(Bounds(0.0, SIZE, 0.0, SIZE, -300.0, 0.0), terrain, UniformCurrent((0.05, -0.02, 0.0)),
                 margins=Margins(min_altitude=10.0, min_depth=5.0, max_depth=300.0), name="random-zones",
                 zones=Zones(tuple(zones), terrain, pad=1.0))


def random_zone(rng: np.random.Generator, name: str) -> Zone:
    """A polygon, a cable corridor or a wreck circle, with a random band."""
    c = rng.uniform(300.0, SIZE - 300.0, 2)
    kind = rng.integers(3)
    if kind == 0:
        pts = c + rng.uniform(-350.0, 350.0, (6, 2))
        fp = shapely.convex_hull(shapely.multipoints(pts))
    elif kind == 1:
        fp = shapely.buffer(shapely.linestrings([c, c + rng.uniform(-900.0, 900.0, 2)]), rng.uniform(10.0, 60.0))
    else:
        fp = shapely.buffer(shapely.points(c), rng.uniform(20.0, 150.0))
    band = rng.integers(3)
    if band == 0:
        return Zone(name, fp)  # surface to seabed
    if band == 1:
        top = rng.uniform(0.0, 150.0)
        return Zone(name, fp, top=top, bottom=top + rng.uniform(20.0, 120.0))
    return Zone(name, fp, above_seabed=rng.uniform(10.0, 60.0))


def free_point(rng: np.random.Generator, world: World) -> np.ndarray:
    """A random point with every constraint satisfied (zones included)."""
    while True:
        p = np.r_[rng.uniform(100.0, SIZE - 100.0, 2), 0.0]
        floor = float(world.seabed(p[0], p[1]))
        p[2] = rng.uniform(floor + 20.0, -10.0)
        if world.is_free(p) and float(world.clearance(p)) > 2.0:
            return p


def independent_entries(world: World, path: np.ndarray) -> list[tuple[int, str]]:
    """Every (leg, zone) where the polyline enters a zone's (unpadded) prism, by shapely alone."""
    p = np.asarray(path, dtype=float)
    hits = []
    zones = world.zones.exact.zones if world.zones else ()
    for k in range(len(p) - 1):
        a, b = p[k], p[k + 1]
        d = b - a
        dd = float(d[0] ** 2 + d[1] ** 2)
        trace = shapely.Point(a[:2]) if dd == 0 else shapely.LineString([a[:2], b[:2]])
        for zone in zones:
            cut = shapely.intersection(trace, zone.footprint)
            if cut.is_empty:
                continue
            for piece in shapely.get_parts(cut):
                xy = shapely.get_coordinates(piece)
                t = np.clip((xy - a[:2]) @ d[:2] / dd, 0.0, 1.0) if dd else np.array([0.0, 1.0])
                t0, t1 = float(t.min()), float(t.max())
                if zone.above_seabed is None:
                    zs = a[2] + np.array([t0, t1]) * d[2]
                    if zs.max() >= -zone.bottom and zs.min() <= -zone.top:
                        hits.append((k + 1, zone.name))
                        break
                else:
                    n = max(int(np.hypot(*(d[:2] * (t1 - t0))) / 1.0), 2)
                    q = a + np.linspace(t0, t1, n)[:, None] * d
                    if (q[:, 2] - world.seabed(q[:, 0], q[:, 1]) <= zone.above_seabed).any():
                        hits.append((k + 1, zone.name))
                        break
    return hits


def spec_for(name: str) -> PlannerSpec:
    """Small budgets: the count of entries, not the optimality, is measured."""
    if name == "timeopt":
        return PlannerSpec(name="timeopt", timeopt=TimeoptParams(cell=150.0, levels=3))
    if name == "grid":  # one lattice of about 20 000 nodes, not the ladder refined to convergence
        return PlannerSpec(name="grid", grid=GridParams(target_nodes=20_000, ladder=False, converge=False))
    return PlannerSpec(name=name, population=12, budget=600, polish=0)


def path_digest(result: PlanResult) -> str:
    """A short hash of a plan's status and path bytes: two runs planned the same iff their digests agree."""
    path = np.ascontiguousarray(result.path, dtype=float)
    status = result.status.value
    return hashlib.sha256(status.encode() + path.tobytes()).hexdigest()[:16]


def montecarlo(missions: int, planners: list[str], seed: int, n_zones: int,
               digests: dict[str, list[str]] | None = None) -> dict[str, dict[str, float]]:
    """Entries of the feasible plans over ``missions`` random missions per planner.

    ``digests``, when given, receives each planner's per-mission :func:`path_digest` (to compare two
    versions of the code mission by mission).
    """
    out: dict[str, dict[str, float]] = {}
    for name in planners:
        if digests is not None:
            digests[name] = []
        rng = np.random.default_rng(seed)
        ok = entries = blocked = 0
        failed: dict[str, str] = {}  # mission: status -> message, of the plans not reported feasible
        t0 = time.process_time()
        for m in range(missions):
            world = random_world(rng, n_zones)
            problem = PlanningProblem(world, free_point(rng, world), free_point(rng, world), speed=1.5)
            blocked += bool(world.zones.exact.segments_enter(np.stack([problem.start, problem.goal])[None])[0])
            result = plan(problem, spec_for(name), rng=m)
            if digests is not None:
                digests[name].append(path_digest(result))
            if result.status.ok:
                ok += 1
                entries += len(independent_entries(world, result.path))
            else:
                failed[f"{m}: {result.status.value}"] = result.message[:120]
            if (m + 1) % 100 == 0 and m + 1 < missions:  # a partial count survives a time box
                print(json.dumps({name: {"missions": m + 1, "straight_line_enters": blocked, "feasible": ok,
                                         "entries": entries, "cpu_s": round(time.process_time() - t0, 1)}}),
                      flush=True)
        out[name] = {"missions": missions, "straight_line_enters": blocked, "feasible": ok, "entries": entries,
                     "cpu_s": round(time.process_time() - t0, 1)}
        if failed:
            print(json.dumps({name: {"not_feasible": failed}}), flush=True)
        print(json.dumps({name: out[name]}), flush=True)
    return out


def scattered_zones(world: World, start: np.ndarray, goal: np.ndarray, n: int, seed: int) -> Zones:
    """``n`` random zones over the world's bounds, none within 1 km of the start or the goal."""
    rng = np.random.default_rng(seed)
    b = world.bounds
    zones: list[Zone] = []
    ends = shapely.multipoints([start[:2], goal[:2]])
    while len(zones) < n:
        c = rng.uniform([b.xmin, b.ymin], [b.xmax, b.ymax])
        k = len(zones) % 3
        if k == 0:
            z = Zone(f"wreck {len(zones)}", shapely.buffer(shapely.points(c), rng.uniform(50, 300)),
                     above_seabed=rng.uniform(10, 50))
        elif k == 1:
            z = Zone(f"cable {len(zones)}", shapely.buffer(shapely.linestrings([c, c + rng.uniform(-2000, 2000, 2)]),
                                                           rng.uniform(20, 100)))
        else:
            z = Zone(f"area {len(zones)}", shapely.box(*(c - 150), *(c + 150)), top=rng.uniform(0, 100),
                     bottom=rng.uniform(150, 3000))
        if shapely.distance(z.footprint, ends) > 1000.0:
            zones.append(z)
    return Zones(tuple(zones), world.terrain, pad=1.0)


def cpu(scenario: str, n_zones: int, repeats: int, planner: str, budget: int = 0) -> dict[str, float]:
    """CPU of the default plan without and with ``n_zones`` zones (``budget``: the plans' budget given
    explicitly, spent exactly: IABC's stop of a stalled swarm off)."""
    base, zoned, spec = _cpu_problems(scenario, n_zones)
    spec = replace(spec, name=planner, budget=budget)
    plan(zoned, spec, rng=0)  # compile every kernel once
    plan(base, spec, rng=0)
    times: dict[str, list[float]] = {"none": [], "zones": []}
    for r in range(repeats):
        for key, problem in (("none", base), ("zones", zoned)):
            t = time.process_time()
            res = plan(problem, spec, rng=r)
            times[key].append(time.process_time() - t)
            assert res.status.ok, res.message
    med = {k: statistics.median(v) for k, v in times.items()}
    what = f"plan, `--budget {budget}`" if budget else "default plan"
    return {"scenario": scenario, "planner": planner, "plan": what, "zones": n_zones,
            "cpu_none_s": round(med["none"], 3), "cpu_zones_s": round(med["zones"], 3),
            "ratio": round(med["zones"] / med["none"], 2),
            "load_1min": os.getloadavg()[0]}


def _cpu_problems(scenario: str, n_zones: int) -> tuple[PlanningProblem, PlanningProblem, PlannerSpec]:
    """The ``cpu`` problem without and with ``n_zones`` scattered zones, and the scenario's planner."""
    from auvplan.io.scenario.build import build
    from auvplan.io.scenario.loader import load
    from auvplan.sim.pipeline import planning_problem

    world, mission = build(load(scenario))
    world = replace(world, zones=None)
    base = planning_problem(world, mission)
    zoned = replace(base, world=replace(world, zones=scattered_zones(world, base.start, base.goal, n_zones, 7)))
    return base, zoned, mission.planner


def passes(scenario: str, n_zones: int, plans: int, repeats: int, planner: str, save: str = "",
           load_from: str = "") -> dict[str, float | str]:
    """CPU of the zones' pass over the populations of ``plans`` plans (per plan; ``load_from``: the
    populations saved by an earlier run with ``save``, of as many plans), replayed."""
    _, zoned, spec = _cpu_problems(scenario, n_zones)
    zones = zoned.world.zones
    assert zones is not None
    if load_from:
        with np.load(load_from) as data:
            pops = [data[k] for k in sorted(data.files, key=lambda k: int(k[1:]))]
    else:
        pops = []
        asked = type(zones).polyline_slack

        def record(self: Zones, points: np.ndarray) -> np.ndarray:
            pops.append(np.array(points, dtype=float))
            return asked(self, points)

        type(zones).polyline_slack = record  # type: ignore[method-assign]
        try:
            for r in range(plans):
                plan(zoned, replace(spec, name=planner), rng=r)
        finally:
            type(zones).polyline_slack = asked  # type: ignore[method-assign]
        if save:
            np.savez(save, **{f"p{i}": p for i, p in enumerate(pops)})
    digest = hashlib.sha256()
    entering = 0
    for p in pops:
        slack = np.ascontiguousarray(zones.polyline_slack(p))
        digest.update(slack.tobytes())
        entering += int(np.isfinite(slack).sum())
    best = np.inf
    for _ in range(repeats):
        t = time.process_time()
        for p in pops:
            zones.polyline_slack(p)
        best = min(best, time.process_time() - t)
    legs = sum(p.shape[0] * (p.shape[1] - 1) for p in pops)
    return {"scenario": scenario, "zones": n_zones, "plans": plans, "calls": len(pops), "legs_per_plan": legs // plans,
            "entering_legs": entering, "pass_s_per_plan": round(best / plans, 4),
            "ns_per_leg": round(1e9 * best / legs, 1),
            "slack_digest": digest.hexdigest()[:16], "load_1min": os.getloadavg()[0]}


def stall(scenario: str, counts: list[int], seeds: int, builtin_seeds: int) -> dict[str, dict[str, float]]:
    """What IABC's stop of a swarm stalled behind its lattice corridor does to the plans: every default plan
    (the stop on) against the same plan with the same budget given explicitly (spent exactly: the stop off),
    same seed, path bytes.  On the ``cpu`` problem with each of ``counts`` zones (seeds 0 .. ``seeds`` - 1)
    and on every built-in whose planner is the seeded IABC at its default budget (``builtin_seeds`` seeds)."""
    from auvplan.io.scenario.build import build
    from auvplan.io.scenario.builtins import builtin_scenarios
    from auvplan.io.scenario.loader import load
    from auvplan.sim.pipeline import planning_problem

    cases: dict[str, list[tuple[PlanningProblem, PlannerSpec, int]]] = {}
    for n in counts:
        _, zoned, spec = _cpu_problems(scenario, n)
        cases[f"`{scenario}` + {n} zones"] = [(zoned, spec, r) for r in range(seeds)]
    for name in sorted(builtin_scenarios()):
        world, mission = build(load(name))
        spec = mission.planner
        if spec.pipeline == "seeded" and spec.name == "iabc" and spec.budget == 0:
            cases.setdefault("built-ins", []).extend((planning_problem(world, mission), spec, r)
                                                     for r in range(builtin_seeds))
    out: dict[str, dict[str, float]] = {}
    for label, runs in cases.items():
        stopped = same = 0
        worst, evals, full_evals = 0.0, 0, 0
        for problem, spec, r in runs:
            a = plan(problem, spec, rng=r)
            b = plan(problem, replace(spec, budget=spec.evaluations), rng=r)
            stopped += "swarm_stopped_at_evaluations" in a.work
            same += a.status == b.status and np.array_equal(a.path, b.path)
            worst = max(worst, a.cost / b.cost - 1.0) if np.isfinite(a.cost + b.cost) else worst
            evals, full_evals = evals + a.evaluations, full_evals + b.evaluations
        out[label] = {"plans": len(runs), "stopped": stopped, "same_path": same, "worst_pct": 100.0 * worst,
                      "evaluations_pct": 100.0 * evals / full_evals}
        print(json.dumps({label: out[label]}), flush=True)
    return out


def gap(scenario: str) -> dict[str, float]:
    """The default plan's cost against the reference's, same zones."""
    from auvplan.io.scenario.build import build
    from auvplan.io.scenario.loader import load
    from auvplan.sim.pipeline import planning_problem

    world, mission = build(load(scenario))
    problem = planning_problem(world, mission)
    default = plan(problem, mission.planner, rng=mission.seed)
    ref = reference(problem, mission.planner)
    return {"scenario": scenario, "planner": mission.planner.name, "status": default.status.value,
            "cost": default.cost, "reference_cost": ref.cost, "gap_pct": 100.0 * (default.cost / ref.cost - 1.0),
            "zone_clearance_min_m": default.cost_terms.get("zone_clearance_min_m", float("nan"))}


def _figure(name: str, text: str) -> None:
    """Write ``docs/figures/<name>.md`` (quoted in docs/zones.md)."""
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "docs" / "figures" / f"{name}.md"
    path.write_text(text.rstrip() + "\n")
    print(f"wrote {path}")


def _figure_text(cmd: str, res: dict, argv: str) -> str:
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    if cmd == "montecarlo":
        rows = "\n".join(f"| `{k}` | {v['missions']} | {v['straight_line_enters']} | {v['feasible']} | "
                         f"**{v['entries']}** | {v['cpu_s']} |" for k, v in res.items())
        return ("| planner | missions | straight line enters a zone | reported feasible | entries (independent "
                "check) | CPU (s) |\n"
                f"| --- | --- | --- | --- | --- | --- |\n{rows}\n\n`python benchmarks/zones.py {argv}`; "
                f"load {load} at the end.")
    if cmd == "stall":
        rows = "\n".join(f"| {k} | {v['plans']} | {v['stopped']} | **{v['same_path']}** | {v['worst_pct']:+.3f} % | "
                         f"{v['evaluations_pct']:.0f} % |" for k, v in res.items())
        return ("| problem | plans | swarm stopped | same path as with the stop off | worst cost change | "
                "evaluations spent |\n| --- | --- | --- | --- | --- | --- |\n"
                f"{rows}\n\n`python benchmarks/zones.py {argv}`; load {load} at the end.")
    if cmd == "cpu":
        return (f"| problem | no zones | {res['zones']} zones | ratio |\n| --- | --- | --- | --- |\n"
                f"| `{res['scenario']}`, `{res['planner']}` {res['plan']} | {res['cpu_none_s']} s CPU | "
                f"{res['cpu_zones_s']} s CPU | **{res['ratio']}×** |\n\n`python benchmarks/zones.py {argv}` (median of "
                f"repeats after a warm-up); load {load} at the end.")
    return (f"| scenario | default plan (`{res['planner']}`) | `--reference` | gap | least distance to a zone |\n"
            f"| --- | --- | --- | --- | --- |\n| `{res['scenario']}` | {res['cost']:.1f} ({res['status']}) | "
            f"{res['reference_cost']:.1f} | **{res['gap_pct']:+.3f} %** | {res['zone_clearance_min_m']:.2f} m |\n\n"
            f"`python benchmarks/zones.py {argv}`; load {load} at the end.")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("montecarlo")
    m.add_argument("--missions", type=int, default=1000)
    m.add_argument("--planners", nargs="+", default=["iabc", "abc", "ga", "pso", "de", "grid", "timeopt"])
    m.add_argument("--zones", type=int, default=20)
    m.add_argument("--seed", type=int, default=53)
    m.add_argument("--digests", default="", help="write each plan's path digest here (JSON, per planner)")
    c = sub.add_parser("cpu")
    c.add_argument("--scenario", default="marcus-wake")
    c.add_argument("--planner", default="iabc")
    c.add_argument("--zones", type=int, default=1000)
    c.add_argument("--repeats", type=int, default=5)
    c.add_argument("--budget", type=int, default=0, help="an explicit budget (spent exactly: the stop off)")
    q = sub.add_parser("passes")
    q.add_argument("--scenario", default="marcus-wake")
    q.add_argument("--planner", default="iabc")
    q.add_argument("--zones", type=int, default=1000)
    q.add_argument("--plans", type=int, default=3)
    q.add_argument("--repeats", type=int, default=5)
    q.add_argument("--save", default="", help="keep the recorded populations here (.npz)")
    q.add_argument("--load", default="", help="replay the populations saved by --save (same --scenario, --zones)")
    t = sub.add_parser("stall")
    t.add_argument("--scenario", default="marcus-wake")
    t.add_argument("--zones", type=int, nargs="+", default=[100, 300, 500, 700, 1000, 1500])
    t.add_argument("--seeds", type=int, default=24)
    t.add_argument("--builtin-seeds", type=int, default=4)
    g = sub.add_parser("gap")
    g.add_argument("--scenario", default="chagos-reefs")
    for p in (m, c, g, t):
        p.add_argument("--figure-md", default="", help="also write docs/figures/<NAME>.md")
    args = ap.parse_args()
    if args.cmd == "montecarlo":
        import signal
        import sys

        signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # a time box still writes the digests
        digests: dict[str, list[str]] = {}
        try:
            res = montecarlo(args.missions, args.planners, args.seed, args.zones, digests)
        finally:
            if args.digests:
                with open(args.digests, "w") as fh:
                    json.dump(digests, fh)
    elif args.cmd == "cpu":
        res = cpu(args.scenario, args.zones, args.repeats, args.planner, args.budget)
    elif args.cmd == "stall":
        res = stall(args.scenario, args.zones, args.seeds, args.builtin_seeds)
    elif args.cmd == "passes":
        res = passes(args.scenario, args.zones, args.plans, args.repeats, args.planner, args.save, args.load)
    else:
        res = gap(args.scenario)
    print(json.dumps(res))
    if getattr(args, "figure_md", ""):
        import sys

        _figure(args.figure_md, _figure_text(args.cmd, res, " ".join(sys.argv[1:])))


if __name__ == "__main__":
    main()
