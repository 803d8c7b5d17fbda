""":func:`auvplan.survey.joins.join_bridges` on bridges by hand: what it must keep, where it must leave the corners,
and that a joined bridge flies as turns of the radius (``helm_check``, as ``mission check``) clear of obstacles
and zones (shapely on the footprint, ``World.path_free``)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from auvplan.path.flyable import VehicleLimits
from auvplan.path.legs import helm_check
from auvplan.survey.joins import join_bridges
from auvplan.survey.mission import TRANSIT
from auvplan.world import Zone, Zones
from auvplan.world.obstacles import Sphere
from auvplan.world.terrain import Terrain
from auvplan.world.world import Bounds, World


def _world(obstacles=(), zones=None, y=(-400.0, 400.0)) -> World:
    x, yy = np.linspace(-300.0, 1300.0, 9), np.linspace(y[0], y[1], 5)
    t = Terrain(x, yy, np.full((5, 9), -200.0))
    return World(bounds=Bounds(-300.0, 1300.0, y[0], y[1], -200.0, 0.0), terrain=t, obstacles=obstacles,
                 zones=None if zones is None else Zones(zones, t))


def _route(xy, lab) -> tuple[np.ndarray, np.ndarray]:
    return np.array([(a, b, -50.0) for a, b in xy], dtype=float), np.array(lab, dtype=np.int64)


def _tightest(route: np.ndarray, radius: float) -> float:
    return float(helm_check(route, VehicleLimits(90.0, radius), min_leg=0.0).tightest_turn_m)


# a line along y = 0 crossing a box (270..430 x -30..30) bridged 60 m to its side: corners of 50 deg whose fly-by
# turns fit 83.4 m only
BOX = shapely.box(270.0, -30.0, 430.0, 30.0)
SHARP = [(0, 0), (100, 0), (200, 0), (250, 60), (450, 60), (500, 0), (600, 0), (700, 0)]
SHARP_LAB = [0, 0, 0, TRANSIT, TRANSIT, 0, 0, 0]


def _kept_in_order(route, labels, joined, lab) -> bool:
    """Every line vertex of the input is in the output, in order, with its label; every added vertex is a
    transit's."""
    k = 0
    for p, lb in zip(joined, lab, strict=True):
        if k < len(route) and np.array_equal(p, route[k]) and lb == labels[k]:
            k += 1
        elif lb != TRANSIT:
            return False
    return k == len(route) or all(labels[k:] == TRANSIT)


@pytest.mark.parametrize(("radius", "cut"), [(100.0, slice(None)), (150.0, slice(None)), (100.0, slice(1, None)),
                                             (100.0, slice(None, -1))])
def test_a_sharp_bridge_is_joined_by_turns_clear_of_the_zone(radius, cut):
    """Also with a single line leg before the bridge, or after it (the least a turn needs)."""
    box = BOX
    world = _world(zones=(Zone("box", box),))
    route, labels = _route(SHARP[cut], SHARP_LAB[cut])
    assert _tightest(route, radius) < radius
    joined, lab = join_bridges(world, route, labels, TRANSIT, radius)
    assert lab.dtype == np.int64 and lab.shape == joined.shape[:1] and joined.shape[0] > route.shape[0]
    assert _tightest(joined, radius) >= radius * (1.0 - 1e-9)
    legs = shapely.linestrings(np.stack([joined[:-1, :2], joined[1:, :2]], axis=1))
    assert not shapely.intersects(legs, box).any() and world.path_free(joined)
    line = labels != TRANSIT
    assert _kept_in_order(route[line], labels[line], joined[lab != TRANSIT], lab[lab != TRANSIT])
    assert np.array_equal(joined[0], route[0]) and np.array_equal(joined[-1], route[-1])


def test_a_bridge_whose_corners_fly_already_is_left_as_it_is():
    """Corners of 10 deg at most, a 5 m radius: each fits as a fly-by turn; nothing to join."""
    route, labels = _route([(0, 0), (200, 0), (400, 0), (600, 30), (800, 30), (1000, 0), (1200, 0)],
                           [0, 0, 0, TRANSIT, TRANSIT, 0, 0])
    world = _world()
    assert _tightest(route, 5.0) >= 5.0
    joined, lab = join_bridges(world, route, labels, TRANSIT, 5.0)
    assert np.array_equal(joined, route) and np.array_equal(lab, labels)


@pytest.mark.parametrize("cut", [slice(3, None), slice(2, None), slice(None, 6), slice(None, 5)])
def test_a_bridge_without_a_line_leg_on_each_side_keeps_its_corners(cut):
    """The sharp bridge with the route starting on it, with one line vertex before it (no leg to turn from), with
    one after it, or ending on it: left as it is (the full route is joined, test above)."""
    route, labels = _route(SHARP[cut], SHARP_LAB[cut])
    joined, out = join_bridges(_world(zones=(Zone("box", BOX),)), route, labels, TRANSIT, 100.0)
    assert np.array_equal(joined, route) and np.array_equal(out, labels)


@pytest.mark.parametrize(("y", "sphere"), [((-35.0, 250.0), None), ((-400.0, 400.0), (200.0, 277.0))])
def test_a_bridge_no_turn_fits_keeps_its_corners(y, sphere):
    """The joining turns of a 100 m radius swing 277 m to the side: with the bounds 250 m off the line, or a sphere
    on the turn in, none fits; the corners stay (the mission's checks report them)."""
    obstacles = () if sphere is None else (Sphere((*sphere, -50.0), 20.0),)
    world = _world(obstacles=obstacles, zones=(Zone("box", BOX),), y=y)
    route, labels = _route(SHARP, SHARP_LAB)
    joined, lab = join_bridges(world, route, labels, TRANSIT, 100.0)
    assert np.array_equal(joined, route) and np.array_equal(lab, labels)


