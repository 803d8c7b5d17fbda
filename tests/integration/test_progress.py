"""Progress of the long commands (issue 40): the departure sweep reports departures done / total with
an ETA on stderr, and nothing under --json."""

from __future__ import annotations

import json

import numpy as np
from test_timeopt import CASES, GOAL, SPEC, START, V, uniform_world

from auvplan.cli import main
from auvplan.planners import PlanningProblem
from auvplan.planners.timeopt.planner import departure_sweep
from helpers import coarse_tides


def test_departure_sweep_calls_progress_after_every_departure():
    world, _, _ = uniform_world(CASES["reversing"], tmax=80000.0)
    calls: list[tuple[int, int]] = []
    rows, _ = departure_sweep(PlanningProblem(world, START, GOAL, speed=V), SPEC, np.array([0.0, 10000.0, 20000.0]),
                              progress=lambda done, total: calls.append((done, total)))
    assert calls == [(1, 3), (2, 3), (3, 3)] and len(rows) == 3


def test_cli_sweep_shows_departures_done_and_eta_and_is_quiet_under_json(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))  # its checkpoints: not the user's cache
    args = ["plan", coarse_tides(tmp_path), "--depart-between", "+0h", "+6h", "--step", "6h"]  # real, 2 km cells
    assert main(args) == 0
    captured = capsys.readouterr()
    assert "departures of juan-de-fuca-tides" in captured.err and "2/2" in captured.err
    assert "<" in captured.err.split("2/2", 1)[1]  # tqdm's elapsed<remaining: the ETA
    assert "best departure" in captured.out
    assert main([*args, "--json"]) == 0
    captured = capsys.readouterr()
    assert "departures of" not in captured.err and json.loads(captured.out)["summary"]["feasible_departures"] == 2
