"""Sweeps on dask: rows independent of the worker count, streamed rows survive a kill, resume
completes without duplicates, and the summary agrees with the rows."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from auvplan.app.bench.rows import COLUMNS, KEY, TIMING, read_histories, read_rows, summarise
from auvplan.app.bench.sweep import SweepSpec, sweep
from auvplan.errors import AuvplanError

SPEC = SweepSpec(scenarios=("track-single", "track-double"), planners=("scenario",), guidance=("hybrid", "los"),
                 seeds=3, chunk=2)


def stable(rows):
    return [{k: r[k] for k in COLUMNS if k not in TIMING} for r in rows]


@pytest.fixture(scope="module")
def in_process(tmp_path_factory):
    """The sweep run in this process (``workers=0``: no dask), the rows the dask runs must give."""
    return sweep(SPEC, tmp_path_factory.mktemp("w0"), workers=0, progress=False)


def test_two_workers_give_the_same_rows_as_this_process(in_process, tmp_path):
    two = sweep(SPEC, tmp_path, workers=2, progress=False)
    assert len(in_process) == 2 * 2 * 3
    assert stable(two) == stable(in_process)
    assert len({tuple(r[k] for k in KEY) for r in two}) == len(two)
    assert {r["status"] for r in two if r["guidance"] == "hybrid"} == {"EXACT"}  # LOS ignores obstacles


def test_an_existing_sweep_is_not_overwritten(in_process, tmp_path):
    sweep(SweepSpec(scenarios=("track-single",), seeds=1), tmp_path, workers=0, progress=False)
    with pytest.raises(AuvplanError, match="--resume"):
        sweep(SweepSpec(scenarios=("track-single",), seeds=1), tmp_path, workers=0, progress=False)


def test_killed_sweep_resumes_without_duplicates(in_process, tmp_path):
    out = tmp_path / "killed"
    args = [sys.executable, "-m", "auvplan.cli", "bench", "--scenarios", "track-single", "track-double",
            "--guidance", "hybrid", "los", "--seeds", "3", "--chunk", "1", "--workers", "1", "--out", str(out)]
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.time() + 120
    while time.time() < deadline and len(read_rows(out / "rows.csv")) < 3:
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    partial = read_rows(out / "rows.csv")
    assert 3 <= len(partial) < 12  # killed midway, finished rows kept
    rows = sweep(SPEC, out, workers=0, resume=True, progress=False)
    assert stable(rows) == stable(in_process)
    with open(out / "rows.csv") as fh:
        assert sum(1 for _ in fh) == 1 + 12  # header + each run once
    keys = [tuple(h["key"]) for h in read_histories(out / "histories.jsonl")]
    assert sorted(keys) == sorted(tuple(r[k] for k in KEY) for r in rows)  # one history per row, no duplicate


def test_summary_matches_the_rows(in_process):
    table = summarise(in_process)
    assert [(t["scenario"], t["guidance"], t["runs"]) for t in table] == [
        ("track-double", "hybrid", 3), ("track-double", "los", 3), ("track-single", "hybrid", 3),
        ("track-single", "los", 3)]
    for t in table:
        rs = [r for r in in_process if (r["scenario"], r["guidance"]) == (t["scenario"], t["guidance"])]
        assert t["success_rate"] == np.mean([r["status"] == "EXACT" for r in rs])
    cpu = [float(r["cpu_s"]) for r in in_process if r["scenario"] == "track-double" and r["guidance"] == "los"]
    assert table[1]["cpu_s_median"] == pytest.approx(np.median(cpu))


def test_bad_sweep_names_are_errors():
    with pytest.raises(AuvplanError, match="planner"):
        SweepSpec(planners=("nope",))
    with pytest.raises(AuvplanError, match="guidance"):
        SweepSpec(guidance=("nope",))
    with pytest.raises(AuvplanError, match="pipeline"):
        SweepSpec(planners=("iabc/fast",))
    with pytest.raises(AuvplanError, match="planner"):
        SweepSpec(planners=("nope/document",))


def test_planner_labels_pick_the_pipeline(tmp_path):
    """``iabc/progressive`` and ``iabc/document`` run those pipelines: the rows' costs are the plans'
    of ``plan`` with the same spec and seed (an independent call), and differ from each other.  On showcase (a
    7 km flight, its planner iabc: 2 rows in ~3 s in this process; marcus-wake-deep's 140 km flights took ~40 s)."""
    from dataclasses import replace

    from auvplan.io.scenario import loader as scenario_io
    from auvplan.planners import plan
    from auvplan.sim import planning_problem

    spec = SweepSpec(scenarios=("showcase",), planners=("iabc/progressive", "iabc/document"),
                     guidance=("hybrid",), seeds=1, budget=600)
    rows = {r["planner"]: r for r in sweep(spec, tmp_path, workers=0, progress=False)}
    world, mission = scenario_io.build(scenario_io.load("showcase"))
    for label in ("iabc/progressive", "iabc/document"):
        pspec = replace(mission.planner, budget=600, pipeline=label.split("/")[1])
        r = plan(planning_problem(world, mission), pspec, rng=0)
        assert float(rows[label]["cost"]) == pytest.approx(r.cost, abs=1e-5), label  # rows hold 6 decimals
    assert rows["iabc/progressive"]["cost"] != rows["iabc/document"]["cost"]


def test_bench_command_writes_the_summary_and_an_offline_report(tmp_path):
    from auvplan.cli import main

    out = tmp_path / "cli"
    assert main(["bench", "--scenarios", "track-single", "--guidance", "hybrid", "ilos", "--seeds", "2",
                 "--workers", "1", "--out", str(out)]) == 0
    page = (out / "bench.html").read_text()
    assert 'id="costs"' in page and 'id="success"' in page and '<table id="summary">' in page
    lines = (out / "summary.csv").read_text().splitlines()
    assert lines[0].startswith("scenario,planner,guidance,runs,success_rate") and len(lines) == 3
