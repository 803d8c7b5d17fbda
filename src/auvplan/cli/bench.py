"""``bench``: its arguments to the job of :mod:`auvplan.app.bench`, and the summary table."""

from __future__ import annotations

import argparse

__all__: list[str] = []  # handlers: CLI internals, not library API


def cmd_bench(args: argparse.Namespace) -> int:
    """``bench``: the sweep, its summary printed and where its files are."""
    from ..app.bench.job import bench
    from ..app.bench.sweep import SweepSpec

    spec = SweepSpec(tuple(args.scenarios), tuple(args.planners), tuple(args.guidance), args.seeds, args.budget,
                     args.reference, args.randomise, args.plan_once, args.chunk, tuple(args.avoidance),
                     tuple(args.members), tuple(args.member_seeds))
    out, _, text = bench(spec, args.out, args.force, args.workers, args.scheduler, args.resume, args.retries)
    print(text)
    print(f"rows in {out / 'rows.csv'}, summary in {out / 'summary.md'}, report {out / 'bench.html'}")
    return 0
