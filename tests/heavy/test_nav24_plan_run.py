"""``plan`` then ``export`` and ``run`` agree on the same route (`make nav-plan-run`, ~15 s: a plan, its exports and a
55 000 s flight, too long for the suite): ``mariana-nav`` without its fixed ``[mission] route`` (so that ``plan``
and ``run`` both fly the planner's route) — the plan folder's exported files are those ``run`` writes, fixes
included (7; the ``.plan`` and ``.csv`` byte for byte, the ``.moos`` but for its time-out, which ``run`` takes from its
flight: 1.5 × 52 945 s flown against 1.5 × 52 052 s planned), and each passes ``mission check``.  With the fixed
route the two differ because the routes do (``docs/navigation.md``, "plan and run";
``tests/integration/test_nav23_plan_export.py``; helper nav2, wave 17)."""

from __future__ import annotations

import json
import re

from auvplan.cli import main
from auvplan.io.scenario.builtins import resolve

FORMATS = ("csv", "plan", "moos")


def test_plan_export_and_run_write_the_same_files_on_the_same_route(tmp_path, capsys):
    text = re.sub(r"route = \[.*?\n\]\n", "", resolve("mariana-nav").read_text(), flags=re.S)
    assert "route =" not in text
    toml = tmp_path / "mariana-planned.toml"
    toml.write_text(text)
    planned, flown = tmp_path / "plan", tmp_path / "run"
    assert main(["-q", "plan", str(toml), "--out", str(planned)]) == 0
    assert main(["-q", "export", str(planned), "--format", *FORMATS]) == 0
    assert main(["-q", "run", str(toml), "--out", str(flown)]) == 0
    for fmt in FORMATS:
        mine, theirs = (planned / f"mission.{fmt}").read_text(), (flown / f"mission.{fmt}").read_text()
        if fmt == "moos":  # the time-out rests on the flight where there is one (run's), else the planned time
            limit = re.compile(r"^\s*max_time\s*=.*$", re.M)
            assert len(limit.findall(mine)) == len(limit.findall(theirs)) == 1
            mine, theirs = limit.sub("", mine), limit.sub("", theirs)
        assert mine == theirs, fmt
        capsys.readouterr()
        assert main(["mission", "check", str(planned / f"mission.{fmt}"), "--scenario", str(toml), "--json"]) == 0
        rec = json.loads(capsys.readouterr().out)
        rec = rec["files"][0] if "files" in rec else rec
        assert rec["navigation"]["ok"] and rec["navigation"]["fixes"] == 7, rec["navigation"]
