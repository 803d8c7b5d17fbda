"""Issue 56's live line through the glider's command (``run``/``plan`` of a glider scenario), which the live-line
tests never took: its stages are written on a line of their own in place of the command's starting clock (they
were printed onto the clock's line, "… 00:04auvplan: planning …", and the clock "run: starting" stayed live
through the whole flight), and the clock is gone before the result goes to stdout."""

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
