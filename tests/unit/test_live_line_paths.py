"""Issue 56's live line through what its tests never took: a command failing once its clock was drawn (the error
line was written onto the clock's), and the glider's command (``run``/``plan`` of a glider scenario), whose
stages were printed onto the clock's line ("… 00:04auvplan: planning …") with the clock "run: starting" live
through the whole flight and over the result: now each stage is a line of its own in place of the clock, and the
clock is gone before the result goes to stdout."""

from __future__ import annotations

import argparse

from auvplan.cli import glider, output


def test_glider_stages_replace_the_starting_clock_and_the_result_follows_it(monkeypatch, capsys):
    shown: list[object] = []

    def fake_job(scenario, out, force, say):  # the job's stages, as app.glider says them
        say("planning g in dive cycles")
        shown.append(output.LIVE.display.desc)
        say("flying the plan")
        shown.append(output.LIVE.display.desc)
        return None, {"scenario": "g", "status": "EXACT", "message": "", "arrived": True}

    def describe(rec):
        shown.append(output.LIVE.display)  # the live line when the result is printed
        return "g: EXACT"

    monkeypatch.setattr("auvplan.app.glider.glider_scenario", fake_job)
    monkeypatch.setattr(glider, "describe_glider", describe)
    output.starting("run: starting")  # as auvplan.cli.main does for a clocked command
    try:
        code = glider.cmd_glider(argparse.Namespace(scenario="g", quiet=False, json=False, out=None))
    finally:
        output.finish()
    assert code == 0
    assert shown == ["planning g in dive cycles", "flying the plan", None]
    captured = capsys.readouterr()
    assert "auvplan: planning g in dive cycles …\nauvplan: flying the plan …\n" in captured.err
    assert captured.out == "g: EXACT\n"


def test_a_quiet_glider_command_says_nothing(monkeypatch, capsys):
    def fake_job(scenario, out, force, say):
        say("planning g in dive cycles")
        return None, {"scenario": "g", "status": "EXACT", "message": "", "arrived": True}

    monkeypatch.setattr("auvplan.app.glider.glider_scenario", fake_job)
    assert glider.cmd_glider(argparse.Namespace(scenario="g", quiet=True, json=False, out=None)) == 0
    assert capsys.readouterr().err == ""


def test_an_error_after_a_drawn_clock_is_a_line_of_its_own(monkeypatch, capsys):
    """A command failing once its clock was drawn (a damaged current file found after seconds of reading the
    seabed): the one error line is not written onto the clock's ("… 00:03auvplan: error: …" before)."""
    from auvplan.cli import main
    from auvplan.errors import AuvplanError

    def fails(args):
        bar = output.LIVE.display
        bar.delay = 0  # drawn, as the live thread draws it after a silence of QUIET_S
        bar.refresh()
        raise AuvplanError("x.toml: [currents] file = 'bad.nc': damaged")

    monkeypatch.setattr("auvplan.cli.run.cmd_run", fails)
    assert main(["run", "x.toml"]) == 2
    err = capsys.readouterr().err
    assert "auvplan: run: starting" in err  # the clock was drawn ...
    before = err[:err.index("auvplan: error: x.toml: [currents] file = 'bad.nc': damaged\n")]
    assert before.endswith(("\r", "\n"))  # ... and cleared: the error starts its line (was "… 00:00auvplan: …")


def test_a_failed_plan_of_simulate_is_a_line_of_its_own(monkeypatch, capsys):
    """``simulate`` whose global plan failed once the clock was drawn: its verdict starts its own line."""
    from types import SimpleNamespace

    from auvplan.cli import main

    def fake_job(*args, **kw):
        bar = output.LIVE.display
        bar.delay = 0
        bar.refresh()  # the clock drawn, as after a silence
        plan = SimpleNamespace(status=SimpleNamespace(value="INFEASIBLE"), message="no path")
        return None, SimpleNamespace(sim=None, plan=plan), 1

    monkeypatch.setattr("auvplan.app.plan.simulate_scenario", fake_job)
    assert main(["simulate", "x.toml"]) == 1
    err = capsys.readouterr().err
    before = err[:err.index("auvplan: the global plan failed (INFEASIBLE): no path\n")]
    assert "reading the scenario" in before and before.endswith(("\r", "\n"))


def test_a_warning_logged_under_a_drawn_clock_is_a_line_of_its_own(capsys):
    """A reader's warning (replayed from the cache when the read ends, seconds into the stage) under the command
    line's log handler: its own line, the clock redrawn beneath ("… 00:02WARNING auvplan…" before)."""
    import logging

    handler = output.LogLines()
    handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
    log = logging.getLogger("auvplan.test.live")
    log.addHandler(handler)
    log.propagate = False
    try:
        output.starting("reading the scenario and its data")
        bar = output.LIVE.display
        bar.delay = 0
        bar.refresh()  # the clock drawn, as after a silence
        log.warning("the box reaches beyond the data; clipped")
    finally:
        output.finish()
        log.removeHandler(handler)
        log.propagate = True
    err = capsys.readouterr().err
    before = err[:err.index("WARNING auvplan.test.live: the box reaches beyond the data; clipped\n")]
    assert "reading the scenario" in before and before.endswith(("\r", "\n"))
