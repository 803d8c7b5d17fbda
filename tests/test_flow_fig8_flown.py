"""The built-in ``flow-fig8`` flown closed loop (plan -> route -> hybrid guidance + predictive avoidance)
stays outside every obstacle's margin: checked on the recorded track with the obstacles' exact distances,
independently of the simulator's own contact test (issue 36, point 1b)."""

from __future__ import annotations

from dataclasses import replace

from auvplan._types import Status
from auvplan.io.scenario import loader as sc
from auvplan.sim.pipeline import run_mission


def _least_clearance(world, track):
    """Least exact distance of the track's points to a real obstacle, minus the margin (m)."""
    return float(min(ob.distance(track).min() for ob in world.obstacles)) - world.margins.obstacle


def test_flow_fig8_is_flown_outside_every_margin():
    """Arrives, and every recorded position is >= 1 m outside the 0.5 m margin of the three obstacles
    (3.5 m measured).  With the corrected field's lateral bias back at its default 2 (the planted fault:
    the bias sends the vehicle to starboard round the ellipsoid the plan passes under) the same flight
    enters the sphere's margin, which this oracle sees."""
    world, mission = sc.build(sc.load("flow-fig8"))
    assert mission.guidance == "hybrid" and mission.hybrid.bias == 0.0
    rec = run_mission(world, mission)
    assert rec.plan is not None and rec.plan.status is Status.EXACT
    assert rec.sim is not None and rec.sim.status is Status.EXACT
    assert _least_clearance(world, rec.sim.position) >= 1.0
    biased = run_mission(world, replace(mission, hybrid=replace(mission.hybrid, lateral_bias=2.0)))
    assert biased.sim is not None and _least_clearance(world, biased.sim.position) < 0.0
