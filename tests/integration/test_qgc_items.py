"""Issue qgc14: a QGroundControl ``.plan`` is judged as its vehicle flies it.  A survey pattern (a ``ComplexItem``,
its generated items under ``TransectStyleComplexItem.Items``) is read in its place, so a pattern that crosses a
charted reef fails ``mission check`` (it passed before: the pattern was skipped); what the check cannot follow
(``DO_JUMP``, return to launch, land, a spline, a circling loiter, an unknown command or pattern) exits 2 with one
line naming the file and ``mission.items[i]``; speed, relay and camera commands are still skipped."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import shapely

from auvplan import cli
from auvplan.errors import DataError
from auvplan.io.data.geo import LocalFrame
from auvplan.io.missions.formats import read_mission, to_qgc_plan
from auvplan.io.missions.readback.deploy_read import read_deploy
from auvplan.io.missions.readback.qgc_items import plan_items
from auvplan.io.missions.readback.speeds import read_leg_speeds
from auvplan.io.missions.readback.terrain_frame import terrain_legs
from helpers import FLAT_SEA

_REEFS = (-7.0, 70.8)  # chagos-reefs' origin
_CAM = {"type": "SimpleItem", "autoContinue": True, "command": 206, "doJumpId": 0, "frame": 2,
        "params": [25, 0, 1, 0, 0, 0, 0]}


def _item(frame: LocalFrame, x: float, y: float, z: float, command: int = 16, fr: int = 3,
          radius: float | None = None) -> dict[str, Any]:
    lon, lat = frame.inverse(x, y)
    p: list[Any] = [0, 0, 0, None, float(lat), float(lon), z]
    if radius is not None:
        p[1 if command == 31 else 2] = radius
    return {"type": "SimpleItem", "autoContinue": True, "command": command, "doJumpId": 0, "frame": fr, "params": p}


def _plan(origin: tuple[float, float], home_xy: tuple[float, float], items: list[dict[str, Any]]) -> dict[str, Any]:
    lon, lat = LocalFrame(*origin).inverse(*home_xy)
    return {"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
            "geoFence": {"circles": [], "polygons": [], "version": 2}, "rallyPoints": {"points": [], "version": 2},
            "mission": {"version": 2, "firmwareType": 3, "vehicleType": 12, "cruiseSpeed": 1.5, "hoverSpeed": 1.5,
                        "plannedHomePosition": [float(lat), float(lon), 0], "items": items}}


def _survey(frame: LocalFrame, xy: list[tuple[float, float]], z: float) -> dict[str, Any]:
    """A QGC survey ComplexItem (version 5) whose generated items fly ``xy`` at ``z``, a camera trigger after each."""
    gen: list[dict[str, Any]] = []
    for x, y in xy:
        gen += [_item(frame, x, y, z), _CAM]
    ll = [[float(v) for v in frame.inverse(x, y)[::-1]] for x, y in xy]
    return {"type": "ComplexItem", "complexItemType": "survey", "version": 5, "angle": 0, "entryLocation": 0,
            "flyAlternateTransects": False, "splitConcavePolygons": False, "polygon": ll,
            "TransectStyleComplexItem": {"version": 2, "Items": gen, "VisualTransectPoints": ll,
                                         "CameraTriggerInTurnAround": True, "FollowTerrain": False,
                                         "HoverAndCapture": False, "Refly90Degrees": False, "TurnAroundDistance": 0}}


def _salomon_zone(frame: LocalFrame) -> shapely.Geometry:
    """Salomon's zone in chagos-reefs, recomputed: Natural Earth's reef line in the local frame, buffered 2 km."""
    doc = json.loads(_REEF_LINES.read_text())
    line = next(f for f in doc["features"] if f["properties"]["name"] == "Salomon Islands")["geometry"]["coordinates"]
    x, y = frame.forward(*np.asarray(line, dtype=float).T)
    return shapely.LineString(np.column_stack([x, y])).buffer(2000.0)


_REEF_LINES = Path(__file__).parents[2] / "src" / "auvplan" / "data" / "ne_10m_reefs_chagos.geojson"


def _run(capsys, *argv: object) -> tuple[int, str, str]:
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_a_survey_pattern_across_a_charted_reef_fails_mission_check(tmp_path, capsys):
    """chagos-reefs (real ETOPO1, Natural Earth's reefs buffered 2 km): simple items 300 m deep at y = 170 km, 8 km
    from Salomon's zone (they passed alone: the survey was skipped), and between them a survey whose generated
    transects run north to y = 184 km, into it.  Oracle: shapely on the generated items' straight legs (the zone
    spans the surface to the seabed, which is > 500 m deep there: a leg enters iff its trace meets the footprint)."""
    frame = LocalFrame(*_REEFS)
    xy = [(156000.0, 172000.0), (156000.0, 184000.0), (160000.0, 184000.0), (160000.0, 172000.0)]
    items = [_item(frame, 142000.0, 170000.0, -300.0), _survey(frame, xy, -300.0),
             _item(frame, 170000.0, 170000.0, -300.0)]
    path = tmp_path / "survey.plan"
    path.write_text(json.dumps(_plan(_REEFS, (140000.0, 170000.0), items)))
    code, out, err = _run(capsys, "mission", "check", path, "--scenario", "chagos-reefs", "--json")
    rec = json.loads(out)
    rec = rec[0] if isinstance(rec, list) else rec
    salomon = _salomon_zone(LocalFrame(*_REEFS))
    flown = [(142000.0, 170000.0), *xy, (170000.0, 170000.0)]  # the items after the home: leg k ends at flown[k]
    want = [k for k in range(1, len(flown))
            if shapely.intersects(shapely.LineString([flown[k - 1], flown[k]]), salomon)]
    assert want == [2, 3, 4]  # the two transects and the turn between them, not the legs to and from the pattern
    got = next(z for z in rec["zones"] if z["name"] == "reef: Salomon Islands")
    assert code == 1 and rec["ok"] is False and got["entered_legs"] == want


@pytest.mark.parametrize(("item", "named"), [
    ({"command": 177, "params": [1, 3, 0, 0, 0, 0, 0]}, r"MAV_CMD_DO_JUMP \(177; repeats part of the mission\)"),
    ({"command": 42, "params": [0] * 7}, r"unknown command 42"),
])
def test_what_the_check_cannot_follow_exits_2_naming_the_item(tmp_path, capsys, item, named):
    """The third item (after a waypoint and a relay, which is skipped) is named: ``mission.items[2]``."""
    frame = LocalFrame(16.0, 145.0)
    relay = {"type": "SimpleItem", "autoContinue": True, "command": 181, "doJumpId": 0, "frame": 2,
             "params": [0, 1, 0, 0, 0, 0, 0]}
    items = [_item(frame, 3000.0, 6000.0, -100.0), relay,
             {"type": "SimpleItem", "autoContinue": True, "doJumpId": 0, "frame": 2, **item},
             _item(frame, 5000.0, 6000.0, -100.0)]
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(_plan((16.0, 145.0), (1000.0, 6000.0), items)))
    toml = tmp_path / "flat.toml"
    toml.write_text(_FLAT_TOML)
    code, out, err = _run(capsys, "mission", "check", path, "--scenario", toml)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert err.startswith("auvplan: error: ") and str(path) in err
    assert re.search(rf"{named} at mission\.items\[2\]: not checked$", err.strip())


_FLAT_TOML = 'name = "flat-300"\n' + FLAT_SEA


@pytest.mark.parametrize(("command", "radius", "named"), [
    (82, None, r"MAV_CMD_NAV_SPLINE_WAYPOINT \(82; the spline leaves the straight leg between its items\)"),
    (20, None, r"MAV_CMD_NAV_RETURN_TO_LAUNCH \(20; its way back is not in the file\)"),
    (21, None, r"MAV_CMD_NAV_LAND \(21; its descent is not in the file\)"),
    (17, 30.0, r"MAV_CMD_NAV_LOITER_UNLIM \(17\) circling 30.0 m around its point"),
    # ArduSub's do_circle flies CIRCLE_RADIUS (10 m by default) when the radius is 0; it skips LOITER_TO_ALT
    # (audit 16: both were read as their point)
    (18, 0, r"MAV_CMD_NAV_LOITER_TURNS \(18; ArduSub circles its point, at CIRCLE_RADIUS when its radius is 0\)"),
    (18, 30.0, r"MAV_CMD_NAV_LOITER_TURNS \(18; ArduSub circles its point, at CIRCLE_RADIUS when its radius is 0\)"),
    (31, 0, r"MAV_CMD_NAV_LOITER_TO_ALT \(31; ArduSub skips it and goes on to the next item\)"),
])
def test_items_that_move_the_vehicle_off_the_file_are_refused(tmp_path, command, radius, named):
    frame = LocalFrame(16.0, 145.0)
    items = [_item(frame, 3000.0, 6000.0, -100.0), _item(frame, 4000.0, 6000.0, -100.0, command, radius=radius)]
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(_plan((16.0, 145.0), (1000.0, 6000.0), items)))
    with pytest.raises(DataError, match=rf"^{path}: QGC plan: {named} at mission\.items\[1\]: not checked$"):
        read_mission(path, (16.0, 145.0))


@pytest.mark.parametrize(("kind", "named"), [("StructureScan", "its waypoints are not stored in the file"),
                                             ("vtolLandingPattern", "an unknown pattern")])
def test_patterns_whose_items_the_file_does_not_hold_are_refused(tmp_path, kind, named):
    frame = LocalFrame(16.0, 145.0)
    items = [_item(frame, 3000.0, 6000.0, -100.0), {"type": "ComplexItem", "complexItemType": kind, "version": 3}]
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(_plan((16.0, 145.0), (1000.0, 6000.0), items)))
    with pytest.raises(DataError, match=rf"ComplexItem '{kind}' \({named}\) at mission\.items\[1\]: not checked$"):
        read_mission(path, (16.0, 145.0))


def test_loiters_at_a_point_and_a_pattern_s_items_are_read_as_flown_and_counted_alike(tmp_path):
    """A LOITER_TIME without a radius is its point; a corridor scan's generated items (a camera trigger and a speed
    change among them, both skipped) are read in their place and in their frames (the second one terrain-following),
    then a relay. Oracle: the positions given, in order; terrain_legs, the speeds and the payload events count the
    same legs as the reader."""
    frame = LocalFrame(16.0, 145.0)
    corridor = _survey(frame, [(5000.0, 6000.0), (6000.0, 6500.0)], -120.0)
    corridor["complexItemType"] = "CorridorScan"
    gen = corridor["TransectStyleComplexItem"]["Items"]
    gen[2]["frame"], gen[2]["params"][6] = 10, 40.0  # 40 m above the seabed
    gen.insert(1, {"type": "SimpleItem", "autoContinue": True, "command": 178, "doJumpId": 0, "frame": 2,
                   "params": [1, 1.2, -1, 0, 0, 0, 0]})
    relay = {"type": "SimpleItem", "autoContinue": True, "command": 181, "doJumpId": 0, "frame": 2,
             "params": [0, 1, 0, 0, 0, 0, 0]}
    items = [_item(frame, 3000.0, 6000.0, -100.0, 19, radius=0), corridor, relay,
             _item(frame, 7000.0, 6000.0, -100.0)]
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(_plan((16.0, 145.0), (1000.0, 6000.0), items)))
    pts, semantics, fmt = read_mission(path, (16.0, 145.0), lambda x, y: np.full(np.shape(x), -300.0))
    want = [[1000, 6000, 0], [3000, 6000, -100], [5000, 6000, -120], [6000, 6500, -260], [7000, 6000, -100]]
    assert fmt == "qgc" and np.allclose(pts, want, atol=1e-6)
    assert terrain_legs(path).tolist() == [False, False, True, False]
    assert np.array_equal(read_leg_speeds(path, 4), [np.nan, np.nan, 1.2, 1.2], equal_nan=True)  # not cruiseSpeed
    deploy = read_deploy(path)  # the relay after the corridor's last item: waypoint 2 (from 0, after the home)
    assert deploy.payload_events == [(2, True)] and deploy.altitude_legs == 1


def test_auvplan_s_own_plan_with_speeds_and_relays_reads_as_its_waypoints(tmp_path):
    """to_qgc_plan's DO_CHANGE_SPEED after every waypoint and a DO_SET_RELAY are skipped: the waypoints read back."""
    origin = (16.0, 145.0)
    pts = np.array([[1000.0, 6000.0, 0.0], [3000.0, 6000.0, -150.0], [9000.0, 7000.0, -150.0],
                    [15000.0, 6000.0, -10.0]])
    doc = to_qgc_plan(pts, origin, np.array([1.0, 1.5, 2.0]))
    doc["mission"]["items"].insert(3, {"type": "SimpleItem", "autoContinue": True, "command": 181, "doJumpId": 0,
                                       "frame": 2, "params": [0, 1, 0, 0, 0, 0, 0]})
    walk = plan_items(doc)
    assert {it.command for it in walk if not it.moves} == {178, 181} and sum(it.moves for it in walk) == 4
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(doc))
    got, _, _ = read_mission(path, origin)
    flown = pts.copy()
    flown[0, 2] = -0.01  # the surface a centimetre deep (ArduSub reads 0 as "hold the current altitude")
    assert np.allclose(got, np.vstack([[*pts[0, :2], 0.0], flown]), atol=1e-3)  # home on the surface, the items
    # the launch at the leading 178's, then leg i's; each a level speed (audit 20: WPNav flies it at v / cos γ)
    from auvplan.io.missions.readback.speeds import along_track_factor

    cos0 = 2000.0 / np.hypot(2000.0, 150.0)
    assert read_leg_speeds(path, 4) * along_track_factor(got) == pytest.approx([cos0, 1.0, 1.5, 2.0], abs=1e-4)


