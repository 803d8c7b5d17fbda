"""The clearance contract between planner and follower (issue 57 item 2, :mod:`auvplan.sim.tracking`).

Oracles: distances to a route by brute force on a 1 mm sampling of its legs (independent of
``route_deviation``'s projection), a sphere's analytic segment distance, and the exact distance of every
recorded position to the real obstacle surfaces (``Shape.distance``, independent of the simulator's contact
flag).  The hard starts are benchmarks/flow_flown.py's (docs/figures/flow-flown.md).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from auvplan.io.scenario import loader as sc
from auvplan.sim.loop import simulate
from auvplan.sim.pipeline import kept_fit, planned_route, run_mission
from auvplan.sim.tracking import contract_world, route_bound, route_deviation, route_keeps
from auvplan.world import Ellipsoid, Sphere

TURNED = Ellipsoid((0.0, 0.0, 0.0), (8.0, 4.0, 3.0), yaw=np.pi / 4)
SPHERES = (Sphere((15.0, 5.0, 0.0), 3.0), Sphere((-12.0, -6.0, 2.0), 2.5))
WORST = (-6.000, -10.149, 1.036)  # the worst start: LOS -0.001 m, ILOS -0.011 m, hybrid -0.115 m
REPLANNED = (-6.012, -7.284, -3.56)  # Fig. 7 (document reading): the first route breaks the contract, a re-plan
# keeps it


def _dense(route, step=1e-3):
    """Points every ``step`` m along each leg and their leg index (brute-force oracle)."""
    pts, legs = [], []
    for i, (a, b) in enumerate(zip(route[:-1], route[1:], strict=True)):
        n = max(2, int(np.ceil(np.linalg.norm(b - a) / step)) + 1)
        pts.append(a + np.linspace(0.0, 1.0, n)[:, None] * (b - a))
        legs.append(np.full(n, i))
    return np.vstack(pts), np.concatenate(legs)


def _deviation(track, route):
    pts, _ = _dense(route, 0.01)
    return np.concatenate([np.linalg.norm(pts[None] - t[:, None], axis=2).min(axis=1)
                           for t in np.array_split(track, max(1, len(track) // 50))])


def _least(world, track):
    return min(float(ob.distance(track).min()) for ob in world.obstacles)


@pytest.fixture(scope="module")
def fig8():
    world, mission = sc.build(sc.load("flow-fig8"))
    return replace(world, obstacles=(TURNED,) + SPHERES), mission


@pytest.fixture(scope="module")
def worst(fig8):
    """The route planned from the worst start without the contract."""
    world, mission = fig8
    return planned_route(world, replace(mission, start=WORST), 0)[1]


def test_route_deviation_is_the_distance_to_the_nearest_leg():
    """Random points about a bent 3-D route (legs of 0.3 to 12 m, a climb): the distance and the leg agree with a
    brute-force search over points every 1 mm of the route."""
    rng = np.random.default_rng(7)
    route = np.array([[0.0, 0.0, 0.0], [12.0, 0.0, 0.0], [12.3, 0.1, 0.2], [15.0, 8.0, 3.0], [4.0, 10.0, 3.0]])
    track = rng.uniform([-2.0, -3.0, -2.0], [17.0, 12.0, 5.0], (60, 3))
    dist, leg = route_deviation(track, route)
    pts, legs = _dense(route)
    for p, d, k in zip(track, dist, leg, strict=True):
        e = np.linalg.norm(pts - p, axis=1)
        assert d == pytest.approx(e.min(), abs=1e-3)
        assert e[legs == k].min() == pytest.approx(e.min(), abs=1e-3)


def test_route_keeps_a_clearance_per_leg_against_the_sphere_distance():
    """A sphere of radius 2 at the origin; a leg 3 m from its centre is 1 m from its surface (analytic)."""
    from auvplan.world import Bounds, World

    world = World(Bounds(-20, 20, -20, 20, -20, 20), obstacles=(Sphere((0.0, 0.0, 0.0), 2.0),))
    route = np.array([[-10.0, -10.0, 0.0], [-10.0, 3.0, 0.0], [10.0, 3.0, 0.0]])  # leg 0: 10 m off, leg 1: 3 m off
    assert route_keeps(world, route, 0.99) == -1
    assert route_keeps(world, route, 1.01) == 1
    assert route_keeps(world, route, [7.99, 0.99]) == -1
    assert route_keeps(world, route, [8.01, 0.5]) == 0
    raised = contract_world(world, 0.75)
    assert raised.margins.obstacle == pytest.approx(world.margins.obstacle + 0.75)


def test_the_bound_is_how_far_the_follower_leaves_the_route(fig8, worst):
    """On the worst start's route the bound per leg is the largest distance of the obstacle-free flight from the
    route (brute force) among the flight's points nearest that leg; the hybrid adds its stated push; a straight
    route flown from its start heading along it is not left at all."""
    world, mission = fig8
    route = worst
    b = route_bound(world, mission, route, "los")
    sim = simulate(replace(world, obstacles=()), mission, route=route, guidance="los", avoidance="none", rng=0)
    dev = _deviation(sim.position, route)
    assert b.flown_m == pytest.approx(dev.max(), abs=0.01) and b.flown_m > 0.5
    pts, legs = _dense(route, 0.01)
    nearest = np.concatenate([legs[np.linalg.norm(pts[None] - t[:, None], axis=2).argmin(axis=1)]
                              for t in np.array_split(sim.position, max(1, len(sim.position) // 50))])
    per_leg = np.zeros(len(route) - 1)
    np.maximum.at(per_leg, nearest, dev)
    np.testing.assert_allclose(b.legs_m, per_leg, atol=0.01)
    hyb = route_bound(world, mission, route, "hybrid")
    assert hyb.push_m == mission.hybrid.push_bound_m > 0 and hyb.total_m == pytest.approx(b.total_m + hyb.push_m,
                                                                                        abs=0.01)
    straight = np.array([[-30.0, -30.0, -5.0], [30.0, -30.0, -5.0]])
    assert route_bound(world, mission, straight, "ilos").flown_m < 1e-6


def test_hybrid_leaves_a_clear_route_by_at_most_los_plus_its_push_bound(fig8, worst):
    """The worst start's clear route (it passes the ellipsoid at 0.78 m and then a sphere), flown by LOS and by the
    hybrid field with only the followers (no avoidance): the hybrid's largest distance from the route (brute
    force) is at most LOS's plus ``push_bound_m``.  Without the bound (a huge push_bound_m, the field before
    issue 57) it flew 2-5x further off than LOS and into the sphere."""
    world, mission = fig8
    route = worst
    fly = {g: simulate(world, mission, route=route, guidance=g, avoidance="none", rng=0) for g in ("los", "hybrid")}
    los, hyb = (_deviation(fly[g].position, route).max() for g in ("los", "hybrid"))
    assert hyb <= los + mission.hybrid.push_bound_m + 0.02
    free = replace(mission, hybrid=replace(mission.hybrid, push_bound_m=1e9))
    unbounded = simulate(world, free, route=route, guidance="hybrid", avoidance="none", rng=0)
    assert _deviation(unbounded.position, route).max() > los + 2.0


@pytest.mark.parametrize("guidance", ["los", "hybrid"])  # ILOS: benchmarks/flow_flown.py
def test_the_contract_refuses_the_start_that_touched_with_its_reason(fig8, worst, guidance):
    """The issue's worst start: without the contract every follower touches an obstacle (exact distance <= 0);
    with it the plan is refused with a status, and the message names the follower, the leg and its bound."""
    world, mission = fig8
    m = replace(mission, start=WORST)
    flown = simulate(world, m, route=worst, guidance=guidance, rng=0)
    assert _least(world, flown.position) <= 0.0
    rec = run_mission(world, m, 0, guidance=guidance)
    assert rec.sim is None and not rec.plan.status.ok
    assert rec.plan.message.startswith(f"clearance contract: the {guidance} follower leaves this route's leg")


@pytest.mark.parametrize("guidance", ["los", "hybrid"])
def test_a_kept_plan_is_flown_at_least_the_margin_away(fig8, guidance):
    """A start whose first route breaks the contract: the re-plan (margin raised by the bound) keeps margin + each
    leg's bound from every surface (1 mm samples of each leg, exact distance), and the flight under the default
    predictive avoidance arrives at least the 0.5 m margin from every real surface."""
    world, mission = fig8
    world = replace(world, obstacles=(TURNED,))
    m = replace(mission, start=REPLANNED)
    _, first = planned_route(world, m, 0)
    plan, fit = kept_fit(world, m, 0, None, guidance)
    route = fit.waypoints
    assert plan.status.ok and (len(route) != len(first) or not np.allclose(route, first))
    b = route_bound(world, m, route, guidance)
    assert plan.cost_terms["tracking_bound_m"] == pytest.approx(b.total_m)
    pts, legs = _dense(route, 0.01)
    clear = TURNED.distance(pts)
    assert (clear >= world.margins.obstacle + b.per_leg_m[legs] - 1e-6).all()
    rec = run_mission(world, m, 0, guidance=guidance)
    assert rec.sim.arrived and _least(world, rec.sim.position) >= world.margins.obstacle - 1e-6
