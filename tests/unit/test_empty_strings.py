"""``key = ''`` for a string key whose default is unset ('' or none) was read as absent: ``[currents] tides = ''``
loaded a scenario with no current at all, ``[terrain] positive = ''`` auto-detected, a zone's ``layer = ''`` read
every layer.  Each is now refused, naming the file, the table, the key and the value (exit 2 at the command line).
A ``name`` may still be '' (an unnamed member or moving obstacle: tests/integration/test_hostile_round20.py)."""

from __future__ import annotations

import dataclasses
import typing

import pytest

from auvplan import cli
from auvplan.errors import ScenarioError
from auvplan.io.scenario import loader as scenario_io
from auvplan.io.scenario.specs import Scenario

BASE = """name = "e"
[origin]
lat = 48.2
lon = -124.0
[bounds]
x = [0.0, 3000.0]
y = [0.0, 3000.0]
z = [-100.0, 0.0]
"""
MISSION = "[mission]\nstart = [500.0, 1000.0, -15.0]\ngoal = [2500.0, 1000.0, -15.0]\n"
TERRAIN = '[terrain]\nbuiltin = "etopo1_chagos"\n'
ZONE = '[[zones]]\nname = "z"\nfile = "a.geojson"\n'

CASES = [  # (the document's tables after BASE, the table as the message names it, the key)
    (MISSION + "[currents]\ntides = ''\n", "[currents]", "tides"),
    (MISSION + "[currents]\nfile = ''\n", "[currents]", "file"),
    (MISSION + "[currents]\nfile = { path = 'c.nc', u = '' }\n", "[currents.file]", "u"),
    (MISSION + "[currents]\nfile = { path = 'c.nc', v = '' }\n", "[currents.file]", "v"),
    (MISSION + "[currents]\nfile = { path = 'c.nc', w = '' }\n", "[currents.file]", "w"),
    (MISSION + "[currents]\nuniform = [0.1, 0.0, 0.0]\nmembers = [{ name = 'a', file = '' }]\n",
     "[currents.members[0]]", "file"),
    (MISSION + "[currents]\nuniform = [0.1, 0.0, 0.0]\nmembers = [{ file = 'm.nc', dimension = '' }]\n",
     "[currents.members[0]]", "dimension"),
    (MISSION + "[terrain]\nfile = ''\n", "[terrain]", "file"),
    (MISSION + "[terrain]\nbuiltin = ''\n", "[terrain]", "builtin"),
    (MISSION + "[terrain]\nfile = 'b.nc'\nvariable = ''\n", "[terrain]", "variable"),
    (MISSION + TERRAIN + "positive = ''\n", "[terrain]", "positive"),
    (MISSION + TERRAIN + "uncertainty = ''\n", "[terrain]", "uncertainty"),
    (MISSION.replace("[mission]\n", "[mission]\nstart_time = ''\n"), "[mission]", "start_time"),
    (MISSION + "[land]\nfile = ''\n", "[land]", "file"),
    (MISSION + "[land]\nbuiltin = ''\n", "[land]", "builtin"),
    (MISSION + "[land]\nfile = 'l.shp'\nlayer = ''\n", "[land]", "layer"),
    (MISSION + "[survey]\nfile = ''\n", "[survey]", "file"),
    (MISSION + "[survey]\ncenterline_file = ''\n", "[survey]", "centerline_file"),
    (MISSION + "[survey]\nfile = 's.geojson'\nlayer = ''\n", "[survey]", "layer"),
    (MISSION + ZONE + "layer = ''\n", "[[zones]] #1", "layer"),
    (MISSION + ZONE + "where = ''\n", "[[zones]] #1", "where"),
    (MISSION + '[[zones]]\nname = "z"\nfile = ""\n', "[[zones]] #1", "file"),
]


@pytest.mark.parametrize(("tables", "table", "key"), CASES, ids=[f"{t}-{k}" for _, t, k in CASES])
def test_an_empty_string_is_refused_naming_the_key(tables, table, key):
    with pytest.raises(ScenarioError) as info:
        scenario_io.loads(BASE + tables, "e.toml")
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith(f"e.toml: {table} {key} = '': "), msg


def _unset_string_keys(cls: type, seen: set[type]) -> list[str]:
    """Every string key (reachable from the scenario's tables) whose default is '' or none: the keys ``''`` was
    read as absent for (an independent walk of the schema's dataclasses)."""
    if cls in seen:
        return []
    seen.add(cls)
    hints, out = typing.get_type_hints(cls), []
    for f in dataclasses.fields(cls):
        if not f.init or f.name.startswith("_"):
            continue
        tp = hints[f.name]
        args = {tp, *typing.get_args(tp), *(a for t in typing.get_args(tp) for a in typing.get_args(t))}
        if str in args and f.default in ("", None) and f.name != "name":  # a name may be '' (unnamed: round 20)
            out.append(f"{cls.__name__}.{f.name}")
        for a in args:
            if dataclasses.is_dataclass(a):
                out += _unset_string_keys(typing.cast(type, a), seen)
    return out


def test_every_unset_string_key_of_the_schema_is_covered():
    """A new key of this kind must refuse '' too: add it to CASES (the zones' keys are read by their own reader)."""
    covered = {f"{t}.{k}" for _, t, k in CASES}
    names = {"TerrainSpec": "[terrain]", "CurrentsSpec": "[currents]", "CurrentsFileSpec": "[currents.file]",
             "MemberSpec": "[currents.members[0]]", "MissionSpec": "[mission]", "LandSpec": "[land]",
             "SurveySpec": "[survey]", "MovingObstacle": "[[moving]] #1", "ZoneSpec": "[[zones]] #1"}
    missing = [k for k in _unset_string_keys(Scenario, set())
               if f"{names.get(k.split('.')[0], k.split('.')[0])}.{k.split('.')[1]}" not in covered]
    assert not missing, missing


def test_at_the_command_line_exit_2_one_line(tmp_path, capsys):
    (tmp_path / "e.toml").write_text(BASE + CASES[0][0])
    assert cli.main(["validate", str(tmp_path / "e.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "e.toml: [currents] tides = '': an empty string is not a value" in err, err