def test_a_sphere_beside_the_turns_leaves_them_joined_and_clear():
    """A sphere inside the turns' loop (300, 200): the joined route keeps clear of it and of the box."""
    world = _world(obstacles=(Sphere((300.0, 200.0, -50.0), 20.0),), zones=(Zone("box", BOX),))
    route, labels = _route(SHARP, SHARP_LAB)
    joined, lab = join_bridges(world, route, labels, TRANSIT, 100.0)
    assert joined.shape[0] > route.shape[0] and world.path_free(joined)
    assert _tightest(joined, 100.0) >= 100.0 * (1.0 - 1e-9)


def test_two_bridges_on_one_line_are_both_joined():
    """The sharp bridge twice along one line, 500 m apart, each round its box: both bridges' corners become
    turns, clear of both boxes."""
    xy = SHARP[:-1] + [(x + 500, y) for x, y in SHARP[1:]]
    lab = SHARP_LAB[:-1] + SHARP_LAB[1:]
    boxes = (Zone("box", BOX), Zone("box 2", shapely.box(770.0, -30.0, 930.0, 30.0)))
    world = _world(zones=boxes)
    route, labels = _route(xy, lab)
    joined, out = join_bridges(world, route, labels, TRANSIT, 100.0)
    assert _tightest(joined, 100.0) >= 100.0 * (1.0 - 1e-9) and world.path_free(joined)
    runs = np.flatnonzero(np.diff(np.r_[0, (out == TRANSIT).astype(int)]) == 1)
    assert runs.size == 2 and joined.shape[0] >= route.shape[0] + 20
    line = labels != TRANSIT
    assert _kept_in_order(route[line], labels[line], joined[out != TRANSIT], out[out != TRANSIT])


_SHIFTED = [(x + 500, y) for x, y in SHARP[1:]]  # the sharp bridge 500 m on, round a second box
_BOX2 = Zone("box 2", shapely.box(770.0, -30.0, 930.0, 30.0))


@pytest.mark.parametrize(("xy", "lab", "zones"), [
    ([(0, 60), (150, 60), (200, 0), (300, 0), (400, 0), (500, 0), (600, 0)], [TRANSIT, TRANSIT, 0, 0, 0, 0, 0], ()),
    ([(0, 0), (100, 0), (200, 0), (300, 20), (400, 20), (500, 0), (600, 0)], [0, 0, 0, TRANSIT, TRANSIT, 0, 0], ()),
    (SHARP[:-1], SHARP_LAB[:-1], (Zone("box", BOX), Zone("on the loop", shapely.box(140.0, 150.0, 260.0, 400.0)))),
], ids=["route starts on a bridge", "corners already fly", "no turn fits"])
def test_a_bridge_left_as_it_is_does_not_stop_the_next_one(xy, lab, zones):
    """The first bridge is left alone (for each of the three reasons); the sharp one after it is still joined."""
    route, labels = _route(xy + _SHIFTED, lab + SHARP_LAB[1:])
    world = _world(zones=(*zones, _BOX2))
    joined, out = join_bridges(world, route, labels, TRANSIT, 100.0)
    n = len(xy)
    assert np.array_equal(joined[:n], route[:n]) and np.array_equal(out[:n], labels[:n])
    assert joined.shape[0] == route.shape[0] + 14 and world.path_free(joined[n - 2:])
    assert _tightest(joined[n - 2:], 100.0) >= 100.0 * (1.0 - 1e-9)


def test_two_bridges_with_two_line_vertices_between_are_both_joined():
    """The second bridge turns from the line vertex the joined route keeps before it (two between the bridges)."""
    xy = SHARP[:-1] + [(650, 60), (850, 60), (900, 0), (1000, 0), (1100, 0)]
    lab = SHARP_LAB[:-1] + [TRANSIT, TRANSIT, 0, 0, 0]
    world = _world(zones=(Zone("box", BOX), Zone("box 2", shapely.box(670.0, -30.0, 830.0, 30.0))))
    route, labels = _route(xy, lab)
    joined, out = join_bridges(world, route, labels, TRANSIT, 100.0)
    assert joined.shape[0] == route.shape[0] + 28 and world.path_free(joined)
    assert _tightest(joined, 100.0) >= 100.0 * (1.0 - 1e-9)
    line = labels != TRANSIT
    assert _kept_in_order(route[line], labels[line], joined[out != TRANSIT], out[out != TRANSIT])


@pytest.mark.parametrize("centre", [(243.75, 20.5), (205.5, 81.5)], ids=["first leg of the turn in", "its last leg"])
def test_a_sphere_on_a_turn_s_first_or_last_leg_is_kept_clear(centre):
    """A small sphere on the first leg of the turn that joins the sharp bridge (from the line's end to the turn's
    first point), or on its last one (into the transit): whatever is kept is clear of it (``World.path_free``)."""
    world = _world(obstacles=(Sphere((*centre, -50.0), 5.0),), zones=(Zone("box", BOX),))
    route, labels = _route(SHARP, SHARP_LAB)
    joined, _ = join_bridges(world, route, labels, TRANSIT, 100.0)
    assert world.path_free(route) and world.path_free(joined)
