"""``plan`` of a scenario with a fixed ``[mission] route`` says that ``run`` flies that route and that this plan goes
from start to goal without it (the plan and run folders of ``mariana-nav`` export different routes:
docs/navigation.md "plan and run"); a scenario without a route gets no such line, and ``--json`` stays one object."""

from __future__ import annotations

import json
import tomllib
from importlib import resources

import pytest

from auvplan.cli import main


def _route_waypoints(name: str) -> int:
    """The number of waypoints of a built-in's ``[mission] route``, read from its TOML (the oracle)."""
    text = resources.files("auvplan.data.scenarios").joinpath(f"{name}.toml").read_text()
    return len(tomllib.loads(text).get("mission", {}).get("route", []))


@pytest.mark.parametrize("name", ["track-single", "showcase"])
def test_plan_names_the_fixed_route_it_does_not_plan(name, capsys):
    n = _route_waypoints(name)
    assert main(["plan", name, "-q"]) == 0
    out = capsys.readouterr().out
    notes = [line for line in out.splitlines() if "[mission] route" in line]
    if n:
        assert notes == [f"  note: the scenario's [mission] route ({n} waypoints) is what `run` flies and exports; "
                         "this plan goes from start to goal without it"], out
    else:
        assert notes == [], out


def test_plan_json_has_no_note(capsys):
    assert main(["plan", "track-single", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert "note" not in json.dumps(record)
