"""Edges 12: the operator surfaces never read "fine" where auvplan's own verdict is FAIL (each test failed on the
code before its fix)."""

from __future__ import annotations

import json

import pytest

_TOML = """
name = "surfaces"
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 3000.0]
y = [0.0, 1000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 200.0
cell_m = 100.0
[mission]
start = [100.0, 500.0, -150.0]
goal = [2100.0, 500.0, -10.0]
min_altitude_m = 20.0
min_depth_m = 1.0
max_depth_m = 300.0
[[zones]]
name = "shallows"
polygon = [[600.0, 300.0], [900.0, 300.0], [900.0, 700.0], [600.0, 700.0]]
top_m = 0.0
bottom_m = 5.0
"""


def _check(tmp_path, capsys, name: str, text: str, scenario: str = _TOML, *extra: str) -> tuple[int, dict]:
    from auvplan.cli import main

    scen = tmp_path / "s.toml"
    scen.write_text(scenario)
    f = tmp_path / name
    f.write_text(text)
    code = main(["mission", "check", str(f), "--scenario", str(scen), "--json", *extra])
    return code, json.loads(capsys.readouterr().out)


@pytest.mark.parametrize(("name", "text", "extra", "failed"), [
    ("zone.csv", "x,y,z\n100,500,-3\n2100,500,-3\n", "", "zones"),  # 3 m deep through the 0-5 m band
    ("steep.csv", "x,y,z\n1000,500,-150\n1100,500,-10\n1300,500,-10\n", "", "vehicle"),  # a 54.5 deg climb
    ("energy.csv", "x,y,z\n100,500,-150\n2100,500,-10\n", "[vehicle]\nbattery_wh = 1.0\n", "energy"),
])
def test_mission_check_json_ok_is_the_exit_code_s_verdict(tmp_path, capsys, name, text, extra, failed):
    """Oracle: the exit code.  ``--json``'s top-level ``ok`` was the seabed check's alone (``MissionCheck.ok``): a
    file entering a zone, breaking the vehicle's pitch or the energy budget read ``"ok": true`` with exit 1."""
    code, rec = _check(tmp_path, capsys, name, text, _TOML + extra)
    assert code == 1 and rec["ok"] is False
    assert rec["check_ok"] is True  # the seabed/obstacles/surface/band/bounds verdict, kept under its own name
    assert {"zones": any(z["entered_legs"] for z in rec.get("zones", [])), "vehicle": not rec["vehicle"]["ok"],
            "energy": rec["energy"]["energy_status"] == "RESERVE_BROKEN"}[failed]


def test_mission_check_json_ok_is_true_when_every_check_passes(tmp_path, capsys):
    code, rec = _check(tmp_path, capsys, "fine.csv", "x,y,z\n100,500,-150\n2100,500,-10\n")
    assert code == 0 and rec["ok"] is True and rec["check_ok"] is True
