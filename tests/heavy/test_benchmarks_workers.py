"""Issue 56: the Monte Carlo benchmarks on dask.distributed give the same rows on 1 and 2 worker processes.

Each of ``benchmarks/montecarlo.py``, ``avoidance.py``, ``formation.py`` and ``gap.py`` is run as a command on a
tiny case with ``--workers 1`` and with ``--workers 2`` (a ``LocalCluster`` of real processes each time); the
rows they write, in task order, must be equal but for the fields that measure time
(``benchmarks/parallel_runs.py``'s ``TIMING``).  Minutes of CPU: ``make bench-workers`` (the suite maps
``gap.py``'s plans in this process and on threads: tests/integration/test_benchmarks_parallel.py)."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "benchmarks"))
from parallel_runs import TIMING  # noqa: E402

CASES = {  # benchmark, its tiny case, the file of its rows
    "montecarlo": (["--seeds", "3"], "rows.jsonl"),
    "avoidance": (["--seeds", "2", "--sets", "avoidance-net", "gauntlet-randomised"], "rows.jsonl"),
    "formation": (["--seeds", "2"], "rows.csv"),
    "gap": (["--scenarios", "marcus-wake", "--planners", "pso", "de", "--seeds", "2", "--budget", "200"],
            "rows.jsonl"),
}
KEYS = ("set", "scenario", "planner", "avoidance", "seed")


def _rows(path: Path) -> list[dict]:
    if path.suffix == ".csv":
        with path.open(newline="") as fh:
            rows: list[dict] = list(csv.DictReader(fh))
    else:
        rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    rows = [{k: v for k, v in r.items() if k not in TIMING} for r in rows]  # written as they finish: sort
    return sorted(rows, key=lambda r: tuple(str(r.get(k, "")) for k in KEYS))


@pytest.mark.parametrize("name", sorted(CASES))
def test_one_and_two_workers_give_the_same_rows(tmp_path, name):
    extra, rows_file = CASES[name]
    got = {}
    for workers in (1, 2):
        out = tmp_path / f"w{workers}"
        cmd = [sys.executable, str(ROOT / "benchmarks" / f"{name}.py"), *extra, "--workers", str(workers),
               "--out", str(out)]
        subprocess.run(cmd, check=name != "gap", cwd=ROOT, stdout=subprocess.DEVNULL)  # gap: exit 1 past 0.05 %
        got[workers] = _rows(out / rows_file)
    print(f"\n{name}: {len(got[1])} rows, equal on 1 and 2 workers: {got[1] == got[2]}")
    assert got[1] and got[1] == got[2]
