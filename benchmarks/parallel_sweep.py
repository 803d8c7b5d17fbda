"""The 51-departure sweep of ``juan-de-fuca-tides`` on dask.distributed (issue 56): the same rows on 1 and 2
workers, the wall-time ratio, and a killed sweep resumed without planning its finished departures again.

    .venv/bin/python benchmarks/parallel_sweep.py [--out results/parallel_sweep] [--kill-at 10] [--coarse]
        [--steps 1 2 resume]

``auvplan plan juan-de-fuca-tides --depart-between +0h +25h --step 30min`` (51 departures, real tides) is run
through :func:`auvplan.app.sweep.sweep_scenario`:

1. on a ``LocalCluster`` of 1 worker process and of 2 (the same cluster start-up cost in both), each with
   an empty checkpoint cache, in the order of ``--steps`` (``1 2 2 1`` for two interleaved rounds); the
   rows are compared bit for bit (all but ``cpu_s``, a measurement) and the total wall times give the
   ratio;
2. ``auvplan plan ... --workers 2 --out DIR`` as a command, killed (SIGKILL to its process group) once
   ``--kill-at`` departures are checkpointed; the checkpoints it left in ``DIR/.auvplan-tasks`` are
   counted, the sweep is run again in ``DIR`` and the departures it planned are counted (``computed`` =
   51 − checkpoints), and its rows are compared with step 1's.

``--coarse`` runs the same sweep (real bathymetry and tides) on a 2 km lattice of one level with the energy
integrated every km (``juan-de-fuca-tides`` edited as in ``tests/integration/test_parallel.py``): ~10× less
CPU per departure, for a loaded machine.

Prints and writes, after each step (a time-boxed run keeps what it measured), ``DIR/summary.json``,
``DIR/tables.json`` (each step's rows) and ``DIR/parallel-sweep.md`` (the table of ``docs/parallel.md``):
wall times, ratio, the load average (1 min) before and after each run (the machine is shared: the ratio is
only as good as the load is steady), counts and the identity of every step's rows.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ARGS: list = ["juan-de-fuca-tides", ["+0h", "+25h"], "30min"]


def _coarse(out: Path) -> str:
    from auvplan.io.scenario.builtins import resolve

    text = Path(resolve("juan-de-fuca-tides")).read_text(encoding="utf-8")
    text = text.replace("cell = 500.0", "cell = 2000.0").replace("levels = 4", "levels = 1")
    path = out / "jdf-coarse.toml"
    path.write_text(text + "\n[endurance]\nds_m = 1000.0\n", encoding="utf-8")
    return str(path.resolve())


def _table(run) -> list[dict]:
    return [{k: v for k, v in row.items() if k != "cpu_s"} for row in run.table]


def _timed(workers: int) -> tuple[object, dict]:
    from auvplan.app.sweep import sweep_scenario
    from auvplan.runtime.parallel import Runner

    with tempfile.TemporaryDirectory() as cache:
        os.environ["XDG_CACHE_HOME"] = cache  # no checkpoint of another run
        load0, t0 = os.getloadavg()[0], time.perf_counter()
        run = sweep_scenario(ARGS[0], ARGS[1], ARGS[2], runner=Runner(workers=workers))
        wall = time.perf_counter() - t0
    return run, {"workers": workers, "wall_s": round(wall, 1), "load_before": load0,
                 "load_after": os.getloadavg()[0], "departures": len(run.rows), "computed": run.computed}


def _killed_and_resumed(out: Path, kill_at: int) -> tuple[object, dict]:
    from auvplan.app.sweep import sweep_scenario
    from auvplan.runtime.parallel import Runner

    cmd = [sys.executable, "-m", "auvplan", "-q", "plan", ARGS[0], "--depart-between", *ARGS[1], "--step", ARGS[2],
           "--workers", "2", "--out", str(out), "--force"]
    proc, t0 = subprocess.Popen(cmd, start_new_session=True), time.perf_counter()
    while len(list((out / ".auvplan-tasks").glob("*.pkl"))) < kill_at and proc.poll() is None:
        time.sleep(0.5)
    os.killpg(proc.pid, signal.SIGKILL)  # the command and its dask workers, at once
    killed_after = time.perf_counter() - t0
    proc.wait()
    left = len(list((out / ".auvplan-tasks").glob("*.pkl")))
    load0, t0 = os.getloadavg()[0], time.perf_counter()
    run = sweep_scenario(ARGS[0], ARGS[1], ARGS[2], out=str(out), force=True, runner=Runner(workers=2))
    return run, {"killed_after_s": round(killed_after, 1), "checkpoints_left": left, "computed_on_resume": run.computed,
                 "resume_wall_s": round(time.perf_counter() - t0, 1), "load_before": load0,
                 "load_after": os.getloadavg()[0]}


def figure(summary: dict) -> str:
    """The table of ``docs/figures/parallel-sweep.md`` from a summary (``runs``, ``identical``, ``resume``)."""
    lines = ["| run | departures planned | wall | load (1 min) before → after |", "| --- | --- | --- | --- |"]
    lines += [f"| {f['workers']} worker{'s' if f['workers'] > 1 else ''} | {f['computed']} | {f['wall_s']:.1f} s | "
              f"{f['load_before']:.1f} → {f['load_after']:.1f} |" for f in summary["runs"]]
    r = summary.get("resume")
    if r:
        lines.append(f"| 2 workers, killed after {r['checkpoints_left']} checkpoints, run again | "
                     f"{r['computed_on_resume']} | {r['resume_wall_s']:.1f} s | {r['load_before']:.1f} → "
                     f"{r['load_after']:.1f} |")
    compared = " and ".join(summary["compared"])
    lines.append(f"| rows (all but `cpu_s`) of {compared} | | "
                 f"{'identical' if summary['identical'] else 'DIFFERENT'} | |")
    return "\n".join(lines) + "\n"


def _write(out: Path, summary: dict, tables: dict[str, list[dict]]) -> None:
    """The summary and the figure of the steps done so far (a time-boxed run keeps what it measured)."""
    first = next(iter(tables.values()), None)
    summary["compared"] = list(tables)
    summary["identical"] = all(t == first for t in tables.values())
    walls = {w: sum(f["wall_s"] for f in summary["runs"] if f["workers"] == w) for w in (1, 2)}
    if walls[1] and walls[2]:
        summary["wall_ratio_2_over_1"] = round(walls[2] / walls[1], 3)  # total over the rounds
    print(json.dumps(summary), flush=True)
    (out / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    (out / "tables.json").write_text(json.dumps(tables) + "\n")
    if tables:
        (out / "parallel-sweep.md").write_text(figure(summary))  # docs/figures/parallel-sweep.md


def main() -> None:
    """Run the sweeps (``--steps``, in that order) and write the summary after each."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="results/parallel_sweep")
    ap.add_argument("--kill-at", type=int, default=10, help="checkpointed departures at which the command is killed")
    ap.add_argument("--coarse", action="store_true", help="a 2 km lattice of one level (see the notes)")
    ap.add_argument("--steps", nargs="+", default=["1", "2", "resume"], choices=["1", "2", "resume"],
                    help="in this order: a sweep on 1 worker, on 2, the killed-and-resumed command (repeat a "
                         "step for another round: 1 2 2 1 resume)")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.coarse:
        ARGS[0] = _coarse(out)
    summary: dict = {"command": f"auvplan plan {ARGS[0]} --depart-between +0h +25h --step 30min",
                     "cores": os.cpu_count(), "runs": []}
    tables: dict[str, list[dict]] = {}
    for k, step in enumerate(args.steps):
        if step == "resume":
            run, summary["resume"] = _killed_and_resumed(out / "killed", args.kill_at)
            tables["resumed"] = _table(run)
        else:
            run, figures = _timed(int(step))
            summary["runs"].append(figures)
            tables[f"{step} worker{'s' if step == '2' else ''} ({k + 1})"] = _table(run)
        _write(out, summary, tables)


if __name__ == "__main__":
    main()
