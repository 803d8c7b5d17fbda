"""Audit 17: a geographic envelope (a ``.plan``'s geofence, a GeoJSON/KML envelope) around a mission that crosses
the antimeridian.  ``mission check`` tested the waypoints against the polygon in [lat, lon]: its vertices at
179.99° and -179.99° made a polygon around the whole Earth the other way, and our own exported ``.plan`` failed
'the mission leaves the envelope's polygon (5 waypoints outside)' (exit 1).  Now in the local frame, where the
envelope was made.  Oracle: the envelope holds the mission it was built around (every waypoint, and a point 50 km
away is outside), on both sides of the antimeridian and of the equator."""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.errors import DataError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.deploy import deploy_info
from auvplan.io.missions.deploy_formats import geo_ring
from auvplan.io.missions.formats import read_mission, to_qgc_plan
from auvplan.io.missions.readback.deploy_read import file_deploy_check
from auvplan.io.scenario import loader

_SCENARIO = """
name = "dateline"
[origin]
lat = LAT
lon = LON
[bounds]
x = [0.0, 3000.0]
y = [0.0, 3000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "flat"
depth = 150.0
cell_m = 50.0
[mission]
start = [300.0, 300.0, -60.0]
goal = [2700.0, 2700.0, -60.0]
"""


def _straddles(origin, info) -> bool:
    lon = geo_ring(LocalFrame(*origin), info.envelope.polygon)[:, 1]
    return bool(lon.max() - lon.min() > 180.0)


@pytest.mark.parametrize(("lat", "lon"), [(-33.0, 179.99), (0.004, 179.985), (45.0, 179.995), (-0.01, -179.99),
                                          (-33.0, 12.3)])
def test_an_exported_plan_lies_in_its_own_geofence_across_the_antimeridian(tmp_path, lat, lon):
    scen = tmp_path / "s.toml"
    scen.write_text(_SCENARIO.replace("LAT", str(lat)).replace("LON", str(lon)))
    world, mission = loader.build(loader.load(str(scen)))
    w = np.array([[300.0, 300.0, -60.0], [1500.0, 800.0, -60.0], [2200.0, 2400.0, -80.0], [2700.0, 2700.0, -60.0]])
    path = tmp_path / "m.plan"
    info = deploy_info(world, mission, w, 1.5)
    if _straddles(world.origin, info):  # export22: ArduPilot would read it round the other side of the Earth
        with pytest.raises(DataError, match=r"the envelope's polygon crosses ±180° longitude .*breached"):
            to_qgc_plan(w, world.origin, 1.5, deploy=info)
        return
    path.write_text(json.dumps(to_qgc_plan(w, world.origin, 1.5, deploy=info)))
    points = read_mission(path, world.origin, world.seabed)[0]
    rec, line = file_deploy_check(path, world.origin, points, "qgc", 50.0, 3000.0)
    assert rec["envelope"]["ok"], line
    far = points.copy()
    far[2, :2] += 50_000.0  # a waypoint 70 km off: outside the envelope
    rec, line = file_deploy_check(path, world.origin, far, "qgc", 50.0, 3000.0)
    assert not rec["envelope"]["ok"] and "1 waypoints outside" in line, line
