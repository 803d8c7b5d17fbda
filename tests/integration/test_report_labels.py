"""``auvplan report`` trusted ``run.json``'s labels: ``"planner": 5`` drew a trace named 5, a 1 MB guidance name
went into the page, ``"seed": "3"`` and ``"cost": "1e5"`` were converted silently, and a label holding plotly's
pseudo-HTML (``<b>``, ``<img …>``) or matplotlib's mathtext (``$\\frac{``) was drawn as markup (or failed to draw).
Now a value of the wrong type or size stops the command (exit 2, one line naming run.json, the key and the value)
and the labels are drawn literally."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from auvplan import cli
from auvplan._types import Status
from auvplan.errors import DataError
from auvplan.io.files import outdir
from auvplan.io.results import records
from auvplan.planners.core.base import PlanResult
from auvplan.sim import RunRecord

SCENARIO = Path(__file__).parents[2] / "src" / "auvplan" / "data" / "scenarios" / "flow-spheres.toml"


@pytest.fixture(autouse=True)
def _release_locks():
    yield
    outdir.release_all()


def _folder(root: Path, scenario: str = "flow-spheres", planner: str = "flow") -> Path:
    """A plan's results folder (run.json, run.npz, scenario.toml) of a hand-made plan over flow-spheres."""
    path = np.array([[-20.0, -20.0, -20.0], [0.0, 5.0, 5.0], [26.0, 28.0, 30.0]])
    plan = PlanResult(Status.EXACT, path, 51.3, {"length_m": 75.0}, 500, 10, 0.4, np.linspace(60.0, 51.3, 10),
                      planner)
    out = root / "r"
    records.write_run(out, RunRecord(scenario, 1, plan, path, path, None), SCENARIO.read_text())
    return out


def _edit(out: Path, change) -> None:
    rec = json.loads((out / "run.json").read_text())
    change(rec)
    (out / "run.json").write_text(json.dumps(rec))


def _set(*keys_value):
    *keys, value = keys_value

    def change(rec):
        for k in keys[:-1]:
            rec = rec[k]
        rec[keys[-1]] = value
    return change


WRONG = [  # (the edit, what the message says after "run.json: ")
    (_set("scenario", 5), "scenario = 5: expected a string"),
    (_set("plan", "planner", 5), "plan.planner = 5: expected a string"),
    (_set("plan", "planner", ["flow"]), "plan.planner = ['flow']: expected a string"),
    (_set("plan", "planner", "x" * 1_000_000), "plan.planner: a string of 1000000 characters (at most "),
    (_set("plan", "planner", "flow\u202e"), "plan.planner = 'flow\\u202e': a control or formatting character"),
    (_set("plan", "message", {"a": 1}), "plan.message = {'a': 1}: expected a string"),
    (_set("plan", "status", "PWNED"), "plan.status = 'PWNED': not a status (EXACT"),
    (_set("plan", "cost", "1e5"), "plan.cost = '1e5': expected a number"),
    (_set("plan", "evaluations", 5.5), "plan.evaluations = 5.5: expected an integer"),
    (_set("plan", "cost_terms", "length_m", True), "plan.cost_terms.length_m = True: expected a number"),
    (_set("seed", "3"), "seed = '3': expected an integer"),
    (_set("plan", []), "plan = []: expected an object"),
]


@pytest.mark.parametrize(("change", "said"), WRONG, ids=[s.split(":")[0] for _, s in WRONG])
def test_a_value_of_the_wrong_type_or_size_is_named(tmp_path, change, said):
    out = _folder(tmp_path)
    _edit(out, change)
    with pytest.raises(DataError) as info:
        records.read_run(out)
    msg = str(info.value)
    assert "\n" not in msg and len(msg) < 300 and msg.startswith(f"{out / 'run.json'}: {said}"), msg


def test_report_of_a_hostile_run_json_exits_2_in_one_line_and_writes_nothing(tmp_path, capsys):
    out = _folder(tmp_path)
    _edit(out, _set("plan", "planner", "g" * 1_000_000))
    before = sorted(p.name for p in out.iterdir())
    assert cli.main(["-q", "report", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "run.json: plan.planner: a string of 1000000" in err and len(err) < 300, err[:300]
    assert sorted(p.name for p in out.iterdir()) == before  # no report.html, no lock left


def test_labels_are_drawn_literally_not_as_markup(tmp_path):
    """Oracle: plotly draws '&lt;' as '<' (so an escaped label shows as written) and reads a raw '<b>' or '<img'
    as markup; matplotlib reads '$…$' as mathtext ('$\\frac{' does not parse) unless the '$' is escaped."""
    import matplotlib

    matplotlib.use("Agg")
    from auvplan.io.scenario import loader
    from auvplan.viz.plots import write_mission_figures
    from auvplan.viz.report import figure_convergence
    from auvplan.viz.scene3d import figure_3d

    out = _folder(tmp_path, scenario="<b>bold</b> $\\frac{$", planner="<img src=x onerror=alert(1)>")
    record, _ = records.read_run(out)
    world, _ = loader.build(loader.load(SCENARIO))
    view = figure_3d(world, record)
    texts = [t.name for t in figure_convergence(record).data] + [t.name for t in view.data] + [view.layout.title.text]
    assert not [t for t in texts if t and ("<img" in t or "<b>" in t)], texts
    assert "&lt;img src=x onerror=alert(1)&gt;" in texts[0] and "&lt;b&gt;bold&lt;/b&gt;" in texts[-1]
    drawn = write_mission_figures(tmp_path / "fig", world, record, formats=("png",))  # mathtext: raised before
    assert len(drawn) == 3 and all(p.stat().st_size > 1000 for p in drawn)
