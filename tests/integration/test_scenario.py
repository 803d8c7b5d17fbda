"""Scenario files: valid files load; every malformed input is a clear, named error."""

from __future__ import annotations

import numpy as np
import pytest

from auvplan.errors import DataError, ScenarioError
from auvplan.io.scenario import loader as sc

BASE = """
name = "lab"
description = "synthetic test scene"
seed = 3

[bounds]
x = [0.0, 1000.0]
y = [0.0, 1000.0]
z = [-120.0, 0.0]

[terrain.synthetic]
kind = "hills"
depth = 100.0
cell_m = 20.0
hills = [[500.0, 500.0, 60.0, 80.0]]

[currents]
uniform = [0.1, 0.0, 0.0]

[[obstacles]]
type = "sphere"
center = [300.0, 700.0, -50.0]
radius = 20.0

[[moving]]
type = "sphere"
radius = 5.0
motion = "linear"
start = [0.0, 500.0, -50.0]
velocity = [0.5, 0.0, 0.0]

[mission]
start = [50.0, 50.0, -50.0]
goal = [950.0, 950.0, -50.0]
min_altitude_m = 5.0

[planner]
name = "pso"
population = 20
iterations = 10
"""


def write(tmp_path, text, name="s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_valid_scenario_builds(tmp_path):
    s = sc.load(write(tmp_path, BASE))
    world, mission = sc.build(s)
    assert s.name == "lab" and s.seed == 3 and mission.planner.name == "pso"
    assert world.terrain.elevation(500.0, 500.0) == pytest.approx(-40.0)
    assert len(world.obstacles) == 1 and len(world.moving) == 1
    assert np.allclose(world.currents.velocity([[0.0, 0.0, -10.0]]), [[0.1, 0.0, 0.0]])


@pytest.mark.parametrize(
    "old, new, key",
    [
        ('seed = 3', 'seed = "three"', "seed"),
        ('seed = 3', 'sed = 3', "'sed'"),
        ('[planner]\nname = "pso"', '[planner]\nname = "astar"', "name"),
        ("population = 20", "population = 2", "population"),
        ("population = 20", "population = 20.5", "population"),
        ("iterations = 10", "iterations = 10\nmutation = 0.1", "'mutation'"),
        ("min_altitude_m = 5.0", "min_altitude_m = -5.0", "min_altitude_m"),
        ("start = [50.0, 50.0, -50.0]", "start = [50.0, 50.0]", "start"),
        ("start = [50.0, 50.0, -50.0]", "start = [50.0, 50.0, -99.0]", "start"),  # inside the margin above the seabed
        ("start = [50.0, 50.0, -50.0]", "start = [50.0, 50.0, -130.0]", "start"),  # below the seabed and the bounds
        ("goal = [950.0, 950.0, -50.0]", "goal = [1950.0, 950.0, -50.0]", "goal"),
        ("goal = [950.0, 950.0, -50.0]", "goal = [500.0, 500.0, -42.0]", "goal"),  # inside the hill
        ('kind = "hills"', 'kind = "volcano"', "kind"),
        ("x = [0.0, 1000.0]", "x = [1000.0, 0.0]", "x"),
        ("radius = 20.0", "radius = -1.0", "radius"),
        ('type = "sphere"\ncenter = [300.0', 'type = "cube"\ncenter = [300.0', "type"),
        ('motion = "linear"', 'motion = "teleport"', "motion"),
        ("velocity = [0.5, 0.0, 0.0]", "velocity = [0.5, 0.0, 0.0]\ncolour = 1", "'colour'"),
        ("uniform = [0.1, 0.0, 0.0]", "uniform = [0.1, 0.0, 0.0]\nvortices = [{x=0.0, y=0.0, gamma=1.0, delta=1.0}]",
         "vortices"),
        ("[currents]", "[currents]\nvortices = [{x=0.0, y=0.0, gamma=1.0, delta=0.0}]\n[unused]", "'unused'"),
        ("[mission]", "[mission]\nroute = [[0.0, 0.0, -10.0], [5000.0, 0.0, -10.0]]", "route[1]"),
        ("[planner]", "[vehicle]\nspeed = 3.0\nmax_speed = 2.0\n[planner]", "speed"),
        ("[planner]", "[guidance]\nname = \"pid\"\n[planner]", "name"),
        ("[planner]", "[avoidance]\nminimum_count = 1\n[planner]", "minimum_count"),
    ],
)
def test_malformed_scenarios_name_the_key_and_file(tmp_path, old, new, key):
    assert old in BASE
    path = write(tmp_path, BASE.replace(old, new, 1))
    with pytest.raises(ScenarioError) as err:
        sc.build(sc.load(path))
    msg = str(err.value)
    assert key in msg, msg
    assert str(path) in msg, msg


def test_invalid_toml(tmp_path):
    p = write(tmp_path, "name = \n")
    with pytest.raises(ScenarioError, match="invalid TOML"):
        sc.load(p)


def test_missing_mission_table(tmp_path):
    p = write(tmp_path, 'name = "x"\n')
    with pytest.raises(ScenarioError, match=r"\[mission\]"):
        sc.load(p)


def test_unknown_scenario_name():
    with pytest.raises(ScenarioError, match="not a built-in scenario"):
        sc.load("no-such-scenario")


def test_missing_bathymetry_file(tmp_path):
    text = BASE.replace(
        '[terrain.synthetic]\nkind = "hills"\ndepth = 100.0\ncell_m = 20.0\nhills = [[500.0, 500.0, 60.0, 80.0]]',
        '[origin]\nlat = 15.0\nlon = 158.0\n[terrain]\nfile = "missing.nc"',
    )
    with pytest.raises(DataError, match=r"\[terrain\].*missing.nc.*not found"):
        sc.build(sc.load(write(tmp_path, text)))


def test_real_terrain_needs_an_origin(tmp_path):
    text = BASE.replace(
        '[terrain.synthetic]\nkind = "hills"\ndepth = 100.0\ncell_m = 20.0\nhills = [[500.0, 500.0, 60.0, 80.0]]',
        '[terrain]\nbuiltin = "etopo1-marcus-wake"',
    )
    with pytest.raises(ScenarioError, match=r"\[origin\]"):
        sc.load(write(tmp_path, text))


def test_bounds_outside_real_terrain(tmp_path):
    text = sc.resolve("marcus-wake").read_text().replace("x = [0.0, 100000.0]", "x = [0.0, 400000.0]")
    with pytest.raises(DataError, match="do not cover"):
        sc.build(sc.load(write(tmp_path, text)))


def test_gridded_current_not_covering_the_area(tmp_path):
    import xarray as xr

    x = np.linspace(0, 500, 6)
    ds = xr.Dataset(
        {"u": (("y", "x"), np.zeros((6, 6))), "v": (("y", "x"), np.zeros((6, 6)))},
        coords={"x": ("x", x, {"units": "m"}), "y": ("y", x, {"units": "m"})},
    )
    ds.to_netcdf(tmp_path / "cur.nc")
    text = BASE.replace("uniform = [0.1, 0.0, 0.0]", 'file = { path = "cur.nc" }')
    with pytest.raises(DataError, match=r"\[currents\]|current field does not cover"):
        sc.build(sc.load(write(tmp_path, text)))


def test_gridded_current_file_loads(tmp_path):
    import xarray as xr

    x = np.linspace(0, 1000, 6)
    depth = np.array([0.0, 200.0])
    u = np.broadcast_to(np.array([0.3, 0.1])[:, None, None], (2, 6, 6))
    ds = xr.Dataset(
        {"uo": (("depth", "y", "x"), u, {"standard_name": "eastward_sea_water_velocity"}),
         "vo": (("depth", "y", "x"), np.zeros((2, 6, 6)), {"standard_name": "northward_sea_water_velocity"})},
        coords={"x": ("x", x, {"units": "m"}), "y": ("y", x, {"units": "m"}),
                "depth": ("depth", depth, {"positive": "down", "standard_name": "depth"})},
    )
    ds.to_netcdf(tmp_path / "cur.nc")
    text = BASE.replace("uniform = [0.1, 0.0, 0.0]", 'file = { path = "cur.nc" }')
    world, _ = sc.build(sc.load(write(tmp_path, text)))
    v = world.currents.velocity([[500.0, 500.0, 0.0], [500.0, 500.0, -100.0], [500.0, 500.0, -200.0]])
    assert np.allclose(v[:, 0], [0.3, 0.2, 0.1])


@pytest.mark.parametrize("name", ["marcus-wake", "salish-shelf"])
def test_builtin_real_scenarios_build(name):
    s = sc.load(name)
    world, mission = sc.build(s)
    assert world.terrain is not None and world.origin is not None
    assert world.is_free(np.asarray(mission.start)) and world.is_free(np.asarray(mission.goal))


def test_every_builtin_scenario_is_listed_and_loads():
    names = sc.builtin_scenarios()
    assert {"marcus-wake", "salish-shelf"} <= set(names)
    for n in names:
        assert sc.load(n).name == n
