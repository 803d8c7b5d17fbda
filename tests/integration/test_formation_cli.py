"""A formation scenario end to end through the CLI: results, one mission per vehicle (each passing the
exact mission check), the fleet report, and bad [[vehicles]] input as exit 2 naming the key."""

from __future__ import annotations

import json

import pytest

from auvplan import cli
from auvplan.io.missions.formats import check_mission_file
from auvplan.io.scenario import loader as sc

SCENARIO = """
name = "hills-formation"
seed = 2

[bounds]
x = [-300.0, 300.0]
y = [-200.0, 1500.0]
z = [-150.0, 0.0]

[terrain.synthetic]
kind = "hills"
depth = 100.0
cell_m = 5.0
hills = [[-60.0, 600.0, 90.0, 25.0], [60.0, 600.0, 90.0, 25.0]]

[currents]
uniform = [0.1, 0.0, 0.0]

[mission]
start = [0.0, 0.0, -50.0]
goal = [0.0, 1300.0, -50.0]
route = [[0.0, 0.0, -50.0], [0.0, 1000.0, -50.0], [0.0, 1300.0, -50.0]]
min_altitude_m = 10.0

[sim]
dt = 0.2

[formation]
shape = "line"
spacing_m = 30.0
transition_m = 150.0
changes = [{ waypoint = 1, shape = "wedge" }]

[[vehicles]]
name = "alpha"
role = "leader"

[[vehicles]]
name = "bravo"

[[vehicles]]
name = "charlie"
depth_offset_m = -5.0
"""


def test_run_writes_one_checked_mission_per_vehicle(tmp_path, capsys):
    path = tmp_path / "hills.toml"
    path.write_text(SCENARIO)
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "--out", str(out), "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["status"] == "EXACT" and rec["metrics"]["arrivals"] == 3 and rec["metrics"]["collisions"] == 0
    shapes = [s["shape"] for s in rec["formation_plan"]["shapes"]]
    assert shapes == ["line", "column", "line", "wedge"], shapes  # reshaped through the passage
    world, _ = sc.build(sc.load(path))
    for name in ("alpha", "bravo", "charlie"):
        for fmt in ("moos", "csv", "yaml"):
            check, _ = check_mission_file(out / name / f"mission.{fmt}", world)
            assert check.ok, (name, fmt, check.as_dict())
        assert (out / name / "track.csv").is_file()
    page = (out / "report.html").read_text()
    assert all(f"{n} flown" in page for n in ("alpha", "bravo", "charlie"))
    assert json.loads((out / "formation.json").read_text())["metrics"]["per_vehicle"]["charlie"]["arrived"]


@pytest.mark.parametrize("edit, key", [
    ('role = "leader"\n\n[[vehicles]]\nname = "bravo"', "leader"),
    ('name = "bravo"\n', "name"),
    ("spacing_m = 30.0", "spacing_m"),
    ('changes = [{ waypoint = 1, shape = "wedge" }]', "changes"),
])
def test_bad_formation_input_is_exit_2_naming_the_key(tmp_path, capsys, edit, key):
    bad = {
        "leader": SCENARIO.replace('name = "bravo"', 'name = "bravo"\nrole = "leader"'),
        "name": SCENARIO.replace('name = "charlie"', 'name = "bravo"'),
        "spacing_m": SCENARIO.replace("spacing_m = 30.0", "spacing_m = 10.0"),
        "changes": SCENARIO.replace("waypoint = 1", "waypoint = 7"),
    }[key]
    path = tmp_path / "bad.toml"
    path.write_text(bad)
    assert cli.main(["validate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and str(path) in err and key.split("_")[0] in err, err
