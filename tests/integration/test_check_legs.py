"""``mission check`` judges every leg the vehicle flies, a ``.plan``'s launch too, and names each leg the same way in
every line: leg k leaves waypoint k, waypoint 0 the file's first (a ``.plan``'s home, so its leg 0 is the launch).
Oracles: the legs' geometry by hand (where a straight leg crosses a prism, where it passes over a ridge's crest)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from auvplan.cli import main
from auvplan.io.data.geo import LocalFrame

# the analytic ridge: 200 m deep, a 50 m deep crest at x = 1250 m on 500 m flanks; a surface band over x 150-225 m
# near the launch, and a 30-45 m band over the crest
_TOML = """
name = "legs"
[origin]
lat = 48.0
lon = -125.0
[bounds]
x = [0.0, 2500.0]
y = [0.0, 500.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "ridge"
depth = 200.0
cell_m = 25.0
ridge_x = 1250.0
ridge_width = 500.0
height = 150.0
[mission]
start = [375.0, 250.0, -40.0]
goal = [2250.0, 250.0, -40.0]
min_altitude_m = 20.0
min_depth_m = 0.0
max_depth_m = 300.0
[[zones]]
name = "harbour shallows"
polygon = [[150.0, 200.0], [225.0, 200.0], [225.0, 300.0], [150.0, 300.0]]
top_m = 0.0
bottom_m = 5.0
[[zones]]
name = "crest cable"
polygon = [[1200.0, 0.0], [1300.0, 0.0], [1300.0, 500.0], [1200.0, 500.0]]
top_m = 30.0
bottom_m = 45.0
"""
_NAV = """[navigation]
drift_pct = 0.5
drift_pct_no_lock = 1.5
dvl_range_m = 100.0
fix_error_m = 3.0
max_error_m = 200.0
"""


def _plan(home: tuple[float, float], items: list[tuple[float, float, float]], frame: int = 3) -> str:
    """A QGC plan by hand: the home on the surface at ``home``, then ``(x, y, z)`` items (frame 3; frame 10: ``z``
    is the altitude above the seabed)."""
    f = LocalFrame(48.0, -125.0)
    hlon, hlat = f.inverse(*home)
    ll = [f.inverse(x, y) for x, y, _ in items]
    return json.dumps({"fileType": "Plan", "version": 1, "groundStation": "QGroundControl", "mission": {
        "plannedHomePosition": [float(hlat), float(hlon), 0.0], "items": [
            {"type": "SimpleItem", "command": 16, "frame": frame, "params": [0, 2, 0, None, float(lat), float(lon), z]}
            for (_, _, z), (lon, lat) in zip(items, ll, strict=True)]}})


def _check(tmp_path, capsys, name: str, text: str, scenario: str = _TOML,  # type: ignore[no-untyped-def]
           human: bool = True) -> tuple[int, dict, str]:
    """The JSON record of ``mission check`` and, if asked, its human output (the same exit code)."""
    scen = tmp_path / "s.toml"
    scen.write_text(scenario)
    f = tmp_path / name
    f.write_text(text)
    capsys.readouterr()
    code = main(["mission", "check", str(f), "--scenario", str(scen), "--json"])
    rec = json.loads(capsys.readouterr().out)
    if human:
        assert main(["mission", "check", str(f), "--scenario", str(scen)]) == code
    return code, rec, capsys.readouterr().out


def test_a_plan_s_launch_leg_through_a_zone_fails_the_check(tmp_path, capsys) -> None:
    """ArduSub flies from its home to the first item: home on the surface at x = 75 m, first item 10 m deep at
    x = 300 m, so the launch leg is 10 (x - 75) / 225 m deep: 3.3-6.7 m over the 0-5 m band's x 150-225 m (in
    it from x = 150 to 187.5).  The items' own legs (10-20 m deep) pass under it and 30 m over the crest.  The zone
    check took the plan's legs after the home (exit 0); the seabed check took the launch: now every check has it,
    leg 0."""
    depth_at = [10.0 * (x - 75.0) / 225.0 for x in (150.0, 187.5, 225.0)]
    assert depth_at[0] < 5.0 <= depth_at[1] < depth_at[2]  # the launch leg enters the band by hand
    items = [(300.0, 250.0, -10.0), (750.0, 250.0, -20.0), (2250.0, 250.0, -20.0)]
    code, rec, out = _check(tmp_path, capsys, "launch.plan", _plan((75.0, 250.0), items), _TOML + _NAV)
    zone = {z["name"]: z for z in rec["zones"]}["harbour shallows"]
    assert code == 1 and rec["ok"] is False and zone["entered_legs"] == [0] and zone["closest_m"] <= 0.0
    assert "zone 'harbour shallows': FAIL — entered by leg 0" in out
    # the navigation check flies the launch too: one record per leg the seabed check flies, numbered alike
    assert [leg["leg"] for leg in rec["navigation"]["legs"]] == list(range(rec["legs"])) == [0, 1, 2]
    # the same items with the home above the first (the launch a vertical descent): no entry, exit 0
    code, rec, _ = _check(tmp_path, capsys, "above.plan", _plan((300.0, 250.0), items), human=False)
    assert code == 0 and {z["name"]: z["entered_legs"] for z in rec["zones"]}["harbour shallows"] == []


@pytest.mark.parametrize(("name", "first"), [("crest.csv", 0), ("crest.plan", 1)])
def test_a_leg_entering_a_zone_and_touching_the_seabed_is_one_leg_number_in_every_line(tmp_path, capsys, name,
                                                                                       first) -> None:
    """Waypoints 40 m deep at x = 375, 750, 1750 and 2250 m: the leg from x = 750 to 1750 m passes 10 m over the
    50 m deep crest (under min_altitude_m 20) and through the 30-45 m band over it (both by hand); a .plan's home
    above the first waypoint adds the launch as leg 0.  The seabed line named it leg 1 and the zone line leg 2 (a
    CSV)."""
    w = np.array([[375.0, 250.0, -40.0], [750.0, 250.0, -40.0], [1750.0, 250.0, -40.0], [2250.0, 250.0, -40.0]])
    crest = -200.0 + 150.0  # the seabed at x = 1250 m, on leg 1 (x 750-1750 m)
    assert -40.0 - crest == 10.0 and -45.0 <= -40.0 <= -30.0
    text = "x,y,z\n" + "".join(f"{x:g},{y:g},{z:g}\n" for x, y, z in w) if name.endswith(".csv") else \
        _plan((375.0, 250.0), [tuple(p) for p in w])
    code, rec, out = _check(tmp_path, capsys, name, text, _TOML + _NAV)
    leg = 1 + first
    zone = {z["name"]: z for z in rec["zones"]}["crest cable"]
    assert code == 1 and rec["min_altitude_leg"] == leg and zone["entered_legs"] == [leg]
    assert rec["min_altitude_m"] == pytest.approx(10.0, abs=1e-6)
    assert f"least altitude 10.00 m (required 20 m, leg {leg})" in out
    assert f"zone 'crest cable': FAIL — entered by leg {leg}" in out
    nav = rec["navigation"]["legs"]
    assert [r["leg"] for r in nav] == list(range(rec["legs"])) and not nav[leg]["clear"]
    assert f"leg {leg}: predicted error" in out and "— TOUCHES" in out.split(f"leg {leg}: predicted error")[1]


def test_a_terrain_frame_plan_s_track_is_made_once_for_every_check(tmp_path, capsys, monkeypatch) -> None:
    """Items 30 m above the ridge's flanks, in the terrain frame: the seabed check, the helm, the terrain-following
    verdict, the zones and the navigation all measure the seabed-following track; it was made five times.  Oracle:
    the same record with the track made by each check on its own (the shared one withheld)."""
    import auvplan.app.check as app_check
    import auvplan.guidance.mission.terrain_legs as terrain_legs

    items = [(500.0, 250.0, 30.0), (1000.0, 250.0, 30.0), (2000.0, 250.0, 30.0)]
    made = []
    real = terrain_legs.flown_track
    monkeypatch.setattr(terrain_legs, "flown_track", lambda *a: made.append(1) or real(*a))
    _, once, _ = _check(tmp_path, capsys, "t.plan", _plan((500.0, 250.0), items, frame=10), _TOML + _NAV, human=False)
    assert len(made) == 1 and once["terrain_following"]["legs"] == [1, 2] and once["zones"] and once["navigation"]
    shared = app_check._terrain_frame
    monkeypatch.setattr(app_check, "_terrain_frame", lambda *a: (shared(*a)[0], None))
    made.clear()
    _, each, _ = _check(tmp_path, capsys, "t.plan", _plan((500.0, 250.0), items, frame=10), _TOML + _NAV, human=False)
    assert len(made) == 1 + 5 and each == once  # the withheld track, then each of the five checks its own
