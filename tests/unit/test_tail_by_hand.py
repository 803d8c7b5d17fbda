"""Tail-first legs by hand (issue 49.3): the planner's tail ground speed against the closed form, and the
mission files' flags read back from files written by hand in each carrying format (CSV column, GeoJSON and
KML leg lists, ROS Path pose yaws), with the refusal line of the formats that fly every leg nose-first.

The oracles are the formats as documented in :mod:`auvplan.io.missions.tail`, written here independently of
the exporters; each test runs in milliseconds (no plan, no scenario).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from auvplan.io.missions.tail import TAIL_FORMATS, any_tail, read_tail, refusal
from auvplan.planners.timeopt.tail import tail_speed
from auvplan.world.currents.crab import HOLD


@pytest.mark.parametrize("fn", ["compiled", "python"])
def test_tail_speed_is_the_far_root_of_the_crab_equation(fn: str) -> None:
    """g₋ = c·ŝ − √(V² − |c⊥|²) for a line along (3, 4, 0)/5 in a current (2.5, 0.5, 0.1), V = 1.5: c·ŝ = 1.9,
    |c|² = 6.51, |c⊥|² = 2.9 ... over 0.97² V²: not held (nan); with V = 2: √(4 − 2.9) taken off 1.9."""
    f = tail_speed if fn == "compiled" else getattr(tail_speed, "py_func", tail_speed)
    ex, ey = 0.6, 0.8
    u, v, w = 2.5, 0.5, 0.1
    par = u * ex + v * ey
    cross = u * u + v * v + w * w - par * par
    assert cross == pytest.approx(2.9)
    assert math.isnan(f(u, v, w, ex, ey, 0.0, 1.5))  # |c⊥| = 1.70 > 0.97 x 1.5
    assert f(u, v, w, ex, ey, 0.0, 2.0) == pytest.approx(par - math.sqrt(4.0 - cross), abs=1e-12)  # 0.851 m/s
    # along the line only: the vehicle heading against a 2 m/s current at 1.5 m/s is carried at 0.5 m/s
    assert f(1.2, 1.6, 0.0, ex, ey, 0.0, 1.5) == pytest.approx(0.5, abs=1e-12)
    # a cross current just under HOLD V is held (the root is √(V² − |c⊥|²)), just over it is not
    for frac, held in ((0.999, True), (1.001, False)):
        c = frac * HOLD * 1.5
        g = f(-0.8 * c, 0.6 * c, 0.0, ex, ey, 0.0, 1.5)
        assert (g == pytest.approx(-math.sqrt(1.5**2 - c * c), rel=1e-9)) if held else math.isnan(g)


def test_any_tail_is_true_when_one_flag_is_set() -> None:
    assert any_tail(None) is False and any_tail([]) is False and any_tail([False, False]) is False
    assert any_tail([False, True, False]) is True and any_tail([True, True]) is True and any_tail([0, 1]) is True


@pytest.mark.parametrize(("flags", "named"), [
    ([3], "leg 3 of this mission is flown"),
    ([1, 2], "legs 1, 2 of this mission are flown"),
    (list(range(8)), "legs 0, 1, 2, 3, 4, 5, 6, 7 of this mission are"),  # eight: all named
    (list(range(9)), "legs 0, 1, 2, 3, 4, 5, 6, 7, … of this mission are"),  # nine: the first eight and …
])
def test_refusal_names_the_legs_the_format_and_the_carrying_formats(flags: list[int], named: str) -> None:
    tail = np.zeros(12, dtype=bool)
    tail[flags] = True
    line = refusal("moos", tail)
    assert line.startswith("mission.moos not written: MOOS-IvP's BHV_Waypoint steers every leg nose-first, and ")
    assert named in line and line.endswith(f"tail-first (a current stronger than the vehicle carries it); use "
                                           f"{', '.join(TAIL_FORMATS)}")
    assert "\n" not in line and "nose-first" in refusal("other", tail)


# ---------------------------------------------------------------------- files written by hand
ROUTE = [(0.0, 0.0), (100.0, 0.0), (100.0, 200.0), (50.0, 250.0), (50.0, 250.5)]  # 4 legs: E, N, NW, a 0.5 m N
TAIL = [False, True, False, True]


def _csv(path: Path, flags: list[str], rows: int | None = None) -> Path:
    lines = ["x,y,z,lat,lon,depth,time,speed,tail_first"]
    for k, (x, y) in enumerate(ROUTE[: rows or len(ROUTE)]):
        lines.append(f"{x},{y},-20,0,0,20,{10 * k},1.5,{flags[k]}")
    path.write_text("\n".join(lines) + "\n")
    return path


def test_csv_flags_are_the_column_of_the_leg_reaching_each_waypoint(tmp_path: Path) -> None:
    """Row k (k >= 1) says whether leg k - 1 is flown tail-first; the first row repeats the first leg's."""
    got = read_tail(_csv(tmp_path / "m.csv", ["0", "0", "1", " 0 ", "1"]), 4)
    assert got is not None and got.tolist() == TAIL
    first = read_tail(_csv(tmp_path / "f.csv", ["1", "1", "0", "0", "0"]), 4)
    assert first is not None and first.tolist() == [True, False, False, False]
    assert read_tail(_csv(tmp_path / "n.csv", ["0"] * 5), 4) is None  # no tail-first leg
    assert read_tail(tmp_path / "m.csv", 3) is None and read_tail(tmp_path / "m.csv", 5) is None  # rows != legs + 1
    assert read_tail(_csv(tmp_path / "s.csv", ["0", "0", "1", "0", "1"], rows=4), 3) is not None
    plain = tmp_path / "p.csv"  # no tail_first column: every leg nose-first
    plain.write_text("x,y,z,lat,lon,depth,time,speed\n0,0,-20,0,0,20,0,1.5\n100,0,-20,0,0,20,10,1.5\n")
    assert read_tail(plain, 1) is None
    empty = tmp_path / "e.csv"
    empty.write_text("x,y,z,lat,lon,depth,time,speed,tail_first\n")
    assert read_tail(empty, 0) is None