def test_the_walk_names_a_malformed_generated_item(tmp_path):
    doc = _plan((16.0, 145.0), (0.0, 0.0), [_survey(LocalFrame(16.0, 145.0), [(1.0, 2.0)], -5.0)])
    doc["mission"]["items"][0]["TransectStyleComplexItem"]["Items"][0]["params"] = [0, 0]
    with pytest.raises(DataError, match=r"mission\.items\[0\]\.TransectStyleComplexItem\.Items\[0\]\.params has 2"):
        plan_items(doc)


@pytest.mark.parametrize("alt", [0.0, -0.004, 0.009])
def test_an_item_at_altitude_zero_is_refused_and_the_export_writes_the_surface_a_centimetre_deep(tmp_path, alt):
    """ArduSub stores an item's altitude in whole centimetres and its do_nav_wp reads 0 as "keep the current
    altitude": a waypoint at 0 m (the surface) was read as the surface while the vehicle flies level to it
    (audit 16; track-arc's goal is at z = 0).  Oracle: refused naming the item; to_qgc_plan's surface point is
    written at -0.01 m and reads back there."""
    frame = LocalFrame(16.0, 145.0)
    items = [_item(frame, 3000.0, 6000.0, -100.0), _item(frame, 4000.0, 6000.0, alt)]
    path = tmp_path / "m.plan"
    path.write_text(json.dumps(_plan((16.0, 145.0), (1000.0, 6000.0), items)))
    with pytest.raises(DataError, match=r"mission\.items\[1\]: altitude .* 'hold the current altitude'"):
        read_mission(path, (16.0, 145.0))
    doc = to_qgc_plan([[0.0, 0.0, 0.0], [100.0, 0.0, -20.0], [200.0, 0.0, alt]], (16.0, 145.0), 1.0)
    items = doc["mission"]["items"]  # a leading 178, the items (a level speed command after each: audit 20)
    assert items[0]["command"] == 178
    assert [it["params"][6] for it in items if it["command"] == 16] == [-0.01, -20.0, -0.01]
    path.write_text(json.dumps(doc))
    assert np.allclose(read_mission(path, (16.0, 145.0))[0][1:, 2], [-0.01, -20.0, -0.01])
