"""``auvplan report`` (and ``export``) of a results folder whose ``scenario.toml`` was replaced after the run: the
report drew the run in the other scenario's world (its track over another seabed, its exports against other
bounds) without a word.  The run now keeps the SHA-256 of the scenario it saved (``run.json``'s
``scenario_sha256``) and report/export refuse the folder in one line (exit 2) when it differs; a folder written
before the field existed is reported as before."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import pytest

from auvplan import cli
from auvplan._types import Status
from auvplan.io.files import outdir
from auvplan.io.results import records
from auvplan.planners.core.base import PlanResult
from auvplan.sim import RunRecord

SCENARIO = Path(__file__).parents[2] / "src" / "auvplan" / "data" / "scenarios" / "flow-spheres.toml"


@pytest.fixture(autouse=True)
def _release_locks():
    yield
    outdir.release_all()


def _folder(root: Path) -> Path:
    path = np.array([[-20.0, -20.0, -20.0], [0.0, 5.0, 5.0], [26.0, 28.0, 30.0]])
    plan = PlanResult(Status.EXACT, path, 51.3, {"length_m": 75.0}, 500, 10, 0.4, np.linspace(60.0, 51.3, 10), "flow")
    out = root / "r"
    records.write_run(out, RunRecord("flow-spheres", 1, plan, path, path, None), SCENARIO.read_text())
    return out


def _report(out: Path, capsys) -> tuple[int, str]:
    code = cli.main(["-q", "report", str(out)])
    return code, capsys.readouterr().err


def test_the_run_keeps_the_digest_of_the_scenario_it_saved(tmp_path):
    out = _folder(tmp_path)
    rec = json.loads((out / "run.json").read_text())
    assert rec["scenario_sha256"] == hashlib.sha256((out / "scenario.toml").read_bytes()).hexdigest()


def test_a_replaced_scenario_is_refused_in_one_line(tmp_path, capsys):
    out = _folder(tmp_path)
    assert _report(out, capsys)[0] == 0  # the folder as written: reported
    (out / "report.html").unlink()
    text = (out / "scenario.toml").read_text()
    (out / "scenario.toml").write_text(text.replace("seed = ", "# moved\nseed = ", 1))  # a one-line edit
    code, err = _report(out, capsys)
    assert code == 2, err
    assert err.count("\n") == 1 and len(err) < 400, err
    assert f"{out / 'scenario.toml'}: not the scenario this run saved" in err and "scenario_sha256" in err
    assert not (out / "report.html").exists()  # nothing drawn from the mix


def test_a_folder_from_before_the_digest_is_still_reported(tmp_path, capsys):
    out = _folder(tmp_path)
    rec = json.loads((out / "run.json").read_text())
    del rec["scenario_sha256"]
    (out / "run.json").write_text(json.dumps(rec))
    assert _report(out, capsys)[0] == 0 and (out / "report.html").is_file()


@pytest.mark.parametrize("bad", [5, "xyz", "A" * 64, ["0" * 64]])
def test_a_malformed_digest_is_named(tmp_path, capsys, bad):
    out = _folder(tmp_path)
    rec = json.loads((out / "run.json").read_text())
    rec["scenario_sha256"] = bad
    (out / "run.json").write_text(json.dumps(rec))
    code, err = _report(out, capsys)
    assert code == 2 and err.count("\n") == 1 and "run.json: scenario_sha256 = " in err, err
