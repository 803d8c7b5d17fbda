"""Audit 14 of wave 12's code: each test failed on the code before its fix."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
import shapely

from helpers import ZONES_PLANE

_SWEEP_TOML = '\nname = "gdb-zones"' + ZONES_PLANE + """[[zones]]
name = "charted"
file = "zones.gdb"
where = "KIND = 1"
"""


def _write_gdb(path, box, kind):
    from pyogrio.raw import write

    write(str(path), geometry=shapely.to_wkb(np.array([shapely.box(*box)])), field_data=[np.array([kind], np.int32)],
          fields=["KIND"], driver="OpenFileGDB", geometry_type="Polygon", crs="EPSG:4326", layer="zones")


def test_a_sweep_s_key_holds_the_files_inside_a_file_geodatabase_folder(tmp_path):
    """Oracle: the data the zones reader reads (``read_vector`` of the ``.gdb`` folder).  A ``[[zones]] file`` may
    name a FileGDB folder; the departure sweep's checkpoint key stamped it by its name alone (a folder has no bytes to
    hash: ``file_stamp`` raised and the name was kept), so zones moved or re-attributed in the geodatabase between a
    kill and the resume read the old departures back."""
    from auvplan.app.sweep import _input_stamps
    from auvplan.io.data.vector.reader import read_vector
    from auvplan.io.scenario.loader import loads

    gdb = tmp_path / "zones.gdb"
    _write_gdb(gdb, (-124.99, 48.001, -124.98, 48.004), 1)
    sc = loads(_SWEEP_TOML, source=str(tmp_path / "s.toml"), base_dir=tmp_path)
    first = _input_stamps(sc)
    assert _input_stamps(sc) == first
    before = read_vector(gdb, "t", ValueError, where="KIND = 1", fields=True).present()
    shutil.rmtree(gdb)
    _write_gdb(gdb, (-124.97, 48.001, -124.96, 48.004), 1)  # the zone moved ~730 m east
    after = read_vector(gdb, "t", ValueError, where="KIND = 1", fields=True).present()
    assert not before[0].equals(after[0])  # the reader sees another zone ...
    assert _input_stamps(sc) != first  # ... so the sweep's key must change


def test_clearly_free_beside_a_cliff_only_where_explain_finds_nothing():
    """Oracle: the compiled seabed (:meth:`World.explain`).  On a grid line the compiled kernel's cell fraction (a
    reciprocal multiplication) may fall in the next cell; the numpy bound counted the coefficients of its own cell
    only, so beside a cliff (a 0.5 m-deep flat cell next to 300 m and 5 km steps, cells 1.7 m, origin 1000 km out)
    the compiled value lay up to 30 bounds off, and ``validate``'s fast path called free 8 points 1e-13 m inside
    ``min_altitude`` that ``explain`` refuses."""
    from auvplan.world import Bounds, Margins, Terrain, World

    said = 0
    for cliff, along_y in ((5000.0, False), (300.0, False), (-300.0, False), (5000.0, True), (300.0, True)):
        g = 1e6 + 1.7 * np.arange(40)
        z = np.full((3, 40), -1.0)
        z[:, np.arange(40) % 4 >= 2] += cliff  # flat cells at 1 m between cliffs
        lines = (g[1:-1, None] + np.arange(-4, 5) * np.spacing(g[1:-1])[:, None]).ravel()  # ulps about each line
        across = np.full_like(lines, 0.5)
        if along_y:  # the same cliffs across the other axis (a 40 x 3 grid)
            x, y, t = np.arange(3.0), g, Terrain(np.arange(3.0), g, z.T.copy())
            xs, ys = across, lines
        else:
            x, y, t = g, np.arange(3.0), Terrain(g, np.arange(3.0), z)
            xs, ys = lines, across
        est, err = t.elevation_bounds(xs, ys)
        exact = t.elevation(xs, ys)
        assert np.all(np.abs(est - exact) <= err)
        w = World(Bounds(x[0], x[-1], y[0], y[-1], -6000.0, 0.0), t, margins=Margins(min_altitude=0.5))
        for p in np.column_stack([xs, ys, np.nextafter(est + 0.5 + err, np.inf)]):  # just clear by the bound
            if p[2] < 0.0:
                clear = w.clearly_free(p)
                assert not (clear and w.explain(p)), p
                said += clear
    assert said > 0  # the fast path still answers there


def test_mission_check_never_passes_a_file_it_did_not_check(tmp_path, capsys, monkeypatch):
    """Oracle: the exit code of the CSV checked alone (1: it enters a zone).  Given a glider file among the files,
    ``mission check`` checked the glider files only and exited with their verdict: a passing ``goto_l10.ma`` beside
    a CSV entering a zone gave exit 0, the CSV never read.  Now the mix is refused (exit 2, naming both).  And a CSV
    named ``targets_v2.csv`` was read as a Seaglider ``targets`` file (exit 2): it is checked as the CSV it is."""
    import auvplan.app.glider as glider
    from auvplan.cli import main

    scen = tmp_path / "s.toml"
    scen.write_text(_SWEEP_TOML.split("[[zones]]")[0] + '[[zones]]\nname = "box"\n'
                    'polygon = [[600.0, 300.0], [900.0, 300.0], [900.0, 700.0], [600.0, 700.0]]\n')
    csv = tmp_path / "m.csv"
    csv.write_text("x,y,z\n100,500,-3\n2100,500,-3\n")  # 3 m deep through the surface-to-seabed box
    ma = tmp_path / "goto_l10.ma"
    ma.write_text("behavior_name=goto_list\n")
    monkeypatch.setattr(glider, "check_glider_files", lambda scenario, names: [
        {"file": n, "format": "slocum", "waypoints": 2, "radius_m": 10.0, "arrived": True, "flown_duration_s": 1.0,
         "energy_wh": 1.0, "battery_wh": 100.0, "ok": True, "message": ""} for n in names])  # a glider file that passes
    assert main(["mission", "check", str(csv), "--scenario", str(scen)]) == 1
    capsys.readouterr()
    assert main(["mission", "check", str(ma), str(csv), "--scenario", str(scen)]) == 2
    err = capsys.readouterr().err
    assert "goto_l10.ma" in err and "m.csv" in err and len(err.strip().splitlines()) == 1
    # a CSV whose name starts with "targets" is a CSV (was taken for a Seaglider targets file: exit 2, unread)
    named = tmp_path / "targets_v2.csv"
    named.write_text(csv.read_text())
    assert main(["mission", "check", str(named), "--scenario", str(scen)]) == 1


def test_a_terrain_frame_leg_enters_a_zone_only_where_its_track_does(tmp_path, capsys):
    """Oracle: the seabed-following track sampled every 0.5 m over the analytic ridge (``test_edges12_surfaces``).
    Items 25 m above the seabed at x = 3.5 and 6.5 km fly 25 m over the crest, 10 m above a cable band (seabed +
    15 m) laid over it; the straight line between them (137.5 m deep) runs under the 50 m deep crest, through the
    band, but ArduSub does not fly it.  The seabed check is the track's (exit 0 without the zone); the zones still
    counted the straight leg: "zone 'cable': FAIL — entered by leg 1", exit 1."""
    from test_edges12_surfaces import _RIDGE, _check, _plan, _ridge_oracle

    cable = ('[[zones]]\nname = "cable"\npolygon = [[4000.0, 0.0], [6000.0, 0.0], [6000.0, 2000.0], [4000.0, 2000.0]]'
             '\nabove_seabed_m = 15.0\n')
    track = _ridge_oracle(3500.0, 6500.0, 25.0)
    seabed = track[:, 2] - 25.0
    on = (track[:, 0] >= 4000.0) & (track[:, 0] <= 6000.0)
    straight = np.interp(track[:, 0], [3500.0, 6500.0], track[[0, -1], 2])
    assert (track[on, 2] - seabed[on]).min() == pytest.approx(25.0)  # flown: 10 m above the band
    assert (straight[on] - seabed[on]).min() < 15.0  # the straight line: inside it (below the crest)
    code, rec = _check(tmp_path, capsys, "low.plan", _plan([(3500.0, 1000.0, 10, 25.0), (6500.0, 1000.0, 10, 25.0)]),
                       _RIDGE.split("[[zones]]")[0] + cable)
    (zone,) = rec["zones"]
    assert zone["entered_legs"] == [] and 9.0 < zone["closest_m"] <= 10.0  # 10 m, less the seabed band's slope bound
    assert code == 0 and rec["ok"] is True and rec["check_ok"] is True


_HILL = """name = "hill"
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [-200.0, 2200.0]
y = [0.0, 1000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "hills"
depth = 100.0
hills = [[1000.0, 500.0, 25.0, 150.0]]
cell_m = 20.0
[mission]
start = [0.0, 500.0, -60.0]
goal = [2000.0, 500.0, -60.0]
min_altitude_m = 10.0
follow_altitude_m = 40.0
[[zones]]
name = "band"
polygon = [[800.0, 300.0], [1200.0, 300.0], [1200.0, 700.0], [800.0, 700.0]]
top_m = 40.0
bottom_m = 50.0
"""


def test_moos_altitude_floor_never_lifts_the_vehicle_off_the_checked_depth(tmp_path):
    """Oracle: a 25 m Gaussian hill on a 100 m seabed (its crest on a grid node, 75 m deep) under a leg held 60 m
    deep, 40 m above the seabed at both ends: the leg's least altitude is 15 m, at the crest.  A
    ``BHV_MinAltitudeX`` of 40 m (the ends' altitude, before) lifts pHelmIvP (its priority above the depth's) to 35 m
    deep over the crest, through the 40-50 m band ``mission check`` passed at the held 60 m; the floor is now 15 m,
    which the charted seabed never triggers."""
    import re

    from auvplan.io.missions.deploy import deploy_info
    from auvplan.io.missions.formats import to_moos
    from auvplan.io.scenario import loader as sc_io

    scen = tmp_path / "hill.toml"
    scen.write_text(_HILL)
    world, mission = sc_io.build(sc_io.load(str(scen)))
    w = np.array([[0.0, 500.0, -60.0], [2000.0, 500.0, -60.0]])
    text = to_moos(w, 1.5, deploy=deploy_info(world, mission, w, 1.5))
    (floor,) = [float(v) for v in re.findall(r"min_altitude = ([0-9.]+)", text)]
    x = np.linspace(0.0, 2000.0, 200_001)
    seabed = np.asarray(world.seabed(x, np.full_like(x, 500.0)))
    assert -seabed.max() == pytest.approx(75.0, abs=1e-9) and floor == pytest.approx(-60.0 - seabed.max(), abs=1e-3)
    assert floor <= 15.0 + 1e-3 and (-60.0 - seabed >= floor - 1e-3).all()  # never above the leg's altitude