def _geojson(path: Path, props: str, name: str = "mission") -> Path:
    path.write_text('{"type": "FeatureCollection", "features": ['
                    '{"type": "Feature", "properties": null, "geometry": {"type": "Point", "coordinates": [0, 0]}},'
                    '{"type": "Feature", "properties": {"name": "start"}, "geometry": null},'
                    f'{{"type": "Feature", "properties": {{"name": "{name}"{props}}}, "geometry": null}}]}}')
    return path


def test_geojson_flags_are_the_mission_features_leg_list(tmp_path: Path) -> None:
    got = read_tail(_geojson(tmp_path / "m.geojson", ', "tail_first_legs": [1, 3]'), 4)
    assert got is not None and got.tolist() == TAIL
    same = read_tail(_geojson(tmp_path / "m.json", ', "tail_first_legs": [3, 1]'), 4)
    assert same is not None and same.tolist() == TAIL
    assert read_tail(_geojson(tmp_path / "n.geojson", ""), 4) is None  # no list: nose-first
    assert read_tail(_geojson(tmp_path / "o.geojson", ', "tail_first_legs": [1]', name="other"), 4) is None


def _kml(path: Path, value: str, name: str = "mission") -> Path:
    path.write_text('<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document>'
                    '<Placemark><name>start</name><ExtendedData><Data name="tail_first_legs"><value>0</value></Data>'
                    '</ExtendedData></Placemark>'
                    f'<Placemark><name>{name}</name><ExtendedData><Data name="speed"><value>0 2</value></Data>'
                    f'<Data name="tail_first_legs"><value>{value}</value></Data></ExtendedData></Placemark>'
                    '<Placemark><ExtendedData><Data name="tail_first_legs"><value>2</value></Data></ExtendedData>'
                    '</Placemark></Document></kml>')
    return path


def test_kml_flags_are_the_mission_placemarks_spaced_leg_list(tmp_path: Path) -> None:
    """Only the placemark named ``mission`` counts (not ``start``, nor one without a name)."""
    got = read_tail(_kml(tmp_path / "m.kml", "1 3"), 4)
    assert got is not None and got.tolist() == TAIL
    assert read_tail(_kml(tmp_path / "n.kml", ""), 4) is None
    assert read_tail(_kml(tmp_path / "o.kml", "1 3", name="other"), 4) is None


def _yaml(path: Path, yaws_deg: list[float]) -> Path:
    lines = ["header:", "  frame_id: map", "poses:"]
    for (x, y), yaw in zip(ROUTE, yaws_deg):
        h = math.radians(yaw) / 2.0
        lines += ["- header: {frame_id: map}", "  pose:", f"    position: {{x: {x}, y: {y}, z: -20.0}}",
                  f"    orientation: {{x: 0.0, y: 0.0, z: {math.sin(h)!r}, w: {math.cos(h)!r}}}"]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_ros_path_flags_are_poses_facing_against_their_leg(tmp_path: Path) -> None:
    """Leg k is tail-first when pose k faces more than 90° away from the leg's direction (ENU yaw): legs east
    (yaw 10°: forward), north (yaw -80°: 170° off, tail-first), north-west (135°; yaw 200°: 65° off, forward), and a
    0.5 m leg north (yaw 275°: 185° off, tail-first); the last pose's yaw is not read."""
    got = read_tail(_yaml(tmp_path / "m.yaml", [10.0, -80.0, 200.0, 275.0, 0.0]), 4)
    assert got is not None and got.tolist() == TAIL
    yml = read_tail(_yaml(tmp_path / "m.yml", [-170.0, 100.0, 120.0, 90.0, 0.0]), 4)
    assert yml is not None and yml.tolist() == [True, False, False, False]
    assert read_tail(_yaml(tmp_path / "n.yaml", [0.0, 90.0, 135.0, 90.0, 0.0]), 4) is None  # every leg forwards
    assert read_tail(tmp_path / "m.yaml", 3) is None and read_tail(tmp_path / "m.yaml", 5) is None  # poses != legs + 1


def test_a_leg_without_length_is_not_judged(tmp_path: Path) -> None:
    """Legs of 0 and of 1e-9 m (no direction: the reader's zero-length guard) are never flagged; the next leg
    (east, the pose facing west: yaw 180°) is."""
    p = tmp_path / "z.yaml"
    p.write_text("poses:\n" + "".join(f"- pose: {{position: {{x: {x}, y: 0.0, z: -20.0}}, orientation: {{x: 0.0, "
                                      f"y: 0.0, z: 1.0, w: 0.0}}}}\n" for x in ("0.0", "0.0", "1.0e-09", "10.0")))
    got = read_tail(p, 3)
    assert got is not None and got.tolist() == [False, False, True]


def test_other_suffixes_carry_no_flags(tmp_path: Path) -> None:
    text = "x,y,z,lat,lon,depth,time,speed,tail_first\n0,0,0,0,0,0,0,1,1\n1,0,0,0,0,0,0,1,1\n"
    for name in ("m.moos", "m.plan", "m.gpx", "m.txt"):
        (tmp_path / name).write_text(text)
        assert read_tail(tmp_path / name, 1) is None
