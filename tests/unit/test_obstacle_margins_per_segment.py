"""A static obstacle's exact segment test takes one margin per segment (the clearance under the navigation error asks
each leg at its own margin + error): the answers are those of the test asked one segment at a time with that
segment's margin as a number (the oracle), for a sphere and a rotated ellipsoid, margins 0 to beyond the shape,
segments inside, grazing and clear; and ``obstacle_within`` / ``route_keeps`` give the loops' answers."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from auvplan.nav.clearance import obstacle_within
from auvplan.sim.tracking import route_keeps
from auvplan.world.obstacles import Ellipsoid, Sphere

SHAPES = [Sphere((0.0, 0.0, -50.0), 20.0),
          Ellipsoid((0.0, 0.0, -50.0), (40.0, 15.0, 8.0), yaw=0.5, pitch=0.2, roll=-0.3)]


def _segments(n: int = 400) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(17)
    a = rng.uniform(-90.0, 90.0, (n, 3)) + [0.0, 0.0, -50.0]
    b = a + rng.normal(scale=40.0, size=(n, 3))
    margin = rng.choice([0.0, 0.5, 3.0, 12.0, 60.0], size=n) * rng.uniform(0.5, 1.5, n)
    margin[::7] = 0.0
    return np.stack([a, b], axis=1), margin


@pytest.mark.parametrize("shape", SHAPES, ids=["sphere", "ellipsoid"])
def test_one_margin_per_segment_is_each_segment_asked_alone(shape):
    seg, margin = _segments()
    got = shape.segments_hit(seg, margin)
    alone = np.array([bool(shape.segments_hit(seg[i:i + 1], float(margin[i]))[0]) for i in range(len(seg))])
    assert got.tolist() == alone.tolist()
    assert 0 < got.sum() < len(seg) and (got & ~shape.segments_hit(seg)).any()  # the margins decide some


def test_obstacle_within_is_the_first_obstacle_of_each_segment():
    seg, r = _segments()
    world = SimpleNamespace(obstacles=SHAPES[::-1], margins=SimpleNamespace(obstacle=2.0))
    want = np.full(len(seg), -1)
    for i in range(len(seg)):
        for j, shape in enumerate(world.obstacles):
            if bool(shape.segments_hit(seg[i:i + 1], 2.0 + float(r[i]))[0]):
                want[i] = j
                break
    got = obstacle_within(world, seg, r)  # type: ignore[arg-type]
    assert got.tolist() == want.tolist() and {-1, 0, 1} <= set(got.tolist())


@pytest.mark.parametrize("stop", [5, 60, 400])
def test_route_keeps_is_the_first_leg_closer_than_its_clearance(stop):
    seg, need = _segments()
    route = np.concatenate([seg[:stop, 0], seg[stop - 1:stop, 1]])  # legs between consecutive starts
    legs = np.stack([route[:-1], route[1:]], axis=1)
    world = SimpleNamespace(obstacles=SHAPES)
    want = next((i for i in range(len(legs)) if any(bool(o.segments_hit(legs[i:i + 1], float(need[i]))[0])
                                                    for o in SHAPES)), -1)
    assert route_keeps(world, route, need[:len(legs)]) == want  # type: ignore[arg-type]
    assert route_keeps(world, route, 0.0) == next(  # type: ignore[arg-type]
        (i for i in range(len(legs)) if any(bool(o.segments_hit(legs[i:i + 1])[0]) for o in SHAPES)), -1)
