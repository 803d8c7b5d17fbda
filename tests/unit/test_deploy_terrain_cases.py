"""The export's terrain-frame items and MOOS floor (``io.missions.deploy``: ``deploy_info``'s altitudes,
``_terrain_items``, ``_followed_free``) by hand, the cases wave 13's tests left open (found by mutation,
docs/mutants.md section 5): no altitudes unless the mission follows the seabed; which leg a track vertex that breaks
a limit (or a zone entered) charges, the launch vertex exempt; a leg followed at exactly the least altitude, and a leg
as steep followed as straight, keep the terrain frame."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import shapely
from test_audit15 import _TRENCH

from auvplan.io.missions.deploy import _followed_free, _terrain_items, deploy_info
from auvplan.io.scenario import loader as sc_io
from auvplan.world import Bounds, Margins, Terrain, World, Zone, Zones
from helpers import flat_world


def test_deploy_info_carries_altitudes_only_when_the_mission_follows_the_seabed(tmp_path):
    """Audit 15's trench (rims 250 m deep at x = 4 and 6 km, 200 m beyond): the altitudes, terrain items and leg
    floors exist for a follow altitude of 0.5 or 25 m, not for 0 (no terrain following: nothing to write)."""
    scen = tmp_path / "s.toml"
    scen.write_text(_TRENCH)
    world, mission = sc_io.build(sc_io.load(str(scen)))
    w = np.array([[4000.0, 1000.0, -225.0], [6000.0, 1000.0, -225.0], [8000.0, 1000.0, -150.0]])
    for follow in (0.0, 0.5, 25.0):
        d = deploy_info(world, replace(mission, follow_altitude_m=follow), w, 1.5)
        assert d.follow_altitude_m == follow
        if follow == 0.0:
            assert d.altitude is None and d.terrain_items is None and d.leg_floor is None
            continue
        assert d.altitude is not None and d.terrain_items is not None and d.leg_floor is not None
        assert d.altitude == pytest.approx(w[:, 2] - world.seabed(w[:, 0], w[:, 1]), abs=1e-9)
        assert d.altitude[:2] == pytest.approx([25.0, 25.0], abs=1e-6)
        assert d.terrain_items.shape == (3,) and d.leg_floor.shape == (2,)


def _band_world(zones: Zones | None = None) -> World:
    """Flat seabed 100 m deep, depth band 5-50 m, least altitude 5 m."""
    x = np.linspace(0.0, 1000.0, 21)
    t = Terrain(x, x, np.full((21, 21), -100.0), name="flat")
    return World(Bounds(0.0, 1000.0, 0.0, 1000.0, -100.0, 0.0), t, zones=zones,
                 margins=Margins(min_altitude=5.0, min_depth=5.0, max_depth=50.0), name="band")


W = np.array([[100.0, 500.0, -20.0], [300.0, 500.0, -20.0], [500.0, 500.0, -20.0]])
LEG = np.array([0, 0, 1, 1])


def _track(**z: float) -> np.ndarray:
    """W's two legs with a vertex at each leg's middle; vertex ``v{k}`` at depth ``z``."""
    track = np.array([W[0], [200.0, 500.0, -20.0], W[1], [400.0, 500.0, -20.0], W[2]])
    for key, value in z.items():
        track[int(key[1:]), 2] = value
    return track


@pytest.mark.parametrize(("z", "free"), [
    ({}, [True, True]),
    ({"v1": -60.0}, [False, True]),  # below the band in leg 0's middle
    ({"v2": -60.0}, [False, True]),  # at item 1, the end of leg 0: vertex v ends segment v - 1
    ({"v3": -60.0}, [True, False]),
    ({"v4": -60.0}, [True, False]),  # the last item
    ({"v0": 0.0}, [True, True]),  # the start on the surface, above the band: the launch, no leg's
])
def test_a_vertex_outside_the_band_charges_the_leg_it_ends(z, free):
    assert _followed_free(_band_world(), W, _track(**z), LEG).tolist() == free


def test_a_zone_the_track_enters_charges_its_leg():
    """A zone round leg 1's middle vertex (zone index 0, entered on segments 2 and 3): leg 1 only."""
    zones = Zones((Zone("box", shapely.box(380.0, 480.0, 420.0, 520.0), top=0.0, bottom=np.inf),))
    assert _followed_free(_band_world(zones), W, _track(), LEG).tolist() == [True, False]


def test_a_leg_followed_at_exactly_the_least_altitude_keeps_the_terrain_frame():
    """Flat seabed 100 m deep, items 10 m above it, least altitude 10 m: followed, each leg holds exactly 10 m,
    which mission check passes (altitude >= required): every item in the terrain frame."""
    world = flat_world(depth=100.0, min_altitude=10.0)
    w = np.array([[100.0, 500.0, -90.0], [600.0, 500.0, -90.0], [900.0, 520.0, -90.0]])
    assert _terrain_items(world, w, 15.0).tolist() == [True, True, True]


def test_a_leg_as_steep_followed_as_straight_keeps_the_terrain_frame():
    """Flat seabed: a leg diving 30 m over 50 m (31 deg, over a 15 deg limit) climbs no steeper followed than
    straight: its item stays in the terrain frame; a level leg too."""
    world = flat_world(depth=100.0, min_altitude=5.0)
    w = np.array([[100.0, 500.0, -20.0], [150.0, 500.0, -50.0], [400.0, 500.0, -50.0]])
    assert _terrain_items(world, w, 15.0).tolist() == [True, True, True]


@pytest.mark.parametrize(("limit", "terrain"), [(1.3, False), (1.6, True)])
def test_a_leg_steeper_followed_than_straight_and_over_the_limit_is_written_at_its_depth(limit, terrain):
    """test_terrain_legs_pitch's saddle (1 km x 1 km cell, elevation h u v, h = 14.142 m): the diagonal leg from
    10 m to 20 m above the seabed climbs at (h + 10) / 1414.2 (0.978 deg) straight, at most (2 h + 10) / 1414.2
    (1.551 deg) followed: over a 1.3 deg limit the item is written at its planned depth, under 1.6 deg in the
    terrain frame."""
    h = 14.142
    terrain_ = Terrain(np.array([0.0, 1000.0]), np.array([0.0, 1000.0]),
                       np.array([[-100.0, -100.0], [-100.0, -100.0 + h]]), name="saddle")
    world = World(Bounds(0.0, 1000.0, 0.0, 1000.0, -150.0, 0.0), terrain_, margins=Margins(min_altitude=5.0))
    w = np.array([[0.0, 0.0, -90.0], [1000.0, 1000.0, -100.0 + h + 20.0]])
    assert _terrain_items(world, w, limit).tolist() == [True, terrain]
