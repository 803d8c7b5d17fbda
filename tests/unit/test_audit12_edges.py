"""Audit 12: what the last wave's fixtures never varied (each test failed on the code before its fix)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from auvplan.world import Zone, Zones
from helpers import ZONES_PLANE, flat_world


@pytest.mark.parametrize(("depth", "h", "pad"), [(0.5, 0.2, 1.0), (0.5, 0.15, 1.0), (1.0, 0.3, 3.0),
                                                  (3.0, 0.1, 1.0), (0.5, 0.35, 1.0)])
def test_the_derived_exact_set_s_seabed_band_is_the_zone_s_own_height(depth, h, pad):
    """Oracle: a set built from the footprints alone.  ``Zones.exact`` took a seabed band's height as
    ``(h + pad) - pad`` (an ulp off: 0.2 -> 0.19999999999999996), so a leg level on the band's top face (the closed
    prism: touching is entering) was passed by ``mission check``'s exact set, or one an ulp above it refused."""
    w = flat_world(depth=depth)
    zone = Zone("cable", shapely.box(400.0, 400.0, 600.0, 600.0), above_seabed=h)
    derived, alone = Zones((zone,), w.terrain, pad=pad).exact, Zones((zone,), w.terrain)
    z = [-depth + h]
    for _ in range(3):
        z = [np.nextafter(z[0], -np.inf), *z, np.nextafter(z[-1], np.inf)]
    seg = np.array([[[300.0, 500.0, v], [700.0, 500.0, v]] for v in z])
    np.testing.assert_array_equal(derived.segments_enter(seg), alone.segments_enter(seg))
    np.testing.assert_array_equal(derived.polyline_slack(seg), alone.polyline_slack(seg))


def test_a_zone_file_with_no_feature_in_the_area_is_kept_too(tmp_path, monkeypatch):
    """Oracle: the reader runs once.  An empty result (no feature reaches the operating area) failed to unpack
    (``zip(strict=True)`` of no names with one start): every warm run read the file again."""
    from auvplan.io.data.vector.kept import kept_geometries

    monkeypatch.setenv("AUVPLAN_CACHE", "1")
    monkeypatch.setenv("AUVPLAN_CACHE_DIR", str(tmp_path / "cache"))
    path = tmp_path / "zones.geojson"
    path.write_text('{"type": "FeatureCollection", "features": []}')
    calls = []
    for _ in range(2):
        assert kept_geometries("zones", ("empty",), path, lambda: calls.append(1) or []) == []
    assert len(calls) == 1
    one = [("a", shapely.box(0.0, 0.0, 1.0, 1.0))]
    for _ in range(2):
        got = kept_geometries("zones", ("one",), path, lambda: calls.append(1) or one)
        assert got[0][0] == "a" and shapely.equals_exact(got[0][1], one[0][1], 0.0)
    assert len(calls) == 2


_HELD_TOML = '\nname = "held-zone"' + ZONES_PLANE + """min_altitude_m = 20.0
min_depth_m = 5.0
max_depth_m = 300.0
[[zones]]
name = "channel"
polygon = [[600.0, 300.0], [900.0, 300.0], [900.0, 700.0], [600.0, 700.0]]
top_m = 0.0
bottom_m = 50.0
[[zones]]
name = "slow"
polygon = [[1500.0, 300.0], [1800.0, 300.0], [1800.0, 700.0], [1500.0, 700.0]]
top_m = 60.0
bottom_m = 120.0
[[zones]]
name = "mid"
polygon = [[2650.0, 300.0], [2700.0, 300.0], [2700.0, 700.0], [2650.0, 700.0]]
top_m = 15.0
bottom_m = 40.0
"""


