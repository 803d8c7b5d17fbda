"""Sweeps on dask: rows independent of the worker count, streamed rows survive a kill, resume
completes without duplicates, and the summary agrees with the rows."""

from __future__ import annotations

import csv
import json
import signal
import subprocess
import sys

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
def in_process_out(tmp_path_factory):
    """The folder of the sweep run in this process (``workers=0``: no dask) and its rows, the rows the dask runs
    must give."""
    out = tmp_path_factory.mktemp("w0")
    return out, sweep(SPEC, out, workers=0, progress=False)


@pytest.fixture(scope="module")
def in_process(in_process_out):
    return in_process_out[1]


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


_KILLED_AFTER_ROWS = """
import os, signal
import tqdm
_real, _n = tqdm.tqdm.update, [0]
def _update(self, n=1):
    _real(self, n)
    _n[0] += n
    if _n[0] == {k}:  # the k-th row and its history flushed: the whole group (workers too) killed
        os.killpg(os.getpgid(0), signal.SIGKILL)
tqdm.tqdm.update = _update
"""


def _assert_each_run_once(out, rows, in_process):
    assert stable(rows) == stable(in_process)
    with open(out / "rows.csv") as fh:
        assert sum(1 for _ in fh) == 1 + 12  # header + each run once
    keys = [tuple(h["key"]) for h in read_histories(out / "histories.jsonl")]
    assert sorted(keys) == sorted(tuple(r[k] for k in KEY) for r in rows)  # one history per row, no duplicate


def test_killed_sweep_resumes_without_duplicates(in_process, tmp_path):
    """A real SIGKILL of the command (and its dask worker) after its third row, at a point the command itself
    picks (no race with a poll: killed midway however loaded the machine), then ``--resume`` in this process."""
    out = tmp_path / "killed"
    code = f"import sys\n{_KILLED_AFTER_ROWS.format(k=3)}\nfrom auvplan import cli\nsys.exit(cli.main(sys.argv[1:]))"
    args = [sys.executable, "-c", code, "bench", "--scenarios", "track-single", "track-double",
            "--guidance", "hybrid", "los", "--seeds", "3", "--chunk", "1", "--workers", "1", "--out", str(out)]
    proc = subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                          start_new_session=True, timeout=600)
    assert proc.returncode == -signal.SIGKILL, proc.stderr[-400:]
    partial = read_rows(out / "rows.csv")
    assert len(partial) == 3  # killed midway, finished rows kept
    rows = sweep(SPEC, out, workers=0, resume=True, progress=False)
    _assert_each_run_once(out, rows, in_process)


def _cut(text: bytes, at: float) -> bytes:
    return text[:int(len(text) * at)]


def _last_line(text: bytes) -> tuple[bytes, bytes]:
    """``text`` split before its last line."""
    k = text.rstrip(b"\n").rfind(b"\n") + 1
    return text[:k], text[k:]


@pytest.mark.parametrize("state", ["nothing", "history only", "history cut", "row cut", "both whole"])
def test_a_kill_at_each_point_of_a_row_s_write_resumes_to_each_run_once(in_process_out, tmp_path, state):
    """The points a kill can land at while a row arrives (its history line written and flushed, then its row),
    made on disk from the whole sweep's files: the last row's history whole or cut, its row absent or cut;
    ``--resume`` runs that row again and leaves each run once in both files."""
    whole, in_process = in_process_out
    out = tmp_path / "k"
    out.mkdir()
    rows_head, last_row = _last_line((whole / "rows.csv").read_bytes())
    hist_head, last_hist = _last_line((whole / "histories.jsonl").read_bytes())
    assert json.loads(last_hist)["key"] == next(csv.reader([last_row.decode()]))[:4]  # the same run's two lines
    hist, row = {"nothing": (b"", b""), "history only": (last_hist, b""), "history cut": (_cut(last_hist, 0.5), b""),
                 "row cut": (last_hist, _cut(last_row, 0.6)), "both whole": (last_hist, last_row)}[state]
    (out / "rows.csv").write_bytes(rows_head + row)
    (out / "histories.jsonl").write_bytes(hist_head + hist)
    assert len(read_rows(out / "rows.csv")) == (12 if state == "both whole" else 11)
    rows = sweep(SPEC, out, workers=0, resume=True, progress=False)
    _assert_each_run_once(out, rows, in_process)
    assert (out / "histories.jsonl").read_text().count("\n") == (12 if state in ("nothing", "history cut",
                                                                                 "both whole") else 13)


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
