"""Round 10's survivors of the clearance under the navigation error (``nav/clearance.py``: ``zone_within``,
``zone_safe_radius``, ``obstacle_safe_radius``, ``hazard_safe_radius``; ``Zones.traces_near``; docs/mutants.md
section 10), on what the suite's fixtures never varied: legs that climb and dive through a zone's band (the suite's
legs were level), several zones of each kind on one leg, a seabed band the leg does or does not come down to, one
leg asked alone, legs already inside an obstacle's margin or less than a metre outside it, and a world whose binding
hazard is in turn the seabed, a zone and an obstacle.

Oracles, independent of the module: each leg sampled at 4 001 points (the part within a band: a sampled distance to
the footprint is at least the true one and at most one sample step above it, by shapely), a flat seabed 400 m deep
(the least altitude of a leg is its deepest end's, by hand), the sphere's distance by hand; and the safe radius as the
inverse of the check (nothing within it, something a little beyond).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from auvplan.nav.clearance import (
    hazard_safe_radius,
    obstacle_safe_radius,
    obstacle_within,
    safe_radius,
    uncertain_clearance,
    zone_safe_radius,
    zone_within,
)
from auvplan.world import Bounds, Margins, Terrain, World
from auvplan.world.obstacles import Sphere
from auvplan.world.zones import Zone, Zones

DEPTH = 400.0
L_SHAPE = shapely.Polygon([(2000, 1000), (3200, 1000), (3200, 1400), (2500, 1400), (2500, 2200), (2000, 2200)])
ZONES = (Zone("l-band", L_SHAPE, top=50.0, bottom=150.0),                        # 50-150 m deep
         Zone("triangle", shapely.Polygon([(600, 2600), (1500, 2500), (900, 3300)])),  # surface to seabed
         Zone("pipeline", shapely.box(3600, 300, 3700, 3200), above_seabed=60.0),    # seabed to 340 m deep
         Zone("deep-box", shapely.box(1200, 600, 1600, 1100), top=200.0, bottom=250.0))


def _world(zones=ZONES, obstacles=()) -> World:
    x, y = np.linspace(0.0, 5000.0, 26), np.linspace(0.0, 4000.0, 11)  # non-square cells
    terrain = Terrain(x, y, np.full((11, 26), -DEPTH), name="flat")
    return World(Bounds(0.0, 5000.0, 0.0, 4000.0, -1000.0, 0.0), terrain, obstacles=tuple(obstacles),
                 margins=Margins(min_altitude=10.0, min_depth=0.0, obstacle=5.0), name="t",
                 zones=Zones(tuple(zones), terrain) if zones else None)


def _segments(n: int = 60) -> np.ndarray:
    rng = np.random.default_rng(24)
    a = np.column_stack([rng.uniform(300, 4700, n), rng.uniform(300, 3700, n), -rng.uniform(0.0, 390.0, n)])
    b = a + np.column_stack([rng.normal(scale=700.0, size=(n, 2)), rng.normal(scale=150.0, size=n)])
    b[:, 2] = np.clip(b[:, 2], -390.0, 0.0)
    b[::5, 2] = a[::5, 2]  # some level
    return np.stack([a, b], axis=1)


def _sampled(seg: np.ndarray, zone: Zone) -> tuple[float, float]:
    """(distance of the sampled part of the leg a zone's band holds to its footprint, one sample step): the true
    distance lies within a step below it; inf when no sample lies in the band."""
    t = np.linspace(0.0, 1.0, 4001)
    p = seg[0] + t[:, None] * (seg[1] - seg[0])
    step = float(np.hypot(*(seg[1, :2] - seg[0, :2]))) / 4000.0
    if zone.above_seabed is not None:  # flat seabed: in the band somewhere iff the deepest end is
        inside = np.full(t.size, float(p[:, 2].min()) + DEPTH <= zone.above_seabed)
    else:
        inside = (p[:, 2] <= -zone.top) & (p[:, 2] >= -zone.bottom)
    if not inside.any():
        return math.inf, step
    return float(shapely.distance(shapely.points(p[inside, :2]), zone.footprint).min()), step


def test_zone_within_is_a_zone_the_sampled_leg_reaches():
    world = _world()
    seg = _segments()
    rng = np.random.default_rng(25)
    r = rng.uniform(0.0, 600.0, len(seg))
    got = zone_within(world, seg, r)
    decided = 0
    for k in range(len(seg)):
        per = [_sampled(seg[k], z) for z in ZONES]
        near = {j for j, (d, _) in enumerate(per) if d <= r[k]}
        far = {j for j, (d, step) in enumerate(per) if d - step > r[k]}
        if len(near) + len(far) < len(ZONES):
            continue  # a distance within a sample step of the radius
        decided += 1
        assert (got[k] in near) if near else got[k] == -1, (k, got[k], near)
    assert decided >= 55 and (got == -1).sum() >= 5 and len(set(got.tolist()) - {-1}) == len(ZONES)
    for k in range(len(seg)):  # one leg asked alone: the same answer
        assert zone_within(world, seg[k:k + 1], r[k])[0] == got[k]


def test_zone_safe_radius_is_the_sampled_distance_and_the_checks_inverse():
    world = _world()
    seg = _segments()
    r_max = 900.0
    got = zone_safe_radius(world, seg[:, 0], seg[:, 1], r_max)
    assert np.isfinite(got).sum() >= 20 and np.isinf(got).sum() >= 5
    for k in range(len(seg)):
        per = [_sampled(seg[k], z) for z in ZONES]
        want = min((d for d, _ in per if d <= r_max), default=math.inf)
        step = max(s for _, s in per)
        if math.isinf(got[k]):
            assert all(d - step > r_max for d, _ in per), k
            continue
        seabed = any(z.above_seabed is not None and abs(d - got[k]) <= 0.5 + step for z, (d, _) in zip(ZONES, per))
        assert got[k] <= want + 1e-9 and got[k] >= want - step - (0.5 if seabed else 1e-5), (k, got[k], want)
        if got[k] == 0.0:  # the leg itself reaches a zone: no radius is safe
            assert zone_within(world, seg[k:k + 1], 0.0)[0] >= 0
            continue
        assert zone_within(world, seg[k:k + 1], got[k])[0] == -1  # nothing within it ...
        assert zone_within(world, seg[k:k + 1], got[k] + (0.5 if seabed else 0.0) + step + 0.01)[0] >= 0  # ...


def test_no_zone_is_minus_one_and_no_zones_is_nothing():
    seg = _segments(5)
    far = _world(zones=(Zone("far", shapely.box(4900, 3900, 4950, 3950)),))
    assert zone_within(far, seg[:1] * [1, 1, 1] - [0, 0, 0], 1.0).tolist() == [-1]
    plain = _world(zones=())
    assert zone_within(plain, seg, 100.0).tolist() == [-1] * 5
    assert zone_safe_radius(plain, seg[:, 0], seg[:, 1], 100.0).tolist() == [math.inf] * 5
    k, j = far.zones.exact.traces_near(seg[:1], 10_000.0)
    assert k.tolist() == [0] and j.tolist() == [0]  # one segment: its pair
    assert [x.size for x in Zones((), None).traces_near(seg, 1e6)] == [0, 0]


CENTRE = np.array([2500.0, 2000.0, -200.0])


@pytest.mark.parametrize("gap", [-3.0, 0.0, 0.4, 0.9, 7.0])
def test_obstacle_safe_radius_inside_and_just_outside_the_margin(gap):
    """A level leg passing the sphere (radius 50 m, margin 5 m) at ``55 + gap`` m from its centre: the safe radius is
    ``gap`` less a micrometre, 0 inside the margin."""
    world = _world(zones=(), obstacles=(Sphere(tuple(CENTRE), 50.0),))
    off = 55.0 + gap
    a, b = CENTRE + [-800.0, off, 0.0], CENTRE + [700.0, off, 0.0]
    r = float(obstacle_safe_radius(world, a, b, 300.0)[0])
    assert r == pytest.approx(max(gap - 1e-6, 0.0), abs=1e-9)
    seg = np.stack([a, b])[None]
    if gap > 0.0:
        assert obstacle_within(world, seg, r)[0] == -1 and obstacle_within(world, seg, gap + 1e-4)[0] == 0
    else:  # on the margin (not within it) or inside it
        assert obstacle_within(world, seg, 1e-4)[0] == 0 and obstacle_within(world, seg, 0.0)[0] == (0 if gap else -1)


@pytest.mark.parametrize("binding", ["seabed", "zone", "obstacle"])
def test_hazard_safe_radius_is_the_least_of_the_three(binding):
    """One leg 250 m deep near a surface-to-seabed zone, a sphere and a rise of the seabed; each in turn the nearest:
    the hazard radius is that one's, and the clearance under it is clear, a metre more not."""
    x, y = np.linspace(0.0, 5000.0, 26), np.linspace(0.0, 4000.0, 11)
    rise = {"seabed": 1200.0, "zone": 2000.0, "obstacle": 2000.0}[binding]  # the row where the seabed is 230 m deep
    z = np.where(y[:, None] >= rise, -230.0, -DEPTH) + 0.0 * x[None, :]  # 260 m deep (10 m under the leg) 129 m
    # (929 m) beyond the row before (bilinear between rows 400 m apart)
    zone_y = {"seabed": 1300.0, "zone": 1080.0, "obstacle": 1300.0}[binding]
    ball_y = {"seabed": 1300.0, "zone": 1300.0, "obstacle": 1120.0}[binding]
    terrain = Terrain(x, y, z, name="step")
    world = World(Bounds(0.0, 5000.0, 0.0, 4000.0, -1000.0, 0.0), terrain,
                  obstacles=(Sphere((2500.0, ball_y + 50.0, -250.0), 50.0),),
                  margins=Margins(min_altitude=10.0, min_depth=0.0, obstacle=5.0), name="t",
                  zones=Zones((Zone("z", shapely.box(1000.0, zone_y, 1400.0, 1900.0)),), terrain))
    a, b = np.array([800.0, 1000.0, -250.0]), np.array([4200.0, 1000.0, -250.0])
    parts = {"seabed": float(safe_radius(terrain, a, b, 10.0, 400.0)[0]),
             "zone": float(zone_safe_radius(world, a, b, 400.0)[0]),
             "obstacle": float(obstacle_safe_radius(world, a, b, 400.0)[0])}
    assert min(parts, key=parts.get) == binding, parts
    r = float(hazard_safe_radius(world, a, b, 400.0)[0])
    assert r == min(parts.values())
    by_hand = {"zone": 80.0 - 1e-6, "obstacle": 170.0 - 50.0 - 5.0 - 1e-6}
    if binding in by_hand:
        assert r == pytest.approx(by_hand[binding], abs=1e-6)
    else:  # the lattice's bound (module notes): below by at most 2 L h and the grown radius h / sqrt(2) (L = 170 / 400,
        # h a fiftieth of the 200 m cell side), and the bisection's 0.5 m
        exact = 800.0 + 400.0 * 140.0 / 170.0 - 1000.0
        assert exact - 0.5 - 2.0 * 0.425 * 4.0 - 4.0 / math.sqrt(2.0) <= r <= exact
    pts = np.stack([a, b])
    assert uncertain_clearance(world, pts, [r], 50.0)[1].all()
    assert not uncertain_clearance(world, pts, [r + 1.0], 50.0)[1].any()


def test_a_seabed_band_out_of_reach_allows_its_distance():
    """A level leg 30 m above a flat seabed (inside a pipeline's seabed + 60 m band, were it over the pipeline), its
    trace 200 m from the pipeline's footprint: the check passes under any error below 200 m and fails beyond, so the
    safe radius is 200 m (less the bisection's 0.5 m at most) and the fix planner's hazard radius with it.  Before it
    was 0 (the band's height tested without the footprint's distance: "no radius is safe" for a leg that never comes
    within 200 m of the zone)."""
    world = _world(zones=(Zone("pipeline", shapely.box(3600, 300, 3700, 3200), above_seabed=60.0),))
    a, b = np.array([3000.0, 1000.0, -370.0]), np.array([3400.0, 2000.0, -370.0])
    seg = np.stack([a, b])[None]
    assert zone_within(world, seg, 199.9)[0] == -1 and zone_within(world, seg, 200.1)[0] == 0  # the check
    r = float(zone_safe_radius(world, a, b, 900.0)[0])
    assert 199.5 <= r <= 200.0
    assert zone_within(world, seg, r)[0] == -1
    assert float(hazard_safe_radius(world, a, b, 900.0)[0]) == r
    high = np.array([a, b]) + [0.0, 0.0, 50.0]  # 80 m above the seabed: over the band, never within it
    assert math.isinf(float(zone_safe_radius(world, high[0], high[1], 900.0)[0]))


BOX = Zone("box", shapely.box(2000.0, 1000.0, 2400.0, 1400.0), top=50.0, bottom=150.0)


@pytest.mark.parametrize(("a", "b", "d"), [
    ((1500.0, 1200.0, -50.0), (1900.0, 1200.0, -50.0), 100.0),    # level, exactly at the band's top
    ((1500.0, 1200.0, -150.0), (1900.0, 1200.0, -150.0), 100.0),  # level, exactly at its bottom
    ((1300.0, 1200.0, -100.0), (1700.0, 1200.0, -100.0), 300.0),  # level inside it, its end 300 m short
    ((1500.0, 1200.0, -30.0), (1900.0, 1200.0, -50.0), 100.0),    # a dive ending exactly at the top: one point
    ((1500.0, 1200.0, -50.5), (1900.0, 1200.0, -49.5), 300.0),    # a climb of exactly 1 m out of the band at x 1700
    ((1500.0, 1200.0, -20.0), (1900.0, 1200.0, -49.9), math.inf),  # a dive ending 10 cm over the band
])
def test_a_band_holds_its_faces_and_only_the_part_of_the_leg_in_it(a, b, d):
    """The distance from the part of the leg whose depth is in [top, bottom] (faces included) to the footprint, by
    hand: the check finds the zone a centimetre beyond it, not a centimetre short, and the safe radius is it."""
    world = _world(zones=(BOX,))
    seg = np.array([a, b])[None]
    r = float(zone_safe_radius(world, seg[:, 0], seg[:, 1], 900.0)[0])
    if math.isinf(d):
        assert math.isinf(r) and zone_within(world, seg, 900.0)[0] == -1
        return
    assert r == pytest.approx(d - 1e-6, abs=1e-9)
    assert zone_within(world, seg, d - 0.01)[0] == -1 and zone_within(world, seg, d + 0.01)[0] == 0


def test_a_seabed_band_a_metre_off_allows_most_of_it():
    """The pipeline's footprint 0.9 m beside the trace of a leg in its height: a radius within the bisection's 0.5 m
    under 0.9 m (not 0: that is for a leg over the footprint itself)."""
    world = _world(zones=(Zone("pipeline", shapely.box(3600, 300, 3700, 3200), above_seabed=60.0),))
    a, b = np.array([3000.0, 1000.0, -370.0]), np.array([3599.1, 2000.0, -370.0])
    r = float(zone_safe_radius(world, a, b, 900.0)[0])
    assert 0.4 - 1e-9 <= r <= 0.9
    over = float(zone_safe_radius(world, a + [650.0, 0.0, 0.0], b + [0.0, 0.0, 0.0], 900.0)[0])
    assert over == 0.0  # the trace crosses the footprint
