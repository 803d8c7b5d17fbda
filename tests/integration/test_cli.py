"""The command line, through cli.main([...])."""

from __future__ import annotations

import json

import pytest

from auvplan.cli import main
from test_scenario import BASE


@pytest.mark.parametrize("name", ["marcus-wake", "salish-shelf"])
def test_validate_builtin(name, capsys):
    assert main(["validate", name]) == 0
    assert "OK" in capsys.readouterr().out


def test_validate_bad_file_exits_2(tmp_path, capsys):
    p = tmp_path / "bad.toml"
    p.write_text(BASE.replace("population = 20", "population = 1"))
    assert main(["validate", str(p)]) == 2
    err = capsys.readouterr().err
    assert "population" in err and str(p) in err


def test_scenarios_lists_builtins(capsys):
    assert main(["scenarios"]) == 0
    out = capsys.readouterr().out
    assert "marcus-wake" in out and "salish-shelf" in out


def test_plan_json_is_one_object_on_stdout(tmp_path, capsys):
    p = tmp_path / "lab.toml"
    p.write_text(BASE)
    code = main(["plan", str(p), "--planner", "iabc", "--seed", "2", "--json", "--out", str(tmp_path / "out")])
    out = capsys.readouterr().out
    rec = json.loads(out)
    assert out.count("\n") == 1
    assert rec["planner"] == "iabc" and rec["seed"] == 2 and rec["scenario"] == "lab"
    assert code == (0 if rec["status"] in ("EXACT", "APPROXIMATE") else 1)
    for key in ("length_m", "energy_j", "duration_s", "min_clearance_m", "collisions", "cost", "cost_terms",
                "evaluations", "iterations", "wall_time_s", "history", "waypoints"):
        assert key in rec
    assert (tmp_path / "out" / "metrics.json").is_file() and (tmp_path / "out" / "path.csv").is_file()


def test_plan_budget_is_respected(tmp_path, capsys):
    p = tmp_path / "lab.toml"
    p.write_text(BASE)
    main(["plan", str(p), "--planner", "abc", "--budget", "333", "--json"])
    assert json.loads(capsys.readouterr().out)["evaluations"] == 333


def test_unknown_planner_is_usage_error(capsys):
    assert main(["plan", "marcus-wake", "--planner", "dijkstra"]) == 2


def test_progress_bar_only_for_iterating_planners():
    """The swarm optimisers report iterations; grid and flow would show a bar stuck at 0 — none is shown."""
    from auvplan.cli.output import Progress as _Progress
    from auvplan.planners import PlannerSpec

    for name, shown in (("iabc", True), ("pso", True), ("grid", False), ("flow", False)):
        bar = _Progress(PlannerSpec(name=name), "scene", quiet=False)
        assert bar.bar.disable is not shown
        bar.close()
    assert _Progress(PlannerSpec(name="iabc"), "scene", quiet=True).bar.disable


def test_long_stages_report_progress_on_stderr_unless_quiet(tmp_path, capsys):
    """The flight gets a bar (simulated seconds of the expected duration), the results a stage
    line; ``-q`` silences both and stdout keeps only the summary."""
    assert main(["simulate", "track-arc", "--seed", "1"]) == 0
    err = capsys.readouterr().err
    assert "flight on track-arc" in err and "s/s" in err
    assert main(["-q", "run", "track-arc", "--out", str(tmp_path / "r")]) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and "track-arc: EXACT" in captured.out
    assert "no seabed" in captured.out and "no obstacle," in captured.out and "inf m" not in captured.out
    assert main(["run", "track-arc", "--out", str(tmp_path / "r2")]) == 0
    assert "auvplan: writing results, report and exports" in capsys.readouterr().err
    assert main(["plan", "track-single", "--planner", "grid", "--reference"]) in (0, 1)
    assert "auvplan: planning with grid" in (err := capsys.readouterr().err) and "auvplan: reference:" in err
