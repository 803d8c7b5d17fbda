"""Speed against the previous release, measured in the same run: the simulator and the flow planner.

    nice -n 5 .venv/bin/python benchmarks/regress.py --prev 3e02e1a --rounds 5 --out results/bench-regress
    make bench-regress PREV=00cab27

The previous release is checked out into a temporary ``git worktree`` (removed afterwards) and both
trees are timed by the same interpreter, in child processes that import ``auvplan`` from
``<tree>/src`` (``PYTHONPATH``), alternating previous / current for ``--rounds`` rounds so that both
see the same machine load; each figure is the best (least CPU) over the rounds.  Measured:

* the simulator: CPU per step and the real-time factor of ``track-arc`` (document 001's sea trial,
  the scenario's own guidance, avoidance and waves) and of a 1-hour straight mission (36 270 steps);
* the flow planner: CPU per plan of ``flow-spheres`` and ``flow-ellipsoid`` (the planner alone,
  scenario loading excluded).

Every figure comes with a checksum of its result (the flown positions' sum, the plan's cost and
path sum), compared between the trees: ``identical`` means bit-identical; where the previous
release plans differently by design (flow-ellipsoid's bodies before wave 2) the row says so.  The
ratio is current / previous CPU: below 1 is faster.  Exit status 1 when a ratio exceeds
``--max-ratio`` (default 1.05: 5 % of noise on a shared machine).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PROBE = r'''
import json, sys, time
import numpy as np
try:
    from auvplan.io.scenario import loader as sc
except ImportError:  # before wave 3 the scenario module was one file
    from auvplan.io import scenario as sc
from dataclasses import replace
from auvplan.planners import plan
from auvplan.sim import Mission, planning_problem, simulate
from auvplan.vehicles import VehicleParams
from auvplan.world import Bounds, UniformCurrent, World

def best(f, repeats):
    out, t = None, float("inf")
    for _ in range(repeats):
        t0 = time.process_time()
        out = f()
        t = min(t, time.process_time() - t0)
    return t, out

rows = {}
world, mission = sc.build(sc.load("track-arc"))
simulate(world, mission, rng=0)
cpu, r = best(lambda: simulate(world, mission, rng=0), 5)
rows["sim track-arc"] = {"unit": "us/step", "value": cpu / r.t.size * 1e6, "xrt": float(r.t[-1]) / cpu,
                         "check": repr(float(np.sum(r.position)))}
length = 1.5 * 3600.0
hw = World(Bounds(-100, length + 100, -500, 500, -100, 0), currents=UniformCurrent((0.0, 0.2, 0.0)))
hm = Mission("hour", (0, 0, -20), (length, 0, -20), route=((0, 0, -20), (length, 0, -20)),
             vehicle=VehicleParams(wave_sigma_r=0.01, wave_sigma_v=0.05))
cpu, r = best(lambda: simulate(hw, hm, guidance="hybrid", rng=0), 2)
rows["sim 1-hour mission"] = {"unit": "us/step", "value": cpu / r.t.size * 1e6, "xrt": float(r.t[-1]) / cpu,
                              "check": repr(float(np.sum(r.position)))}
for key, scenario, rankine in json.loads(sys.argv[1]):
    w, m = sc.build(sc.load(scenario))
    prob = planning_problem(w, m)
    spec = replace(m.planner, name="flow")
    if rankine:
        spec = replace(spec, flow=replace(spec.flow, rankine=rankine))
    plan(prob, spec, 1)
    cpu, res = best(lambda: [plan(prob, spec, 1) for _ in range(5)][-1], 5)
    rows[key] = {"unit": "ms/plan", "value": cpu / 5 * 1e3, "xrt": None,
                 "check": repr((float(res.cost), float(np.sum(res.path))))}
print(json.dumps(rows))
'''


FIG8 = str(ROOT / "src" / "auvplan" / "data" / "scenarios" / "flow-fig8.toml")
"""flow-fig8 is newer than the release: both trees read today's file."""

FLOW_CASES: tuple[tuple[str, str, str | None, str | None, str], ...] = (
    # key, scenario, the previous tree's rankine, the current tree's rankine (None: the tree's default), kind
    ("flow flow-spheres", "flow-spheres", None, None, "default (spheres only: the same work)"),
    ("flow flow-ellipsoid", "flow-ellipsoid", None, None, "default vs default (today: Lamb ellipsoid; release: line)"),
    ("flow flow-fig8", FIG8, None, None, "default vs default (today: Lamb ellipsoid; release: line)"),
    ("flow flow-ellipsoid, line body", "flow-ellipsoid", "line", "line", "like for like (rankine = line in both)"),
    ("flow flow-fig8, line body", FIG8, "line", "line", "like for like (rankine = line in both)"),
)
"""The flow rows: (i) each tree's default settings (what a user sees), (ii) the same body in both."""