def test_mission_check_flies_a_held_depth_mission_through_the_zones_as_its_executor(tmp_path, capsys):
    """Oracle: the executor's track by hand.  A MOOS mission (depth held per leg) from 150 m to 10 m over 2 km
    climbs at 15° within 522 m and crosses the surface channel (0-50 m, x 600-900) at 10 m, where its straight
    leg passes 87-108 m deep: ``mission check`` tested the straight legs only and said OK (exit 0).  A second
    climbs 140 m on a 400 m leg (19.3°, within the vehicle's 20°) and, at 15°, finishes the climb 122 m into the
    next, level leg (outside that leg's envelope): at x 2650-2700 it is 30-17 m deep, in the 15-40 m band there.
    The first mission's envelope (150-10 m) also meets the 60-120 m band at x 1500-1800, which its straight leg
    (52-31 m deep) and the 15° track (10 m) pass above: a vehicle climbing slower than 15° flies through it."""
    import json

    from auvplan.cli import main
    from auvplan.io.missions import formats

    scen = tmp_path / "held.toml"
    scen.write_text(_HELD_TOML)
    early = tmp_path / "early.moos"
    early.write_text(formats.to_moos(np.array([[100.0, 500.0, -150.0], [2100.0, 500.0, -10.0]]), 1.5))
    ramp = tmp_path / "ramp.csv"  # the same leg flown as a ramp: below the channel, clear
    ramp.write_text("x,y,z\n100,500,-150\n2100,500,-10\n")
    late = tmp_path / "late.moos"
    late.write_text(formats.to_moos(np.array([[2200.0, 500.0, -150.0], [2600.0, 500.0, -10.0],
                                              [2900.0, 500.0, -10.0]]), 1.5))
    codes, zones = [], []
    for f in (early, ramp, late):
        codes.append(main(["mission", "check", str(f), "--scenario", str(scen), "--json"]))
        zones.append({z["name"]: z["entered_legs"] for z in json.loads(capsys.readouterr().out)["zones"]})
    assert codes == [1, 0, 1]
    assert zones == [{"channel": [0], "slow": [0], "mid": []}, {"channel": [], "slow": [], "mid": []},
                     {"channel": [], "slow": [], "mid": [1]}]  # leg k leaves waypoint k (from 0)


def test_the_page_s_check_flies_a_held_depth_mission_through_the_zones_as_its_executor():
    """Oracle: as above (the page's check said the same as ``mission check``: the straight legs only)."""
    from auvplan.app.page.check import CheckSettings, IncrementalCheck
    from auvplan.io.scenario.build import build
    from auvplan.io.scenario.loader import loads

    world, mission = build(loads(_HELD_TOML, source="held.toml"))
    checker = IncrementalCheck(world, mission)
    w = np.array([[100.0, 500.0, -150.0], [2100.0, 500.0, -10.0]])
    held = checker.run(w, CheckSettings("held", 15.0))
    assert held.summary["zone_entries"] == 2 and not held.summary["ok"]
    assert [v["text"] for v in held.violations if v["kind"] == "zone"] == ["leg 0: enters no-go zone 'channel'",
                                                                           "leg 0: enters no-go zone 'slow'"]
    ramp = checker.run(w, CheckSettings("ramp", 15.0))
    assert ramp.summary["zone_entries"] == 0


def test_a_sweep_s_key_holds_every_file_of_a_named_data_set(tmp_path):
    """Oracle: the readers' own list of a data set's files (``dataset_files``: a shapefile's ``.dbf`` and ``.prj``,
    a GeoTIFF's ``.aux.xml``).  The departure sweep's checkpoint key stamped the named file alone, so a zone
    shapefile whose attributes (``where`` filters on them) or projection were edited between a kill and the
    resume read the old departures back."""
    from auvplan.app.sweep import _input_stamps
    from auvplan.io.scenario.loader import loads

    for suffix in (".shp", ".shx", ".dbf", ".prj"):
        (tmp_path / f"zones{suffix}").write_bytes(b"v1" + suffix.encode())
    text = _HELD_TOML.split("[[zones]]")[0] + '[[zones]]\nname = "charted"\nfile = "zones.shp"\nwhere = "KIND = 1"\n'
    sc = loads(text, source=str(tmp_path / "s.toml"), base_dir=tmp_path)
    first = _input_stamps(sc)
    assert _input_stamps(sc) == first
    for suffix in (".dbf", ".prj"):
        (tmp_path / f"zones{suffix}").write_bytes(b"v2, longer" + suffix.encode())
        again = _input_stamps(sc)
        assert again != first
        first = again
