"""consist19: three figures an operator saw disagree.

1. ``mission check`` of a ``.plan`` printed the envelope's predicted time through still water without the launch
   leg and the holds (34 752 s on marcus-terrain-follow's export) beside the energy check's duration with all three
   (37 630 s); and "1588 legs at altitude" (terrain-frame items, the launch's counted) beside the terrain-following
   check's "1587 legs of 1594".  Oracle: the duration by hand, leg by leg at the ground speed a crabbing vehicle
   makes in a uniform current (``g = u·c + sqrt(v² - |c|² + (u·c)²)``) plus the hold; one leg count.
2. The glider's ``mission check`` numbered its blocked legs by the waypoint they reach, from 1; every other output
   numbers a leg by the waypoint it leaves, from 0 (docs/missions.md "Leg numbers").  Oracle: two shoals placed by
   hand on known legs.
3. ``plan --depart-between … --scheduler <dead> --out DIR`` left DIR with a lock and an empty manifest.  Oracle:
   the folder's absence (and a folder the user had kept, with its file).
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from auvplan import cli
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.formats import read_mission, to_qgc_plan

ORIGIN = (48.0, -125.0)
CURRENT = (0.3, -0.2)
SCENARIO = f"""
name = "drift"
seed = 1
[origin]
lat = {ORIGIN[0]}
lon = {ORIGIN[1]}
[bounds]
x = [-500.0, 5500.0]
y = [-1500.0, 3500.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 150.0
slope = [-0.005, -0.01]
cell_m = 50.0
[currents]
uniform = [{CURRENT[0]}, {CURRENT[1]}, 0.0]
[mission]
start = [200.0, -300.0, -10.0]
goal = [4000.0, 2000.0, -20.0]
min_altitude_m = 5.0
min_depth_m = 2.0
max_depth_m = 300.0
[vehicle]
speed = 1.0
"""
POINTS = np.array([[200.0, -300.0, -10.0], [1500.0, -300.0, -30.0], [1500.0, 1200.0, -30.0],
                   [4000.0, 2000.0, -20.0]])
HOLD_S = 90.0


def _plan() -> dict:
    """The export of POINTS at 1.2 m/s, its envelope the bounds, a hold at its second item, and its second and
    third items in the terrain frame (40 m above the seabed): the launch leg (home to item 0) never follows it."""
    doc = to_qgc_plan(POINTS, ORIGIN, 1.2)
    lon, lat = LocalFrame(*ORIGIN).inverse(np.array([-500.0, 5500.0, 5500.0, -500.0]),
                                           np.array([-1500.0, -1500.0, 3500.0, 3500.0]))
    doc["geoFence"]["polygons"] = [{"inclusion": True, "polygon": [[float(a), float(b)] for a, b in zip(lat, lon)],
                                    "version": 1}]
    wps = [it for it in doc["mission"]["items"] if it["command"] == 16]
    wps[1]["params"][0] = HOLD_S
    for it in (wps[0], wps[1]):
        it["frame"], it["params"][6] = 10, 40.0
    return doc


def _by_hand(points: np.ndarray, speed: np.ndarray | float, hold: float) -> float:
    """Each straight leg at the ground speed that keeps the vehicle on it through a uniform current, plus the hold
    (``speed`` through the water: one, or one per leg)."""
    c = np.array([*CURRENT, 0.0])
    t = hold
    for a, b, v in zip(points[:-1], points[1:], np.broadcast_to(speed, (len(points) - 1,))):
        length = float(np.linalg.norm(b - a))
        uc = float(np.dot((b - a) / length, c))
        t += length / (uc + np.sqrt(v * v - c @ c + uc * uc))
    return t


def test_the_envelope_s_time_is_the_energy_check_s_and_legs_are_counted_once(tmp_path):
    scen = tmp_path / "s.toml"
    scen.write_text(SCENARIO, encoding="utf-8")
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(_plan()), encoding="utf-8")
    outs = []
    for flag in (["--json"], []):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            cli.main(["mission", "check", str(path), "--scenario", str(scen), *flag])
        outs.append(buf.getvalue())
    rec, text = json.loads(outs[0]), outs[1]
    from auvplan.io.scenario import loader

    world, _ = loader.build(loader.load(str(scen)))
    points = read_mission(path, world.origin, world.seabed)[0]  # the home on the surface, then the items
    # the export's speed commands are horizontal (audit 20: WPNav keeps a 178's speed level), made for POINTS'
    # pitches; the legs edited into the terrain frame have others: each leg flies its command / cos γ
    items = json.loads(path.read_text())["mission"]["items"]
    cmd, leg_cmd = None, []
    for it in items:
        if it["command"] == 178:
            cmd = it["params"][1]
        elif it["command"] == 16:
            leg_cmd.append(cmd)
    d = np.diff(points, axis=0)
    flat = np.hypot(d[:, 0], d[:, 1])
    v = np.asarray(leg_cmd) * np.where(flat > 0, np.linalg.norm(d, axis=1) / np.where(flat > 0, flat, 1), 1.0)
    v = np.where(flat > 0, v, 1.5)  # a vertical leg (the launch): AC_WPNav's default WPNAV_SPEED_DN (export22)
    want = _by_hand(points, v, HOLD_S)
    assert rec["energy"]["duration_s"] == pytest.approx(want, rel=1e-6)
    assert rec["deploy"]["envelope"]["predicted_s"] == rec["energy"]["duration_s"]
    assert f"(predicted {want:.0f} s)" in text
    # one count of the legs flown at altitude: item 1's leg (item 0's is the launch, flown as a straight descent)
    assert rec["terrain_following"]["legs"] == [1] and rec["deploy"]["altitude_legs"] == 1
    assert "; 1 legs at altitude" in text and "(MAV_FRAME 10: 1)" in text


GLIDER = """
name = "glider-legs"
[origin]
lat = 67.25
lon = 13.75
[bounds]
x = [-1000.0, 9000.0]
y = [-3000.0, 4000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "hills"
depth = 200.0
cell_m = 100.0
hills = [[5000.0, 0.0, 195.0, 300.0], [1250.0, 0.0, 195.0, 150.0]]
[mission]
start = [0.0, 0.0, -10.0]
goal = [7500.0, 0.0, -10.0]
min_altitude_m = 10.0
[vehicle]
type = "glider"
[vehicle.glider]
dive_depth_m = 100.0
climb_depth_m = 10.0
"""


def test_the_glider_check_numbers_legs_by_the_waypoint_they_leave_from_0(tmp_path, capsys):
    """A shoal 5 m deep under the file's waypoint 2 (x = 5 km) and a second one half-way along the start's leg: the
    legs blocked at the 10 m climb depth are 0 (leaving the start, waypoint 0), 1 and 2 (into and out of
    waypoint 2); leg 3 (7.5 km east to 7.5 km, 2 km north) is free."""
    from auvplan.io.missions.glider import seaglider_targets

    scen = tmp_path / "g.toml"
    scen.write_text(GLIDER, encoding="utf-8")
    wps = np.array([[2500.0, 0.0, -10.0], [5000.0, 0.0, -10.0], [7500.0, 0.0, -10.0], [7500.0, 2000.0, -10.0]])
    targets = tmp_path / "targets"
    targets.write_text(seaglider_targets(wps, (67.25, 13.75), 500.0), encoding="utf-8")
    assert cli.main(["mission", "check", str(targets), "--scenario", str(scen), "--json"]) == 1
    rec = json.loads(capsys.readouterr().out)  # one file: its record
    assert rec["shallow_waypoints"] == [2] and rec["blocked_legs"] == [0, 1, 2]
    assert "legs [0, 1, 2] cross land" in rec["message"]


@pytest.mark.parametrize("existing", [False, True], ids=["new", "the-user-s"])
def test_a_sweep_that_reaches_no_scheduler_leaves_no_folder_it_made(tmp_path, capsys, monkeypatch, existing):
    """A local port that refuses at once (the handshake stubbed to refuse, as dask's connect does there)."""
    pytest.importorskip("distributed")
    from auvplan.runtime import parallel

    def refused(address: str, wait: float) -> None:
        raise ConnectionRefusedError(f"Connection refused: {address}")

    monkeypatch.setattr(parallel, "_handshake", refused)
    out = tmp_path / "a" / "sweep"
    if existing:
        out.mkdir(parents=True)
        (out / "notes.txt").write_text("mine", encoding="utf-8")
    code = cli.main(["plan", "track-arc", "--depart-between", "+0h", "+30min", "--scheduler", "tcp://127.0.0.1:1",
                     "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and "--scheduler 'tcp://127.0.0.1:1': no dask scheduler reached there" in err
    if existing:  # the user's folder and file stay
        assert (out / "notes.txt").read_text(encoding="utf-8") == "mine"
    else:  # nor the parent it made for it
        assert not (tmp_path / "a").exists(), sorted(Path(tmp_path).rglob("*"))