def probe(tree: Path, side: str) -> dict[str, dict]:
    """The figures of the ``auvplan`` in ``tree/src``, measured in a child process."""
    env = {**os.environ, "PYTHONPATH": str(tree / "src")}
    cases = [(key, scen, prev if side == "prev" else cur) for key, scen, prev, cur, _ in FLOW_CASES]
    out = subprocess.run([sys.executable, "-c", PROBE, json.dumps(cases)], env=env, cwd=tempfile.gettempdir(),
                         check=True, capture_output=True, text=True).stdout
    rows: dict[str, dict] = json.loads(out.strip().splitlines()[-1])
    return rows


def compare(prev: Path, cur: Path, rounds: int) -> tuple[dict[str, dict], dict[str, dict]]:
    """Median figures of both trees over ``rounds`` alternating rounds (each round's figure a best of repeats)."""
    runs: dict[str, dict[str, list[dict]]] = {"prev": {}, "cur": {}}
    for k in range(rounds):
        for side, tree in (("prev", prev), ("cur", cur)) if k % 2 == 0 else (("cur", cur), ("prev", prev)):
            for key, row in probe(tree, side).items():
                runs[side].setdefault(key, []).append(row)
        print(f"round {k + 1}/{rounds} done", file=sys.stderr)
    med: dict[str, dict[str, dict]] = {"prev": {}, "cur": {}}
    for side, rows in runs.items():
        for key, seq in rows.items():
            values = sorted(r["value"] for r in seq)
            n = len(values)
            value = values[n // 2] if n % 2 else 0.5 * (values[n // 2 - 1] + values[n // 2])
            xrt = [r["xrt"] for r in seq if r["xrt"]]
            checks = {r["check"] for r in seq}
            med[side][key] = {"unit": seq[0]["unit"], "value": value,
                              "xrt": sorted(xrt)[len(xrt) // 2] if xrt else None,
                              "check": seq[0]["check"] if len(checks) == 1 else "not repeatable"}
    return med["prev"], med["cur"]


def _fmt(r: dict) -> str:
    return f"{r['value']:.2f} {r['unit']}" + (f" ({r['xrt']:,.0f}x real time)" if r["xrt"] else "")


KINDS = {key: kind for key, _, _, _, kind in FLOW_CASES}


def table(prev: dict[str, dict], cur: dict[str, dict], label: str) -> tuple[str, float]:
    """Markdown rows and the worst ratio."""
    lines = [f"| measure | compared | previous ({label}) | current | ratio (current / previous CPU) | results |",
             "|---|---|---|---|---|---|"]
    worst = 0.0
    for key, c in cur.items():
        p = prev[key]
        ratio = c["value"] / p["value"]
        worst = max(worst, ratio)
        same = "identical" if c["check"] == p["check"] else f"differ: {p['check']} vs {c['check']}"
        kind = KINDS.get(key, "the same code path (default guidance)")
        lines.append(f"| {key} | {kind} | {_fmt(p)} | {_fmt(c)} | {ratio:.3f} | {same} |")
    return "\n".join(lines), worst


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--prev", default="f5c6a15", help="the previous release's commit (default: wave 3's end)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--max-ratio", type=float, default=1.05)
    ap.add_argument("--out", default="results/bench-regress")
    ap.add_argument("--figure-md", default="", help="also write docs/figures/NAME.md (quoted in the docs)")
    args = ap.parse_args(argv)
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="auvplan-prev-") as tmp:
        wt = Path(tmp) / "prev"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(wt), args.prev], check=True)
        try:
            prev, cur = compare(wt, ROOT, args.rounds)
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(wt)], check=False)
    text, worst = table(prev, cur, args.prev)
    text = (f"Speed against the previous release ({args.prev}), measured in one run (`make bench-regress`): "
            f"{args.rounds} interleaved rounds (previous / current, then current / previous), each figure a "
            f"round's best of 5 repeats (the simulator's 1-hour mission: of 2) after a warm-up, the median "
            f"over the rounds; seed 0 for the simulator, 1 for the flow planner; CPU time (`process_time`), "
            f"`nice -n 5`; load average {load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end "
            f"(2 cores, shared).  Worst ratio {worst:.3f}.\n\n{text}\n")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.md").write_text(text)
    if args.figure_md:
        (ROOT / "docs" / "figures" / f"{args.figure_md}.md").write_text(text)
    print(text)
    return 0 if worst <= args.max_ratio else 1


if __name__ == "__main__":
    raise SystemExit(main())
