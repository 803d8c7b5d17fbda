"""``--reference`` (:func:`auvplan.planners.reference`: the lattice ladder plus three seeded swarms at twice
the budget, each refined) on the hard problems, this tree's code against another commit's, in one run.

The other commit (``--peer``, e.g. the branch point) is checked out into a temporary git worktree and run
in a child process (:class:`release_peer.ReleasePeer`, as ``benchmarks/hard.py --reference-peer``); the
two are interleaved problem by problem and repeat by repeat, so both see the same load.  Each side's first
reference of a problem is a warm-up (numba's cache), not timed.  CPU = ``time.process_time()`` around
``reference`` alone; the median of the repeats is reported.

    nice -n 5 .venv/bin/python benchmarks/grid_reference.py --peer 07f244c --repeats 2 \\
        --figure docs/figures/lattice-reference-cpu.md
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from release_peer import ReleasePeer  # noqa: E402

SCENARIOS = ("ninetyeast-ridge", "new-england-seamounts", "chagos-banks", "marcus-wake-deep", "new-england-chain",
             "mariana-arc")


def main(argv: list[str] | None = None) -> int:
    from auvplan.io.scenario import loader as sc
    from auvplan.planners import reference
    from auvplan.sim import planning_problem

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--peer", required=True, help="the commit whose --reference is the yardstick")
    ap.add_argument("--scenarios", nargs="+", default=list(SCENARIOS))
    ap.add_argument("--budget", type=int, default=10_000, help="the plans' budget (the swarms run twice it)")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--figure", type=Path, help="write the table to this docs figure file")
    args = ap.parse_args(argv)
    rows = []
    loads = [os.getloadavg()[0]]
    with ReleasePeer(args.peer) as peer:
        for name in args.scenarios:
            world, mission = sc.build(sc.load(name))
            prob = planning_problem(world, mission)
            spec = replace(mission.planner, budget=args.budget)
            reference(prob, spec)  # warm-up, as the peer's first reference
            peer.plan(name, -1, args.budget)
            ours, theirs, cost, peer_cost, message = [], [], 0.0, 0.0, ""
            for _ in range(args.repeats):
                c0 = time.process_time()
                r = reference(prob, spec)
                ours.append(time.process_time() - c0)
                cost, message = r.cost, r.message
                row = peer.plan(name, -1, args.budget)
                theirs.append(float(row["cpu_s"]))  # type: ignore[arg-type]
                peer_cost = float(row["cost"])  # type: ignore[arg-type]
            loads.append(os.getloadavg()[0])
            rows.append({"scenario": name, "cpu": float(np.median(ours)), "peer_cpu": float(np.median(theirs)),
                         "cost": cost, "peer_cost": peer_cost, "winner": message.rsplit("each refined): ", 1)[-1]})
            r = rows[-1]
            print(f"{name:24s} cost {r['cost']:.2f} (peer {r['peer_cost']:.2f})  CPU {r['cpu']:.2f} s "
                  f"(peer {r['peer_cpu']:.2f} s, ratio {r['cpu'] / r['peer_cpu']:.2f})  {r['winner']}", flush=True)
    if args.figure is not None:
        cmd = " ".join(sys.argv[1:] if argv is None else argv)
        lines = [f"`nice -n 5 .venv/bin/python benchmarks/grid_reference.py {cmd}` "
                 f"(load average {min(loads):.1f}–{max(loads):.1f} on the shared 2-core host; `--reference` with the "
                 f"scenario's settings at budget {args.budget}; CPU = process time of `reference` alone, median of "
                 f"{args.repeats} repeats interleaved with the peer commit {args.peer}'s code in a child process)", "",
                 "| scenario | reference cost: now / peer | CPU s: now / peer (ratio) | the winning candidate now |",
                 "|---|---|---|---|"]
        for r in rows:
            lines.append(f"| {r['scenario']} | {r['cost']:,.2f} / {r['peer_cost']:,.2f} | {r['cpu']:.2f} / "
                         f"{r['peer_cpu']:.2f} ({r['cpu'] / r['peer_cpu']:.2f}) | {r['winner']} |")
        total = sum(r["cpu"] for r in rows) / sum(r["peer_cpu"] for r in rows)
        lines += ["", f"All problems: CPU ratio {total:.2f} (sum of the medians)."]
        args.figure.parent.mkdir(parents=True, exist_ok=True)
        args.figure.write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
